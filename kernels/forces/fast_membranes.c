/* Fast pass of a sheet's membranes and a flat sheet's plates: the
 * reference's elements (kernels/forces/membrane.c and plate.c, in double)
 * one triangle at a time over a color's slots (a slot runs its plate and
 * its membrane: the coloring saw the plate's stencil), reading the packed
 * sb_real positions (and velocities, for a triangle with
 * stiffness-proportional damping) and adding to the packed forces, as the
 * tetrahedra's pass does (kernels/forces/fast_tets.c). Scalar: a lane-wise
 * element over kernels/runtime/wide.h is not written. The blocked coloring
 * (kernels/forces/fast_model.h) keeps threads apart and the summation
 * order fixed; the padding slots past a color's end are never run. */
#include "kernels/forces/fast_membranes.h"
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
    (void)serial; /* one element at a time either way */
    double sum = 0.0, bend = 0.0;
    bool bad = false;
    for (uint32_t s = begin; s < end; s++) {
        bend += sb_fast_plate(m, fr, s);
        double p[3][3], dm_inv[4], g[3][3], e;
        uint32_t v[3];
        if (!sb_membrane_slot(m, fr, s, v, p, dm_inv)) continue;
        if (!sb_fast_membrane_forces(m, fr, s, v, p, dm_inv, g, &e)) {
            bad = true; /* the reference names it (sb_report_collapse) */
            continue;
        }
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++) fr->forces4[4 * (size_t)v[c] + k] += (sb_real)g[c][k];
        sum += e;
    }
    energy[0] += sum;
    energy[1] += bend;
    return bad ? SB_KERNEL_COLLAPSED : 0;
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
