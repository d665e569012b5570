/* --budget-ms: pick the resolution whose measured step time fits and,
 * with --max-error, whose error against the full model is small enough. */
#ifndef SB_BUDGET_H
#define SB_BUDGET_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "scenes/scene.h"

typedef struct sb_budget_level {
    uint32_t vertices; /* the model's size at this level */
    double step_ms;    /* measured time of one step */
    double error;      /* m: RMS distance of its vertices from the full model's after a trial run (0: not measured) */
} sb_budget_level;

/* Among the levels whose error is at most max_error (INFINITY: all), the
 * index of the one with the most vertices whose step_ms <= budget_ms; when
 * none fits, the one with the fewest vertices, and *fits (if not NULL) is
 * false. count >= 1; the full model's error is 0, so some level is within
 * any max_error >= 0. */
int sb_budget_choose(const sb_budget_level* levels, int count, double budget_ms, double max_error, bool* fits);

/* The scene's mesh at the resolution that fits: the mesh the scene asks
 * for, then simplified to 1/2, 1/4, ... of its vertices (down to about 64,
 * at most 6 levels; boundary and fixed vertices kept). Each level's model
 * gets a solver with the scene's settings but the fast kernels, takes 3
 * warm-up steps, then is timed in 3 rounds of steps (each until 10 ms or
 * 100 steps have passed); its time is the best round's per step. With a
 * finite max_error (m), every level also runs the scene's first
 * SB_BUDGET_TRIAL seconds (or its duration when shorter) beside the full
 * mesh, and its error is the RMS distance of its vertices from the same
 * vertices of the full model at the end (simplification never moves a
 * vertex). The runs take the scene's colliders (made afresh for each run)
 * but not its handles, point loads or haptics. The level chosen by
 * sb_budget_choose is returned in out; the table and the choice are
 * printed on stream when not NULL. */
#define SB_BUDGET_TRIAL 0.5
sb_status sb_budget_mesh(const sb_scene* scene, const sb_solver_def* def, double budget_ms, double max_error,
                         sb_mesh* out, FILE* stream, sb_error* err);

#endif
