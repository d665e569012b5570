/* Private: a sheet membrane's stiffness for the implicit integrators
 * (hessian_membranes.c), and the functions of an element whose stiffness
 * is one matrix (the membrane's co-rotated K; kernels/forces/hessian.h). */
#ifndef SB_HESSIAN_MEMBRANES_H
#define SB_HESSIAN_MEMBRANES_H

#include "common/dual.h"
#include "mesh/model_internal.h"

/* Membrane `tri` at its corners x[3]: its exact forces into f (9 doubles,
 * corner-major, may be NULL) and the co-rotated stiffness into k (9 × 9
 * row-major, may be NULL). False when the triangle collapsed (nothing
 * written). */
bool sb_membrane_element_stiffness(const sb_model* m, uint32_t tri, const sb_vec3* x, double* f, double* k);

/* For an element of `count` vertices whose forces are `forces` (3 count)
 * and whose stiffness is the matrix k (3 count square, row-major): */
/* the dual forces: forces as value, −k p as derivative (p the seeds' d);   */
void sb_matrix_forces_dual(int count, const double* forces, const double* k, const sb_dvec3* x, sb_dvec3* f);
/* vertex `place`'s force added to f and its diagonal block to block (3 × 3); */
void sb_matrix_vertex_share(int count, const double* forces, const double* k, int place, double* f, double* block);
/* scale k in hessian.h's block layout (block (r, c) at blocks + 9 (count r + c)). */
void sb_matrix_blocks(int count, const double* k, double scale, double* blocks);

#endif
