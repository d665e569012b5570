/* Fast pass of the co-rotated tetrahedra: the reference's element
 * (kernels/forces/corotated.c, in double) one tetrahedron at a time over a
 * color's slots, reading the packed sb_real positions and adding to the
 * packed forces. Scalar: the polar decomposition's Jacobi sweeps branch per
 * element, and a lane-wise version over kernels/runtime/wide.h is not
 * written yet. The blocked coloring (kernels/forces/fast_model.h) keeps
 * threads apart and the summation order fixed, as for the other passes;
 * the padding slots past a color's end are never run. */
#include "kernels/forces/fast_tets.h"
#include "kernels/forces/corotated.h"

int sb_fast_tets(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                 double energy[1]) {
    (void)serial; /* one element at a time either way */
    double sum = 0.0;
    bool bad = false;
    for (uint32_t s = begin; s < end; s++) {
        if (m->tet_mu[s] == 0.0 && m->tet_lambda[s] == 0.0) continue;
        double p[4][3], dm_inv[9], g[4][3], e;
        uint32_t v[4];
        for (int c = 0; c < 4; c++) {
            v[c] = m->tet_v[c][s];
            for (int k = 0; k < 3; k++) p[c][k] = fr->positions4[4 * (size_t)v[c] + k];
        }
        for (int k = 0; k < 9; k++) dm_inv[k] = m->tet_dm_inv[k][s];
        if (!sb_corotated_tet(p, dm_inv, m->tet_volume[s], m->tet_mu[s], m->tet_lambda[s], g, &e)) {
            bad = true; /* the reference names it (sb_report_collapse) */
            continue;
        }
        for (int c = 0; c < 4; c++)
            for (int k = 0; k < 3; k++) fr->forces4[4 * (size_t)v[c] + k] += (sb_real)g[c][k];
        sum += e;
    }
    energy[0] += sum;
    return bad ? SB_KERNEL_COLLAPSED : 0;
}
