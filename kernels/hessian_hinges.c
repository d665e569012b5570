/* A hinge on dual numbers (kernels/hessian.h): E = ½ k (φ − φ0)², the
 * gradient of kernels/reference_hinges.c; local vertices e0, e1, o0, o1.
 * The dihedral angle's derivative comes through atan2's (common/dual.h). */
#include "kernels/hessian.h"

#define SB_MIN_WING_RATIO 1e-12 /* as kernels/reference_hinges.c */

void sb_hinge_forces_dual(const sb_model* m, uint32_t h, const sb_dvec3* x, sb_dvec3* f, bool* collapsed) {
    double k = m->term_enabled[SB_TERM_BEND] ? m->hinge_k[h] : 0.0;
    sb_dvec3 e0 = x[0], e1 = x[1], o0 = x[2], o1 = x[3];
    sb_dvec3 edge = sb_dv3_sub(e1, e0);
    sb_dvec3 n0 = sb_dv3_cross(sb_dv3_sub(o0, e0), sb_dv3_sub(o0, e1));
    sb_dvec3 n1 = sb_dv3_cross(sb_dv3_sub(o1, e1), sb_dv3_sub(o1, e0));
    sb_dual length = sb_dv3_length(edge), n0_sq = sb_dv3_dot(n0, n0), n1_sq = sb_dv3_dot(n1, n1);
    double limit = SB_MIN_WING_RATIO * length.v * length.v;
    *collapsed = !(length.v > 0.0) || !(n0_sq.v > limit * limit) || !(n1_sq.v > limit * limit);
    if (*collapsed) return;
    sb_dual inv_length = sb_d_div(sb_d_const(1.0), length);
    sb_dual sine = sb_d_mul(sb_dv3_dot(sb_dv3_cross(n0, n1), edge), inv_length);
    sb_dual phi = sb_d_atan2(sine, sb_dv3_dot(n0, n1));
    /* the wrap of sb_angle_difference moves the value by 2π, not the slope */
    double delta = sb_angle_difference(phi.v, m->hinge_phi0[h]);
    sb_dual magnitude = sb_d(k * delta, k * phi.d);
    sb_dvec3 w0 = sb_dv3_scale(n0, sb_d_div(sb_d_const(1.0), n0_sq));
    sb_dvec3 w1 = sb_dv3_scale(n1, sb_d_div(sb_d_const(1.0), n1_sq));
    sb_dvec3 unit_edge = sb_dv3_scale(edge, inv_length);
    sb_dvec3 u_o0 = sb_dv3_scale(w0, length), u_o1 = sb_dv3_scale(w1, length);
    sb_dvec3 u_e0 = sb_dv3_add(sb_dv3_scale(w0, sb_dv3_dot(sb_dv3_sub(o0, e1), unit_edge)),
                               sb_dv3_scale(w1, sb_dv3_dot(sb_dv3_sub(o1, e1), unit_edge)));
    sb_dvec3 u_e1 = sb_dv3_add(sb_dv3_scale(w0, sb_d_scale(sb_dv3_dot(sb_dv3_sub(o0, e0), unit_edge), -1.0)),
                               sb_dv3_scale(w1, sb_d_scale(sb_dv3_dot(sb_dv3_sub(o1, e0), unit_edge), -1.0)));
    f[0] = sb_dv3_scale(u_e0, magnitude);
    f[1] = sb_dv3_scale(u_e1, magnitude);
    f[2] = sb_dv3_scale(u_o0, magnitude);
    f[3] = sb_dv3_scale(u_o1, magnitude);
}
