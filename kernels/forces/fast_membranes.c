/* Fast pass of a sheet's membranes (and a flat sheet's plates, below),
 * over a color's slots, reading the packed sb_real positions (and velocities, for a triangle with
 * stiffness-proportional damping) and adding to the packed forces.
 *
 * Lane-wise: SB_WIDTH triangles at once in sb_real over
 * kernels/runtime/wide.h, the reference's formulas (kernels/forces/
 * membrane.c): F = D_s D_m⁻¹ (3 × 2), S = √(FᵀF) in closed form and
 * R = F S⁻¹, the stress P = 2μ (F − R) + λ (tr S − 2) R plus, with
 * damping, β R (μ (M + Mᵀ) + λ tr(M) I), M = Rᵀ Ḟ, and the corners'
 * forces −V P D_m⁻ᵀ, one scatter per corner; no iteration, no branch per
 * lane. In float the corners are placed about corner 0 with the carries
 * (kernels/forces/fast_block.h).
 *
 * Scalar, by the reference's element in double, for a block with a lane
 * whose det FᵀF is below ε (tr FᵀF)² (ε of sb_real: a triangle nearly
 * collapsed, where sb_real's rounding of F could hide the collapse the
 * reference reports) or whose stress is not finite, and for the serial
 * overflow color. The branch is per block, on the elements' own data, so
 * the answer does not depend on the thread count. The blocked coloring
 * (kernels/forces/fast_model.h) keeps threads apart and the summation order
 * fixed; the padding slots past a color's end are never written.
 *
 * The plates (kernels/forces/plate.c: a flat sheet's bending with ν) run
 * by the reference's element in double, one slot at a time after the
 * block's membranes: a slot runs its triangle's plate, and the coloring saw
 * the plate's stencil. */
#include "kernels/forces/fast_membranes.h"
#include "kernels/forces/fast_block.h"
#include "kernels/forces/fast_hessian.h"
#include "kernels/forces/membrane.h"
#include "kernels/forces/plate.h"

/* Slot s's corners v[3], their positions p and D_m⁻¹: false for an
 * element without stiffness. */
static bool sb_membrane_slot(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t s, uint32_t v[3], double p[3][3],
                             double dm_inv[4]) {
    if (m->membrane_mu[s] == 0.0 && m->membrane_lambda[s] == 0.0) return false;
    for (int c = 0; c < 3; c++) {
        v[c] = m->membrane_v[c][s];
        for (int k = 0; k < 3; k++) p[c][k] = sb_fast_position(fr, v[c], k);
    }
    for (int k = 0; k < 4; k++) dm_inv[k] = m->membrane_dm_inv[k][s];
    return true;
}

/* The triangle's forces, damped where it has β > 0; false when not
 * finite. */
static bool sb_fast_membrane_forces(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t s, const uint32_t v[3],
                                    const double p[3][3], const double dm_inv[4], double g[3][3], double* energy) {
    double volume = m->membrane_volume[s], mu = m->membrane_mu[s], lambda = m->membrane_lambda[s];
    double beta = m->membrane_beta[s];
    if (!(m->membrane_damped && beta > 0.0)) return sb_membrane_triangle(p, dm_inv, volume, mu, lambda, g, energy);
    double u[3][3];
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++) u[c][k] = fr->velocities4[4 * (size_t)v[c] + k];
    return sb_membrane_triangle_damped(p, u, dm_inv, volume, mu, lambda, beta, g, energy);
}

/* The slots [begin, end) one at a time by the reference's element; adds
 * their energy to *sum; false when one collapsed or is not finite. */
static bool sb_fast_membranes_scalar(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end,
                                     double* sum) {
    bool finite = true;
    for (uint32_t s = begin; s < end; s++) {
        double p[3][3], dm_inv[4], g[3][3], e;
        uint32_t v[3];
        if (!sb_membrane_slot(m, fr, s, v, p, dm_inv)) continue;
        if (!sb_fast_membrane_forces(m, fr, s, v, p, dm_inv, g, &e)) {
            finite = false; /* the reference names it (sb_report_collapse) */
            continue;
        }
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++) fr->forces4[4 * (size_t)v[c] + k] += (sb_real)g[c][k];
        *sum += e;
    }
    return finite;
}

/* A block of triangles, one per lane: D_m⁻¹ (2 × 2 row-major), V, μ, λ, β. */
typedef struct sb_wmembrane {
    sb_wide dm_inv[4], volume, mu, lambda, beta;
} sb_wmembrane;

