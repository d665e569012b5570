/* Reading one map of a scene list (see map_reader.h): moved out of
 * colliders.c so that the handles read their entries the same way. */
#define _POSIX_C_SOURCE 200809L
#include "scenes/map_reader.h"
#include "scenes/suggest.h"
#include "common/error.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

sb_status sb_map_fail(const sb_map_reader* r, const sb_scene_node* node, const char* format, ...) {
    char message[sizeof r->err->message];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    return sb_scene_node_fail(r->tree, node, r->err, "%s", message);
}

const char* sb_map_full_name(const sb_map_reader* r, const char* key, char* out, size_t size) {
    snprintf(out, size, "%s.%s", r->prefix, key);
    return out;
}

/* ---- maps: known keys, each once ------------------------------------------- */

static sb_status unknown_key(const sb_map_reader* r, const sb_scene_node* key, const char* const* names, int count) {
    char name[128], near_name[128];
    sb_map_full_name(r, key->text, name, sizeof name);
    const char* near = sb_suggest(key->text, names, (size_t)count);
    if (!near) return sb_map_fail(r, key, "unknown key '%s'", name);
    return sb_map_fail(r, key, "unknown key '%s' (did you mean '%s'?)", name,
                       sb_map_full_name(r, near, near_name, sizeof near_name));
}

sb_status sb_map_index(sb_map_reader* r, const char* const* names, int count) {
    r->names = names;
    r->name_count = count;
    for (size_t p = 0; p < r->map->count; p++) {
        const sb_scene_node* key = &r->map->keys[p];
        int k = 0;
        while (k < count && strcmp(names[k], key->text) != 0) k++;
        char name[128];
        sb_map_full_name(r, key->text, name, sizeof name);
        if (k == count) return unknown_key(r, key, names, count);
        if (r->keys[k] && r->keys[k]->line)
            return sb_map_fail(r, key, "duplicate key '%s' (first set at line %zu)", name, r->keys[k]->line);
        if (r->keys[k]) return sb_map_fail(r, key, "duplicate key '%s'", name);
        r->keys[k] = key;
        r->values[k] = &r->map->items[p];
    }
    return SB_OK;
}

int sb_map_key_at(const sb_map_reader* r, size_t p) {
    int k = 0;
    while (k < r->name_count && strcmp(r->names[k], r->map->keys[p].text) != 0) k++;
    return k;
}

sb_status sb_map_expect_map(const sb_map_reader* r, const sb_scene_node* node, const char* what) {
    if (node->kind == SB_NODE_MAP) return SB_OK;
    char got[100];
    sb_scene_node_describe(node, got, sizeof got);
    return sb_map_fail(r, node, "'%s' expects %s, got %s", r->prefix, what, got);
}

/* ---- values ---------------------------------------------------------------- */

sb_status sb_map_type_fail(const sb_map_reader* r, const sb_scene_node* node, const char* name, const char* expected) {
    char got[100];
    sb_scene_node_describe(node, got, sizeof got);
    return sb_map_fail(r, node, "'%s' expects %s, got %s", name, expected, got);
}

sb_status sb_map_read_number(const sb_map_reader* r, int key, double* out) {
    char name[128];
    sb_map_full_name(r, r->names[key], name, sizeof name);
    const sb_scene_node* node = r->values[key];
    if (!sb_scene_node_number(node, out)) return sb_map_type_fail(r, node, name, "a number");
    if (!isfinite(*out)) return sb_map_fail(r, node, "'%s' must be finite, got %g", name, *out);
    return SB_OK;
}

/* key's value >= 0 (> 0 when positive), at most `max`. */
sb_status sb_map_read_range(const sb_map_reader* r, int key, bool positive, double max, double* out) {
    sb_status status = sb_map_read_number(r, key, out);
    if (status != SB_OK) return status;
    char name[128];
    sb_map_full_name(r, r->names[key], name, sizeof name);
    if (max < INFINITY && (*out < 0.0 || *out > max))
        return sb_map_fail(r, r->values[key], "'%s' must be in [0, %g], got %g", name, max, *out);
    if (positive ? *out <= 0.0 : *out < 0.0)
        return sb_map_fail(r, r->values[key], "'%s' must be %s 0, got %g", name, positive ? ">" : ">=", *out);
    return SB_OK;
}

sb_status sb_map_read_vec3(const sb_map_reader* r, const sb_scene_node* node, const char* key, double out[3]) {
    char name[128];
    sb_map_full_name(r, key, name, sizeof name);
    bool comma = node->kind == SB_NODE_SCALAR && sb_scene_comma_vec3(node->text, node->plain, out);
    if (!comma && (node->kind != SB_NODE_SEQUENCE || node->count != 3))
        return sb_map_type_fail(r, node, name, SB_SCENE_VEC3_FORMS);
    for (int k = 0; k < 3 && !comma; k++)
        if (!sb_scene_node_number(&node->items[k], &out[k]))
            return sb_map_type_fail(r, &node->items[k], name, "a number");
    if (!isfinite(out[0]) || !isfinite(out[1]) || !isfinite(out[2]))
        return sb_map_fail(r, node, "'%s' must be finite", name);
    return SB_OK;
}

