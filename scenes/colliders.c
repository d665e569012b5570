/* The scene's colliders (see colliders.h).
 *
 * An entry is checked in the order a reader would fix it: it is a map; its
 * keys are known and each given once; its type; no key of another shape;
 * its shape's required keys are there; then each value as written (type,
 * then range); then static_friction against friction. Names come last, when
 * every entry's default name is known. The ranges mirror sb_collider_create's
 * checks, so that a scene's mistake is named at its line; whatever
 * sb_collider_create still refuses gets the entry's place in front. */
#define _POSIX_C_SOURCE 200809L
#include "scenes/colliders.h"
#include "scenes/suggest.h"
#include "common/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    PLANE = 1u << SB_COLLIDER_PLANE,
    SPHERE = 1u << SB_COLLIDER_SPHERE,
    CAPSULE = 1u << SB_COLLIDER_CAPSULE,
    BOX = 1u << SB_COLLIDER_BOX,
    MESH = 1u << SB_COLLIDER_MESH,
    ALL = PLANE | SPHERE | CAPSULE | BOX | MESH
};

/* X(id, name, type, default, unit, shapes, meaning): the entry's keys, in
 * the order `softbond keys` prints them. The parser reads the names from
 * here, the shapes that may have each key (key_shapes) and, from a default
 * of SB_ENTRY_REQUIRED, those that must (key_required). */
#define COLLIDER_KEYS(X)                                                                                               \
    X(TYPE, "type", STRING, SB_ENTRY_REQUIRED, "", ALL,                                                                \
      "the shape: plane, sphere, capsule, box or mesh; it decides which other keys the entry may have")                \
    X(NAME, "name", STRING, "<type><index>", "", ALL,                                                                  \
      "how log.csv names its force columns and messages: 1 to 63 letters, digits, '_', '-' or '.', unique; by "        \
      "default the type and the entry's index (plane0, sphere1)")                                                      \
    X(POINT, "point", VEC3, "[0, 0, 0]", "m", PLANE, "a point of the plane")                                           \
    X(NORMAL, "normal", VEC3, "[0, 0, 1]", "", PLANE,                                                                  \
      "the plane's normal (need not be unit, not [0, 0, 0]); the solid is the half-space below it")                    \
    X(CENTER, "center", VEC3, SB_ENTRY_REQUIRED, "m", SPHERE | BOX, "the centre")                                      \
    X(A, "a", VEC3, SB_ENTRY_REQUIRED, "m", CAPSULE, "one end of the capsule's segment")                               \
    X(B, "b", VEC3, SB_ENTRY_REQUIRED, "m", CAPSULE, "the other end of the segment")                                   \
    X(RADIUS, "radius", NUMBER, SB_ENTRY_REQUIRED, "m", SPHERE | CAPSULE,                                              \
      "the radius, > 0 (over 100 times the body's extent is refused as a slip of units)")                              \
    X(HALF_EXTENTS, "half_extents", VEC3, SB_ENTRY_REQUIRED, "m", BOX,                                                 \
      "half the box's size along its own axes, each > 0")                                                              \
    X(ROTATE, "rotate", VEC3, "[0, 0, 0]", "deg", BOX | MESH,                                                          \
      "box: degrees about x, then y, then z; mesh: its placement's rotation (as mesh.rotate)")                         \
    X(FILE, "file", STRING, SB_ENTRY_REQUIRED, "", MESH,                                                               \
      "any file mesh.file reads, relative to the scene file; a closed mesh is solid inside, an open one (a "           \
      "bowl) a shell of its thickness, which must then be > 0")                                                        \
    X(SCALE, "scale", VEC3_OR_NUMBER, "1", "1", MESH,                                                                  \
      "the mesh's placement: its scale (as mesh.scale), finite, not 0")                                                \
    X(TRANSLATE, "translate", VEC3, "[0, 0, 0]", "m", MESH,                                                            \
      "the mesh's placement: its shift (as mesh.translate), after scale and rotate")                                   \
    X(FRICTION, "friction", NUMBER, "0", "1", ALL, "Coulomb coefficient while sliding, >= 0")                          \
    X(STATIC_FRICTION, "static_friction", NUMBER, "friction", "1", ALL,                                                \
      "the coefficient below which a vertex sticks, >= friction")                                                      \
    X(RESTITUTION, "restitution", NUMBER, "0", "1", ALL,                                                               \
      "in [0, 1]: the normal velocity after a contact is -restitution x the one before")                               \
    X(THICKNESS, "thickness", NUMBER, "0", "m", ALL,                                                                   \
      "the surface is inflated by it (and by contact.thickness), >= 0; over the body's whole extent is refused")       \
    X(FOOTPRINT, "footprint", NUMBER, "0", "m", SPHERE | CAPSULE | BOX | MESH,                                         \
      ">= 0; > 0: the radius of the patch of the body's surface (at rest) each contact presses, its load spread "      \
      "smoothly over it, no vertex answered alone: a tool smaller than the mesh's spacing then feels no bump at "      \
      "the vertices (about 2.5 spacings); at least the surface's longest edge, not with tearing")                      \
    X(PATH, "path", LIST, "[]", "", ALL,                                                                               \
      "keyframes {time (s, increasing), translate (m), rotate (deg)} of a moving (kinematic) collider, rotate about "  \
      "its reference point (the plane's point, the centre, the capsule's midpoint, the placed mesh's bounding box's "  \
      "centre); the pose holds before the first and after the last; [] fixed")                                         \
    X(INTERPOLATION, "interpolation", STRING, "linear", "", ALL,                                                       \
      "between keyframes: linear (constant speed) or smooth (eased in and out of each keyframe)")                      \
    X(MASS, "mass", NUMBER, "0", "kg", SPHERE | BOX,                                                                   \
      ">= 0; > 0 makes it dynamic, a solid rigid body the bodies push back, moved by gravity and "                     \
      "contact (not with a path); 0 static or kinematic")                                                              \
    X(VELOCITY, "velocity", VEC3, "[0, 0, 0]", "m/s", SPHERE | BOX,                                                    \
      "its velocity at the start, only with a mass > 0 (an unknown key without one)")                                  \
    X(ANGULAR_VELOCITY, "angular_velocity", VEC3, "[0, 0, 0]", "rad/s", SPHERE | BOX,                                  \
      "its spin at the start about the world's axes, only with a mass > 0 (an unknown key without one)")

