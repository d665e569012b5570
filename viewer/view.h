/* `softbond view`: the real-time viewer. The simulation runs on its own
 * thread (viewer/sim_thread.h); this thread draws the latest snapshot of
 * the state buffer at a fixed frame rate and turns keys and mouse (from
 * the window or a script) into controls for it. */
#ifndef SB_VIEWER_VIEW_H
#define SB_VIEWER_VIEW_H

#include "scenes/simulation.h"
#include "viewer/camera.h"

typedef struct sb_view_options {
    const sb_simulation_args* args; /* the scene, --set, --threads */
    const char* screenshot;         /* PNG of the last frame, or NULL */
    uint64_t frames;                /* stop after this many frames; 0 = until closed */
    double seconds;                 /* stop after this many wall-clock seconds; 0 = until closed */
    const char* script;             /* scripted input (viewer/input_script.h), or NULL */
    int width, height;              /* pixels */
    double fps;                     /* frames per second drawn at most */
    double realtime;                /* simulated seconds per wall second; 0 = as fast as it can */
    /* The most of the wall clock the render thread takes: after a frame
     * that took d seconds to draw it waits at least d (1/share − 1), so a
     * slow renderer (Mesa's llvmpipe on the solver's cores) lowers its
     * frame rate instead of the solver's; 1 = no limit. Default 0.15. */
    double render_share;
} sb_view_options;

sb_view_options sb_default_view_options(const sb_simulation_args* args);

/* What the viewer showed last, for tests and the benchmark. */
typedef struct sb_view_result {
    uint32_t vertex_count;
    double time; /* s, simulated, of the last snapshot drawn */
    uint64_t step;
    double* positions; /* 3n: the last snapshot drawn */
    double* velocities;
    int64_t picked; /* the vertex the mouse held last, -1 = none */
    double target[3];
    uint64_t frames;
    double frame_seconds;    /* mean wall time to draw a frame (without the wait for the next) */
    double steps_per_second; /* the simulation's, over the whole run */
    double realtime_factor;  /* the same: simulated over wall seconds */
    sb_camera camera;        /* as it was at the last frame */
    int width, height;
} sb_view_result;

/* Runs the viewer until the window closes, the script quits, `escape`,
 * options->frames frames or options->seconds. On error nothing was shown, or err says what
 * failed. */
sb_status sb_view_run(const sb_view_options* options, sb_view_result* result, sb_error* err);
void sb_view_result_free(sb_view_result* result);

#endif
