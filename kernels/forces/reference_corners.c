/* Scalar reference for the per-corner terms: angle bend (Eq. 4) and
 * stretch-bend (Eq. 5), with the exact gradients of DESIGN.md.
 *
 * Corner at i with neighbours j, k: a = x_j − x_i, b = x_k − x_i, A = |a|,
 * B = |b|, c = â·b̂, S = (A − A0) + (B − B0),
 *   E = ½ kθ (c − c0)² + ksb (c − c0) S,
 *   g = kθ (c − c0) + ksb S,  h = ksb (c − c0),
 *   F_j = −(g/A)(b̂ − c â) − h â,  F_k = −(g/B)(â − c b̂) − h b̂,
 *   F_i = −F_j − F_k.
 * No 1/sin θ appears: the only singularity is A or B collapsing to zero,
 * which is reported instead of divided by. */
#include "kernels/forces/reference_corners.h"
#include "kernels/forces/reference_terms.h"
#include "common/error.h"
#include "common/geometry.h"

typedef struct sb_corner {
    uint32_t i, j, k;
    double cos0, a0, b0;  /* rest cosine, rest lengths of i-j and i-k */
    double k_angle, k_sb; /* already weighted */
} sb_corner;

static sb_corner sb_corner_of(const sb_model* m, uint32_t t, int c, double angle_weight, double sb_weight) {
    return (sb_corner){
        .i = m->tri_v[c][t],
        .j = m->tri_v[(c + 1) % 3][t],
        .k = m->tri_v[(c + 2) % 3][t],
        .cos0 = m->tri_cos0[c][t],
        .a0 = m->tri_len0[c][t],
        .b0 = m->tri_len0[(c + 2) % 3][t],
        .k_angle = angle_weight * m->angle_k[t],
        .k_sb = sb_weight * m->stretch_bend_k[t],
    };
}

/* Adds the corner's forces; returns its energy, or NAN when an edge collapsed. */
static double sb_corner_apply(const sb_corner* q, const double* x, double* f) {
    sb_vec3 p = sb_v3(x + 3 * q->i);
    sb_vec3 a = sb_v3_sub(sb_v3(x + 3 * q->j), p), b = sb_v3_sub(sb_v3(x + 3 * q->k), p);
    double A = sb_v3_length(a), B = sb_v3_length(b);
    if (!(A >= SB_COLLAPSE_RATIO * q->a0) || !(B >= SB_COLLAPSE_RATIO * q->b0)) return NAN;
    sb_vec3 ua = sb_v3_scale(a, 1.0 / A), ub = sb_v3_scale(b, 1.0 / B);
    double c = sb_v3_dot(ua, ub), dc = c - q->cos0, S = (A - q->a0) + (B - q->b0);
    double g = q->k_angle * dc + q->k_sb * S, h = q->k_sb * dc;
    sb_vec3 fj = sb_v3_add(sb_v3_scale(sb_v3_sub(ub, sb_v3_scale(ua, c)), -g / A), sb_v3_scale(ua, -h));
    sb_vec3 fk = sb_v3_add(sb_v3_scale(sb_v3_sub(ua, sb_v3_scale(ub, c)), -g / B), sb_v3_scale(ub, -h));
    sb_v3_add_to(f + 3 * q->j, fj, 1.0);
    sb_v3_add_to(f + 3 * q->k, fk, 1.0);
    sb_v3_add_to(f + 3 * q->i, sb_v3_add(fj, fk), -1.0);
    return 0.5 * q->k_angle * dc * dc + q->k_sb * dc * S;
}

sb_status sb_reference_corners(const sb_model* m, double angle_weight, double stretch_bend_weight, const double* x,
                               double* f, double* energy, sb_error* err) {
    double total = 0.0;
    for (uint32_t t = 0; t < m->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            sb_corner q = sb_corner_of(m, t, c, angle_weight, stretch_bend_weight);
            if (q.k_angle == 0.0 && q.k_sb == 0.0) continue;
            double e = sb_corner_apply(&q, x, f);
            if (isnan(e))
                return sb_error_set(err, SB_ERR_DEGENERATE, "triangle %u (%u, %u, %u): an edge at corner %u collapsed",
                                    t, m->tri_v[0][t], m->tri_v[1][t], m->tri_v[2][t], q.i);
            total += e;
        }
    *energy = total;
    return SB_OK;
}
