/* --budget-ms: the choice, kept apart from the timing so that tests can
 * give it timings, and the calibration that measures them; with
 * --max-error, the trial runs that measure what each level gives up. */
#define _POSIX_C_SOURCE 200809L
#include "scenes/budget.h"
#include "common/clock.h"

int sb_budget_choose(const sb_budget_level* levels, int count, double budget_ms, double max_error, bool* fits) {
    int best = -1, smallest = -1;
    for (int i = 0; i < count; i++) {
        if (levels[i].error > max_error) continue;
        if (smallest < 0 || levels[i].vertices < levels[smallest].vertices) smallest = i;
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
#include "scenes/colliders.h"
#include "scenes/scene_model.h"

enum { MAX_LEVELS = 6 };

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

/* A level's model and solver: the scene's settings on the fast kernels,
 * with colliders of its own (a dynamic one is moved by the steps taken
 * here, and must start the real run where the scene puts it). */
typedef struct level_run {
    sb_model* model;
    sb_scene_colliders colliders;
    sb_solver* solver;
} level_run;

static void level_close(level_run* r) {
    sb_solver_destroy(r->solver);
    sb_scene_colliders_free(&r->colliders);
    sb_model_destroy(r->model);
}

static sb_status level_open(const sb_scene* scene, const sb_solver_def* def, const sb_mesh* mesh, level_run* r,
                            sb_error* err) {
    *r = (level_run){0};
    sb_solver_def fast = *def;
    fast.kernels = SB_KERNELS_FAST;
    sb_status status = (r->model = sb_scene_build_model(scene, mesh, "budget", err)) ? SB_OK : SB_ERR_INVALID;
    if (status == SB_OK) status = sb_scene_colliders_read(scene, &r->colliders, err);
    if (status == SB_OK) status = sb_scene_colliders_create(&r->colliders, err);
    if (status == SB_OK) sb_scene_colliders_attach(&r->colliders, &fast);
    if (status == SB_OK && !(r->solver = sb_solver_create(r->model, &fast, err))) status = SB_ERR_INVALID;
    if (status != SB_OK) level_close(r);
    return status;
}

/* Milliseconds per step of the fast step on this mesh. */
static sb_status time_step(const sb_scene* scene, const sb_solver_def* def, const sb_mesh* mesh, double* step_ms,
                           sb_error* err) {
    level_run r;
    sb_status status = level_open(scene, def, mesh, &r, err);
    if (status != SB_OK) return status;
    double dt = sb_scene_number(scene, SB_KEY_DT);
    for (int i = 0; i < 3; i++) sb_solver_advance(r.solver, dt);
    /* The best of 3 rounds: another process taking the cores for a while
     * makes a round slow, never fast. */
    *step_ms = INFINITY;
    for (int round = 0; round < 3; round++) {
        int steps = 0;
        double start = sb_wall_seconds(), elapsed = 0.0;
        while (steps < 100 && elapsed < 0.01) {
            sb_solver_advance(r.solver, dt); /* a blow-up costs the same: time it anyway */
            steps++;
            elapsed = sb_wall_seconds() - start;
        }
        *step_ms = fmin(*step_ms, 1e3 * elapsed / steps);
    }
    level_close(&r);
    return SB_OK;
}

static double trial_seconds(const sb_scene* scene) {
    return fmin(SB_BUDGET_TRIAL, sb_scene_number(scene, SB_KEY_DURATION));
}

/* The positions (3n into out) after the trial run of this mesh. */
static sb_status trial_run(const sb_scene* scene, const sb_solver_def* def, const sb_mesh* mesh, double* out,
                           sb_error* err) {
    level_run r;
    sb_status status = level_open(scene, def, mesh, &r, err);
    if (status != SB_OK) return status;
    double dt = sb_scene_number(scene, SB_KEY_DT);
    long steps = lround(trial_seconds(scene) / dt);
    for (long k = 0; k < steps && status == SB_OK; k++)
        if (sb_solver_advance(r.solver, dt) != SB_OK)
            status = sb_error_set(err, SB_ERR_INVALID, "--max-error: the %u-vertex level failed at t = %g s: %s",
                                  mesh->vertex_count, (double)k * dt, sb_solver_error(r.solver));
    if (status == SB_OK) sb_solver_get_positions(r.solver, out);
    level_close(&r);
    return status;
}

/* Each level's error: the RMS distance of its vertices from the same
 * vertices of the full model (full_index[l]: level l's vertex → the full
 * mesh's) after the trial runs; *moved: the full model's vertices' RMS
 * distance from where they started. */
static sb_status measure_errors(const sb_scene* scene, const sb_solver_def* def, const sb_mesh* meshes,
                                uint32_t* const* full_index, sb_budget_level* levels, int count, double* moved,
                                sb_error* err) {
    double *full = malloc(3 * (size_t)meshes[0].vertex_count * sizeof *full + 1),
           *level = malloc(3 * (size_t)meshes[0].vertex_count * sizeof *level + 1);
    sb_status status = full && level ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    if (status == SB_OK) status = trial_run(scene, def, &meshes[0], full, err);
    double sum = 0.0;
    for (uint32_t i = 0; status == SB_OK && i < meshes[0].vertex_count; i++)
        for (int a = 0; a < 3; a++) sum += pow(full[3 * i + a] - meshes[0].positions[3 * i + a], 2);
    *moved = sqrt(sum / meshes[0].vertex_count);
    levels[0].error = 0.0;
    for (int l = 1; l < count && status == SB_OK; l++) {
        status = trial_run(scene, def, &meshes[l], level, err);
        sum = 0.0;
        for (uint32_t i = 0; status == SB_OK && i < meshes[l].vertex_count; i++)
            for (int a = 0; a < 3; a++) sum += pow(level[3 * i + a] - full[3 * full_index[l][i] + a], 2);
        levels[l].error = sqrt(sum / meshes[l].vertex_count);
    }
    free(full);
    free(level);
    return status;
}

/* The next level: half the vertices of the last, and its vertices' indices
 * in the full mesh; false (nothing added) when it is stuck, the locked
 * vertices being most of it. */
static sb_status add_level(const sb_scene* scene, sb_mesh* meshes, uint32_t** full_index, int count, bool* added,
                           sb_error* err) {
    const sb_mesh* last = &meshes[count - 1];
    uint32_t* origin = malloc((size_t)last->vertex_count * sizeof *origin + 1);
    full_index[count] = malloc((size_t)last->vertex_count * sizeof *full_index[count] + 1);
    sb_status status = origin && full_index[count] ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    if (status == SB_OK) status = copy_mesh(last, &meshes[count], err);
    if (status == SB_OK) status = sb_scene_simplify(scene, &meshes[count], last->vertex_count / 2, origin, NULL, err);
    *added = status == SB_OK && (uint64_t)meshes[count].vertex_count * 10 <= (uint64_t)last->vertex_count * 9;
    for (uint32_t i = 0; *added && i < meshes[count].vertex_count; i++)
        full_index[count][i] = count == 1 ? origin[i] : full_index[count - 1][origin[i]];
    if (!*added) sb_mesh_free(&meshes[count]);
    free(origin);
    return status;
}

static void print_table(FILE* stream, const sb_mesh* meshes, const sb_budget_level* levels, int count, int pick,
                        bool fits, double budget_ms, double max_error, double moved, double trial) {
    bool errors = isfinite(max_error);
    fprintf(stream, "softbond: --budget-ms %g: calibrated the fast step at %d resolution%s\n", budget_ms, count,
            count == 1 ? "" : "s");
    if (errors)
        fprintf(stream,
                "softbond: --max-error %g m: each level's RMS distance from the full model after %g s (its "
                "vertices moved %.4g m RMS)\n",
                max_error, trial, moved);
    for (int i = 0; i < count; i++) {
        fprintf(stream, "  %8u vertices %8u triangles %10.4f ms/step", levels[i].vertices, meshes[i].triangle_count,
                levels[i].step_ms);
        if (errors) fprintf(stream, " %10.4g m RMS", levels[i].error);
        fprintf(stream, "%s\n", i == pick ? "  <- picked" : "");
    }
    const char* within = errors ? " within the error" : "";
    if (fits)
        fprintf(stream, "softbond: picked %u vertices (%.4f ms/step <= %g ms", levels[pick].vertices,
                levels[pick].step_ms, budget_ms);
    else
        fprintf(stream, "softbond: picked %u vertices (%.4f ms/step; nothing%s fits %g ms: the smallest%s",
                levels[pick].vertices, levels[pick].step_ms, within, budget_ms, within);
    if (errors)
        fprintf(stream, "; %.4g m RMS from the full model, %.3g %% of its motion", levels[pick].error,
                moved > 0 ? 100 * levels[pick].error / moved : 0.0);
    fprintf(stream, ")\n");
}

sb_status sb_budget_mesh(const sb_scene* scene, const sb_solver_def* def, double budget_ms, double max_error,
                         sb_mesh* out, FILE* stream, sb_error* err) {
    sb_mesh meshes[MAX_LEVELS] = {{0}};
    uint32_t* full_index[MAX_LEVELS] = {0};
    sb_budget_level levels[MAX_LEVELS] = {{0}};
    int count = 0;
    sb_status status = sb_scene_make_mesh(scene, &meshes[0], err);
    if (status == SB_OK && sb_scene_volumetric(scene))
        status = sb_error_set(err, SB_ERR_INVALID,
                              "--budget-ms: level of detail applies to surface meshes, not tetrahedral files");
    if (status == SB_OK) count = 1;
    for (bool added = true; status == SB_OK && added && count < MAX_LEVELS && meshes[count - 1].vertex_count / 2 >= 64;)
        if ((status = add_level(scene, meshes, full_index, count, &added, err)) == SB_OK && added) count++;
    for (int i = 0; i < count && status == SB_OK; i++) {
        levels[i].vertices = meshes[i].vertex_count;
        status = time_step(scene, def, &meshes[i], &levels[i].step_ms, err);
    }
    double moved = 0.0;
    if (status == SB_OK && isfinite(max_error))
        status = measure_errors(scene, def, meshes, full_index, levels, count, &moved, err);
    if (status == SB_OK) {
        bool fits;
        int pick = sb_budget_choose(levels, count, budget_ms, max_error, &fits);
        if (stream)
            print_table(stream, meshes, levels, count, pick, fits, budget_ms, max_error, moved, trial_seconds(scene));
        *out = meshes[pick];
        meshes[pick] = (sb_mesh){0};
    }
    for (int i = 0; i < MAX_LEVELS; i++) {
        sb_mesh_free(&meshes[i]);
        free(full_index[i]);
    }
    return status;
}
