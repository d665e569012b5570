/* A scene's point load: the constant force `load.force` (N) on the free
 * vertex nearest the point `load.at` (m) of the placed rest shape, from
 * t = 0 on — the Sudhamani sheet pushed at its middle or at a corner.
 * `load.force: [0, 0, 0]` (the default) is no load. */
#ifndef SB_POINT_LOAD_H
#define SB_POINT_LOAD_H

#include "scenes/scene.h"

#include <stdio.h>

typedef struct sb_point_load {
    bool active;
    uint32_t vertex;
    double force[3];
} sb_point_load;

/* Finds the loaded vertex of `model` (the lowest index on a tie). A load
 * whose nearest vertex is fixed is an error naming load.at's place, the
 * vertex and why. */
sb_status sb_point_load_prepare(const sb_scene* scene, const sb_model* model, sb_point_load* load, sb_error* err);
/* Says which vertex an active load acts on, one line, e.g. "softbond: load
 * [0, 0, 0.5] N on vertex 84 at [0.5, 0.5, 0] m (0 m from load.at)": the
 * vertex is chosen by distance, so a point given in the wrong unit shows. */
void sb_point_load_print(const sb_point_load* load, const sb_scene* scene, const sb_model* model, FILE* stream);
/* Makes `def` apply an active load (kept by pointer: it must outlive the
 * solver). */
void sb_point_load_attach(sb_point_load* load, sb_solver_def* def);

#endif
