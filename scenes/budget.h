/* --budget-ms: pick the resolution whose measured step time fits. */
#ifndef SB_BUDGET_H
#define SB_BUDGET_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "scenes/scene.h"

typedef struct sb_budget_level {
    uint32_t vertices; /* the model's size at this level */
    double step_ms;    /* measured time of one step */
} sb_budget_level;

/* The index of the level with the most vertices whose step_ms <= budget_ms;
 * when none fits, the level with the fewest vertices, and *fits (if not
 * NULL) is false. count >= 1. */
int sb_budget_choose(const sb_budget_level* levels, int count, double budget_ms, bool* fits);

/* The scene's mesh at the resolution that fits: the mesh the scene asks
 * for, then simplified to 1/2, 1/4, ... of its vertices (down to about 64,
 * at most 6 levels; boundary and fixed vertices kept). Each level's model
 * gets a solver with the scene's settings but the fast kernels, takes 3
 * warm-up steps, then is timed in 3 rounds of steps (each until 10 ms or
 * 100 steps have passed); its time is the best round's per step. The level chosen by sb_budget_choose is returned in
 * out; the table and the choice are printed on stream when not NULL. */
sb_status sb_budget_mesh(const sb_scene* scene, const sb_solver_def* def, double budget_ms, sb_mesh* out, FILE* stream,
                         sb_error* err);

#endif
