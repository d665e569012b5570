/* The scene library's one call (include/softbond/scene.h): a simulation
 * prepared as the program prepares one (scenes/simulation.c), without the
 * program's options, the solver or the haptic device. The handle owns the
 * prepared simulation, so everything the solver definition points at lives
 * as long as it does. */
#include "softbond/scene.h"
#include "scenes/simulation.h"
#include "common/error.h"

#include <limits.h>
#include <stdlib.h>

struct sb_scene_file {
    sb_simulation sim;
};

sb_status sb_scene_file_load(const char* path, const char* const* overrides, size_t count, sb_scene_file** out,
                             sb_error* err) {
    *out = NULL;
    if (!path || (count && !overrides) || count > INT_MAX)
        return sb_error_set(err, SB_ERR_INVALID, "sb_scene_file_load: a path and count overrides expected");
    sb_scene_file* scene = calloc(1, sizeof *scene);
    if (!scene) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    sb_simulation_args args = {.input = path, .sets = overrides, .set_count = (int)count};
    sb_status status = sb_simulation_prepare(&scene->sim, &args, err);
    if (status == SB_OK)
        *out = scene;
    else
        sb_scene_file_destroy(scene);
    return status;
}

void sb_scene_file_destroy(sb_scene_file* scene) {
    if (!scene) return;
    sb_simulation_free(&scene->sim);
    free(scene);
}

const sb_model* sb_scene_file_model(const sb_scene_file* scene) { return scene->sim.model; }

const sb_solver_def* sb_scene_file_solver_def(const sb_scene_file* scene) { return &scene->sim.def; }

double sb_scene_file_dt(const sb_scene_file* scene) { return sb_scene_number(&scene->sim.scene, SB_KEY_DT); }

double sb_scene_file_duration(const sb_scene_file* scene) {
    return sb_scene_number(&scene->sim.scene, SB_KEY_DURATION);
}

double sb_scene_file_frame_interval(const sb_scene_file* scene) {
    return sb_scene_number(&scene->sim.scene, SB_KEY_FRAME_INTERVAL);
}

sb_status sb_scene_file_number(const sb_scene_file* scene, const char* key, double* out, sb_error* err) {
    sb_scene_key id;
    if (!key || !sb_scene_key_find(key, &id))
        return sb_error_set(err, SB_ERR_INVALID, "%s: no such scene key", key ? key : "(null)");
    sb_scene_type type = sb_scene_key_get(id)->type;
    if (type != SB_SCENE_NUMBER && type != SB_SCENE_INTEGER)
        return sb_error_set(err, SB_ERR_INVALID, "%s: not a number", key);
    *out = type == SB_SCENE_NUMBER ? sb_scene_number(&scene->sim.scene, id)
                                   : (double)sb_scene_integer(&scene->sim.scene, id);
    return SB_OK;
}

const char* sb_scene_file_name(const sb_scene_file* scene) { return scene->sim.scene.name; }
