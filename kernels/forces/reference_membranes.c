/* Scalar reference for a thin sheet's membranes: kernels/forces/membrane.h
 * per triangle, forces added in membrane order. */
#include "kernels/forces/reference_membranes.h"
#include "kernels/forces/membrane.h"
#include "common/error.h"

sb_status sb_reference_membranes(const sb_model* m, const double* x, double* f, double* energy, sb_error* err) {
    double total = 0.0;
    for (uint32_t t = 0; t < m->membrane_count; t++) {
        if (m->membrane_mu[t] == 0.0 && m->membrane_lambda[t] == 0.0) continue;
        double p[3][3], dm_inv[4], g[3][3], e;
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++) p[c][k] = x[3 * (size_t)m->membrane_v[c][t] + k];
        for (int k = 0; k < 4; k++) dm_inv[k] = m->membrane_dm_inv[k][t];
        if (!sb_membrane_triangle(p, dm_inv, m->membrane_volume[t], m->membrane_mu[t], m->membrane_lambda[t], g, &e))
            return sb_error_set(err, SB_ERR_DEGENERATE, "membrane %u (%u, %u, %u): the triangle collapsed", t,
                                m->membrane_v[0][t], m->membrane_v[1][t], m->membrane_v[2][t]);
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++) f[3 * (size_t)m->membrane_v[c][t] + k] += g[c][k];
        total += e;
    }
    *energy = total;
    return SB_OK;
}