typedef enum entry_key {
#define ENTRY_KEY_ENUM(id, name, type, def, unit, shapes, meaning) KEY_##id,
    COLLIDER_KEYS(ENTRY_KEY_ENUM)
#undef ENTRY_KEY_ENUM
        KEY_COUNT
} entry_key;

static const sb_entry_key key_table[KEY_COUNT] = {
#define ENTRY_KEY_INFO(id, name, type, def, unit, shapes, meaning) {name, SB_SCENE_##type, def, unit, shapes, meaning},
    COLLIDER_KEYS(ENTRY_KEY_INFO)
#undef ENTRY_KEY_INFO
};

/* The names alone, as sb_map_index takes them. */
static const char* const entry_keys[KEY_COUNT] = {
#define ENTRY_KEY_NAME(id, name, type, def, unit, shapes, meaning) name,
    COLLIDER_KEYS(ENTRY_KEY_NAME)
#undef ENTRY_KEY_NAME
};

const sb_entry_key* sb_scene_collider_keys(size_t* count) {
    *count = KEY_COUNT;
    return key_table;
}

/* The shapes that may have key k, and those that must. */
static unsigned key_shapes(int k) { return key_table[k].shapes; }
static unsigned key_required(int k) {
    return strcmp(key_table[k].default_value, SB_ENTRY_REQUIRED) == 0 ? key_table[k].shapes : 0;
}

static sb_status read_path(const sb_map_reader* r, sb_scene_collider* out) {
    sb_status status = sb_map_read_path(r, KEY_PATH, &out->path, &out->def.path_count);
    out->def.path = out->path;
    return status;
}

/* ---- an entry ------------------------------------------------------------------ */

