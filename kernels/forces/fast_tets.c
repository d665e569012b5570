/* Fast pass of the co-rotated tetrahedra: the reference's element
 * (kernels/forces/corotated.c, in double) one tetrahedron at a time over a
 * color's slots, reading the packed sb_real positions (and velocities, for
 * a model with stiffness-proportional damping) and adding to the packed
 * forces. Scalar: the polar decomposition's Jacobi sweeps branch per
 * element, and a lane-wise version over kernels/runtime/wide.h is not
 * written yet. The blocked coloring (kernels/forces/fast_model.h) keeps
 * threads apart and the summation order fixed, as for the other passes;
 * the padding slots past a color's end are never run. */
#include "kernels/forces/fast_tets.h"
#include "kernels/forces/fast_hessian.h"
#include "kernels/forces/corotated.h"

/* The corners of slot s in a packed array, in double. */
static void sb_fast_tet_corners(const sb_fast_model* m, uint32_t s, const sb_real* packed, double p[4][3]) {
    for (int c = 0; c < 4; c++)
        for (int k = 0; k < 3; k++) p[c][k] = packed[4 * (size_t)m->tet_v[c][s] + k];
}

/* The element's elastic (and damping) forces, added to the packed ones;
 * false when not finite. */
static bool sb_fast_tet(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t s, double* energy) {
    double p[4][3], dm_inv[9], g[4][3];
    sb_fast_tet_corners(m, s, fr->positions4, p);
    for (int k = 0; k < 9; k++) dm_inv[k] = m->tet_dm_inv[k][s];
    double volume = m->tet_volume[s], mu = m->tet_mu[s], lambda = m->tet_lambda[s], beta = m->tet_beta[s];
    if (m->tet_damped && beta > 0.0) {
        double u[4][3];
        sb_fast_tet_corners(m, s, fr->velocities4, u);
        if (!sb_corotated_tet_damped(p, u, dm_inv, volume, mu, lambda, beta, g, energy)) return false;
    } else if (!sb_corotated_tet(p, dm_inv, volume, mu, lambda, g, energy)) {
        return false;
    }
    for (int c = 0; c < 4; c++)
        for (int k = 0; k < 3; k++) fr->forces4[4 * (size_t)m->tet_v[c][s] + k] += (sb_real)g[c][k];
    return true;
}

int sb_fast_tets(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                 double energy[1]) {
    (void)serial; /* one element at a time either way */
    double sum = 0.0;
    bool bad = false;
    for (uint32_t s = begin; s < end; s++) {
        if (m->tet_mu[s] == 0.0 && m->tet_lambda[s] == 0.0) continue;
        double e;
        if (!sb_fast_tet(m, fr, s, &e)) {
            bad = true; /* the reference names it (sb_report_collapse) */
            continue;
        }
        sum += e;
    }
    energy[0] += sum;
    return bad ? SB_KERNEL_COLLAPSED : 0;
}

int sb_fast_tets_hessian(const sb_fast_model* m, const sb_fast_frame* base, uint32_t begin, uint32_t end, bool serial,
                         double* energy) {
    (void)serial, (void)energy;
    const sb_hessian_frame* fr = (const sb_hessian_frame*)base;
    for (uint32_t s = begin; s < end; s++) {
        if (m->tet_mu[s] == 0.0 && m->tet_lambda[s] == 0.0) continue;
        double p[4][3], dm_inv[9], k[144];
        uint32_t v[4];
        for (int c = 0; c < 4; c++) {
            v[c] = m->tet_v[c][s];
            for (int q = 0; q < 3; q++) p[c][q] = base->positions4[4 * (size_t)v[c] + q];
        }
        for (int q = 0; q < 9; q++) dm_inv[q] = m->tet_dm_inv[q][s];
        if (!sb_corotated_stiffness(p, dm_inv, m->tet_volume[s], m->tet_mu[s], m->tet_lambda[s], k)) continue;
        double weight = fr->scale * (1.0 + (double)fr->damping * m->tet_beta[s]); /* K + damping D, D = β K */
        if (base->velocities4) { /* the product: the forces' pass reports what is not finite */
            double d[12];
            for (int c = 0; c < 4; c++)
                for (int q = 0; q < 3; q++) d[3 * c + q] = base->velocities4[4 * (size_t)v[c] + q];
            for (int r = 0; r < 12; r++) {
                double sum = 0.0;
                for (int c = 0; c < 12; c++) sum += k[12 * r + c] * d[c];
                base->forces4[4 * (size_t)v[r / 3] + r % 3] += (sb_real)(weight * sum);
            }
            continue;
        }
        for (int a = 0; a < 4; a++) { /* the upper triangle xx xy xz yy yz zz */
            sb_real* block = fr->blocks + SB_BLOCK_STRIDE * (size_t)v[a];
            static const int rows[SB_BLOCK_SIZE] = {0, 0, 0, 1, 1, 2}, cols[SB_BLOCK_SIZE] = {0, 1, 2, 1, 2, 2};
            for (int q = 0; q < SB_BLOCK_SIZE; q++)
                block[sb_block_offset[q]] += (sb_real)(weight * k[(3 * a + rows[q]) * 12 + 3 * a + cols[q]]);
        }
    }
    return 0;
}
