/* Private: the bond's second derivatives, on dual numbers and in closed form (hessian_edges.c). */
#ifndef SB_HESSIAN_EDGES_H
#define SB_HESSIAN_EDGES_H

#include "common/dual.h"
#include "mesh/model_internal.h"

/* One per term family (kernels/forces/hessian_edges.c, _corners.c, _hinges.c);
 * *collapsed is set when an edge or a wing collapsed (f not written). */
void sb_bond_forces_dual(const sb_model* m, uint32_t bond, const sb_dvec3* x, sb_dvec3* f, bool* collapsed);
/* K_e in closed form (hessian.h's sb_element_stiffness). */
bool sb_bond_stiffness_matrix(const sb_model* m, uint32_t bond, const sb_vec3* x, double* k);
/* The vertex's share (hessian.h's sb_element_vertex_share). */
bool sb_bond_vertex_share(const sb_model* m, uint32_t bond, const sb_vec3* x, int place, double* f, double* block);
/* The positive semi-definite stand-in for K_e (hessian.h's
 * sb_element_stiffness_definite). */
void sb_bond_definite(const sb_model* m, uint32_t bond, const sb_vec3* x, double* k);
/* Its share of J (hessian.h's sb_element_jacobian_blocks). */
bool sb_bond_jacobian_blocks(const sb_model* m, uint32_t bond, const sb_vec3* x, bool definite, double dt,
                             double* blocks);
/* The spring's damping block d u uᵀ (D_ii = D_jj = −D_ij), row-major 3 × 3;
 * false for a bond without damping or a collapsed one. */
bool sb_bond_damping_block(const sb_model* m, uint32_t bond, const double* x, double* block);

#endif
