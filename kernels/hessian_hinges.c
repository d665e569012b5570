/* A hinge on dual numbers (kernels/hessian.h): E = ½ k (φ − φ0)², the
 * gradient of kernels/reference_hinges.c; local vertices e0, e1, o0, o1.
 * The dihedral angle's derivative is ∇φ · ẋ with ∇φ = −u (the gradient the
 * reference derives), so atan2 runs on values only. */
#include "kernels/hessian.h"

#define SB_MIN_WING_RATIO 1e-12 /* as kernels/reference_hinges.c */

/* φ and u = −∇φ on each local vertex (e0, e1, o0, o1), on dual numbers;
 * false when a wing collapsed. */
static bool sb_hinge_angle_dual(const sb_dvec3* x, sb_dual* phi, sb_dvec3* u) {
    sb_dvec3 e0 = x[0], e1 = x[1], o0 = x[2], o1 = x[3];
    sb_dvec3 edge = sb_dv3_sub(e1, e0);
    sb_dvec3 n0 = sb_dv3_cross(sb_dv3_sub(o0, e0), sb_dv3_sub(o0, e1));
    sb_dvec3 n1 = sb_dv3_cross(sb_dv3_sub(o1, e1), sb_dv3_sub(o1, e0));
    sb_dual length = sb_dv3_length(edge), n0_sq = sb_dv3_dot(n0, n0), n1_sq = sb_dv3_dot(n1, n1);
    double limit = SB_MIN_WING_RATIO * length.v * length.v;
    if (!(length.v > 0.0) || !(n0_sq.v > limit * limit) || !(n1_sq.v > limit * limit)) return false;
    sb_dual inv_length = sb_d_div(sb_d_const(1.0), length);
    sb_dvec3 w0 = sb_dv3_scale(n0, sb_d_div(sb_d_const(1.0), n0_sq));
    sb_dvec3 w1 = sb_dv3_scale(n1, sb_d_div(sb_d_const(1.0), n1_sq));
    sb_dvec3 unit_edge = sb_dv3_scale(edge, inv_length);
    u[0] = sb_dv3_add(sb_dv3_scale(w0, sb_dv3_dot(sb_dv3_sub(o0, e1), unit_edge)),
                      sb_dv3_scale(w1, sb_dv3_dot(sb_dv3_sub(o1, e1), unit_edge)));
    u[1] = sb_dv3_add(sb_dv3_scale(w0, sb_d_scale(sb_dv3_dot(sb_dv3_sub(o0, e0), unit_edge), -1.0)),
                      sb_dv3_scale(w1, sb_d_scale(sb_dv3_dot(sb_dv3_sub(o1, e0), unit_edge), -1.0)));
    u[2] = sb_dv3_scale(w0, length);
    u[3] = sb_dv3_scale(w1, length);
    /* φ's value by atan2; its derivative is ∇φ · ẋ = −Σ u · ẋ, no dual atan2 */
    double sine = sb_v3_dot(sb_v3_cross(n0.v, n1.v), edge.v) / length.v;
    *phi = sb_d(atan2(sine, sb_v3_dot(n0.v, n1.v)), 0.0);
    for (int a = 0; a < 4; a++) phi->d -= sb_v3_dot(u[a].v, x[a].d);
    return true;
}

static double sb_hinge_stiffness(const sb_model* m, uint32_t h) {
    return m->term_enabled[SB_TERM_BEND] ? m->hinge_k[h] : 0.0;
}

void sb_hinge_forces_dual(const sb_model* m, uint32_t h, const sb_dvec3* x, sb_dvec3* f, bool* collapsed) {
    double k = sb_hinge_stiffness(m, h);
    sb_dual phi;
    sb_dvec3 u[4];
    *collapsed = !sb_hinge_angle_dual(x, &phi, u);
    if (*collapsed) return;
    /* the wrap of sb_angle_difference moves the value by 2π, not the slope */
    double delta = sb_angle_difference(phi.v, m->hinge_phi0[h]);
    sb_dual magnitude = sb_d(k * delta, k * phi.d);
    for (int a = 0; a < 4; a++) f[a] = sb_dv3_scale(u[a], magnitude);
}

void sb_hinge_definite(const sb_model* m, uint32_t h, const sb_vec3* x, double* k) {
    sb_dvec3 xs[4], u[4];
    for (int a = 0; a < 4; a++) xs[a] = (sb_dvec3){x[a], {0, 0, 0}};
    sb_dual phi;
    if (!sb_hinge_angle_dual(xs, &phi, u)) {
        k[0] = NAN;
        return;
    }
    double w[12];
    for (int a = 0; a < 4; a++) w[3 * a] = u[a].v.x, w[3 * a + 1] = u[a].v.y, w[3 * a + 2] = u[a].v.z;
    sb_add_outer(k, 12, w, sb_hinge_stiffness(m, h));
}
