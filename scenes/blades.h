/* A scene's blades: the `blades` list (softbond/blade.h), edges that cut
 * the bonds they cross as they move.
 *
 *   blades:
 *     - a: [0.05, -0.02, -0.01]   # the edge's ends at time 0, m
 *       b: [0.05, -0.02, 0.01]
 *       path: [{time: 0, translate: [0, 0, 0]}, {time: 0.5, translate: [0, 0.2, 0]}]
 *       interpolation: linear
 *
 * Each entry is a map with a and b (required, distinct), path (keyframes
 * {time, translate, rotate}, rotate degrees about the edge's midpoint) and
 * interpolation (linear, smooth). Entries are checked when the scene is
 * validated, each problem one line naming the place of the offending key
 * and the key as blades[i].key. */
#ifndef SB_SCENE_BLADES_H
#define SB_SCENE_BLADES_H

#include "scenes/scene.h"

typedef struct sb_scene_blades {
    uint32_t count;
    sb_blade_def* defs; /* each def's path points into paths[i] */
    sb_keyframe** paths;
} sb_scene_blades;

/* Reads and checks the scene's blades; on failure *out is empty. */
sb_status sb_scene_blades_read(const sb_scene* scene, sb_scene_blades* out, sb_error* err);
/* sb_scene_validate's check: reads the blades and lets them go. */
sb_status sb_scene_blades_check(const sb_scene* scene, sb_error* err);
/* The entries' keys, the parser's own table: name, type, default, unit,
 * meaning (`softbond keys blades`). */
const sb_entry_key* sb_scene_blade_keys(size_t* count);
/* Points def's blades at them (the solver copies them). */
void sb_scene_blades_attach(const sb_scene_blades* blades, sb_solver_def* def);
void sb_scene_blades_free(sb_scene_blades* blades);

#endif
