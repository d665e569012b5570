/* sb_bench_viewer: what drawing the simulation costs the solver.
 *
 *   xvfb-run -a sb_bench_viewer SCENE [--seconds S] [--threads N] [--render-share X] [--set key=value]...
 *
 * The scene (bench/viewer.sh: the default sheet at 317 x 317 = 100 489
 * vertices) runs S seconds (default 10) as fast as it goes, alone on this
 * thread (sb_solver_advance in a loop, nothing published) before and after
 * (their mean is the rate alone: on a shared machine the load drifts), and in
 * `softbond view` for S seconds (the simulation thread as fast as it can,
 * publishing a snapshot per batch; the render thread drawing at up to 60
 * frames per second within its render share, 960 x 720, edges and lit
 * faces); and prints a CSV row: vertices, solver threads, render share,
 * steps per second without and with the viewer, their ratio, the mean time
 * to draw a frame and the frames per second reached. Run under Xvfb, the drawing is Mesa's llvmpipe on the CPU: it
 * competes with the solver for the same cores. */
#define _GNU_SOURCE
#include "scenes/simulation.h"
#include "common/clock.h"
#include "viewer/view.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Steps per second of the scene advanced alone for `seconds`. */
static double alone(const sb_simulation_args* args, double seconds, uint32_t* vertices) {
    sb_simulation sim = {0};
    sb_error err;
    if (sb_simulation_prepare(&sim, args, &err) != SB_OK || sb_simulation_start(&sim, NULL, &err) != SB_OK) {
        fprintf(stderr, "sb_bench_viewer: %s\n", err.message);
        exit(2);
    }
    *vertices = sb_solver_vertex_count(sim.solver);
    double dt = sb_scene_number(&sim.scene, SB_KEY_DT), start = sb_wall_seconds(), end = start + seconds;
    uint64_t steps = 0;
    while (sb_wall_seconds() < end && sb_solver_advance(sim.solver, dt) == SB_OK) steps++;
    double rate = steps / (sb_wall_seconds() - start);
    sb_simulation_free(&sim);
    return rate;
}

int main(int argc, char** argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: sb_bench_viewer SCENE [--seconds S] [--threads N] [--set key=value]...\n");
        return 2;
    }
    double seconds = 10.0, share = sb_default_view_options(NULL).render_share;
    const char* sets[64];
    sb_simulation_args args = {.input = argv[1], .sets = sets};
    for (int i = 2; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--seconds") == 0) seconds = atof(argv[i + 1]);
        if (strcmp(argv[i], "--threads") == 0) args.threads = argv[i + 1];
        if (strcmp(argv[i], "--set") == 0 && args.set_count < 64) sets[args.set_count++] = argv[i + 1];
        if (strcmp(argv[i], "--render-share") == 0) share = atof(argv[i + 1]);
    }
    uint32_t vertices;
    double before = alone(&args, seconds, &vertices);
    sb_view_options o = sb_default_view_options(&args);
    o.realtime = 0.0;
    o.render_share = share;
    o.frames = 0;
    o.seconds = seconds;
    sb_view_result r;
    sb_error err;
    double start = sb_wall_seconds();
    if (sb_view_run(&o, &r, &err) != SB_OK) {
        fprintf(stderr, "sb_bench_viewer: %s\n", err.message);
        return 2;
    }
    double wall = sb_wall_seconds() - start, after = alone(&args, seconds, &vertices), without = 0.5 * (before + after);
    printf("vertices,threads,render_share,steps_per_s_alone,steps_per_s_viewer,ratio,frame_ms,fps\n");
    printf("%u,%s,%g,%.1f,%.1f,%.3f,%.2f,%.1f\n", vertices, args.threads ? args.threads : "default", share, without,
           r.steps_per_second, r.steps_per_second / without, 1e3 * r.frame_seconds, r.frames / wall);
    sb_view_result_free(&r);
    return 0;
}
