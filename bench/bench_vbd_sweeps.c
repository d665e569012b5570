/* sb_bench_vbd_sweeps: how far vbd's sweeps converge within a step, on the
 * default scene's sheet at 100 × 100 vertices, dt = 1 ms (issue 36: a
 * different Gauss-Seidel order must not converge worse).
 *
 * The sheet falls for --warm steps (default 100) at 4 sweeps, one thread,
 * to a moving state; from that state (a checkpoint) one step is taken with
 * k sweeps for each k listed and with --converged sweeps (default 400),
 * whose positions x* stand for the step's fixed point. One line per k:
 *   SWEEPS,ERROR
 * ERROR = |x_k − x*| / |x* − x_start| over all coordinates: the part of the
 * step's move the k sweeps have not made (0: converged). Deterministic for
 * a given build and order: no timing. */
#include "softbond/softbond.h"
#include "softbond/scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void sb_fail(const char* what, const sb_error* err) {
    fprintf(stderr, "sb_bench_vbd_sweeps: %s: %s\n", what, err ? err->message : "out of memory");
    exit(1);
}

/* One step with `sweeps` sweeps from the checkpoint; positions into x. */
static void sb_step_from(const sb_model* m, const sb_solver_def* base, int sweeps, const void* state, size_t size,
                         double dt, double* x) {
    sb_solver_def def = *base;
    def.vbd_iterations = sweeps;
    sb_error err = {0};
    sb_solver* s = sb_solver_create(m, &def, &err);
    if (!s) sb_fail("sb_solver_create", &err);
    if (sb_solver_load_state(s, state, size, &err) != SB_OK) sb_fail("sb_solver_load_state", &err);
    if (sb_solver_advance(s, dt) != SB_OK) sb_fail(sb_solver_error(s), NULL);
    sb_solver_get_positions(s, x);
    sb_solver_destroy(s);
}

int main(int argc, char** argv) {
    int warm = 100, converged = 400, ks[16] = {1, 2, 3, 4, 6, 8}, k_count = 6;
    const char* scene_path = SB_BENCH_SOURCE_DIR "/scenes/default.yaml";
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--warm"))
            warm = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--converged"))
            converged = atoi(argv[i + 1]);
        else {
            fprintf(stderr, "usage: sb_bench_vbd_sweeps [--warm 100] [--converged 400]\n");
            return 2;
        }
    }
    const char* overrides[] = {"mesh.nx=100", "mesh.ny=100", "integrator=vbd", "vbd.iterations=4", "threads=1"};
    sb_scene_file* scene;
    sb_error err = {0};
    if (sb_scene_file_load(scene_path, overrides, sizeof overrides / sizeof *overrides, &scene, &err) != SB_OK)
        sb_fail(scene_path, &err);
    const sb_model* m = sb_scene_file_model(scene);
    const sb_solver_def* def = sb_scene_file_solver_def(scene);
    const double dt = 1e-3;
    sb_solver* s = sb_solver_create(m, def, &err);
    if (!s) sb_fail("sb_solver_create", &err);
    for (int i = 0; i < warm; i++)
        if (sb_solver_advance(s, dt) != SB_OK) sb_fail(sb_solver_error(s), NULL);
    size_t size = sb_solver_state_size(s), n3 = 3 * (size_t)sb_solver_vertex_count(s);
    void* state = malloc(size);
    double *start = malloc(n3 * sizeof *start), *best = malloc(n3 * sizeof *best), *x = malloc(n3 * sizeof *x);
    if (!state || !start || !best || !x) sb_fail("allocation", NULL);
    if (sb_solver_save_state(s, state, size, &err) != SB_OK) sb_fail("sb_solver_save_state", &err);
    sb_solver_get_positions(s, start);
    sb_solver_destroy(s);
    sb_step_from(m, def, converged, state, size, dt, best);
    double move = 0.0;
    for (size_t q = 0; q < n3; q++) move += (best[q] - start[q]) * (best[q] - start[q]);
    printf("sweeps,error\n");
    for (int k = 0; k < k_count; k++) {
        sb_step_from(m, def, ks[k], state, size, dt, x);
        double off = 0.0;
        for (size_t q = 0; q < n3; q++) off += (x[q] - best[q]) * (x[q] - best[q]);
        printf("%d,%.6g\n", ks[k], sqrt(off / move));
    }
    free(state), free(start), free(best), free(x);
    sb_scene_file_destroy(scene);
    return 0;
}
