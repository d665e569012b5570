/* A co-rotated tetrahedron of either order: see tet_element.h. */
#include "kernels/forces/tet_element.h"
#include "kernels/forces/corotated.h"

bool sb_tet_element_forces(int nodes, const double p[][3], const sb_tet_material* mat, double f[][3], double* energy) {
    if (nodes == SB_QUAD_NODES)
        return sb_corotated_quadratic_tet(p, mat->dm_inv, mat->volume, mat->mu, mat->lambda, f, energy);
    return sb_corotated_tet(p, mat->dm_inv, mat->volume, mat->mu, mat->lambda, f, energy);
}

bool sb_tet_element_damped_forces(int nodes, const double p[][3], const double v[][3], const sb_tet_material* mat,
                                  double beta, double f[][3], double* energy) {
    if (nodes == SB_QUAD_NODES)
        return sb_corotated_quadratic_tet_damped(p, v, mat->dm_inv, mat->volume, mat->mu, mat->lambda, beta, f, energy);
    return sb_corotated_tet_damped(p, v, mat->dm_inv, mat->volume, mat->mu, mat->lambda, beta, f, energy);
}

bool sb_tet_element_stiffness(int nodes, const double p[][3], const sb_tet_material* mat, double* k) {
    if (nodes == SB_QUAD_NODES)
        return sb_corotated_quadratic_stiffness(p, mat->dm_inv, mat->volume, mat->mu, mat->lambda, k);
    return sb_corotated_stiffness(p, mat->dm_inv, mat->volume, mat->mu, mat->lambda, k);
}
