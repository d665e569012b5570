/* A scene made ready to advance (scenes/simulation.h). Nothing is created
 * before the scene is valid; the model is compiled before the handles
 * select their vertices in it. */
#include "scenes/simulation.h"
#include "scenes/budget.h"
#include "scenes/scene_model.h"
#include "common/error.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* --budget-ms: a positive finite number of milliseconds. */
static sb_status budget(const char* text, double* ms, sb_error* err) {
    char* end;
    *ms = strtod(text, &end);
    if (end == text || *end != '\0' || !(*ms > 0.0) || !isfinite(*ms))
        return sb_error_set(err, SB_ERR_INVALID, "--budget-ms: expected a number of milliseconds > 0, got '%s'", text);
    return SB_OK;
}

/* --max-error: a finite number of metres >= 0, with --budget-ms. */
static sb_status max_error(const sb_simulation_args* args, double* m, sb_error* err) {
    *m = INFINITY;
    if (!args->max_error) return SB_OK;
    if (!args->budget_ms) return sb_error_set(err, SB_ERR_INVALID, "--max-error: needs --budget-ms");
    char* end;
    *m = strtod(args->max_error, &end);
    if (end == args->max_error || *end != '\0' || !(*m >= 0.0) || !isfinite(*m))
        return sb_error_set(err, SB_ERR_INVALID, "--max-error: expected a distance in metres >= 0, got '%s'",
                            args->max_error);
    return SB_OK;
}

static sb_status make_mesh(sb_simulation* sim, const sb_simulation_args* args, const sb_solver_def* def,
                           sb_error* err) {
    double ms, tolerance;
    sb_status status = max_error(args, &tolerance, err);
    if (status != SB_OK) return status;
    if (!args->budget_ms) return sb_scene_make_mesh(&sim->scene, &sim->mesh, err);
    status = budget(args->budget_ms, &ms, err);
    if (status == SB_OK) status = sb_budget_mesh(&sim->scene, def, ms, tolerance, &sim->mesh, stdout, err);
    fflush(stdout);
    return status;
}

/* A built-in collider's own size and its name: a sphere's or capsule's
 * radius, a capsule's length, a box's largest half extent; 0 for a plane or
 * a mesh (a mesh's size is its file's, checked as it is read). */
static double collider_size(const sb_collider_def* d, const char** what) {
    switch (d->shape) {
    case SB_COLLIDER_SPHERE: *what = "radius"; return d->radius;
    case SB_COLLIDER_CAPSULE: {
        double length = sqrt((d->b[0] - d->a[0]) * (d->b[0] - d->a[0]) + (d->b[1] - d->a[1]) * (d->b[1] - d->a[1]) +
                             (d->b[2] - d->a[2]) * (d->b[2] - d->a[2]));
        *what = length > d->radius ? "length" : "radius";
        return fmax(length, d->radius);
    }
    case SB_COLLIDER_BOX:
        *what = "half extent";
        return fmax(d->half_extents[0], fmax(d->half_extents[1], d->half_extents[2]));
    default: return 0.0;
    }
}

/* Lengths checked against the body's own scale, where a slip of units is
 * likely: a contact thickness (contact.thickness, a collider's thickness)
 * larger than the body's whole extent (its bounding box's diagonal), or a
 * collider's own size (a radius, a capsule's length, a box's half extent)
 * over 100 times it, is refused. contact.thickness: 10 (metres, in a scene of centimetres) was
 * taken, and every step searched the whole sheet for contacts: 1.3 s a
 * step instead of 10 ms, in silence. */
