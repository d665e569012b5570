/* Scalar reference for the co-rotated tetrahedra: kernels/forces/corotated.h
 * per element, its elastic forces and, where the model has β > 0 and
 * velocities are given, its stiffness-proportional damping, added in
 * tetrahedron order. */
#include "kernels/forces/reference_tets.h"
#include "kernels/forces/corotated.h"
#include "common/error.h"

/* The corners' positions (or velocities) of tetrahedron t. */
static void sb_tet_corners(const sb_model* m, uint32_t t, const double* x, double p[4][3]) {
    for (int c = 0; c < 4; c++)
        for (int k = 0; k < 3; k++) p[c][k] = x[3 * (size_t)m->tet_v[c][t] + k];
}

static void sb_tet_add(const sb_model* m, uint32_t t, const double g[4][3], double* f) {
    for (int c = 0; c < 4; c++)
        for (int k = 0; k < 3; k++) f[3 * (size_t)m->tet_v[c][t] + k] += g[c][k];
}

/* The element's forces at x (and v), added to f; false when not finite. */
static bool sb_reference_tet(const sb_model* m, uint32_t t, const double* x, const double* v, double* f, double* e) {
    double p[4][3], dm_inv[9], g[4][3];
    sb_tet_corners(m, t, x, p);
    for (int k = 0; k < 9; k++) dm_inv[k] = m->tet_dm_inv[k][t];
    double volume = m->tet_volume[t], mu = m->tet_mu[t], lambda = m->tet_lambda[t], beta = m->tet_beta[t];
    if (v && beta > 0.0) {
        double u[4][3];
        sb_tet_corners(m, t, v, u);
        if (!sb_corotated_tet_damped(p, u, dm_inv, volume, mu, lambda, beta, g, e)) return false;
    } else if (!sb_corotated_tet(p, dm_inv, volume, mu, lambda, g, e)) {
        return false;
    }
    sb_tet_add(m, t, g, f);
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
