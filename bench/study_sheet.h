/* The integrator study's test object: the square sheet of Sudhamani &
 * Merriliance (2019), 1 m², fixed along its left edge, and what every part
 * of the study does with it — its highest frequency, a solver on it, the
 * largest step a solver survives, a run under loads on chosen vertices, and
 * the distance between two runs' end states. */
#ifndef SB_STUDY_SHEET_H
#define SB_STUDY_SHEET_H

#include "softbond/softbond.h"

#include <stdio.h>

#define STUDY_MASS 0.01 /* kg per vertex */

typedef struct study_sheet {
    sb_mesh mesh;
    sb_model* model;
    uint32_t side;   /* vertices per side */
    uint32_t middle; /* the vertex at the centre */
    uint32_t corner; /* the free corner at y = 0 (x = 1 m) */
} study_sheet;

/* The study's usual constants: bond stretch k (N/m), angle bend 1e-3 k. */
sb_material_def study_material(double k);
/* side × side vertices over 1 m², the material's terms, STUDY_MASS per
 * vertex (material.mass is overridden), left edge (x = 0) fixed. Exits on
 * failure: the study has nothing to do without its sheet. */
study_sheet study_sheet_make(uint32_t side, const sb_material_def* material);
void study_sheet_free(study_sheet* s);

/* The largest angular frequency at rest: power iteration on M^-1/2 K M^-1/2,
 * K p the central directional difference of the reference forces. */
double study_omega_max(const study_sheet* s);

/* No gravity, the double scalar reference, one thread. */
sb_solver_def study_solver_def(sb_integrator integrator);
sb_solver* study_solver(const study_sheet* s, const sb_solver_def* def);

/* How a step is tried: a run of 400 steps (or, when duration > 0, of
 * duration s) from the rest shape with every free vertex moved by up to
 * 1 mm out of plane (and in plane too when in_plane: an out-of-plane
 * perturbation reaches the sheet's in-plane modes only through rounding). */
#define STUDY_STABLE_STEPS 400
typedef struct study_trial {
    double duration;
    bool in_plane;
} study_trial;

/* Whether the trial run neither stops (SB_ERR_UNSTABLE) nor multiplies its
 * total energy by more than 10. */
bool study_survives(const study_sheet* s, const sb_solver_def* def, double dt, const study_trial* trial);
/* The largest dt that survives, by bisection on log dt in [lo, hi]; hi
 * when hi survives, 0 when nothing does. */
double study_largest_stable_step(const study_sheet* s, const sb_solver_def* def, double lo, double hi,
                                 const study_trial* trial);

/* Constant forces on a set of vertices: the external-force callback's data. */
typedef struct study_load {
    const uint32_t* vertices;
    uint32_t count;
    double force[3]; /* N, on each of them */
} study_load;

/* A solver whose external forces are the load (which must outlive it). */
sb_solver* study_loaded_solver(const study_sheet* s, const sb_solver_def* def, const study_load* load);
/* A run of `duration` s in steps of dt (which should divide it) under the
 * load: end positions into out (3n), returns the CPU seconds, or a negative
 * number when the solver stopped. */
double study_load_run(const study_sheet* s, const sb_solver_def* def, const study_load* load, double dt,
                      double duration, double* out);
/* The step closest to but not above dt that divides duration evenly. */
double study_dividing_step(double duration, double dt);

/* The largest distance between a vertex's positions in a and b (3n each). */
double study_max_distance(const double* a, const double* b, uint32_t vertex_count);

FILE* study_open(const char* dir, const char* name);

#endif