static sb_status check_scale(sb_simulation* sim, sb_error* err) {
    const sb_mesh* mesh = &sim->mesh;
    if (mesh->vertex_count == 0) return SB_OK;
    /* Coordinates whose squares overflow the state's precision: a mesh at
     * 1e20 m gave 'an edge collapsed', naming no file (float overflow was
     * the cause). */
    const double reach = sizeof(sb_real) == 4 ? 1e18 : 1e150;
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        const double* p = mesh->positions + 3 * (size_t)v;
        if (fabs(p[0]) <= reach && fabs(p[1]) <= reach && fabs(p[2]) <= reach) continue;
        bool from_file = strcmp(sb_scene_string(&sim->scene, SB_KEY_MESH_GENERATOR), "file") == 0;
        char* file = from_file ? sb_scene_path(&sim->scene, SB_KEY_MESH_FILE) : NULL;
        sb_status status = sb_scene_fail(
            &sim->scene, from_file ? SB_KEY_MESH_FILE : SB_KEY_MESH_GENERATOR, err,
            "%s%svertex %u at (%g, %g, %g) m, beyond %g m: its squared lengths overflow the solver's %s arithmetic (a "
            "slip of units? lengths are in metres)",
            file ? file : "", file ? ": " : "", v, p[0], p[1], p[2], reach, sizeof(sb_real) == 4 ? "float" : "double");
        free(file);
        return status;
    }
    double low[3], high[3];
    for (int k = 0; k < 3; k++) low[k] = high[k] = mesh->positions[k];
    for (uint32_t v = 1; v < mesh->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            low[k] = fmin(low[k], mesh->positions[3 * (size_t)v + k]);
            high[k] = fmax(high[k], mesh->positions[3 * (size_t)v + k]);
        }
    double extent = sqrt((high[0] - low[0]) * (high[0] - low[0]) + (high[1] - low[1]) * (high[1] - low[1]) +
                         (high[2] - low[2]) * (high[2] - low[2]));
    if (!(extent > 0)) return SB_OK;
    double thickness = sb_scene_number(&sim->scene, SB_KEY_CONTACT_THICKNESS);
    if (thickness > extent)
        return sb_scene_fail(&sim->scene, SB_KEY_CONTACT_THICKNESS, err,
                             "'contact.thickness' %g m is more than the body's whole extent (%.3g m, its bounding "
                             "box's diagonal): a slip of units? (lengths are in metres)",
                             thickness, extent);
    for (uint32_t c = 0; c < sim->colliders.count; c++) {
        const sb_scene_collider* e = &sim->colliders.entries[c];
        double own = e->def.thickness;
        if (own > extent)
            return sb_error_set(err, SB_ERR_INVALID,
                                "%s: collider '%s': thickness %g m is more than the body's whole extent (%.3g m, its "
                                "bounding box's diagonal): a slip of units? (lengths are in metres)",
                                e->where, e->name, own, extent);
        const char* what = NULL;
        double size = collider_size(&e->def, &what);
        if (size > 100 * extent)
            return sb_error_set(err, SB_ERR_INVALID,
                                "%s: collider '%s': %s %g m is more than 100 times the body's whole extent (%.3g m, "
                                "its bounding box's diagonal): a slip of units? (lengths are in metres)",
                                e->where, e->name, what, size, extent);
    }
    return SB_OK;
}

static sb_status make_model(sb_simulation* sim, const sb_simulation_args* args, const sb_solver_def* def,
                            sb_error* err) {
    sb_status status = make_mesh(sim, args, def, err);
    if (status == SB_OK) status = check_scale(sim, err); /* before the model: its lengths could overflow */
    if (status != SB_OK) return status;
    bool from_file = strcmp(sb_scene_string(&sim->scene, SB_KEY_MESH_GENERATOR), "file") == 0;
    char* source = from_file ? sb_scene_path(&sim->scene, SB_KEY_MESH_FILE) : NULL;
    /* a model's error names the scene's file and line (of mesh.file or
     * mesh.generator) as well as the mesh file: it named only one of them */
    sim->model = sb_scene_build_model(&sim->scene, &sim->mesh,
                                      source ? source : sb_scene_where(&sim->scene, SB_KEY_MESH_GENERATOR), err);
    free(source);
    if (!sim->model && from_file) sb_error_prefix(err, SB_ERR_INVALID, sb_scene_where(&sim->scene, SB_KEY_MESH_FILE));
    return sim->model ? SB_OK : SB_ERR_INVALID;
}

static sb_status make_colliders(sb_simulation* sim, sb_solver_def* def, sb_error* err) {
    sb_status status = sb_scene_colliders_read(&sim->scene, &sim->colliders, err);
    if (status == SB_OK) status = sb_scene_colliders_create(&sim->colliders, err);
    if (status == SB_OK) sb_scene_colliders_attach(&sim->colliders, def);
    return status;
}

/* The scene's handles, their vertices selected in the model. */
static sb_status make_handles(sb_simulation* sim, sb_solver_def* def, sb_error* err) {
    sb_status status = sb_scene_handles_read(&sim->scene, &sim->handles, err);
    if (status == SB_OK) status = sb_scene_handles_create(&sim->handles, sim->model, err);
    if (status == SB_OK) sb_scene_handles_attach(&sim->handles, def);
    return status;
}

