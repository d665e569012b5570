/* Reading one map of a scene list (`colliders`, `handles`): its keys known
 * and each given once, then each value by type and range, every problem one
 * line naming the line of the offending node and the key as
 * "list[i].key". Shared by scenes/colliders.c and scenes/handles.c. */
#ifndef SB_SCENE_MAP_READER_H
#define SB_SCENE_MAP_READER_H

#include "scenes/scene.h"

#define SB_MAP_MAX_KEYS 32

typedef struct sb_map_reader {
    const sb_scene_tree* tree;
    const char* base_dir; /* where a relative file is; NULL: the current directory */
    const sb_scene_node* map;
    char prefix[96];          /* the map's own name: "colliders[2]", "colliders[2].path[0]" */
    const char* const* names; /* the known keys (sb_map_index) */
    int name_count;
    /* once indexed, the value and key node of each known key (NULL when not written) */
    const sb_scene_node* values[SB_MAP_MAX_KEYS];
    const sb_scene_node* keys[SB_MAP_MAX_KEYS];
    sb_error* err;
} sb_map_reader;

/* "SOURCE:LINE: message" at node; returns SB_ERR_INVALID. */
sb_status sb_map_fail(const sb_map_reader* r, const sb_scene_node* node, const char* format, ...)
    __attribute__((format(printf, 3, 4)));
/* "colliders[2].radius" */
const char* sb_map_full_name(const sb_map_reader* r, const char* key, char* out, size_t size);
/* The node is a map ("'colliders[2]' expects WHAT, got ..." otherwise). */
sb_status sb_map_expect_map(const sb_map_reader* r, const sb_scene_node* node, const char* what);
/* Indexes the map's keys among `names` (at most SB_MAP_MAX_KEYS): unknown
 * (with a suggestion) and duplicate keys fail. */
sb_status sb_map_index(sb_map_reader* r, const char* const* names, int count);
/* Which of the names the map's p-th key is (after sb_map_index). */
int sb_map_key_at(const sb_map_reader* r, size_t p);
/* "'NAME' expects EXPECTED, got ..." */
sb_status sb_map_type_fail(const sb_map_reader* r, const sb_scene_node* node, const char* name, const char* expected);
/* Key values: a finite number; one >= 0 (> 0 when positive) and at most
 * max; three finite numbers; a scalar's text. */
sb_status sb_map_read_number(const sb_map_reader* r, int key, double* out);
sb_status sb_map_read_range(const sb_map_reader* r, int key, bool positive, double max, double* out);
sb_status sb_map_read_vec3(const sb_map_reader* r, const sb_scene_node* node, const char* key, double out[3]);
sb_status sb_map_read_text(const sb_map_reader* r, int key, const char** out);
/* linear or smooth */
sb_status sb_map_read_interpolation(const sb_map_reader* r, int key, sb_interpolation* out);
/* Keyframes {time, translate, rotate} in increasing time; *path is
 * allocated (the caller frees it, also on failure). */
sb_status sb_map_read_path(const sb_map_reader* r, int key, sb_keyframe** path, uint32_t* count);
/* 1 to SB_SCENE_NAME_MAX letters, digits, '_', '-' or '.': names head columns of log.csv. */
#define SB_SCENE_NAME_MAX 63
bool sb_scene_good_name(const char* name);

#endif
