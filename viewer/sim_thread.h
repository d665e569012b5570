/* The viewer's simulation thread: the only thread that touches the solver.
 * It advances at the wall clock's pace (or as fast as it can when the
 * solver is slower), publishes snapshots to the state buffer, and meets
 * the render thread in one small shared record, guarded by a mutex that
 * the simulation thread only ever tries (pthread_mutex_trylock): it never
 * waits for the renderer. */
#ifndef SB_VIEWER_SIM_THREAD_H
#define SB_VIEWER_SIM_THREAD_H

#include "scenes/simulation.h"
#include "viewer/topology.h"

#include <pthread.h>

/* What the render thread asks for. */
typedef struct sb_sim_controls {
    bool paused;           /* space: no steps, the clock stops */
    bool stopped;          /* s: the bodies stopped (velocities zeroed) and held until resumed */
    bool gravity_off;      /* g */
    bool gravity_reversed; /* r */
    uint64_t resets;       /* the reset key: each new count puts the bodies back at rest */
    int64_t pick;          /* the vertex the mouse holds, -1 = none */
    uint64_t picks;        /* each new pick (press) counts one */
    double target[3];      /* m: where the cursor pulls the picked vertex (or the tool) */
    bool tool;             /* the mouse moves the haptic tool to target */
    uint64_t single_steps; /* n: each new count takes one step while paused or stopped */
    /* s, simulated: no step starts at or after it (a script's next event,
     * until the renderer has handled it); INFINITY = none */
    double hold;
    bool quit;
} sb_sim_controls;

/* What the simulation thread reports (besides the snapshots). */
typedef struct sb_sim_report {
    double steps_per_second;
    double realtime_factor; /* simulated over wall-clock seconds, over the last half second */
    double pick_force[3];   /* N: the mouse's spring on the picked vertex */
    uint32_t collider_count;
    double poses[16][12]; /* per collider (the first 16): row-major rotation, then center, m */
    char failure[256];    /* the solver's message once it failed ("" before) */
} sb_sim_report;

enum { SB_SIM_MAX_COLLIDERS = 16 };

typedef struct sb_sim_thread {
    sb_simulation* sim;
    sb_state_buffer* buffer;
    sb_handle* grab;         /* the mouse's one-vertex soft handle (attached to the solver) */
    sb_haptic_device* mouse; /* the scene's "mouse" haptic device, or NULL */
    double tool_rest[3];     /* m: the tool's rest position, the device's origin */
    double realtime;         /* the pace: simulated seconds per wall second (0 = as fast as it can) */
    pthread_mutex_t lock;    /* guards controls, report and topology */
    sb_sim_controls controls;
    sb_sim_report report;
    sb_view_topology topology; /* the latest handed over */
    pthread_t thread;
    bool started;
} sb_sim_thread;

/* The grab handle to attach to the solver before it is made (stiffness
 * and damping per vertex, N/m and N s/m). */
sb_handle* sb_sim_grab_handle(double stiffness, double damping, sb_error* err);

/* Starts the thread on a prepared simulation (its solver made with the
 * grab handle attached) and a buffer for its vertices' capacity with room
 * for two held snapshots. Controls already set in t->controls apply before
 * the first step. t->topology is the solver's from here on. */
sb_status sb_sim_thread_start(sb_sim_thread* t, sb_error* err);
/* Asks it to finish and joins it. */
void sb_sim_thread_stop(sb_sim_thread* t);

/* Render thread: copies the controls in and the report out, under the
 * lock, and the topology into `topology` (made for the same solver) when it
 * changed since `topology->version`; true then. */
bool sb_sim_thread_exchange(sb_sim_thread* t, const sb_sim_controls* controls, sb_sim_report* report,
                            sb_view_topology* topology);

#endif