/* Keys of a dynamic collider's motion, not of its geometry. */
static bool motion_key(int key) { return key == KEY_MASS || key == KEY_VELOCITY || key == KEY_ANGULAR_VELOCITY; }

/* "point, normal" (geometry keys) or "center and radius" (required keys) of a shape. */
static void shape_keys(sb_collider_shape shape, unsigned (*table)(int), const char* last_join, char* out, size_t size) {
    int count = 0, total = 0;
    for (int k = 0; k < KEY_COUNT; k++) total += table(k) != ALL && !motion_key(k) && (table(k) & (1u << shape));
    out[0] = '\0';
    for (int k = 0; k < KEY_COUNT; k++) {
        if (table(k) == ALL || motion_key(k) || !(table(k) & (1u << shape))) continue;
        size_t used = strlen(out);
        snprintf(out + used, size - used, "%s%s",
                 count == 0           ? ""
                 : count == total - 1 ? last_join
                                      : ", ",
                 entry_keys[k]);
        count++;
    }
}

static sb_status read_shape(const sb_map_reader* r, sb_collider_shape* shape) {
    char name[128];
    sb_map_full_name(r, "type", name, sizeof name);
    if (!r->values[KEY_TYPE])
        return sb_map_fail(r, r->map, "'%s' is not set (plane, sphere, capsule, box or mesh)", name);
    const char* type = "";
    sb_status status = sb_map_read_text(r, KEY_TYPE, &type);
    if (status != SB_OK) return status;
    if (!sb_collider_shape_from_name(type, shape)) {
        char near[96];
        return sb_map_fail(r, r->values[KEY_TYPE], "'%s' must be plane, sphere, capsule, box or mesh, got '%s'%s", name,
                           type, sb_suggest_hint(type, "plane, sphere, capsule, box, mesh", near, sizeof near));
    }
    return SB_OK;
}

/* No key of another shape; every key the shape needs. */
static sb_status check_shape_keys(const sb_map_reader* r, sb_collider_shape shape) {
    const char* kind = sb_collider_shape_name(shape);
    char name[128], keys[128];
    for (size_t p = 0; p < r->map->count; p++) {
        int k = 0;
        while (strcmp(entry_keys[k], r->map->keys[p].text) != 0) k++;
        if (key_shapes(k) & (1u << shape)) continue;
        if (motion_key(k)) /* only a sphere or box can be dynamic: to any other shape the key is unknown */
            return sb_map_fail(r, &r->map->keys[p], "unknown key '%s'",
                               sb_map_full_name(r, entry_keys[k], name, sizeof name));
        shape_keys(shape, key_shapes, ", ", keys, sizeof keys);
        return sb_map_fail(r, &r->map->keys[p], "'%s' does not apply to a %s (its shape's keys: %s)",
                           sb_map_full_name(r, entry_keys[k], name, sizeof name), kind, keys);
    }
    for (int k = 0; k < KEY_COUNT; k++) {
        if (!(key_required(k) & (1u << shape)) || r->values[k]) continue;
        shape_keys(shape, key_required, " and ", keys, sizeof keys);
        return sb_map_fail(r, r->map, "'%s' is not set (a %s needs %s)",
                           sb_map_full_name(r, entry_keys[k], name, sizeof name), kind, keys);
    }
    return SB_OK;
}

