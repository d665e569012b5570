/* A scene's colliders: the `colliders` list and `contact.thickness`.
 *
 *   colliders:
 *     - {type: plane, name: floor, restitution: 0.5}
 *     - type: sphere
 *       center: [0, 0, 0.3]
 *       radius: 0.2
 *       path: [{time: 0, translate: [0, 0, 0]}, {time: 1, translate: [0, 0, 0.5]}]
 *
 * Each entry is a map. `type` (plane, sphere, capsule, box, mesh) is
 * required and decides which shape keys the entry may have: plane point,
 * normal; sphere center, radius; capsule a, b, radius; box center,
 * half_extents, rotate; mesh file (any file mesh.file reads, relative to
 * the scene file), scale, rotate, translate (placing it as mesh.scale,
 * mesh.rotate and mesh.translate place the body).
 * Every entry may have name (default: the type and the entry's index, e.g.
 * sphere1), friction, static_friction (default: friction), restitution,
 * thickness, path (keyframes {time, translate, rotate}) and interpolation
 * (linear, smooth). A plane's point and normal default to the origin and
 * +z, a box's rotate to none; every other shape key is required. A sphere
 * or box may have mass (kg, >= 0; > 0 makes it dynamic: a rigid body the
 * soft bodies push back, moved by gravity and contact; not with a path) and
 * velocity (m/s, its velocity at the start) and angular_velocity (rad/s,
 * world frame, its spin at the start), both only with a mass > 0. To any
 * other shape, and velocity or angular_velocity without a mass, they are
 * unknown keys.
 * Coordinates are the world's: mesh.scale, mesh.rotate and mesh.translate
 * place the mesh, not the colliders.
 *
 * Entries are checked when the scene is validated, each problem one line
 * naming the place of the offending key (file:line, or the --set) and the
 * key as colliders[i].key. */
#ifndef SB_SCENE_COLLIDERS_H
#define SB_SCENE_COLLIDERS_H

#include "scenes/map_reader.h"
#include "scenes/scene.h"

/* The longest collider name, without its terminating zero. */
#define SB_SCENE_COLLIDER_NAME_MAX SB_SCENE_NAME_MAX

typedef struct sb_scene_collider {
    sb_collider_def def; /* def.name and def.path point into this entry */
    char name[SB_SCENE_COLLIDER_NAME_MAX + 1];
    sb_keyframe* path;
    sb_mesh mesh;                    /* a mesh collider's triangles, loaded and placed; def.mesh points here */
    sb_mesh_transform_def placement; /* its scale, rotate and translate */
    char where[400];                 /* the entry's place, "file:line" or the --set */
} sb_scene_collider;

typedef struct sb_scene_colliders {
    uint32_t count;
    sb_scene_collider* entries;
    sb_collider** colliders; /* made by sb_scene_colliders_create (count of them), or NULL */
    double thickness;        /* contact.thickness, m */
} sb_scene_colliders;

/* Reads and checks the scene's colliders into definitions; errors name the
 * entry's key and where it was written. On failure *out is empty. */
sb_status sb_scene_colliders_read(const sb_scene* scene, sb_scene_colliders* out, sb_error* err);
/* sb_scene_validate's check: reads the colliders and lets them go. */
sb_status sb_scene_colliders_check(const sb_scene* scene, sb_error* err);
/* The entries' keys, the parser's own table: name, type, default, unit, the
 * shapes that take each, meaning (`softbond keys colliders`). */
const sb_entry_key* sb_scene_collider_keys(size_t* count);
/* Makes the library's colliders from the definitions (sb_collider_create);
 * its errors get the entry's place in front. */
sb_status sb_scene_colliders_create(sb_scene_colliders* colliders, sb_error* err);
/* Points def's colliders, collider_count and contact_thickness at them:
 * they must outlive the solver made from def. */
void sb_scene_colliders_attach(const sb_scene_colliders* colliders, sb_solver_def* def);
/* Destroys the colliders made and frees the definitions. */
void sb_scene_colliders_free(sb_scene_colliders* colliders);

#endif
