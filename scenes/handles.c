/* The scene's handles (see handles.h), read as colliders.c reads its
 * entries (scenes/map_reader.c): the map, its keys, then each value by type
 * and range, then the combinations (vertices or at; radius with at), then
 * the names; the vertices once the model is built. */
#define _POSIX_C_SOURCE 200809L
#include "scenes/handles.h"
#include "common/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* X(id, name, type, default, unit, meaning): the entry's keys, in the order
 * `softbond keys` prints them; the parser reads the names from here. */
#define HANDLE_KEYS(X)                                                                                                 \
    X(NAME, "name", STRING, "handle<index>", "",                                                                       \
      "log.csv's columns and messages: 1 to 63 letters, digits, '_', '-' or '.', unique; by default handle and the "   \
      "entry's index (handle0)")                                                                                       \
    X(VERTICES, "vertices", INDICES, "none", "",                                                                       \
      "the vertices it holds, at least one, each once; give vertices or at, not both")                                 \
    X(AT, "at", VEC3, "none", "m",                                                                                     \
      "holds the vertices within radius of this point of the placed rest shape (without radius the nearest one); "     \
      "give vertices or at, not both")                                                                                 \
    X(RADIUS, "radius", NUMBER, "none", "m", "with at only: the distance within which vertices are held, > 0")         \
    X(STIFFNESS, "stiffness", NUMBER, "0", "N/m",                                                                      \
      "per vertex, >= 0: > 0 makes the handle soft (a spring-damper to its target), 0 hard (moved by position)")       \
    X(DAMPING, "damping", NUMBER, "0", "N s/m", "per vertex, >= 0: a soft handle's damping")                           \
    X(PATH, "path", LIST, "[]", "",                                                                                    \
      "keyframes {time (s, increasing), translate (m), rotate (deg, about the centroid of its vertices)}; [] holds "   \
      "the vertices where they are")                                                                                   \
    X(INTERPOLATION, "interpolation", STRING, "linear", "",                                                            \
      "between keyframes: linear (constant speed) or smooth (eased in and out of each keyframe)")                      \
    X(RELEASE_AT, "release_at", NUMBER, "never", "s",                                                                  \
      "the handle lets go at the end of the first advance that reaches this time, >= 0")

typedef enum entry_key {
#define ENTRY_KEY_ENUM(id, name, type, def, unit, meaning) KEY_##id,
    HANDLE_KEYS(ENTRY_KEY_ENUM)
#undef ENTRY_KEY_ENUM
        KEY_COUNT
} entry_key;

static const sb_entry_key key_table[KEY_COUNT] = {
#define ENTRY_KEY_INFO(id, name, type, def, unit, meaning) {name, SB_SCENE_##type, def, unit, 0, meaning},
    HANDLE_KEYS(ENTRY_KEY_INFO)
#undef ENTRY_KEY_INFO
};

/* The names alone, as sb_map_index takes them. */
static const char* const entry_keys[KEY_COUNT] = {
#define ENTRY_KEY_NAME(id, name, type, def, unit, meaning) name,
    HANDLE_KEYS(ENTRY_KEY_NAME)
#undef ENTRY_KEY_NAME
};

const sb_entry_key* sb_scene_handle_keys(size_t* count) {
    *count = KEY_COUNT;
    return key_table;
}

/* A sequence of vertex indices (whole numbers >= 0), at least one. */
static sb_status read_vertices(const sb_map_reader* r, sb_scene_handle* out) {
    const sb_scene_node* list = r->values[KEY_VERTICES];
    char name[128];
    sb_map_full_name(r, "vertices", name, sizeof name);
    if (list->kind != SB_NODE_SEQUENCE || list->count == 0)
        return sb_map_type_fail(r, list, name, "a sequence of vertex indices");
    if (list->count > UINT32_MAX) return sb_map_fail(r, list, "'%s': too many vertices", name);
    if (!(out->vertices = malloc(list->count * sizeof *out->vertices)))
        return sb_error_set(r->err, SB_ERR_NOMEM, "out of memory");
    for (size_t j = 0; j < list->count; j++) {
        double v;
        if (!sb_scene_node_number(&list->items[j], &v) || !(v >= 0.0 && v <= UINT32_MAX - 1.0) || v != floor(v))
            return sb_map_type_fail(r, &list->items[j], name, "vertex indices (whole numbers >= 0)");
        out->vertices[j] = (uint32_t)v;
        for (size_t i = 0; i < j; i++)
            if (out->vertices[i] == out->vertices[j])
                return sb_map_fail(r, &list->items[j], "'%s': vertex %u is listed twice", name, out->vertices[j]);
    }
    out->def.vertex_count = (uint32_t)list->count;
    return SB_OK;
}

