/* Private: the scalar reference for a thin sheet's membranes (kernels/forces/reference_membranes.c). */
#ifndef SB_REFERENCE_MEMBRANES_H
#define SB_REFERENCE_MEMBRANES_H

#include "mesh/model_internal.h"

/* Co-rotated linear plane-stress triangles (kernels/forces/membrane.c), in
 * membrane order; v (may be NULL: no damping) the velocities for the
 * damped ones. */
sb_status sb_reference_membranes(const sb_model* m, const double* x, const double* v, double* f, double* energy,
                                 sb_error* err);

#endif
