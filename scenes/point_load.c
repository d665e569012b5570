/* The scene's point load (see point_load.h). */
#include "scenes/point_load.h"

#include <math.h>
#include <string.h>

/* Squared distance from vertex v's rest position to `at`; x receives it. */
static double distance2(const sb_model* model, uint32_t v, const double at[3], double x[3]) {
    sb_model_rest_position(model, v, x);
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) d2 += (x[k] - at[k]) * (x[k] - at[k]);
    return d2;
}

static uint32_t nearest_vertex(const sb_model* model, const double at[3]) {
    uint32_t best = 0, count = sb_model_vertex_count(model);
    double best_d2 = INFINITY, x[3];
    for (uint32_t v = 0; v < count; v++) {
        double d2 = distance2(model, v, at, x);
        if (d2 < best_d2) best = v, best_d2 = d2;
    }
    return best;
}

sb_status sb_point_load_prepare(const sb_scene* scene, const sb_model* model, sb_point_load* load, sb_error* err) {
    const double* force = sb_scene_vec3(scene, SB_KEY_LOAD_FORCE);
    bool nonzero = force[0] != 0.0 || force[1] != 0.0 || force[2] != 0.0;
    *load = (sb_point_load){.active = nonzero && sb_model_vertex_count(model) > 0};
    memcpy(load->force, force, sizeof load->force);
    if (!load->active) return SB_OK;
    const double* at = sb_scene_vec3(scene, SB_KEY_LOAD_AT);
    load->vertex = nearest_vertex(model, at);
    if (!sb_model_is_fixed(model, load->vertex)) return SB_OK;
    double x[3];
    sb_model_rest_position(model, load->vertex, x);
    return sb_scene_fail(scene, SB_KEY_LOAD_AT, err,
                         "'load.at' [%g, %g, %g]: the nearest vertex, %u at [%g, %g, %g], is fixed, so "
                         "the load would do nothing",
                         at[0], at[1], at[2], load->vertex, x[0], x[1], x[2]);
}

void sb_point_load_print(const sb_point_load* load, const sb_scene* scene, const sb_model* model, FILE* stream) {
    if (!load->active) return;
    const double *f = load->force, *at = sb_scene_vec3(scene, SB_KEY_LOAD_AT);
    double x[3], d = sqrt(distance2(model, load->vertex, at, x));
    fprintf(stream, "softbond: load [%g, %g, %g] N on vertex %u at [%g, %g, %g] m (%g m from load.at)\n", f[0], f[1],
            f[2], load->vertex, x[0], x[1], x[2], d);
}

static void apply(void* user, uint32_t vertex, double time, const double position[3], const double velocity[3],
                  double force[3]) {
    (void)time, (void)position, (void)velocity;
    const sb_point_load* load = user;
    if (vertex != load->vertex) return;
    for (int k = 0; k < 3; k++) force[k] += load->force[k];
}

void sb_point_load_attach(sb_point_load* load, sb_solver_def* def) {
    if (!load->active) return;
    def->external_force = apply;
    def->external_user = load;
}
