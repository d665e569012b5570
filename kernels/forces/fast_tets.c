/* Fast pass of the co-rotated tetrahedra, linear and quadratic, over a
 * color's slots, reading the packed sb_real positions (and velocities, for
 * an element with stiffness-proportional damping) and adding to the packed
 * forces.
 *
 * Lane-wise, for blocks of linear elements: SB_WIDTH tetrahedra at once in
 * sb_real over kernels/runtime/wide.h, the reference's formulas
 * (kernels/forces/corotated.h): F = D_s D_m⁻¹, R of F = R S by a
 * fixed-count Newton iteration (kernels/forces/wide_polar.h), the stress
 * P = 2μ (F − R) + λ (tr(RᵀF) − 3) R plus, with damping, β's viscous
 * stress of L = Ḟ Rᵀ pulled back by R, and the corners' forces −V X D_m⁻ᵀ
 * of their sum X, one scatter per corner. In float the corners are placed
 * about corner 0 with the carries (kernels/forces/fast_block.h), so F
 * comes from differences rounded to the element's size.
 *
 * Scalar, by the reference's element in double (kernels/forces/
 * tet_element.h), for a block that holds a quadratic element (10 nodes:
 * one element at a time, its polar decomposition by Jacobi sweeps), or a
 * lane whose rotation the iteration does not give as the reference does
 * (an inverted, flat or non-finite element: wide_polar.h), and for the
 * serial overflow color. The branch is per block, on the elements' own
 * data, so the answer does not depend on the thread count. The blocked
 * coloring (kernels/forces/fast_model.h) keeps threads apart and the
 * summation order fixed, as for the other passes; the padding slots past
 * a color's end are never written. */
#include "kernels/forces/fast_tets.h"
#include "kernels/forces/fast_block.h"
#include "kernels/forces/fast_hessian.h"
#include "kernels/forces/tet_element.h"
#include "kernels/forces/wide_polar.h"

/* Slot s's nodes: their vertices, positions and material; the node count. */
static int sb_fast_tet_at(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t s, uint32_t v[SB_TET_NODES],
                          double p[SB_TET_NODES][3], double dm_inv[9], sb_tet_material* mat) {
    int nodes = m->tet_nodes[s];
    for (int c = 0; c < nodes; c++) {
        v[c] = m->tet_v[c][s];
        for (int k = 0; k < 3; k++) p[c][k] = sb_fast_position(fr, v[c], k);
    }
    for (int k = 0; k < 9; k++) dm_inv[k] = m->tet_dm_inv[k][s];
    *mat = (sb_tet_material){dm_inv, m->tet_volume[s], m->tet_mu[s], m->tet_lambda[s]};
    return nodes;
}

/* The element's elastic forces, and its damping where it has β > 0; false
 * when not finite. */
static bool sb_fast_tet_forces(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t s, int nodes,
                               const uint32_t v[SB_TET_NODES], const double p[SB_TET_NODES][3],
                               const sb_tet_material* mat, double g[SB_TET_NODES][3], double* energy) {
    double beta = m->tet_beta[s];
    if (!(m->tet_damped && beta > 0.0)) return sb_tet_element_forces(nodes, p, mat, g, energy);
    double u[SB_TET_NODES][3];
    for (int c = 0; c < nodes; c++)
        for (int k = 0; k < 3; k++) u[c][k] = fr->velocities4[4 * (size_t)v[c] + k];
    return sb_tet_element_damped_forces(nodes, p, u, mat, beta, g, energy);
}

/* The slots [begin, end) one at a time by the reference's element; adds
 * their energy to *sum; false when one is not finite. */
static bool sb_fast_tets_scalar(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end,
                                double* sum) {
    bool finite = true;
    for (uint32_t s = begin; s < end; s++) {
        if (m->tet_mu[s] == 0.0 && m->tet_lambda[s] == 0.0) continue;
        double p[SB_TET_NODES][3], dm_inv[9], g[SB_TET_NODES][3], e;
        uint32_t v[SB_TET_NODES];
        sb_tet_material mat;
        int nodes = sb_fast_tet_at(m, fr, s, v, p, dm_inv, &mat);
        if (!sb_fast_tet_forces(m, fr, s, nodes, v, p, &mat, g, &e)) {
            finite = false; /* the reference names it (sb_report_collapse) */
            continue;
        }
        for (int c = 0; c < nodes; c++)
            for (int k = 0; k < 3; k++) fr->forces4[4 * (size_t)v[c] + k] += (sb_real)g[c][k];
        *sum += e;
    }
    return finite;
}

/* A block of linear elements, one per lane: D_m⁻¹ (row-major), V, μ, λ, β. */
typedef struct sb_wtet {
    sb_wide dm_inv[9], volume, mu, lambda, beta;
} sb_wtet;

