/* sb_bench_pbd: xpbd on the 100 × 100 sheet of the Jolt peer (issue 15).
 *
 * The sheet_10k case (1 m × 1 m, 100 × 100 vertices, one diagonal per cell,
 * no jitter: Jolt's cloth is a regular grid), hanging from the two corners
 * of its top row, gravity, xpbd with --iterations sweeps (default 5), dt
 * 1 ms, the fast kernels. Two cases:
 *   bonds    only the bonds (29 601 distance constraints): angle and
 *            stretch-bend constants 0;
 *   corners  the bonds and the angle term's corners (58 806 direction
 *            constraints), stretch-bend 0.
 * Each case and thread count is timed --repeats times, the cases and counts
 * interleaved (so that a busy moment of a shared machine hits all alike);
 * the best time counts. One line per case and thread count on stdout:
 *   softbond,CASE,THREADS,STEPS,MS_PER_STEP,BOND_PROJECTIONS,CORNER_PROJECTIONS,BARRIERS
 * (projections per step: constraints × sweeps; the team's barriers a step
 * on more than one thread, kernels/integrators/fast_pbd.c). bench/jolt/run.sh runs it
 * beside the Jolt peer. */
#include "bench/bench_cases.h"
#include "common/clock.h"
#include "kernels/integrators/fast_pbd.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SB_PBD_BENCH_DT 1e-3 /* s: the peer's step */

typedef struct sb_pbd_options {
    int threads[4], thread_count;
    int iterations, repeats;
    uint64_t steps;
} sb_pbd_options;

static void sb_usage(void) {
    fprintf(stderr, "usage: sb_bench_pbd [--threads-list 1,2] [--iterations 5] [--steps 400] [--repeats 5]\n");
    exit(2);
}

static sb_pbd_options sb_parse(int argc, char** argv) {
    sb_pbd_options o = {{1, 2}, 2, 5, 5, 400};
    for (int i = 1; i < argc; i++) {
        if (i + 1 >= argc) sb_usage();
        const char *key = argv[i], *value = argv[++i];
        if (!strcmp(key, "--threads-list")) {
            o.thread_count = 0;
            for (char* end = (char*)value; *value && o.thread_count < 4; value = end + (*end == ',')) {
                o.threads[o.thread_count++] = (int)strtol(value, &end, 10);
                if (end == value || o.threads[o.thread_count - 1] < 1) sb_usage();
            }
        } else if (!strcmp(key, "--iterations"))
            o.iterations = atoi(value);
        else if (!strcmp(key, "--steps"))
            o.steps = strtoull(value, NULL, 10);
        else if (!strcmp(key, "--repeats"))
            o.repeats = atoi(value);
        else
            sb_usage();
    }
    if (o.iterations < 1 || o.repeats < 1 || o.steps < 1) sb_usage();
    return o;
}

/* The sheet with the bonds alone, or with the angle term's corners too. */
static sb_model* sb_sheet(bool corners, uint32_t* bonds, uint32_t* triangles) {
    sb_bench_options options = {.all_terms = false, .jitter = 0.0};
    sb_bench_setup setup;
    sb_error err = {{0}};
    sb_builder* b = NULL;
    sb_model* m = NULL;
    if (sb_bench_prepare(sb_bench_find_case("sheet_10k"), &options, &setup, &err) == SB_OK &&
        (b = sb_builder_create())) {
        setup.material.stretch_bend_k = 0.0;
        if (!corners) setup.material.angle_k = 0.0;
        if (sb_builder_add_mesh(b, &setup.mesh, &setup.material, &err) == SB_OK) {
            for (uint32_t p = 0; p < setup.pin_count; p++) sb_builder_vertex(b, setup.pins[p])->fixed = true;
            m = sb_builder_compile(b, &err);
        }
    }
    sb_builder_destroy(b);
    sb_bench_setup_free(&setup);
    if (!m) {
        fprintf(stderr, "sb_bench_pbd: %s\n", err.message);
        exit(1);
    }
    *bonds = sb_model_bond_count(m);
    *triangles = corners ? sb_model_triangle_count(m) : 0;
    return m;
}

static sb_solver* sb_pbd_solver(const sb_model* m, const sb_pbd_options* o, int threads) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_XPBD;
    def.pbd_iterations = o->iterations;
    def.gravity[0] = def.gravity[1] = 0.0;
    def.gravity[2] = -SB_BENCH_GRAVITY;
    def.runtime = (sb_runtime_def){.threads = threads, .pin = threads > 1, .wait = SB_WAIT_SPIN};
    sb_error err = {{0}};
    sb_solver* s = sb_solver_create(m, &def, &err);
    if (!s) {
        fprintf(stderr, "sb_bench_pbd: %s\n", err.message);
        exit(1);
    }
    return s;
}

/* Seconds for `steps` steps from the rest state (after as many to warm up). */
static double sb_time_steps(sb_solver* s, uint64_t steps) {
    double t0 = 0.0;
    if (sb_solver_set_state(s, NULL, NULL) != SB_OK) return NAN;
    for (uint64_t k = 0; k < 2 * steps; k++) {
        if (k == steps) t0 = sb_wall_seconds();
        if (sb_solver_advance(s, SB_PBD_BENCH_DT) != SB_OK) {
            fprintf(stderr, "sb_bench_pbd: %s\n", sb_solver_error(s));
            exit(1);
        }
    }
    return sb_wall_seconds() - t0;
}

int main(int argc, char** argv) {
    sb_pbd_options o = sb_parse(argc, argv);
    enum { CASES = 2 };
    const char* names[CASES] = {"bonds", "corners"};
    sb_model* models[CASES];
    uint32_t bonds[CASES], triangles[CASES];
    sb_solver* solvers[CASES][4];
    double best[CASES][4];
    for (int c = 0; c < CASES; c++) {
        models[c] = sb_sheet(c == 1, &bonds[c], &triangles[c]);
        for (int t = 0; t < o.thread_count; t++) {
            solvers[c][t] = sb_pbd_solver(models[c], &o, o.threads[t]);
            best[c][t] = INFINITY;
        }
    }
    for (int r = 0; r < o.repeats; r++)
        for (int c = 0; c < CASES; c++)
            for (int t = 0; t < o.thread_count; t++)
                best[c][t] = fmin(best[c][t], sb_time_steps(solvers[c][t], o.steps));
    for (int c = 0; c < CASES; c++) {
        for (int t = 0; t < o.thread_count; t++) {
            printf("softbond,%s,%d,%llu,%.6f,%llu,%llu,%u\n", names[c], o.threads[t], (unsigned long long)o.steps,
                   1e3 * best[c][t] / (double)o.steps, (unsigned long long)bonds[c] * (unsigned)o.iterations,
                   3ull * triangles[c] * (unsigned)o.iterations, sb_pbd_wide_barriers(solvers[c][t]));
            sb_solver_destroy(solvers[c][t]);
        }
        sb_model_destroy(models[c]);
    }
    return 0;
}