static sb_wmembrane sb_wmembrane_load(const sb_fast_model* m, uint32_t s) {
    sb_wmembrane t;
    for (int k = 0; k < 4; k++) t.dm_inv[k] = sb_w_load(m->membrane_lane_dm_inv[k] + s);
    t.volume = sb_w_load(m->membrane_lane_volume + s);
    t.mu = sb_w_load(m->membrane_lane_mu + s);
    t.lambda = sb_w_load(m->membrane_lane_lambda + s);
    t.beta = sb_w_load(m->membrane_lane_beta + s);
    return t;
}

/* F = D_s D_m⁻¹ (3 × 2: its columns) of the corners' positions (or
 * velocities: Ḟ). */
static void sb_w_plane_deformation(const sb_wvec3 p[3], const sb_wide dm_inv[4], sb_wvec3 F[2]) {
    sb_wvec3 e1 = sb_wv_sub(p[1], p[0]), e2 = sb_wv_sub(p[2], p[0]);
    for (int k = 0; k < 2; k++) F[k] = sb_wv_add(sb_wv_scale(e1, dm_inv[k]), sb_wv_scale(e2, dm_inv[2 + k]));
}

/* R = F S⁻¹ (its columns) and tr S, S = √(FᵀF) = (C + √det C I) / √(tr C +
 * 2 √det C); the lanes nearly collapsed, as the file's note says. */
static sb_wmask sb_w_plane_rotation(const sb_wvec3 F[2], sb_wvec3 R[2], sb_wide* trace_s) {
    sb_wide c00 = sb_wv_dot(F[0], F[0]), c01 = sb_wv_dot(F[0], F[1]), c11 = sb_wv_dot(F[1], F[1]);
    sb_wvec3 normal = sb_wv_cross(F[0], F[1]); /* det C = |F₀ × F₁|², without c00 c11 − c01²'s cancellation */
    sb_wide det = sb_wv_dot(normal, normal), trace = sb_w_add(c00, c11);
    const sb_real epsilon = SB_DOUBLE ? (sb_real)DBL_EPSILON : (sb_real)FLT_EPSILON;
    sb_wmask collapsed = sb_w_less(det, sb_w_mul(sb_w_set(epsilon), sb_w_mul(trace, trace)));
    sb_wide root = sb_w_sqrt(det), scale = sb_w_rsqrt(sb_w_add(trace, sb_w_add(root, root)));
    sb_wide s00 = sb_w_mul(sb_w_add(c00, root), scale), s01 = sb_w_mul(c01, scale);
    sb_wide s11 = sb_w_mul(sb_w_add(c11, root), scale);
    sb_wide inverse_det = sb_w_div(sb_w_set(1), sb_w_sub(sb_w_mul(s00, s11), sb_w_mul(s01, s01)));
    sb_wide i00 = sb_w_mul(s11, inverse_det), i01 = sb_w_mul(sb_w_sub(sb_w_set(0), s01), inverse_det);
    sb_wide i11 = sb_w_mul(s00, inverse_det);
    R[0] = sb_wv_add(sb_wv_scale(F[0], i00), sb_wv_scale(F[1], i01));
    R[1] = sb_wv_add(sb_wv_scale(F[0], i01), sb_wv_scale(F[1], i11));
    *trace_s = sb_w_add(s00, s11);
    return collapsed;
}

/* Adds β R (μ (M + Mᵀ) + λ tr(M) I), M = Rᵀ Ḟ, to P's columns. */
static void sb_w_plane_viscous(const sb_wvec3 Fdot[2], const sb_wvec3 R[2], const sb_wmembrane* t, sb_wvec3 P[2]) {
    sb_wide m00 = sb_wv_dot(R[0], Fdot[0]), m01 = sb_wv_dot(R[0], Fdot[1]);
    sb_wide m10 = sb_wv_dot(R[1], Fdot[0]), m11 = sb_wv_dot(R[1], Fdot[1]);
    sb_wide bmu = sb_w_mul(t->beta, t->mu), bl = sb_w_mul(sb_w_mul(t->beta, t->lambda), sb_w_add(m00, m11));
    sb_wide s00 = sb_w_add(sb_w_mul(bmu, sb_w_add(m00, m00)), bl),
            s11 = sb_w_add(sb_w_mul(bmu, sb_w_add(m11, m11)), bl);
    sb_wide s01 = sb_w_mul(bmu, sb_w_add(m01, m10));
    P[0] = sb_wv_add(P[0], sb_wv_add(sb_wv_scale(R[0], s00), sb_wv_scale(R[1], s01)));
    P[1] = sb_wv_add(P[1], sb_wv_add(sb_wv_scale(R[0], s01), sb_wv_scale(R[1], s11)));
}