static sb_status read_vector_key(const sb_map_reader* r, int key, sb_scene_collider* out) {
    sb_collider_def* def = &out->def;
    double* targets[KEY_COUNT] = {[KEY_POINT] = def->point,
                                  [KEY_NORMAL] = def->normal,
                                  [KEY_CENTER] = def->center,
                                  [KEY_A] = def->a,
                                  [KEY_B] = def->b,
                                  [KEY_HALF_EXTENTS] = def->half_extents,
                                  [KEY_ROTATE] = def->shape == SB_COLLIDER_MESH ? out->placement.rotate : def->rotate,
                                  [KEY_TRANSLATE] = out->placement.translate,
                                  [KEY_VELOCITY] = def->velocity,
                                  [KEY_ANGULAR_VELOCITY] = def->angular_velocity};
    double* v = targets[key];
    sb_status status = sb_map_read_vec3(r, r->values[key], entry_keys[key], v);
    if (status != SB_OK) return status;
    char name[128];
    sb_map_full_name(r, entry_keys[key], name, sizeof name);
    if (key == KEY_NORMAL && v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0)
        return sb_map_fail(r, r->values[key], "'%s' must not be [0, 0, 0]", name);
    if (key == KEY_HALF_EXTENTS && !(v[0] > 0.0 && v[1] > 0.0 && v[2] > 0.0))
        return sb_map_fail(r, r->values[key], "'%s' must be > 0, got [%g, %g, %g]", name, v[0], v[1], v[2]);
    return SB_OK;
}

/* A mesh's scale: one number or three, none of them 0 (sb_mesh_transform's rule). */
static sb_status read_scale(const sb_map_reader* r, sb_scene_collider* out) {
    const sb_scene_node* node = r->values[KEY_SCALE];
    double* scale = out->placement.scale;
    char name[128];
    sb_map_full_name(r, "scale", name, sizeof name);
    if (node->kind == SB_NODE_SCALAR) {
        if (!sb_scene_node_number(node, &scale[0])) return sb_map_type_fail(r, node, name, "a number or 3 numbers");
        scale[1] = scale[2] = scale[0];
    } else {
        sb_status status = sb_map_read_vec3(r, node, "scale", scale);
        if (status != SB_OK) return status;
    }
    if (!(isfinite(scale[0]) && isfinite(scale[1]) && isfinite(scale[2])) || scale[0] == 0.0 || scale[1] == 0.0 ||
        scale[2] == 0.0)
        return sb_map_fail(r, node, "'%s' must be finite and not 0, got [%g, %g, %g]", name, scale[0], scale[1],
                           scale[2]);
    return SB_OK;
}

/* A mesh collider's file (relative to the scene file's directory), read
 * with the program's mesh loader and placed by scale, rotate and
 * translate (as mesh.scale, mesh.rotate, mesh.translate place the body). */
static sb_status load_mesh(const sb_map_reader* r, sb_scene_collider* out) {
    const sb_scene_node* node = r->values[KEY_FILE];
    const char* file = node->text;
    char name[128], *path = NULL;
    sb_map_full_name(r, "file", name, sizeof name);
    size_t size = strlen(file) + (r->base_dir ? strlen(r->base_dir) + 2 : 1);
    if (!(path = malloc(size))) return sb_error_set(r->err, SB_ERR_NOMEM, "out of memory");
    if (file[0] == '/' || !r->base_dir)
        snprintf(path, size, "%s", file);
    else
        snprintf(path, size, "%s/%s", r->base_dir, file);
    sb_error cause;
    sb_status status = sb_mesh_load(path, &out->mesh, &cause);
    if (status == SB_OK && out->mesh.triangle_count == 0)
        status = sb_error_set(&cause, SB_ERR_INVALID, "%s has no triangles", path);
    if (status == SB_OK) status = sb_mesh_transform(&out->mesh, &out->placement, &cause);
    free(path);
    if (status != SB_OK) return sb_map_fail(r, node, "'%s': %s", name, cause.message);
    out->def.mesh = &out->mesh;
    return SB_OK;
}

