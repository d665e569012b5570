/* Fast pass of the co-rotated tetrahedra, linear and quadratic: the
 * reference's element (kernels/forces/tet_element.h, in double) one
 * tetrahedron at a time over a color's slots, reading the packed sb_real
 * positions (and velocities, for an element with stiffness-proportional
 * damping, kernels/forces/tet_element.h) and adding to the packed forces. Scalar: the polar
 * decomposition's Jacobi sweeps branch per element, and a lane-wise version
 * over kernels/runtime/wide.h is not written yet. The blocked coloring
 * (kernels/forces/fast_model.h) keeps threads apart and the summation order
 * fixed, as for the other passes; the padding slots past a color's end are
 * never run. */
#include "kernels/forces/fast_tets.h"
#include "kernels/forces/fast_hessian.h"
#include "kernels/forces/tet_element.h"

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

int sb_fast_tets(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                 double energy[1]) {
    (void)serial; /* one element at a time either way */
    double sum = 0.0;
    bool bad = false;
    for (uint32_t s = begin; s < end; s++) {
        if (m->tet_mu[s] == 0.0 && m->tet_lambda[s] == 0.0) continue;
        double p[SB_TET_NODES][3], dm_inv[9], g[SB_TET_NODES][3], e;
        uint32_t v[SB_TET_NODES];
        sb_tet_material mat;
        int nodes = sb_fast_tet_at(m, fr, s, v, p, dm_inv, &mat);
        if (!sb_fast_tet_forces(m, fr, s, nodes, v, p, &mat, g, &e)) {
            bad = true; /* the reference names it (sb_report_collapse) */
            continue;
        }
        for (int c = 0; c < nodes; c++)
            for (int k = 0; k < 3; k++) fr->forces4[4 * (size_t)v[c] + k] += (sb_real)g[c][k];
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