static sb_wtet sb_wtet_load(const sb_fast_model* m, uint32_t s) {
    sb_wtet t;
    for (int k = 0; k < 9; k++) t.dm_inv[k] = sb_w_load(m->tet_lane_dm_inv[k] + s);
    t.volume = sb_w_load(m->tet_lane_volume + s);
    t.mu = sb_w_load(m->tet_lane_mu + s);
    t.lambda = sb_w_load(m->tet_lane_lambda + s);
    t.beta = sb_w_load(m->tet_lane_beta + s);
    return t;
}

/* F = D_s D_m⁻¹ of the corners' positions (or velocities: Ḟ), the edges
 * D_s's columns p_c − p_0. */
static void sb_w_deformation(const sb_wvec3 p[4], const sb_wide dm_inv[9], sb_wide F[9]) {
    sb_wvec3 e[3];
    for (int c = 0; c < 3; c++) e[c] = sb_wv_sub(p[c + 1], p[0]);
    for (int k = 0; k < 3; k++) {
        sb_wvec3 column = sb_wv_add(sb_wv_add(sb_wv_scale(e[0], dm_inv[k]), sb_wv_scale(e[1], dm_inv[3 + k])),
                                    sb_wv_scale(e[2], dm_inv[6 + k]));
        F[k] = column.x, F[3 + k] = column.y, F[6 + k] = column.z;
    }
}

/* The elastic stress P = 2μ (F − R) + λ (tr(RᵀF) − 3) R into X; returns
 * the energy density μ ‖F − R‖² + ½ λ (tr(RᵀF) − 3)². */
static sb_wide sb_w_elastic_stress(const sb_wide F[9], const sb_wide R[9], const sb_wtet* t, sb_wide X[9]) {
    sb_wide trace = sb_w_set(0), norm = sb_w_set(0), d[9];
    for (int k = 0; k < 9; k++) {
        d[k] = sb_w_sub(F[k], R[k]);
        trace = sb_w_add(trace, sb_w_mul(R[k], F[k]));
        norm = sb_w_add(norm, sb_w_mul(d[k], d[k]));
    }
    sb_wide volumetric = sb_w_sub(trace, sb_w_set(3)), two_mu = sb_w_add(t->mu, t->mu);
    sb_wide lt = sb_w_mul(t->lambda, volumetric);
    for (int k = 0; k < 9; k++) X[k] = sb_w_add(sb_w_mul(two_mu, d[k]), sb_w_mul(lt, R[k]));
    return sb_w_add(sb_w_mul(t->mu, norm), sb_w_mul(sb_w_mul(sb_w_set((sb_real)0.5), lt), volumetric));
}

/* Adds β (μ (L + Lᵀ) + λ tr(L) I) R, L = Ḟ Rᵀ, to X: Rayleigh's damping
 * −β R K0 Rᵀ v as a viscous stress (kernels/forces/corotated.c). */
static void sb_w_viscous_stress(const sb_wide Fdot[9], const sb_wide R[9], const sb_wtet* t, sb_wide X[9]) {
    sb_wide L[9], trace = sb_w_set(0);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            L[3 * i + j] = sb_wv_dot((sb_wvec3){Fdot[3 * i], Fdot[3 * i + 1], Fdot[3 * i + 2]},
                                     (sb_wvec3){R[3 * j], R[3 * j + 1], R[3 * j + 2]});
        trace = sb_w_add(trace, L[4 * i]);
    }
    sb_wide bmu = sb_w_mul(t->beta, t->mu), bl = sb_w_mul(sb_w_mul(t->beta, t->lambda), trace), sigma[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            sigma[3 * i + j] = sb_w_mul(bmu, sb_w_add(L[3 * i + j], L[3 * j + i]));
            if (i == j) sigma[3 * i + j] = sb_w_add(sigma[3 * i + j], bl);
        }
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            X[3 * i + k] =
                sb_w_add(X[3 * i + k], sb_wv_dot((sb_wvec3){sigma[3 * i], sigma[3 * i + 1], sigma[3 * i + 2]},
                                                 (sb_wvec3){R[k], R[3 + k], R[6 + k]}));
}

/* The corners' forces of the stress X: f_{c+1} = −V X g_c (g_c row c of
 * D_m⁻¹), f_0 = −Σ. */
static void sb_w_stress_forces(const sb_wide X[9], const sb_wtet* t, sb_wvec3 f[4]) {
    sb_wide scale = sb_w_sub(sb_w_set(0), t->volume);
    f[0] = (sb_wvec3){sb_w_set(0), sb_w_set(0), sb_w_set(0)};
    for (int c = 0; c < 3; c++) {
        sb_wvec3 g = {t->dm_inv[3 * c], t->dm_inv[3 * c + 1], t->dm_inv[3 * c + 2]};
        f[c + 1] = sb_wv_scale((sb_wvec3){sb_wv_dot((sb_wvec3){X[0], X[1], X[2]}, g),
                                          sb_wv_dot((sb_wvec3){X[3], X[4], X[5]}, g),
                                          sb_wv_dot((sb_wvec3){X[6], X[7], X[8]}, g)},
                               scale);
        f[0] = sb_wv_sub(f[0], f[c + 1]);
    }
}