/* def's handles, then extra. */
static sb_status add_handle(sb_simulation* sim, sb_handle* extra, sb_solver_def* def, sb_error* err) {
    uint32_t count = def->handle_count;
    if (!(sim->attached = malloc((count + 1) * sizeof *sim->attached)))
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    if (count) memcpy(sim->attached, def->handles, count * sizeof *sim->attached);
    sim->attached[count] = extra;
    def->handles = sim->attached;
    def->handle_count = count + 1;
    return SB_OK;
}

sb_status sb_simulation_prepare(sb_simulation* sim, const sb_simulation_args* args, sb_error* err) {
    sb_status status = sb_scene_read(&sim->scene, args->input, args->sets, (size_t)args->set_count, err);
    if (status != SB_OK) return status;
    sim->def = sb_scene_solver_def(&sim->scene);
    status = sb_simulation_threads(args->threads, &sim->scene, &sim->def.runtime.threads, err);
    if (status == SB_OK) status = make_colliders(sim, &sim->def, err);
    if (status == SB_OK) status = make_model(sim, args, &sim->def, err);
    if (status == SB_OK) status = make_handles(sim, &sim->def, err);
    if (status == SB_OK) status = sb_scene_blades_read(&sim->scene, &sim->blades, err);
    if (status == SB_OK) sb_scene_blades_attach(&sim->blades, &sim->def);
    if (status == SB_OK) status = sb_point_load_prepare(&sim->scene, sim->model, &sim->load, err);
    if (status == SB_OK) sb_point_load_attach(&sim->load, &sim->def);
    return status;
}

/* A thread count: a whole number in [min, SB_MAX_THREADS]. */
static bool parse_threads(const char* text, long min, int* out) {
    char* end;
    errno = 0;
    long value = strtol(text, &end, 10);
    if (end == text || *end != '\0' || errno != 0 || value < min || value > SB_MAX_THREADS) return false;
    *out = (int)value;
    return true;
}

/* --threads and the scene's threads take 0 (the default: SOFTBOND_THREADS,
 * else one per processor); SOFTBOND_THREADS, the default itself, does not. */
sb_status sb_simulation_threads(const char* requested, const sb_scene* scene, int* out, sb_error* err) {
    const char* env = getenv("SOFTBOND_THREADS");
    *out = (int)sb_scene_integer(scene, SB_KEY_THREADS);
    if (requested && !parse_threads(requested, 0, out))
        return sb_error_set(err, SB_ERR_INVALID, "--threads: expected an integer in [0, %d], got '%s'", SB_MAX_THREADS,
                            requested);
    if (requested || *out != 0 || !env || env[0] == '\0') return SB_OK;
    if (parse_threads(env, 1, out)) return SB_OK;
    return sb_error_set(err, SB_ERR_INVALID, "SOFTBOND_THREADS: expected an integer in [1, %d], got '%s'",
                        SB_MAX_THREADS, env);
}

sb_status sb_simulation_start(sb_simulation* sim, sb_handle* extra, sb_error* err) {
    if (extra && add_handle(sim, extra, &sim->def, err) != SB_OK) return SB_ERR_NOMEM;
    sim->solver = sb_solver_create(sim->model, &sim->def, err);
    if (!sim->solver) return SB_ERR_INVALID;
    return sb_scene_haptics_create(&sim->haptics, &sim->scene, &sim->colliders, err);
}

void sb_simulation_free(sb_simulation* sim) {
    sb_scene_haptics_free(&sim->haptics);
    sb_solver_destroy(sim->solver);
    sb_scene_colliders_free(&sim->colliders);
    sb_scene_handles_free(&sim->handles);
    sb_scene_blades_free(&sim->blades);
    free(sim->attached);
    sb_model_destroy(sim->model);
    sb_mesh_free(&sim->mesh);
    sb_scene_free(&sim->scene);
    memset(sim, 0, sizeof *sim);
}

void sb_simulation_up(const sb_simulation* sim, double up[3]) {
    const double* g = sb_scene_vec3(&sim->scene, SB_KEY_GRAVITY);
    bool none = g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0;
    for (int k = 0; k < 3; k++) up[k] = none ? (k == 2) : -g[k];
}
