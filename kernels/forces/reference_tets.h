/* Private: the scalar reference for the co-rotated tetrahedra (kernels/forces/reference_tets.c). */
#ifndef SB_REFERENCE_TETS_H
#define SB_REFERENCE_TETS_H

#include "mesh/model_internal.h"

/* Co-rotated linear elasticity of the tetrahedra, with their
 * stiffness-proportional damping where v is not NULL, in tetrahedron order. */
sb_status sb_reference_tets(const sb_model* m, const double* x, const double* v, double* f, double* energy,
                            sb_error* err);

#endif