static sb_status read_value(const sb_map_reader* r, int key, sb_scene_handle* out) {
    sb_handle_def* def = &out->def;
    const char* ignored;
    switch ((entry_key)key) {
    case KEY_NAME: return sb_map_read_text(r, key, &ignored); /* checked with the other names */
    case KEY_VERTICES: return read_vertices(r, out);
    case KEY_AT: out->has_at = true; return sb_map_read_vec3(r, r->values[key], "at", out->at);
    case KEY_RADIUS: return sb_map_read_range(r, key, true, INFINITY, &out->radius);
    case KEY_STIFFNESS: return sb_map_read_range(r, key, false, INFINITY, &def->stiffness);
    case KEY_DAMPING: return sb_map_read_range(r, key, false, INFINITY, &def->damping);
    case KEY_PATH: return sb_map_read_path(r, key, &out->path, &def->path_count);
    case KEY_INTERPOLATION: return sb_map_read_interpolation(r, key, &def->interpolation);
    case KEY_RELEASE_AT: return sb_map_read_range(r, key, false, INFINITY, &def->release_time);
    default: return SB_OK;
    }
}

/* vertices or at, not both; radius only with at. */
static sb_status check_selection(const sb_map_reader* r) {
    char name[128];
    if (r->values[KEY_VERTICES] && r->values[KEY_AT])
        return sb_map_fail(r, r->keys[KEY_AT], "'%s': give vertices or at, not both",
                           sb_map_full_name(r, "at", name, sizeof name));
    if (!r->values[KEY_VERTICES] && !r->values[KEY_AT])
        return sb_map_fail(r, r->map, "'%s' is not set (a handle holds vertices: a list, or those near at)",
                           sb_map_full_name(r, "vertices", name, sizeof name));
    if (r->values[KEY_RADIUS] && !r->values[KEY_AT])
        return sb_map_fail(r, r->keys[KEY_RADIUS], "'%s' applies to at, not to vertices",
                           sb_map_full_name(r, "radius", name, sizeof name));
    return SB_OK;
}

static sb_status read_entry(const sb_scene_tree* tree, uint32_t index, sb_scene_handle* out,
                            const sb_scene_node** name_node, sb_error* err) {
    const sb_scene_node* node = &tree->root.items[index];
    sb_map_reader r = {.tree = tree, .map = node, .err = err};
    snprintf(r.prefix, sizeof r.prefix, "handles[%u]", index);
    out->def = sb_default_handle_def();
    sb_status status = sb_map_expect_map(&r, node, "a map");
    if (status == SB_OK) status = sb_map_index(&r, entry_keys, KEY_COUNT);
    for (size_t p = 0; status == SB_OK && p < node->count; p++) status = read_value(&r, sb_map_key_at(&r, p), out);
    if (status == SB_OK) status = check_selection(&r);
    out->def.path = out->path;
    if (node->line)
        snprintf(out->where, sizeof out->where, "%s:%zu", tree->source, node->line);
    else
        snprintf(out->where, sizeof out->where, "%s", tree->source);
    *name_node = r.values[KEY_NAME];
    return status;
}

/* Each entry's name (written, or handle and its index), checked and
 * unique: a soft handle's name heads columns of log.csv. */
static sb_status set_names(const sb_scene_tree* tree, sb_scene_handles* h, const sb_scene_node* const* name_nodes,
                           sb_error* err) {
    for (uint32_t i = 0; i < h->count; i++) {
        sb_scene_handle* e = &h->entries[i];
        const sb_scene_node* named = name_nodes[i];
        if (named && !sb_scene_good_name(named->text))
            return sb_scene_node_fail(tree, named, err,
                                      "'handles[%u].name' must be 1 to %d letters, digits, '_', '-' or '.', got "
                                      "'%.80s'",
                                      i, SB_SCENE_NAME_MAX, named->text);
        if (named)
            snprintf(e->name, sizeof e->name, "%s", named->text);
        else
            snprintf(e->name, sizeof e->name, "handle%u", i);
        e->def.name = e->name;
        for (uint32_t j = 0; j < i; j++)
            if (strcmp(h->entries[j].name, e->name) == 0)
                return sb_scene_node_fail(tree, named ? named : &tree->root.items[i], err,
                                          "'handles[%u].name': '%s' is already handles[%u]'s name", i, e->name, j);
    }
    return SB_OK;
}

