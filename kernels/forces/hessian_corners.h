/* Private: the triangle's second derivatives, on dual numbers and in closed form (hessian_corners.c). */
#ifndef SB_HESSIAN_CORNERS_H
#define SB_HESSIAN_CORNERS_H

#include "common/dual.h"
#include "mesh/model_internal.h"

/* One per term family (kernels/forces/hessian_edges.c, _corners.c, _hinges.c);
 * *collapsed is set when an edge or a wing collapsed (f not written). */
void sb_triangle_forces_dual(const sb_model* m, uint32_t triangle, const sb_dvec3* x, sb_dvec3* f, bool* collapsed);
/* K_e in closed form (hessian.h's sb_element_stiffness). */
bool sb_triangle_stiffness(const sb_model* m, uint32_t triangle, const sb_vec3* x, double* k);
/* The vertex's share (hessian.h's sb_element_vertex_share). */
bool sb_triangle_vertex_share(const sb_model* m, uint32_t triangle, const sb_vec3* x, int place, double* f,
                              double* block);
/* The positive semi-definite stand-in for K_e (hessian.h's
 * sb_element_stiffness_definite). */
void sb_triangle_definite(const sb_model* m, uint32_t triangle, const sb_vec3* x, double* k);
/* Its share of J (hessian.h's sb_element_jacobian_blocks): scale K_e's blocks. */
bool sb_triangle_stiffness_blocks(const sb_model* m, uint32_t triangle, const sb_vec3* x, double scale, double* blocks);

#endif