sb_status sb_map_read_text(const sb_map_reader* r, int key, const char** out) {
    const sb_scene_node* node = r->values[key];
    char name[128];
    if (node->kind != SB_NODE_SCALAR)
        return sb_map_type_fail(r, node, sb_map_full_name(r, r->names[key], name, sizeof name), "a string");
    *out = node->text;
    return SB_OK;
}

/* ---- the path ---------------------------------------------------------------- */

enum { FRAME_TIME, FRAME_TRANSLATE, FRAME_ROTATE, FRAME_COUNT };
static const char* const frame_keys[FRAME_COUNT] = {"time", "translate", "rotate"};

static sb_status read_keyframe(const sb_map_reader* entry, const sb_scene_node* node, size_t j, sb_keyframe* out) {
    sb_map_reader r = {.tree = entry->tree, .map = node, .err = entry->err};
    snprintf(r.prefix, sizeof r.prefix, "%.40s.path[%zu]", entry->prefix, j);
    sb_status status = sb_map_expect_map(&r, node, "a map {time, translate, rotate}");
    if (status == SB_OK) status = sb_map_index(&r, frame_keys, FRAME_COUNT);
    if (status != SB_OK) return status;
    char name[128];
    sb_map_full_name(&r, "time", name, sizeof name);
    if (!r.values[FRAME_TIME]) return sb_map_fail(&r, node, "'%s' is not set", name);
    if (!sb_scene_node_number(r.values[FRAME_TIME], &out->time))
        return sb_map_type_fail(&r, r.values[FRAME_TIME], name, "a number");
    if (!isfinite(out->time))
        return sb_map_fail(&r, r.values[FRAME_TIME], "'%s' must be finite, got %g", name, out->time);
    if (j > 0 && !(out->time > out[-1].time))
        return sb_map_fail(&r, r.values[FRAME_TIME], "'%s' (%g) must be > the time before it (%g)", name, out->time,
                           out[-1].time);
    if (r.values[FRAME_TRANSLATE])
        status = sb_map_read_vec3(&r, r.values[FRAME_TRANSLATE], "translate", out->translate);
    if (status == SB_OK && r.values[FRAME_ROTATE])
        status = sb_map_read_vec3(&r, r.values[FRAME_ROTATE], "rotate", out->rotate);
    return status;
}

sb_status sb_map_read_path(const sb_map_reader* r, int key, sb_keyframe** path_out, uint32_t* count) {
    const sb_scene_node* path = r->values[key];
    char name[128];
    sb_map_full_name(r, r->names[key], name, sizeof name);
    if (path->kind != SB_NODE_SEQUENCE)
        return sb_map_type_fail(r, path, name, "a sequence of keyframes {time, translate, rotate}");
    if (path->count > UINT32_MAX) return sb_map_fail(r, path, "'%s': too many keyframes", name);
    if (!(*path_out = calloc(path->count ? path->count : 1, sizeof **path_out)))
        return sb_error_set(r->err, SB_ERR_NOMEM, "out of memory");
    for (size_t j = 0; j < path->count; j++) {
        sb_status status = read_keyframe(r, &path->items[j], j, &(*path_out)[j]);
        if (status != SB_OK) return status;
    }
    *count = (uint32_t)path->count;
    return SB_OK;
}

sb_status sb_map_read_interpolation(const sb_map_reader* r, int key, sb_interpolation* out) {
    const char* text = "";
    sb_status status = sb_map_read_text(r, key, &text);
    if (status != SB_OK) return status;
    if (strcmp(text, "linear") == 0 || strcmp(text, "smooth") == 0) {
        *out = text[0] == 'l' ? SB_INTERPOLATION_LINEAR : SB_INTERPOLATION_SMOOTH;
        return SB_OK;
    }
    char name[128], near[96];
    return sb_map_fail(r, r->values[key], "'%s' must be linear or smooth, got '%s'%s",
                       sb_map_full_name(r, r->names[key], name, sizeof name), text,
                       sb_suggest_hint(text, "linear, smooth", near, sizeof near));
}

bool sb_scene_good_name(const char* name) {
    size_t length = strlen(name);
    if (length == 0 || length > SB_SCENE_NAME_MAX) return false;
    for (const char* c = name; *c; c++)
        if (!(('a' <= *c && *c <= 'z') || ('A' <= *c && *c <= 'Z') || ('0' <= *c && *c <= '9') || *c == '_' ||
              *c == '-' || *c == '.'))
            return false;
    return true;
}
