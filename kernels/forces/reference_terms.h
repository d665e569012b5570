/* Private: the per-term scalar reference functions behind sb_reference_term.
 * Each adds its forces to f (3n interleaved) and returns its energy through
 * *energy; velocities may be NULL. */
#ifndef SB_REFERENCE_TERMS_H
#define SB_REFERENCE_TERMS_H

#include "mesh/model_internal.h"

/* An edge shorter than this fraction of its rest length has collapsed. */
#define SB_COLLAPSE_RATIO 1e-9

/* Bond stretch (Eq. 3) when spring is false; damped spring (Eq. 2) when true. */
sb_status sb_reference_edges(const sb_model* m, bool spring, const double* x, const double* v, double* f,
                             double* energy, sb_error* err);

/* Angle bend (Eq. 4) and stretch-bend (Eq. 5) per corner, each scaled by its
 * weight (1 to include the term, 0 to leave it out). */
sb_status sb_reference_corners(const sb_model* m, double angle_weight, double stretch_bend_weight, const double* x,
                               double* f, double* energy, sb_error* err);

/* Dihedral hinges. */
sb_status sb_reference_hinges(const sb_model* m, const double* x, double* f, double* energy, sb_error* err);

#endif
