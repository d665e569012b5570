/* A scene's handles: the `handles` list (softbond/handle.h).
 *
 *   handles:
 *     - name: hook
 *       at: [0.5, 1.0, 0]     # the vertices within radius of this point of the placed rest shape
 *       radius: 0.05          # m; without it, the vertex nearest `at`
 *       path: [{time: 0, translate: [0, 0, 0]}, {time: 2, translate: [0, 0.3, 0.2]}]
 *     - {name: grasper, vertices: [12, 13], stiffness: 50, damping: 0.5, release_at: 1.5}
 *
 * Each entry is a map with `vertices` (a list of vertex indices) or `at`
 * (with an optional `radius`), not both; name (default: handle and the
 * entry's index, e.g. handle0), stiffness (N/m per vertex; > 0 makes the
 * handle soft, a spring-damper; 0, the default, hard), damping (N s/m per
 * vertex, soft handles), path (keyframes {time, translate, rotate}, rotate
 * degrees about the centroid of the handle's vertices) and interpolation
 * (linear, smooth), release_at (s: let go then). Each soft handle adds the
 * columns <name>_fx, <name>_fy, <name>_fz to log.csv: the force it exerts
 * on the body, N.
 *
 * Entries are checked when the scene is validated, each problem one line
 * naming the place of the offending key and the key as handles[i].key;
 * the vertices against the model once it is built. */
#ifndef SB_SCENE_HANDLES_H
#define SB_SCENE_HANDLES_H

#include "scenes/map_reader.h"
#include "scenes/scene.h"

typedef struct sb_scene_handle {
    sb_handle_def def; /* def.name, def.path and def.vertices point into this entry */
    char name[SB_SCENE_NAME_MAX + 1];
    sb_keyframe* path;
    uint32_t* vertices; /* the indices written, or those `at` selects (sb_scene_handles_create) */
    bool has_at;
    double at[3], radius;
    char where[400]; /* the entry's place, "file:line" or the --set */
} sb_scene_handle;

typedef struct sb_scene_handles {
    uint32_t count;
    sb_scene_handle* entries;
    sb_handle** handles; /* made by sb_scene_handles_create (count of them), or NULL */
} sb_scene_handles;

/* Reads and checks the scene's handles; on failure *out is empty. */
sb_status sb_scene_handles_read(const sb_scene* scene, sb_scene_handles* out, sb_error* err);
/* sb_scene_validate's check: reads the handles and lets them go. */
sb_status sb_scene_handles_check(const sb_scene* scene, sb_error* err);
/* The entries' keys, the parser's own table: name, type, default, unit,
 * meaning (`softbond keys handles`). */
const sb_entry_key* sb_scene_handle_keys(size_t* count);
/* Selects each entry's vertices in the model (indices in range; `at`
 * finds at least one) and makes the library's handles; errors name the
 * entry's place. */
sb_status sb_scene_handles_create(sb_scene_handles* handles, const sb_model* model, sb_error* err);
/* Points def's handles at them: they must outlive the solver made from def. */
void sb_scene_handles_attach(const sb_scene_handles* handles, sb_solver_def* def);
void sb_scene_handles_free(sb_scene_handles* handles);

#endif