/* The block of `count` triangles from slot s, lane-wise; adds its energy to
 * *sum. false, writing nothing, when a lane nearly collapsed or its stress
 * is not finite: the caller then runs the block scalar. */
static bool sb_fast_membranes_wide(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t s, int count,
                                   sb_wide* sum) {
    sb_wmembrane t = sb_wmembrane_load(m, s);
    sb_worigin origin;
    sb_wvec3 p[3], F[2], R[2], P[2];
    p[0] = sb_wv_origin_at(fr, m->membrane_v[0] + s, &origin);
    for (int c = 1; c < 3; c++) p[c] = sb_wv_vertex_at(fr, m->membrane_v[c] + s, &origin);
    sb_w_plane_deformation(p, t.dm_inv, F);
    sb_wide trace_s;
    if (sb_w_any(sb_w_plane_rotation(F, R, &trace_s), count)) return false;
    sb_wide dilation = sb_w_sub(trace_s, sb_w_set(2)), two_mu = sb_w_add(t.mu, t.mu);
    sb_wide ld = sb_w_mul(t.lambda, dilation), norm = sb_w_set(0);
    for (int k = 0; k < 2; k++) {
        sb_wvec3 d = sb_wv_sub(F[k], R[k]);
        norm = sb_w_add(norm, sb_wv_dot(d, d));
        P[k] = sb_wv_add(sb_wv_scale(d, two_mu), sb_wv_scale(R[k], ld));
    }
    if (m->membrane_damped) {
        sb_wvec3 v[3], Fdot[2];
        for (int c = 0; c < 3; c++) v[c] = sb_wv_load4_at(fr->velocities4, m->membrane_v[c] + s);
        sb_w_plane_deformation(v, t.dm_inv, Fdot);
        sb_w_plane_viscous(Fdot, R, &t, P);
    }
    const sb_wide entries[6] = {P[0].x, P[0].y, P[0].z, P[1].x, P[1].y, P[1].z};
    if (sb_w_any(sb_w_not_finite(entries, 6), count)) return false;
    sb_wide scale = sb_w_sub(sb_w_set(0), t.volume);
    sb_wvec3 f1 = sb_wv_scale(sb_wv_add(sb_wv_scale(P[0], t.dm_inv[0]), sb_wv_scale(P[1], t.dm_inv[1])), scale);
    sb_wvec3 f2 = sb_wv_scale(sb_wv_add(sb_wv_scale(P[0], t.dm_inv[2]), sb_wv_scale(P[1], t.dm_inv[3])), scale);
    sb_wv_add4_at(fr->forces4, m->membrane_v[0] + s, sb_wv_neg(sb_wv_add(f1, f2)), count);
    sb_wv_add4_at(fr->forces4, m->membrane_v[1] + s, f1, count);
    sb_wv_add4_at(fr->forces4, m->membrane_v[2] + s, f2, count);
    sb_wide density = sb_w_add(sb_w_mul(t.mu, norm), sb_w_mul(sb_w_mul(sb_w_set((sb_real)0.5), ld), dilation));
    *sum = sb_w_add(*sum, sb_w_keep(sb_w_mul(t.volume, density), count));
    return true;
}

/* The plate of slot s's membrane, if any: its stencil's vertices v, their
 * positions x; its count (0: none). */
static int sb_plate_slot(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t s, uint32_t* v, sb_vec3* x) {
    const sb_model* model = m->plate_model;
    if (!model) return 0;
    uint32_t t = m->membranes.source[s];
    int count = model->plate_nodes[t];
    for (int a = 0; a < count; a++) {
        v[a] = model->plate_v[SB_PLATE_NODES * (size_t)t + (size_t)a];
        x[a] = (sb_vec3){sb_fast_position(fr, v[a], 0), sb_fast_position(fr, v[a], 1), sb_fast_position(fr, v[a], 2)};
    }
    return count;
}

/* Slot s's plate's forces added; its energy. */
static double sb_fast_plate(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t s) {
    uint32_t v[SB_PLATE_NODES];
    sb_vec3 x[SB_PLATE_NODES];
    double g[3 * SB_PLATE_NODES];
    int count = sb_plate_slot(m, fr, s, v, x);
    if (!count) return 0.0;
    double e = sb_plate_element(m->plate_model, m->membranes.source[s], x, g, NULL);
    for (int a = 0; a < count; a++)
        for (int k = 0; k < 3; k++) fr->forces4[4 * (size_t)v[a] + k] += (sb_real)g[3 * a + k];
    return e;
}