/* Whether the `count` slots from s are all linear elements. */
static bool sb_linear_block(const sb_fast_model* m, uint32_t s, int count) {
    for (int l = 0; l < count; l++)
        if (m->tet_nodes[s + l] != 4) return false;
    return true;
}

/* The block of `count` linear elements from slot s, lane-wise; adds its
 * energy to *sum. false, writing nothing, when a lane's rotation is not
 * the reference's (wide_polar.h) or its stress is not finite: the caller
 * then runs the block scalar, which reports what is not finite. */
static bool sb_fast_tets_wide(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t s, int count, sb_wide* sum) {
    sb_wtet t = sb_wtet_load(m, s);
    sb_worigin origin;
    sb_wvec3 p[4];
    p[0] = sb_wv_origin_at(fr, m->tet_v[0] + s, &origin);
    for (int c = 1; c < 4; c++) p[c] = sb_wv_vertex_at(fr, m->tet_v[c] + s, &origin);
    sb_wide F[9], R[9], X[9];
    sb_w_deformation(p, t.dm_inv, F);
    if (sb_w_any(sb_w_polar(F, R), count)) return false;
    sb_wide density = sb_w_elastic_stress(F, R, &t, X);
    if (m->tet_damped) {
        sb_wvec3 v[4];
        for (int c = 0; c < 4; c++) v[c] = sb_wv_load4_at(fr->velocities4, m->tet_v[c] + s);
        sb_wide Fdot[9];
        sb_w_deformation(v, t.dm_inv, Fdot);
        sb_w_viscous_stress(Fdot, R, &t, X);
    }
    if (sb_w_any(sb_w_not_finite(X, 9), count)) return false;
    sb_wvec3 f[4];
    sb_w_stress_forces(X, &t, f);
    for (int c = 0; c < 4; c++) sb_wv_add4_at(fr->forces4, m->tet_v[c] + s, f[c], count);
    *sum = sb_w_add(*sum, sb_w_keep(sb_w_mul(t.volume, density), count));
    return true;
}

int sb_fast_tets(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                 double energy[1]) {
    uint32_t step = sb_block_step(serial);
    sb_wide wide_sum = sb_w_set(0);
    double scalar_sum = 0.0;
    bool finite = true;
    for (uint32_t s = begin; s < end; s += step) {
        int count = sb_block_count(s, end, step);
        bool wide = !serial && sb_linear_block(m, s, count) && sb_fast_tets_wide(m, fr, s, count, &wide_sum);
        if (!wide) finite &= sb_fast_tets_scalar(m, fr, s, s + (uint32_t)count, &scalar_sum);
    }
    energy[0] += sb_w_sum(wide_sum, SB_WIDTH) + scalar_sum;
    return finite ? 0 : SB_KERNEL_COLLAPSED;
}

int sb_fast_tets_hessian(const sb_fast_model* m, const sb_fast_frame* base, uint32_t begin, uint32_t end, bool serial,
                         double* energy) {
    (void)serial, (void)energy;
    const sb_hessian_frame* fr = (const sb_hessian_frame*)base;
    for (uint32_t s = begin; s < end; s++) {
        if (m->tet_mu[s] == 0.0 && m->tet_lambda[s] == 0.0) continue;
        double p[SB_TET_NODES][3], dm_inv[9], k[SB_QUAD_DOFS * SB_QUAD_DOFS];
        uint32_t v[SB_TET_NODES];
        sb_tet_material mat;
        int nodes = sb_fast_tet_at(m, base, s, v, p, dm_inv, &mat), size = 3 * nodes;
        if (!sb_tet_element_stiffness(nodes, p, &mat, k)) continue;
        double weight = fr->scale * (1.0 + (double)fr->damping * m->tet_beta[s]); /* K + damping D, D = β K */
        if (base->velocities4) { /* the product: the forces' pass reports what is not finite */
            double d[SB_QUAD_DOFS];
            for (int c = 0; c < nodes; c++)
                for (int q = 0; q < 3; q++) d[3 * c + q] = base->velocities4[4 * (size_t)v[c] + q];
            for (int r = 0; r < size; r++) {
                double sum = 0.0;
                for (int c = 0; c < size; c++) sum += k[size * r + c] * d[c];
                base->forces4[4 * (size_t)v[r / 3] + r % 3] += (sb_real)(weight * sum);
            }
            continue;
        }
        for (int a = 0; a < nodes; a++) { /* the upper triangle xx xy xz yy yz zz */
            sb_real* block = fr->blocks + SB_BLOCK_STRIDE * (size_t)v[a];
            static const int rows[SB_BLOCK_SIZE] = {0, 0, 0, 1, 1, 2}, cols[SB_BLOCK_SIZE] = {0, 1, 2, 1, 2, 2};
            for (int q = 0; q < SB_BLOCK_SIZE; q++)
                block[sb_block_offset[q]] += (sb_real)(weight * k[(3 * a + rows[q]) * size + 3 * a + cols[q]]);
        }
    }
    return 0;
}
