/* Scalar reference for the co-rotated tetrahedra, linear and quadratic:
 * kernels/forces/tet_element.h per element, its elastic forces and, where
 * the element has β > 0 and velocities are given, its stiffness-
 * proportional damping −β R K0 Rᵀ v, added in tetrahedron order. */
#include "kernels/forces/reference_tets.h"
#include "kernels/forces/tet_element.h"
#include "common/error.h"

/* The nodes' positions (or velocities) of tetrahedron t. */
static void sb_tet_nodes_at(const sb_model* m, uint32_t t, int nodes, const double* x, double p[][3]) {
    for (int c = 0; c < nodes; c++)
        for (int k = 0; k < 3; k++) p[c][k] = x[3 * (size_t)m->tet_v[c][t] + k];
}

/* The element's forces at x (and v), added to f; false when not finite. */
static bool sb_reference_tet(const sb_model* m, uint32_t t, const double* x, const double* v, double* f, double* e) {
    int nodes = m->tet_nodes[t];
    double p[SB_TET_NODES][3], dm_inv[9], g[SB_TET_NODES][3];
    sb_tet_nodes_at(m, t, nodes, x, p);
    for (int k = 0; k < 9; k++) dm_inv[k] = m->tet_dm_inv[k][t];
    sb_tet_material mat = {dm_inv, m->tet_volume[t], m->tet_mu[t], m->tet_lambda[t]};
    double beta = m->tet_beta[t];
    if (v && beta > 0.0) {
        double u[SB_TET_NODES][3];
        sb_tet_nodes_at(m, t, nodes, v, u);
        if (!sb_tet_element_damped_forces(nodes, p, u, &mat, beta, g, e)) return false;
    } else if (!sb_tet_element_forces(nodes, p, &mat, g, e)) {
        return false;
    }
    for (int c = 0; c < nodes; c++)
        for (int k = 0; k < 3; k++) f[3 * (size_t)m->tet_v[c][t] + k] += g[c][k];
    return true;
}

sb_status sb_reference_tets(const sb_model* m, const double* x, const double* v, double* f, double* energy,
                            sb_error* err) {
    double total = 0.0;
    for (uint32_t t = 0; t < m->tet_count; t++) {
        if (m->tet_mu[t] == 0.0 && m->tet_lambda[t] == 0.0) continue;
        double e;
        if (!sb_reference_tet(m, t, x, v, f, &e))
            return sb_error_set(err, SB_ERR_DEGENERATE, "tetrahedron %u (%u, %u, %u, %u): non-finite deformation", t,
                                m->tet_v[0][t], m->tet_v[1][t], m->tet_v[2][t], m->tet_v[3][t]);
        total += e;
    }
    *energy = total;
    return SB_OK;
}
