/* A triangle's three corners on dual numbers (kernels/hessian.h): angle bend
 * and stretch-bend, the formulas of kernels/reference_corners.c. Corner c
 * sits at local vertex c with neighbours c + 1 and c + 2 (mod 3). */
#include "kernels/hessian.h"
#include "kernels/reference_terms.h"

/* Adds one corner's forces to f (local vertices i, j, k). */
static void sb_corner_dual(double k_angle, double k_sb, double cos0, double a0, double b0, const sb_dvec3* x, int i,
                           int j, int k, sb_dvec3* f, bool* collapsed) {
    sb_dvec3 a = sb_dv3_sub(x[j], x[i]), b = sb_dv3_sub(x[k], x[i]);
    sb_dual A = sb_dv3_length(a), B = sb_dv3_length(b);
    if (!(A.v >= SB_COLLAPSE_RATIO * a0) || !(B.v >= SB_COLLAPSE_RATIO * b0)) {
        *collapsed = true;
        return;
    }
    sb_dual inv_a = sb_d_div(sb_d_const(1.0), A), inv_b = sb_d_div(sb_d_const(1.0), B);
    sb_dvec3 ua = sb_dv3_scale(a, inv_a), ub = sb_dv3_scale(b, inv_b);
    sb_dual c = sb_dv3_dot(ua, ub), dc = sb_d_sub(c, sb_d_const(cos0));
    sb_dual S = sb_d_add(sb_d_sub(A, sb_d_const(a0)), sb_d_sub(B, sb_d_const(b0)));
    sb_dual g = sb_d_add(sb_d_scale(dc, k_angle), sb_d_scale(S, k_sb)), h = sb_d_scale(dc, k_sb);
    sb_dual minus_h = sb_d_scale(h, -1.0);
    sb_dvec3 fj = sb_dv3_add(sb_dv3_scale(sb_dv3_sub(ub, sb_dv3_scale(ua, c)), sb_d_scale(sb_d_mul(g, inv_a), -1.0)),
                             sb_dv3_scale(ua, minus_h));
    sb_dvec3 fk = sb_dv3_add(sb_dv3_scale(sb_dv3_sub(ua, sb_dv3_scale(ub, c)), sb_d_scale(sb_d_mul(g, inv_b), -1.0)),
                             sb_dv3_scale(ub, minus_h));
    f[j] = sb_dv3_add(f[j], fj);
    f[k] = sb_dv3_add(f[k], fk);
    f[i] = sb_dv3_sub(f[i], sb_dv3_add(fj, fk));
}

void sb_triangle_forces_dual(const sb_model* m, uint32_t t, const sb_dvec3* x, sb_dvec3* f, bool* collapsed) {
    double k_angle = m->term_enabled[SB_TERM_ANGLE] ? m->angle_k[t] : 0.0;
    double k_sb = m->term_enabled[SB_TERM_STRETCH_BEND] ? m->stretch_bend_k[t] : 0.0;
    *collapsed = false;
    for (int c = 0; c < 3; c++) f[c] = (sb_dvec3){{0, 0, 0}, {0, 0, 0}};
    if (k_angle == 0.0 && k_sb == 0.0) return;
    for (int c = 0; c < 3; c++)
        sb_corner_dual(k_angle, k_sb, m->tri_cos0[c][t], m->tri_len0[c][t], m->tri_len0[(c + 2) % 3][t], x, c,
                       (c + 1) % 3, (c + 2) % 3, f, collapsed);
}

/* One corner's λ w wᵀ (kernels/hessian.h), added to the triangle's 9 × 9 k. */
static void sb_corner_definite(double k_angle, double k_sb, const sb_vec3* x, int i, int j, int l, double* k) {
    sb_vec3 a = sb_v3_sub(x[j], x[i]), b = sb_v3_sub(x[l], x[i]);
    double A = sb_v3_length(a), B = sb_v3_length(b);
    sb_vec3 ua = sb_v3_scale(a, 1.0 / A), ub = sb_v3_scale(b, 1.0 / B);
    double c = sb_v3_dot(ua, ub);
    double lambda = 0.5 * (k_angle + sqrt(k_angle * k_angle + 4.0 * k_sb * k_sb));
    double p = k_sb != 0.0 ? k_sb : 1.0, q = k_sb != 0.0 ? lambda - k_angle : 0.0, norm = sqrt(p * p + q * q);
    p /= norm, q /= norm;
    /* w on j and l: p ∇c + q ∇S; on i minus their sum */
    sb_vec3 wj = sb_v3_add(sb_v3_scale(sb_v3_sub(ub, sb_v3_scale(ua, c)), p / A), sb_v3_scale(ua, q));
    sb_vec3 wl = sb_v3_add(sb_v3_scale(sb_v3_sub(ua, sb_v3_scale(ub, c)), p / B), sb_v3_scale(ub, q));
    sb_vec3 wi = sb_v3_scale(sb_v3_add(wj, wl), -1.0);
    double w[9];
    const sb_vec3* parts[3] = {&wi, &wj, &wl};
    const int at[3] = {i, j, l};
    for (int v = 0; v < 3; v++) {
        w[3 * at[v]] = parts[v]->x, w[3 * at[v] + 1] = parts[v]->y, w[3 * at[v] + 2] = parts[v]->z;
    }
    sb_add_outer(k, 9, w, lambda);
}

void sb_triangle_definite(const sb_model* m, uint32_t t, const sb_vec3* x, double* k) {
    double k_angle = m->term_enabled[SB_TERM_ANGLE] ? m->angle_k[t] : 0.0;
    double k_sb = m->term_enabled[SB_TERM_STRETCH_BEND] ? m->stretch_bend_k[t] : 0.0;
    if (k_angle == 0.0 && k_sb == 0.0) return;
    for (int c = 0; c < 3; c++) sb_corner_definite(k_angle, k_sb, x, c, (c + 1) % 3, (c + 2) % 3, k);
}
