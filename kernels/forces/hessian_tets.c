/* The co-rotated tetrahedron's stiffness (Müller & Gross 2004; computed by
 * kernels/forces/tet_element.h's sb_tet_element_stiffness): the element's
 * K0 turned by the element's rotation, R K0 Rᵀ, leaving out the derivative
 * of R (the standard co-rotated approximation). The quadratic element's is
 * the same with its ten shape functions (corotated_quadratic.h), summed
 * over its Gauss points.
 *
 * With g_a the gradient of the linear shape function of corner a
 * (g_{c+1} row c of D_m⁻¹, g_0 = −Σ g_{c+1}), F = Σ_a x_a g_aᵀ, and the
 * linear element's energy V (μ ε:ε + ½ λ (tr ε)²), ε = sym(F) − I, has
 * the blocks
 *     K0_ab = V (μ ((g_a·g_b) I + g_b g_aᵀ) + λ g_a g_bᵀ),
 * so R K0_ab Rᵀ = V (μ ((g_a·g_b) I + r_b r_aᵀ) + λ r_a r_bᵀ), r_a = R g_a.
 * It is symmetric (block ba is block ab transposed) and positive
 * semi-definite (its form is V (2μ ‖sym(Rᵀ δF)‖² + λ (tr Rᵀ δF)²), and
 * 3λ + 2μ > 0 for ν in (−1, ½)). For the linear element it is the
 * energy's exact Hessian at rest and at any rotation of the rest shape
 * (the energy is invariant under rotations, and there S = I); under strain
 * the left-out terms of dR/dx grow with the stress
 * (kernels/forces/hessian.h). For the quadratic one it is the Jacobian of
 * its forces f = −R K0 (Rᵀx − X) with R held. */
#include "kernels/forces/hessian_tets.h"
#include "kernels/forces/tet_element.h"

bool sb_tet_stiffness(const sb_model* m, uint32_t t, const sb_vec3* x, double* f, double* k) {
    int nodes = m->tet_nodes[t];
    double p[SB_TET_NODES][3], dm_inv[9], forces[SB_TET_NODES][3], energy;
    for (int c = 0; c < nodes; c++) {
        p[c][0] = x[c].x;
        p[c][1] = x[c].y;
        p[c][2] = x[c].z;
    }
    for (int q = 0; q < 9; q++) dm_inv[q] = m->tet_dm_inv[q][t];
    sb_tet_material mat = {dm_inv, m->tet_volume[t], m->tet_mu[t], m->tet_lambda[t]};
    if (f) {
        if (!sb_tet_element_forces(nodes, p, &mat, forces, &energy)) return false;
        for (int c = 0; c < nodes; c++)
            for (int q = 0; q < 3; q++) f[3 * c + q] = forces[c][q];
    }
    return !k || sb_tet_element_stiffness(nodes, p, &mat, k);
}
