/* Private: the scalar reference for the per-corner terms (kernels/forces/reference_corners.c). */
#ifndef SB_REFERENCE_CORNERS_H
#define SB_REFERENCE_CORNERS_H

#include "mesh/model_internal.h"

/* Angle bend (Eq. 4) and stretch-bend (Eq. 5) per corner, each scaled by its
 * weight (1 to include the term, 0 to leave it out). */
sb_status sb_reference_corners(const sb_model* m, double angle_weight, double stretch_bend_weight, const double* x,
                               double* f, double* energy, sb_error* err);

#endif
