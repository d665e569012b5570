/* The scene's blades (see blades.h), read as handles.c reads its entries
 * (scenes/map_reader.c): the map, its keys, then each value by type and
 * range, then the edge's two ends. */
#define _POSIX_C_SOURCE 200809L
#include "scenes/blades.h"
#include "scenes/map_reader.h"
#include "common/error.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* X(id, name, type, default, unit, meaning): the entry's keys, in the order
 * `softbond keys` prints them; the parser reads the names from here. */
#define BLADE_KEYS(X)                                                                                                  \
    X(A, "a", VEC3, SB_ENTRY_REQUIRED, "m", "one end of the cutting edge at time 0")                                   \
    X(B, "b", VEC3, SB_ENTRY_REQUIRED, "m", "the other end of the edge at time 0, not a")                              \
    X(PATH, "path", LIST, "[]", "",                                                                                    \
      "keyframes {time (s, increasing), translate (m), rotate (deg, about the edge's midpoint)}; [] still")            \
    X(INTERPOLATION, "interpolation", STRING, "linear", "",                                                            \
      "between keyframes: linear (constant speed) or smooth (eased in and out of each keyframe)")

typedef enum entry_key {
#define ENTRY_KEY_ENUM(id, name, type, def, unit, meaning) KEY_##id,
    BLADE_KEYS(ENTRY_KEY_ENUM)
#undef ENTRY_KEY_ENUM
        KEY_COUNT
} entry_key;

static const sb_entry_key key_table[KEY_COUNT] = {
#define ENTRY_KEY_INFO(id, name, type, def, unit, meaning) {name, SB_SCENE_##type, def, unit, 0, meaning},
    BLADE_KEYS(ENTRY_KEY_INFO)
#undef ENTRY_KEY_INFO
};

/* The names alone, as sb_map_index takes them. */
static const char* const entry_keys[KEY_COUNT] = {
#define ENTRY_KEY_NAME(id, name, type, def, unit, meaning) name,
    BLADE_KEYS(ENTRY_KEY_NAME)
#undef ENTRY_KEY_NAME
};

const sb_entry_key* sb_scene_blade_keys(size_t* count) {
    *count = KEY_COUNT;
    return key_table;
}

static sb_status read_value(const sb_map_reader* r, int key, sb_blade_def* def, sb_keyframe** path) {
    switch ((entry_key)key) {
    case KEY_A: return sb_map_read_vec3(r, r->values[key], "a", def->a);
    case KEY_B: return sb_map_read_vec3(r, r->values[key], "b", def->b);
    case KEY_PATH: return sb_map_read_path(r, key, path, &def->path_count);
    case KEY_INTERPOLATION: return sb_map_read_interpolation(r, key, &def->interpolation);
    default: return SB_OK;
    }
}

/* a and b given, and apart. */
static sb_status check_edge(const sb_map_reader* r, const sb_blade_def* def) {
    char name[128];
    for (int k = 0; k < KEY_COUNT; k++)
        if (strcmp(key_table[k].default_value, SB_ENTRY_REQUIRED) == 0 && !r->values[k])
            return sb_map_fail(r, r->map, "'%s' is not set (a blade is the edge from a to b)",
                               sb_map_full_name(r, entry_keys[k], name, sizeof name));
    if (memcmp(def->a, def->b, sizeof def->a) == 0)
        return sb_map_fail(r, r->keys[KEY_B], "'%s': the edge's ends a and b are the same point",
                           sb_map_full_name(r, "b", name, sizeof name));
    return SB_OK;
}

static sb_status read_entry(const sb_scene_tree* tree, uint32_t index, sb_blade_def* def, sb_keyframe** path,
                            sb_error* err) {
    const sb_scene_node* node = &tree->root.items[index];
    sb_map_reader r = {.tree = tree, .map = node, .err = err};
    snprintf(r.prefix, sizeof r.prefix, "blades[%u]", index);
    sb_status status = sb_map_expect_map(&r, node, "a map");
    if (status == SB_OK) status = sb_map_index(&r, entry_keys, KEY_COUNT);
    for (size_t p = 0; status == SB_OK && p < node->count; p++)
        status = read_value(&r, sb_map_key_at(&r, p), def, path);
    if (status == SB_OK) status = check_edge(&r, def);
    def->path = *path;
    return status;
}

sb_status sb_scene_blades_read(const sb_scene* scene, sb_scene_blades* out, sb_error* err) {
    memset(out, 0, sizeof *out);
    const sb_scene_tree* tree = sb_scene_tree_value(scene, SB_KEY_BLADES);
    if (!tree || tree->root.kind != SB_NODE_SEQUENCE) return SB_OK;
    const sb_scene_node* root = &tree->root;
    if (root->count > UINT32_MAX) return sb_scene_node_fail(tree, root, err, "'blades': too many entries");
    out->count = (uint32_t)root->count;
    out->defs = calloc(root->count ? root->count : 1, sizeof *out->defs);
    out->paths = calloc(root->count ? root->count : 1, sizeof *out->paths);
    sb_status status = out->defs && out->paths ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    for (uint32_t i = 0; i < out->count && status == SB_OK; i++)
        status = read_entry(tree, i, &out->defs[i], &out->paths[i], err);
    if (status != SB_OK) sb_scene_blades_free(out);
    return status;
}

sb_status sb_scene_blades_check(const sb_scene* scene, sb_error* err) {
    sb_scene_blades blades;
    sb_status status = sb_scene_blades_read(scene, &blades, err);
    sb_scene_blades_free(&blades);
    return status;
}

void sb_scene_blades_attach(const sb_scene_blades* blades, sb_solver_def* def) {
    def->blades = blades->defs;
    def->blade_count = blades->count;
}

void sb_scene_blades_free(sb_scene_blades* blades) {
    for (uint32_t i = 0; blades->paths && i < blades->count; i++) free(blades->paths[i]);
    free(blades->paths);
    free(blades->defs);
    memset(blades, 0, sizeof *blades);
}