static sb_status read_value(const sb_map_reader* r, int key, sb_scene_collider* out) {
    sb_collider_def* def = &out->def;
    const char* ignored;
    switch ((entry_key)key) {
    case KEY_TYPE: return SB_OK;
    case KEY_NAME: return sb_map_read_text(r, KEY_NAME, &ignored); /* checked with the other names */
    case KEY_RADIUS: return sb_map_read_range(r, key, true, INFINITY, &def->radius);
    case KEY_FRICTION: return sb_map_read_range(r, key, false, INFINITY, &def->friction);
    case KEY_STATIC_FRICTION: return sb_map_read_range(r, key, false, INFINITY, &def->static_friction);
    case KEY_RESTITUTION: return sb_map_read_range(r, key, false, 1.0, &def->restitution);
    case KEY_THICKNESS: return sb_map_read_range(r, key, false, INFINITY, &def->thickness);
    case KEY_FOOTPRINT: return sb_map_read_range(r, key, false, INFINITY, &def->footprint);
    case KEY_MASS: return sb_map_read_range(r, key, false, INFINITY, &def->mass);
    case KEY_PATH: return read_path(r, out);
    case KEY_INTERPOLATION: return sb_map_read_interpolation(r, key, &def->interpolation);
    case KEY_FILE: return sb_map_read_text(r, KEY_FILE, &ignored); /* loaded once the placement is known */
    case KEY_SCALE: return read_scale(r, out);
    default: return read_vector_key(r, key, out);
    }
}

static sb_status read_values(const sb_map_reader* r, sb_scene_collider* out) {
    for (size_t p = 0; p < r->map->count; p++) {
        int k = 0;
        while (strcmp(entry_keys[k], r->map->keys[p].text) != 0) k++;
        sb_status status = read_value(r, k, out);
        if (status != SB_OK) return status;
    }
    sb_collider_def* def = &out->def;
    char name[128];
    if (def->mass > 0.0 && r->values[KEY_PATH])
        return sb_map_fail(r, r->keys[KEY_PATH], "'%s': a dynamic collider (mass %g) cannot have a path",
                           sb_map_full_name(r, "path", name, sizeof name), def->mass);
    for (int k = KEY_VELOCITY; k <= KEY_ANGULAR_VELOCITY; k++) /* only a dynamic collider has them */
        if (r->values[k] && !(def->mass > 0.0))
            return sb_map_fail(r, r->keys[k], "unknown key '%s'",
                               sb_map_full_name(r, entry_keys[k], name, sizeof name));
    if (!r->values[KEY_STATIC_FRICTION]) def->static_friction = def->friction;
    if (def->static_friction < def->friction)
        return sb_map_fail(r, r->values[KEY_STATIC_FRICTION], "'%s' (%g) must be >= 'friction' (%g)",
                           sb_map_full_name(r, "static_friction", name, sizeof name), def->static_friction,
                           def->friction);
    return def->shape == SB_COLLIDER_MESH ? load_mesh(r, out) : SB_OK;
}

static sb_status read_entry(const sb_scene_tree* tree, const char* base_dir, uint32_t index, sb_scene_collider* out,
                            const sb_scene_node** name_node, sb_error* err) {
    const sb_scene_node* node = &tree->root.items[index];
    sb_map_reader r = {.tree = tree, .base_dir = base_dir, .map = node, .err = err};
    snprintf(r.prefix, sizeof r.prefix, "colliders[%u]", index);
    sb_status status = sb_map_expect_map(&r, node, "a map");
    if (status == SB_OK) status = sb_map_index(&r, entry_keys, KEY_COUNT);
    sb_collider_shape shape = SB_COLLIDER_PLANE;
    if (status == SB_OK) status = read_shape(&r, &shape);
    if (status == SB_OK) status = check_shape_keys(&r, shape);
    out->def = sb_default_collider_def();
    out->def.shape = shape;
    out->placement = sb_default_mesh_transform_def();
    if (status == SB_OK) status = read_values(&r, out);
    if (node->line)
        snprintf(out->where, sizeof out->where, "%s:%zu", tree->source, node->line);
    else
        snprintf(out->where, sizeof out->where, "%s", tree->source);
    *name_node = r.values[KEY_NAME];
    return status;
}

/* ---- names ----------------------------------------------------------------------- */

/* Each entry's name (written, or its type and index), checked and unique:
 * names head columns of log.csv. */
