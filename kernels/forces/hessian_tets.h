/* Private: the co-rotated tetrahedron's stiffness (hessian_tets.c). */
#ifndef SB_HESSIAN_TETS_H
#define SB_HESSIAN_TETS_H

#include "common/geometry.h"
#include "mesh/model_internal.h"

/* Tetrahedron `tet` (n = 4 or 10 nodes, tet_nodes) at its nodes x[n]: its
 * forces into f (3 n doubles, node-major, may be NULL) and the co-rotated
 * stiffness R K0 Rᵀ into k (3 n × 3 n row-major, may be NULL). False when the
 * deformation is not finite (nothing written). */
bool sb_tet_stiffness(const sb_model* m, uint32_t tet, const sb_vec3* x, double* f, double* k);

#endif
