/* Fast per-hinge kernel: the dihedral bending term of
 * kernels/forces/reference_hinges.c (which derives the gradient), in SIMD.
 *
 * The angle: φ = atan2((n0 × n1)·ê, n0·n1) by kernels/runtime/wide.h's vector
 * atan2 (a polynomial, within one unit in the last place of π of libm), then
 * φ − φ0 wrapped into (−π, π] with the reference's own two comparisons, lane
 * by lane without a branch. A fold through itself therefore behaves as in
 * the reference: φ jumps from π to −π, the difference does not. A
 * formulation without inverse trigonometry (the rotation from the rest
 * normal pair) would need sin φ0 and cos φ0 per hinge: one more stream to
 * read for the same accuracy. */
#include "kernels/forces/fast_hinges.h"
#include "kernels/forces/fast_block.h"

int sb_fast_hinges(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                   double energy[1]) {
    uint32_t step = sb_block_step(serial);
    sb_wide sum = sb_w_set(0);
    bool collapsed = false;
    for (uint32_t s = begin; s < end; s += step) {
        int count = sb_block_count(s, end, step);
        sb_windex v[4];
        sb_wvec3 p[4]; /* e0, e1, o0, o1 */
        sb_worigin origin;
        for (int a = 0; a < 4; a++) {
            v[a] = sb_w_index(m->hinge_v[a] + s);
            p[a] = a == 0 ? sb_wv_origin_at(fr, m->hinge_v[a] + s, &origin)
                          : sb_wv_vertex_at(fr, m->hinge_v[a] + s, &origin);
        }
        sb_wvec3 edge = sb_wv_sub(p[1], p[0]);
        sb_wvec3 n0 = sb_wv_cross(sb_wv_sub(p[2], p[0]), sb_wv_sub(p[2], p[1]));
        sb_wvec3 n1 = sb_wv_cross(sb_wv_sub(p[3], p[1]), sb_wv_sub(p[3], p[0]));
        sb_wide edge_sq = sb_wv_dot(edge, edge), n0_sq = sb_wv_dot(n0, n0), n1_sq = sb_wv_dot(n1, n1);
        sb_wide limit = sb_w_wing_limit(edge_sq);
        collapsed |= sb_w_any(sb_w_less(n0_sq, limit), count) || sb_w_any(sb_w_less(n1_sq, limit), count);
        sb_wide length = sb_w_sqrt(edge_sq), inv_length = sb_w_div(sb_w_set(1), length);
        sb_wide sine = sb_w_mul(sb_wv_dot(sb_wv_cross(n0, n1), edge), inv_length);
        sb_wide delta = sb_w_angle_delta(sine, sb_wv_dot(n0, n1), sb_w_load(m->hinge_phi0 + s));
        sb_wide k = sb_w_constant(m->hinge_k, s), kd = sb_w_mul(k, delta);
        sb_wvec3 w0 = sb_wv_scale(n0, sb_w_div(kd, n0_sq)), w1 = sb_wv_scale(n1, sb_w_div(kd, n1_sq));
        sb_wvec3 unit = sb_wv_scale(edge, inv_length);
        sb_wvec3 f_o0 = sb_wv_scale(w0, length), f_o1 = sb_wv_scale(w1, length);
        sb_wvec3 f_e0 = sb_wv_add(sb_wv_scale(w0, sb_wv_dot(sb_wv_sub(p[2], p[1]), unit)),
                                  sb_wv_scale(w1, sb_wv_dot(sb_wv_sub(p[3], p[1]), unit)));
        sb_wvec3 f_e1 = sb_wv_neg(sb_wv_add(f_o0, sb_wv_add(f_o1, f_e0)));
        sb_wv_add4(fr->forces4, v[0], f_e0, count);
        sb_wv_add4(fr->forces4, v[1], f_e1, count);
        sb_wv_add4(fr->forces4, v[2], f_o0, count);
        sb_wv_add4(fr->forces4, v[3], f_o1, count);
        sum = sb_w_add(sum, sb_w_keep(sb_w_mul(sb_w_mul(sb_w_set((sb_real)0.5), kd), delta), count));
    }
    energy[0] += sb_w_sum(sum, SB_WIDTH);
    return collapsed ? SB_KERNEL_COLLAPSED : 0;
}
