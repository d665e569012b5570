/* The scene's key table, its values and their accessors. Parsing lives in
 * scene_yaml.c, checks in scene_validate.c. */
#define _POSIX_C_SOURCE 200809L
#include "scenes/scene.h"
#include "common/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const sb_scene_key_info key_table[SB_KEY_COUNT] = {
#define SB_SCENE_KEY_INFO(id, name, type, def, unit, meaning) {name, SB_SCENE_##type, def, unit, meaning},
    SB_SCENE_KEYS(SB_SCENE_KEY_INFO)
#undef SB_SCENE_KEY_INFO
};

const sb_scene_key_info* sb_scene_key_get(sb_scene_key key) { return &key_table[key]; }

bool sb_scene_key_find(const char* name, sb_scene_key* out) {
    for (int i = 0; i < SB_KEY_COUNT; i++) {
        if (strcmp(key_table[i].name, name) == 0) {
            *out = (sb_scene_key)i;
            return true;
        }
    }
    return false;
}

sb_status sb_scene_init(sb_scene* scene, sb_error* err) {
    memset(scene, 0, sizeof *scene);
    for (int i = 0; i < SB_KEY_COUNT; i++) {
        char assignment[256];
        snprintf(assignment, sizeof assignment, "%s=%s", key_table[i].name, key_table[i].default_value);
        sb_status status = sb_scene_set(scene, assignment, err);
        if (status != SB_OK) {
            sb_scene_free(scene);
            return status;
        }
        scene->values[i].where[0] = '\0'; /* a default comes from nowhere */
    }
    return SB_OK;
}

void sb_scene_free(sb_scene* scene) {
    for (int i = 0; i < SB_KEY_COUNT; i++) {
        free(scene->values[i].string);
        free(scene->values[i].indices);
        free(scene->values[i].base_dir);
        sb_scene_tree_free(scene->values[i].tree);
    }
    free(scene->path);
    free(scene->name);
    memset(scene, 0, sizeof *scene);
}

static sb_status fill(sb_scene* scene, const char* path, const char* const* sets, size_t set_count, sb_error* err) {
    sb_status status = path ? sb_scene_load(scene, path, err) : SB_OK;
    for (size_t i = 0; i < set_count && status == SB_OK; i++) status = sb_scene_set(scene, sets[i], err);
    return status == SB_OK ? sb_scene_validate(scene, err) : status;
}

sb_status sb_scene_read(sb_scene* scene, const char* path, const char* const* sets, size_t set_count, sb_error* err) {
    sb_status status = sb_scene_init(scene, err);
    if (status != SB_OK) return status;
    status = fill(scene, path, sets, set_count, err);
    if (status != SB_OK) sb_scene_free(scene);
    return status;
}

double sb_scene_number(const sb_scene* scene, sb_scene_key key) { return scene->values[key].number; }

int64_t sb_scene_integer(const sb_scene* scene, sb_scene_key key) { return scene->values[key].integer; }

bool sb_scene_bool(const sb_scene* scene, sb_scene_key key) { return scene->values[key].boolean; }

const char* sb_scene_string(const sb_scene* scene, sb_scene_key key) { return scene->values[key].string; }

const double* sb_scene_vec3(const sb_scene* scene, sb_scene_key key) { return scene->values[key].vec3; }

const uint32_t* sb_scene_indices(const sb_scene* scene, sb_scene_key key, uint32_t* count) {
    *count = scene->values[key].index_count;
    return scene->values[key].indices;
}

const sb_scene_tree* sb_scene_tree_value(const sb_scene* scene, sb_scene_key key) { return scene->values[key].tree; }

const char* sb_scene_where(const sb_scene* scene, sb_scene_key key) {
    return scene->values[key].where[0] ? scene->values[key].where : scene->path;
}

sb_status sb_scene_fail(const sb_scene* scene, sb_scene_key key, sb_error* err, const char* format, ...) {
    const char* where = sb_scene_where(scene, key);
    va_list args;
    va_start(args, format);
    sb_error_vset(err, SB_ERR_INVALID, format, args);
    va_end(args);
    return where ? sb_error_prefix(err, SB_ERR_INVALID, where) : SB_ERR_INVALID;
}

char* sb_scene_path(const sb_scene* scene, sb_scene_key key) {
    const sb_scene_value* value = &scene->values[key];
    if (value->string[0] == '/' || !value->base_dir) return strdup(value->string);
    size_t size = strlen(value->base_dir) + strlen(value->string) + 2;
    char* path = malloc(size);
    if (path) snprintf(path, size, "%s/%s", value->base_dir, value->string);
    return path;
}
