/* Private: the hinge's second derivatives, on dual numbers and in closed form (hessian_hinges.c). */
#ifndef SB_HESSIAN_HINGES_H
#define SB_HESSIAN_HINGES_H

#include "common/dual.h"
#include "mesh/model_internal.h"

/* One per term family (kernels/forces/hessian_edges.c, _corners.c, _hinges.c);
 * *collapsed is set when an edge or a wing collapsed (f not written). */
void sb_hinge_forces_dual(const sb_model* m, uint32_t hinge, const sb_dvec3* x, sb_dvec3* f, bool* collapsed);
/* The vertex's share (hessian.h's sb_element_vertex_share). */
bool sb_hinge_vertex_share(const sb_model* m, uint32_t hinge, const sb_vec3* x, int place, double* f, double* block);
/* The positive semi-definite stand-in for K_e (hessian.h's
 * sb_element_stiffness_definite). */
void sb_hinge_definite(const sb_model* m, uint32_t hinge, const sb_vec3* x, double* k);
/* Its share of J (hessian.h's sb_element_jacobian_blocks): scale times the stand-in's blocks. */
bool sb_hinge_definite_blocks(const sb_model* m, uint32_t hinge, const sb_vec3* x, double scale, double* blocks);

#endif