int sb_fast_membranes(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                      double energy[2]) {
    uint32_t step = sb_block_step(serial);
    sb_wide wide_sum = sb_w_set(0);
    double scalar_sum = 0.0, bend = 0.0;
    bool finite = true;
    for (uint32_t s = begin; s < end; s += step) {
        int count = sb_block_count(s, end, step);
        if (serial || !sb_fast_membranes_wide(m, fr, s, count, &wide_sum))
            finite &= sb_fast_membranes_scalar(m, fr, s, s + (uint32_t)count, &scalar_sum);
        for (uint32_t t = s; m->plate_model && t < s + (uint32_t)count; t++) bend += sb_fast_plate(m, fr, t);
    }
    energy[0] += sb_w_sum(wide_sum, SB_WIDTH) + scalar_sum;
    energy[1] += bend;
    return finite ? 0 : SB_KERNEL_COLLAPSED;
}

/* Slot s's plate's share of the product (velocities4 the direction) or of
 * the diagonal blocks: its constant H ⊗ I₃ times the frame's scale. */
static void sb_fast_plate_hessian(const sb_fast_model* m, const sb_hessian_frame* fr, uint32_t s) {
    const sb_fast_frame* base = &fr->base;
    uint32_t v[SB_PLATE_NODES];
    sb_vec3 x[SB_PLATE_NODES];
    double k[9 * SB_PLATE_NODES * SB_PLATE_NODES];
    int count = sb_plate_slot(m, base, s, v, x), size = 3 * count;
    if (!count) return;
    sb_plate_element(m->plate_model, m->membranes.source[s], x, NULL, k);
    double weight = fr->scale;
    for (int a = 0; a < count; a++)
        for (int i = 0; i < 3; i++) {
            int r = 3 * a + i;
            if (base->velocities4) { /* the product */
                double sum = 0.0;
                for (int b = 0; b < count; b++)
                    sum += k[r * size + 3 * b + i] * base->velocities4[4 * (size_t)v[b] + i];
                base->forces4[4 * (size_t)v[a] + i] += (sb_real)(weight * sum);
            } else { /* the diagonal block, a multiple of I₃: xx, yy, zz */
                static const int diagonal[3] = {0, 3, 5};
                fr->blocks[SB_BLOCK_STRIDE * (size_t)v[a] + sb_block_offset[diagonal[i]]] +=
                    (sb_real)(weight * k[r * size + r]);
            }
        }
}

int sb_fast_membranes_hessian(const sb_fast_model* m, const sb_fast_frame* base, uint32_t begin, uint32_t end,
                              bool serial, double* energy) {
    (void)serial, (void)energy;
    const sb_hessian_frame* fr = (const sb_hessian_frame*)base;
    for (uint32_t s = begin; s < end; s++) {
        sb_fast_plate_hessian(m, fr, s);
        double p[3][3], dm_inv[4], k[81];
        uint32_t v[3];
        if (!sb_membrane_slot(m, base, s, v, p, dm_inv)) continue;
        if (!sb_membrane_stiffness(p, dm_inv, m->membrane_volume[s], m->membrane_mu[s], m->membrane_lambda[s], k))
            continue; /* the forces' pass reports it */
        /* K + damping D, D = β K */
        double weight = fr->scale * (1.0 + (double)fr->damping * m->membrane_beta[s]);
        if (base->velocities4) { /* the product */
            double d[9];
            for (int c = 0; c < 3; c++)
                for (int q = 0; q < 3; q++) d[3 * c + q] = base->velocities4[4 * (size_t)v[c] + q];
            for (int r = 0; r < 9; r++) {
                double sum = 0.0;
                for (int c = 0; c < 9; c++) sum += k[9 * r + c] * d[c];
                base->forces4[4 * (size_t)v[r / 3] + r % 3] += (sb_real)(weight * sum);
            }
            continue;
        }
        for (int a = 0; a < 3; a++) { /* the upper triangle xx xy xz yy yz zz */
            sb_real* block = fr->blocks + SB_BLOCK_STRIDE * (size_t)v[a];
            static const int rows[SB_BLOCK_SIZE] = {0, 0, 0, 1, 1, 2}, cols[SB_BLOCK_SIZE] = {0, 1, 2, 1, 2, 2};
            for (int q = 0; q < SB_BLOCK_SIZE; q++)
                block[sb_block_offset[q]] += (sb_real)(weight * k[(3 * a + rows[q]) * 9 + 3 * a + cols[q]]);
        }
    }
    return 0;
}