sb_status sb_scene_handles_read(const sb_scene* scene, sb_scene_handles* out, sb_error* err) {
    memset(out, 0, sizeof *out);
    const sb_scene_tree* tree = sb_scene_tree_value(scene, SB_KEY_HANDLES);
    if (!tree || tree->root.kind != SB_NODE_SEQUENCE) return SB_OK;
    const sb_scene_node* root = &tree->root;
    if (root->count > UINT32_MAX) return sb_scene_node_fail(tree, root, err, "'handles': too many entries");
    out->count = (uint32_t)root->count;
    out->entries = calloc(root->count ? root->count : 1, sizeof *out->entries);
    const sb_scene_node** names = calloc(root->count ? root->count : 1, sizeof *names);
    sb_status status = out->entries && names ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    for (uint32_t i = 0; i < out->count && status == SB_OK; i++)
        status = read_entry(tree, i, &out->entries[i], &names[i], err);
    if (status == SB_OK) status = set_names(tree, out, names, err);
    free(names);
    if (status != SB_OK) sb_scene_handles_free(out);
    return status;
}

sb_status sb_scene_handles_check(const sb_scene* scene, sb_error* err) {
    sb_scene_handles handles;
    sb_status status = sb_scene_handles_read(scene, &handles, err);
    sb_scene_handles_free(&handles);
    return status;
}

static double distance2(const sb_model* model, uint32_t v, const double at[3]) {
    double x[3], d2 = 0.0;
    sb_model_rest_position(model, v, x);
    for (int k = 0; k < 3; k++) d2 += (x[k] - at[k]) * (x[k] - at[k]);
    return d2;
}

/* The vertices within radius of at (radius 0: the nearest one). */
static sb_status select_near(sb_scene_handle* e, uint32_t index, const sb_model* model, sb_error* err) {
    uint32_t n = sb_model_vertex_count(model), count = 0, nearest = 0;
    double best = INFINITY;
    for (uint32_t v = 0; v < n; v++) {
        double d2 = distance2(model, v, e->at);
        count += e->radius > 0.0 && d2 <= e->radius * e->radius;
        if (d2 < best) best = d2, nearest = v;
    }
    if (n == 0 || (e->radius > 0.0 && count == 0))
        return sb_error_set(err, SB_ERR_INVALID,
                            "%s: 'handles[%u].at': no vertex within radius %g of [%g, %g, %g] (the nearest is "
                            "%.3g m away)",
                            e->where, index, e->radius, e->at[0], e->at[1], e->at[2], sqrt(best));
    count = e->radius > 0.0 ? count : 1;
    if (!(e->vertices = malloc(count * sizeof *e->vertices))) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    e->def.vertex_count = 0;
    for (uint32_t v = 0; v < n; v++)
        if (e->radius > 0.0 ? distance2(model, v, e->at) <= e->radius * e->radius : v == nearest)
            e->vertices[e->def.vertex_count++] = v;
    return SB_OK;
}

static sb_status check_indices(const sb_scene_handle* e, uint32_t index, const sb_model* model, sb_error* err) {
    uint32_t n = sb_model_vertex_count(model);
    for (uint32_t j = 0; j < e->def.vertex_count; j++)
        if (e->vertices[j] >= n)
            return sb_error_set(err, SB_ERR_INVALID,
                                "%s: 'handles[%u].vertices': vertex %u is not in the model (%u vertices)", e->where,
                                index, e->vertices[j], n);
    return SB_OK;
}

sb_status sb_scene_handles_create(sb_scene_handles* h, const sb_model* model, sb_error* err) {
    if (h->count == 0) return SB_OK;
    if (!(h->handles = calloc(h->count, sizeof *h->handles))) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    for (uint32_t i = 0; i < h->count; i++) {
        sb_scene_handle* e = &h->entries[i];
        sb_status status = e->has_at ? select_near(e, i, model, err) : check_indices(e, i, model, err);
        if (status != SB_OK) return status;
        e->def.vertices = e->vertices;
        if (!(h->handles[i] = sb_handle_create(&e->def, err))) return sb_error_prefix(err, SB_ERR_INVALID, e->where);
    }
    return SB_OK;
}

void sb_scene_handles_attach(const sb_scene_handles* h, sb_solver_def* def) {
    def->handles = h->handles;
    def->handle_count = h->handles ? h->count : 0;
}

void sb_scene_handles_free(sb_scene_handles* h) {
    for (uint32_t i = 0; h->handles && i < h->count; i++) sb_handle_destroy(h->handles[i]);
    for (uint32_t i = 0; h->entries && i < h->count; i++) {
        free(h->entries[i].path);
        free(h->entries[i].vertices);
    }
    free(h->handles);
    free(h->entries);
    memset(h, 0, sizeof *h);
}
