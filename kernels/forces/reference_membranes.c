/* Scalar reference for a thin sheet's membranes: kernels/forces/membrane.h
 * per triangle, with its stiffness-proportional damping where it has β > 0
 * and velocities are given, forces added in membrane order. */
#include "kernels/forces/reference_membranes.h"
#include "kernels/forces/membrane.h"
#include "common/error.h"

/* Corner c's position (or velocity) of membrane t. */
static void sb_membrane_corners(const sb_model* m, uint32_t t, const double* x, double p[3][3]) {
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++) p[c][k] = x[3 * (size_t)m->membrane_v[c][t] + k];
}

/* Membrane t's forces into g (damped where it has β and v is given). */
static bool sb_reference_membrane(const sb_model* m, uint32_t t, const double* x, const double* v, double g[3][3],
                                  double* e) {
    double p[3][3], dm_inv[4], beta = m->membrane_beta[t];
    sb_membrane_corners(m, t, x, p);
    for (int k = 0; k < 4; k++) dm_inv[k] = m->membrane_dm_inv[k][t];
    double volume = m->membrane_volume[t], mu = m->membrane_mu[t], lambda = m->membrane_lambda[t];
    if (!(v && beta > 0.0)) return sb_membrane_triangle(p, dm_inv, volume, mu, lambda, g, e);
    double u[3][3];
    sb_membrane_corners(m, t, v, u);
    return sb_membrane_triangle_damped(p, u, dm_inv, volume, mu, lambda, beta, g, e);
}

sb_status sb_reference_membranes(const sb_model* m, const double* x, const double* v, double* f, double* energy,
                                 sb_error* err) {
    double total = 0.0;
    for (uint32_t t = 0; t < m->membrane_count; t++) {
        if (m->membrane_mu[t] == 0.0 && m->membrane_lambda[t] == 0.0) continue;
        double g[3][3], e;
        if (!sb_reference_membrane(m, t, x, v, g, &e))
            return sb_error_set(err, SB_ERR_DEGENERATE, "membrane %u (%u, %u, %u): the triangle collapsed", t,
                                m->membrane_v[0][t], m->membrane_v[1][t], m->membrane_v[2][t]);
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++) f[3 * (size_t)m->membrane_v[c][t] + k] += g[c][k];
        total += e;
    }
    *energy = total;
    return SB_OK;
}