static sb_status set_names(const sb_scene_tree* tree, sb_scene_colliders* c, const sb_scene_node* const* name_nodes,
                           sb_error* err) {
    for (uint32_t i = 0; i < c->count; i++) {
        sb_scene_collider* e = &c->entries[i];
        const sb_scene_node* named = name_nodes[i];
        if (named && !sb_scene_good_name(named->text))
            return sb_scene_node_fail(tree, named, err,
                                      "'colliders[%u].name' must be 1 to %d letters, digits, '_', '-' or '.', got "
                                      "'%.80s'",
                                      i, SB_SCENE_COLLIDER_NAME_MAX, named->text);
        if (named)
            snprintf(e->name, sizeof e->name, "%s", named->text);
        else
            snprintf(e->name, sizeof e->name, "%s%u", sb_collider_shape_name(e->def.shape), i);
        e->def.name = e->name;
        for (uint32_t j = 0; j < i; j++) {
            if (strcmp(c->entries[j].name, e->name) != 0) continue;
            if (named)
                return sb_scene_node_fail(tree, named, err,
                                          "'colliders[%u].name': '%s' is already colliders[%u]'s name", i, e->name, j);
            return sb_scene_node_fail(tree, &tree->root.items[i], err,
                                      "'colliders[%u]': its default name '%s' is already colliders[%u]'s name", i,
                                      e->name, j);
        }
    }
    return SB_OK;
}

/* ---- entry points ------------------------------------------------------------------ */

static sb_status read_all(const sb_scene_tree* tree, const char* base_dir, sb_scene_colliders* out, sb_error* err) {
    const sb_scene_node* root = &tree->root;
    if (root->count > UINT32_MAX) return sb_scene_node_fail(tree, root, err, "'colliders': too many entries");
    out->count = (uint32_t)root->count;
    out->entries = calloc(root->count ? root->count : 1, sizeof *out->entries);
    const sb_scene_node** names = calloc(root->count ? root->count : 1, sizeof *names);
    sb_status status = out->entries && names ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    for (uint32_t i = 0; i < out->count && status == SB_OK; i++)
        status = read_entry(tree, base_dir, i, &out->entries[i], &names[i], err);
    if (status == SB_OK) status = set_names(tree, out, names, err);
    free(names);
    return status;
}

sb_status sb_scene_colliders_read(const sb_scene* scene, sb_scene_colliders* out, sb_error* err) {
    memset(out, 0, sizeof *out);
    out->thickness = sb_scene_number(scene, SB_KEY_CONTACT_THICKNESS);
    const sb_scene_tree* tree = sb_scene_tree_value(scene, SB_KEY_COLLIDERS);
    if (!tree || tree->root.kind != SB_NODE_SEQUENCE) return SB_OK;
    sb_status status = read_all(tree, scene->values[SB_KEY_COLLIDERS].base_dir, out, err);
    if (status != SB_OK) sb_scene_colliders_free(out);
    return status;
}

sb_status sb_scene_colliders_check(const sb_scene* scene, sb_error* err) {
    sb_scene_colliders colliders;
    sb_status status = sb_scene_colliders_read(scene, &colliders, err);
    sb_scene_colliders_free(&colliders);
    return status;
}

sb_status sb_scene_colliders_create(sb_scene_colliders* c, sb_error* err) {
    if (c->count == 0) return SB_OK;
    if (!(c->colliders = calloc(c->count, sizeof *c->colliders)))
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    for (uint32_t i = 0; i < c->count; i++) {
        c->colliders[i] = sb_collider_create(&c->entries[i].def, err);
        if (!c->colliders[i]) return sb_error_prefix(err, SB_ERR_INVALID, c->entries[i].where);
    }
    return SB_OK;
}

void sb_scene_colliders_attach(const sb_scene_colliders* c, sb_solver_def* def) {
    def->colliders = c->colliders;
    def->collider_count = c->colliders ? c->count : 0;
    def->contact_thickness = c->thickness;
}

void sb_scene_colliders_free(sb_scene_colliders* c) {
    for (uint32_t i = 0; c->colliders && i < c->count; i++)
        if (c->colliders[i]) sb_collider_destroy(c->colliders[i]);
    for (uint32_t i = 0; c->entries && i < c->count; i++) {
        free(c->entries[i].path);
        sb_mesh_free(&c->entries[i].mesh);
    }
    free(c->colliders);
    free(c->entries);
    memset(c, 0, sizeof *c);
}
