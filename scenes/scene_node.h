/* A structured scene value kept as it was read.
 *
 * Most keys hold one scalar or a short sequence, checked as the file is
 * read. A key of type SB_SCENE_LIST (`colliders`) holds a list of maps whose
 * keys depend on each entry (a sphere has a radius, a plane a normal), and
 * whose entries nest further lists (a collider's `path`). The loader keeps
 * such a value as a tree of nodes — scalars, sequences and maps — each with
 * the line it starts on, and the module that owns the key (colliders.c)
 * reads and checks it when the scene is validated, naming the exact line of
 * whatever is wrong. Nothing here knows about colliders. */
#ifndef SB_SCENE_NODE_H
#define SB_SCENE_NODE_H

#include "softbond/types.h"

#include <stdbool.h>
#include <stddef.h>

typedef enum sb_scene_node_kind { SB_NODE_SCALAR, SB_NODE_SEQUENCE, SB_NODE_MAP } sb_scene_node_kind;

typedef struct sb_scene_node sb_scene_node;
struct sb_scene_node {
    sb_scene_node_kind kind;
    size_t line;          /* 1-based; 0 when the source has no lines (a --set) */
    char* text;           /* scalar: its text */
    bool plain;           /* scalar: written without quotes (only a plain scalar is a number) */
    size_t count;         /* sequence: items; map: pairs */
    sb_scene_node* items; /* sequence: the items; map: the values */
    sb_scene_node* keys;  /* map: the keys, in the order written */
};

/* A tree and where it came from: the file its lines refer to, or the whole
 * "--set key=value". */
typedef struct sb_scene_tree {
    char* source;
    sb_scene_node root;
} sb_scene_tree;

void sb_scene_tree_free(sb_scene_tree* tree);

/* Formats "SOURCE:LINE: message" (or "SOURCE: message" for a node without a
 * line) into err; returns SB_ERR_INVALID. */
sb_status sb_scene_node_fail(const sb_scene_tree* tree, const sb_scene_node* node, sb_error* err, const char* format,
                             ...) __attribute__((format(printf, 4, 5)));

/* What a node is, for "expects a number, got ..." messages: "a sequence of
 * 2", "a map" or the scalar's text in quotes. */
void sb_scene_node_describe(const sb_scene_node* node, char* out, size_t size);

/* A scalar's text read as a number (the scene loader's rule for every
 * number: a plain scalar that strtod reads whole, so `'1'` is a string). */
bool sb_scene_scalar_number(const char* text, bool plain, double* out);
bool sb_scene_node_number(const sb_scene_node* node, double* out);

/* "x,y,z" in one plain scalar: three numbers by the same rule, spaces
 * around each allowed. Every vector of a scene (top-level keys and the
 * lists' keys alike) is [x, y, z] or this. */
bool sb_scene_comma_vec3(const char* text, bool plain, double out[3]);
#define SB_SCENE_VEC3_FORMS "3 numbers: [x, y, z] or x,y,z"

#endif
