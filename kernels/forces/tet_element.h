/* Private: a co-rotated tetrahedron of either order, by its node count (4:
 * corotated.h's linear element, 10: corotated_quadratic.h's), so that the
 * reference, the fast pass and the stiffness run both through one loop. */
#ifndef SB_TET_ELEMENT_H
#define SB_TET_ELEMENT_H

#include "kernels/forces/corotated_quadratic.h"

/* The element's material and rest shape. */
typedef struct sb_tet_material {
    const double* dm_inv; /* 9, row-major */
    double volume, mu, lambda;
} sb_tet_material;

/* Forces of the `nodes` nodes at p into f; the energy; false when the
 * deformation is not finite. */
bool sb_tet_element_forces(int nodes, const double p[][3], const sb_tet_material* mat, double f[][3], double* energy);

/* The forces as above plus Rayleigh's stiffness-proportional damping
 * −β R K0 Rᵀ v (v the nodes' velocities); false when not finite. */
bool sb_tet_element_damped_forces(int nodes, const double p[][3], const double v[][3], const sb_tet_material* mat,
                                  double beta, double f[][3], double* energy);

/* The co-rotated stiffness R K0 Rᵀ, 3 nodes × 3 nodes row-major,
 * node-major; false when not finite. */
bool sb_tet_element_stiffness(int nodes, const double p[][3], const sb_tet_material* mat, double* k);

#endif
