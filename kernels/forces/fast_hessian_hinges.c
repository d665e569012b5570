/* The hinges' second derivatives (kernels/forces/fast_hessian.h): the dihedral
 * bend of kernels/forces/fast_hinges.c, F_a = k (φ − φ0) g_a with g_a = −∇_a φ,
 * on wide duals. As in kernels/forces/hessian_hinges.c, φ's derivative is
 * −Σ g_a · ẋ_a, so atan2 runs on values only, and the wrap of φ − φ0 moves
 * the value by 2π, not the slope. */
#include "kernels/forces/fast_hessian_hinges.h"
#include "kernels/forces/fast_hessian.h"

static void sb_wdual_hinge(const sb_fast_model* m, uint32_t s, sb_wide damping, const sb_wdvec3* x, sb_wdvec3* f) {
    (void)damping;
    sb_wdvec3 edge = sb_wdv_sub(x[1], x[0]);
    sb_wdvec3 n0 = sb_wdv_cross(sb_wdv_sub(x[2], x[0]), sb_wdv_sub(x[2], x[1]));
    sb_wdvec3 n1 = sb_wdv_cross(sb_wdv_sub(x[3], x[1]), sb_wdv_sub(x[3], x[0]));
    sb_wdual edge_sq = sb_wdv_dot(edge, edge), inv_length = sb_wd_rsqrt(edge_sq);
    sb_wdual length = sb_wd_mul(edge_sq, inv_length);
    sb_wdvec3 w0 = sb_wdv_scale(n0, sb_wd_inverse(sb_wdv_dot(n0, n0)));
    sb_wdvec3 w1 = sb_wdv_scale(n1, sb_wd_inverse(sb_wdv_dot(n1, n1)));
    sb_wdvec3 unit = sb_wdv_scale(edge, inv_length);
    sb_wdvec3 g[4];
    g[2] = sb_wdv_scale(w0, length);
    g[3] = sb_wdv_scale(w1, length);
    g[0] = sb_wdv_add(sb_wdv_scale(w0, sb_wdv_dot(sb_wdv_sub(x[2], x[1]), unit)),
                      sb_wdv_scale(w1, sb_wdv_dot(sb_wdv_sub(x[3], x[1]), unit)));
    g[1] = sb_wdv_neg(sb_wdv_add(g[2], sb_wdv_add(g[3], g[0])));
    sb_wide sine = sb_w_mul(sb_wv_dot(sb_wv_cross(n0.v, n1.v), edge.v), inv_length.v);
    sb_wide delta = sb_w_angle_delta(sine, sb_wv_dot(n0.v, n1.v), sb_w_load(m->hinge_phi0 + s));
    sb_wide slope = sb_w_set(0); /* φ's derivative */
    for (int a = 0; a < 4; a++) slope = sb_w_sub(slope, sb_wv_dot(g[a].v, x[a].d));
    sb_wide k = sb_w_constant(m->hinge_k, s);
    sb_wdual magnitude = {sb_w_mul(k, delta), sb_w_mul(k, slope)};
    for (int a = 0; a < 4; a++) f[a] = sb_wdv_scale(g[a], magnitude);
}

int sb_fast_hinges_hessian(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end,
                           bool serial, double* unused) {
    (void)unused;
    sb_hessian_pass(m, frame, begin, end, serial, 4, m->hinge_v, sb_wdual_hinge);
    return 0;
}
