/* Private: the co-rotated tetrahedron's stiffness (hessian_tets.c). */
#ifndef SB_HESSIAN_TETS_H
#define SB_HESSIAN_TETS_H

#include "common/geometry.h"
#include "mesh/model_internal.h"

/* Tetrahedron `tet` at its corners x[4]: its exact forces into f (12
 * doubles, corner-major, may be NULL) and the co-rotated stiffness
 * R K0 Rᵀ into k (12 × 12 row-major, may be NULL). False when the
 * deformation is not finite (nothing written). */
bool sb_tet_stiffness(const sb_model* m, uint32_t tet, const sb_vec3* x, double* f, double* k);

#endif
