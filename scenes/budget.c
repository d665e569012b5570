/* --budget-ms: the choice, kept apart from the timing so that tests can
 * give it timings, and the calibration that measures them. */
#define _POSIX_C_SOURCE 200809L
#include "scenes/budget.h"

int sb_budget_choose(const sb_budget_level* levels, int count, double budget_ms, bool* fits) {
    int best = -1, smallest = 0;
    for (int i = 0; i < count; i++) {
        if (levels[i].vertices < levels[smallest].vertices) smallest = i;
        if (levels[i].step_ms <= budget_ms && (best < 0 || levels[i].vertices > levels[best].vertices)) best = i;
    }
    if (fits) *fits = best >= 0;
    return best >= 0 ? best : smallest;
}

/* ---- calibration ----------------------------------------------------------- */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/error.h"
#include "scenes/scene_model.h"

enum { MAX_LEVELS = 6 };

static double seconds_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static sb_status copy_mesh(const sb_mesh* in, sb_mesh* out, sb_error* err) {
    *out = (sb_mesh){in->vertex_count, malloc(3 * (size_t)in->vertex_count * sizeof(double) + 1), in->triangle_count,
                     malloc(3 * (size_t)in->triangle_count * sizeof(uint32_t) + 1)};
    if (!out->positions || !out->triangles) {
        sb_mesh_free(out);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    }
    memcpy(out->positions, in->positions, 3 * (size_t)in->vertex_count * sizeof(double));
    memcpy(out->triangles, in->triangles, 3 * (size_t)in->triangle_count * sizeof(uint32_t));
    return SB_OK;
}

/* Milliseconds per step of the fast step on this mesh. */
static sb_status time_step(const sb_scene* scene, const sb_solver_def* def, const sb_mesh* mesh, double* step_ms,
                           sb_error* err) {
    sb_model* model = sb_scene_build_model(scene, mesh, "budget", err);
    if (!model) return SB_ERR_INVALID;
    sb_solver_def fast = *def;
    fast.kernels = SB_KERNELS_FAST;
    sb_solver* solver = sb_solver_create(model, &fast, err);
    if (!solver) {
        sb_model_destroy(model);
        return SB_ERR_INVALID;
    }
    double dt = sb_scene_number(scene, SB_KEY_DT);
    for (int i = 0; i < 3; i++) sb_solver_advance(solver, dt);
    /* The best of 3 rounds: another process taking the cores for a while
     * makes a round slow, never fast. */
    *step_ms = INFINITY;
    for (int round = 0; round < 3; round++) {
        int steps = 0;
        double start = seconds_now(), elapsed = 0.0;
        while (steps < 100 && elapsed < 0.01) {
            sb_solver_advance(solver, dt); /* a blow-up costs the same: time it anyway */
            steps++;
            elapsed = seconds_now() - start;
        }
        *step_ms = fmin(*step_ms, 1e3 * elapsed / steps);
    }
    sb_solver_destroy(solver);
    sb_model_destroy(model);
    return SB_OK;
}

sb_status sb_budget_mesh(const sb_scene* scene, const sb_solver_def* def, double budget_ms, sb_mesh* out, FILE* stream,
                         sb_error* err) {
    sb_mesh meshes[MAX_LEVELS] = {{0}};
    sb_budget_level levels[MAX_LEVELS];
    int count = 0;
    sb_status status = sb_scene_make_mesh(scene, &meshes[0], err);
    if (status == SB_OK && sb_scene_volumetric(scene))
        status = sb_error_set(err, SB_ERR_INVALID,
                              "--budget-ms: level of detail applies to surface meshes, not tetrahedral files");
    if (status == SB_OK) count = 1;
    while (status == SB_OK && count < MAX_LEVELS && meshes[count - 1].vertex_count / 2 >= 64) {
        uint32_t target = meshes[count - 1].vertex_count / 2;
        status = copy_mesh(&meshes[count - 1], &meshes[count], err);
        if (status == SB_OK) status = sb_scene_simplify(scene, &meshes[count], target, NULL, err);
        if (status != SB_OK) break;
        if ((uint64_t)meshes[count].vertex_count * 10 > (uint64_t)meshes[count - 1].vertex_count * 9) {
            sb_mesh_free(&meshes[count]); /* stuck: the locked vertices are most of it */
            break;
        }
        count++;
    }
    for (int i = 0; i < count && status == SB_OK; i++) {
        levels[i].vertices = meshes[i].vertex_count;
        status = time_step(scene, def, &meshes[i], &levels[i].step_ms, err);
    }
    if (status == SB_OK) {
        bool fits;
        int pick = sb_budget_choose(levels, count, budget_ms, &fits);
        if (stream) {
            fprintf(stream, "softbond: --budget-ms %g: calibrated the fast step at %d resolution%s\n", budget_ms, count,
                    count == 1 ? "" : "s");
            for (int i = 0; i < count; i++)
                fprintf(stream, "  %8u vertices %8u triangles %10.4f ms/step%s\n", levels[i].vertices,
                        meshes[i].triangle_count, levels[i].step_ms, i == pick ? "  <- picked" : "");
            fprintf(stream,
                    fits ? "softbond: picked %u vertices (%.4f ms/step <= %g ms)\n"
                         : "softbond: picked %u vertices (%.4f ms/step; nothing fits %g ms: the smallest)\n",
                    levels[pick].vertices, levels[pick].step_ms, budget_ms);
        }
        *out = meshes[pick];
        meshes[pick] = (sb_mesh){0};
    }
    for (int i = 0; i < MAX_LEVELS; i++) sb_mesh_free(&meshes[i]);
    return status;
}
