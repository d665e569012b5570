/* The narrow phase of self-contact (kernels/contact/proximity.h).
 *
 * Design. The continuous tests follow Provot (1997) and Bridson, Fedkiw
 * and Anderson (2002): with every point moving on a straight line over the
 * step, a vertex can pass through a triangle (or an edge through an edge)
 * only at a time when the four points are coplanar, a root of a cubic in t.
 * The cubic's sign changes in [0, 1] are bracketed between the roots of its
 * derivative and refined by bisection to rounding level (no Newton step that
 * could jump out of its interval); at each, in time order, the features are
 * tested for proximity within `reach` (the contact thickness), so a crossing
 * just beside an edge counts and one far outside the triangle does not. A
 * cubic that touches zero without changing sign (a vertex that grazes the
 * plane and turns back) or is zero throughout (motion in a common plane) has
 * no crossing: the proximity test of the contact pass answers those. */
#include "kernels/contact/proximity.h"

#include <float.h>

double sb_point_triangle_closest(sb_vec3 p, sb_vec3 a, sb_vec3 b, sb_vec3 c, double w[3]) {
    sb_vec3 ab = sb_v3_sub(b, a), ac = sb_v3_sub(c, a), ap = sb_v3_sub(p, a);
    double d1 = sb_v3_dot(ab, ap), d2 = sb_v3_dot(ac, ap);
    /* the Voronoi regions of the corners, the edges and the face, in turn */
    if (d1 <= 0.0 && d2 <= 0.0) {
        w[0] = 1.0, w[1] = w[2] = 0.0;
    } else {
        sb_vec3 bp = sb_v3_sub(p, b), cp = sb_v3_sub(p, c);
        double d3 = sb_v3_dot(ab, bp), d4 = sb_v3_dot(ac, bp), d5 = sb_v3_dot(ab, cp), d6 = sb_v3_dot(ac, cp);
        double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
        if (d3 >= 0.0 && d4 <= d3) {
            w[1] = 1.0, w[0] = w[2] = 0.0;
        } else if (d6 >= 0.0 && d5 <= d6) {
            w[2] = 1.0, w[0] = w[1] = 0.0;
        } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
            double s = d1 / (d1 - d3);
            w[0] = 1.0 - s, w[1] = s, w[2] = 0.0;
        } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
            double s = d2 / (d2 - d6);
            w[0] = 1.0 - s, w[2] = s, w[1] = 0.0;
        } else if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
            double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
            w[1] = 1.0 - s, w[2] = s, w[0] = 0.0;
        } else {
            double sum = va + vb + vc;
            if (!(sum > 0.0)) { /* degenerate: the closest point of the three edges */
                sb_vec3 corners[3] = {a, b, c};
                double best = DBL_MAX, s, u;
                for (int e = 0; e < 3; e++) {
                    double d = sb_segments_closest(p, p, corners[e], corners[(e + 1) % 3], &s, &u);
                    if (d < best) {
                        best = d;
                        w[e] = 1.0 - u, w[(e + 1) % 3] = u, w[(e + 2) % 3] = 0.0;
                    }
                }
                return best;
            }
            w[0] = va / sum, w[1] = vb / sum, w[2] = vc / sum;
        }
    }
    sb_vec3 q = sb_v3_add(sb_v3_add(sb_v3_scale(a, w[0]), sb_v3_scale(b, w[1])), sb_v3_scale(c, w[2]));
    sb_vec3 d = sb_v3_sub(p, q);
    return sb_v3_dot(d, d);
}

static double sb_clamp01(double x) { return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x; }

double sb_segments_closest(sb_vec3 p0, sb_vec3 p1, sb_vec3 q0, sb_vec3 q1, double* s, double* u) {
    sb_vec3 d1 = sb_v3_sub(p1, p0), d2 = sb_v3_sub(q1, q0), r = sb_v3_sub(p0, q0);
    double a = sb_v3_dot(d1, d1), e = sb_v3_dot(d2, d2), f = sb_v3_dot(d2, r);
    const double tiny = 1e-300;
    if (a <= tiny && e <= tiny) {
        *s = *u = 0.0;
    } else if (a <= tiny) {
        *s = 0.0;
        *u = sb_clamp01(f / e);
    } else {
        double c = sb_v3_dot(d1, r);
        if (e <= tiny) {
            *u = 0.0;
            *s = sb_clamp01(-c / a);
        } else {
            double b = sb_v3_dot(d1, d2), denom = a * e - b * b;
            /* parallel segments (denom 0): any s; take 0 and clamp u */
            *s = denom > 0.0 ? sb_clamp01((b * f - c * e) / denom) : 0.0;
            *u = (b * *s + f) / e;
            if (*u < 0.0) {
                *u = 0.0;
                *s = sb_clamp01(-c / a);
            } else if (*u > 1.0) {
                *u = 1.0;
                *s = sb_clamp01((b - c) / a);
            }
        }
    }
    sb_vec3 pc = sb_v3_add(p0, sb_v3_scale(d1, *s)), qc = sb_v3_add(q0, sb_v3_scale(d2, *u));
    sb_vec3 d = sb_v3_sub(pc, qc);
    return sb_v3_dot(d, d);
}

static double sb_cubic_at(const double k[4], double t) { return ((k[0] * t + k[1]) * t + k[2]) * t + k[3]; }

/* The root of the cubic in [lo, hi], where its values at the ends differ in
 * sign: regula falsi with the Illinois modification (the end that stays
 * has its value halved, so convergence is superlinear and never stalls),
 * always inside the bracket, to 1e-13 of the step. */
static double sb_bisect(const double k[4], double lo, double hi, double f_lo) {
    double f_hi = sb_cubic_at(k, hi);
    int side = 0;
    for (int i = 0; i < 100 && hi - lo > 1e-13; i++) {
        double mid = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
        double f_mid = sb_cubic_at(k, mid);
        if (f_mid == 0.0) return mid;
        if ((f_mid < 0.0) == (f_lo < 0.0)) {
            lo = mid, f_lo = f_mid;
            if (side == -1) f_hi *= 0.5;
            side = -1;
        } else {
            hi = mid, f_hi = f_mid;
            if (side == 1) f_lo *= 0.5;
            side = 1;
        }
    }
    return 0.5 * (lo + hi);
}

/* Whether the cubic keeps one strict sign over [0, 1]: its Bernstein
 * coefficients there all share it (the curve lies in their convex hull).
 * Rejects most pairs before any root is sought. */
static bool sb_cubic_one_sign(double a3, double a2, double a1, double a0) {
    double b[4] = {a0, a0 + a1 / 3.0, a0 + (2.0 * a1 + a2) / 3.0, a0 + a1 + a2 + a3};
    bool positive = b[0] > 0.0 && b[1] > 0.0 && b[2] > 0.0 && b[3] > 0.0;
    bool negative = b[0] < 0.0 && b[1] < 0.0 && b[2] < 0.0 && b[3] < 0.0;
    return positive || negative;
}

int sb_cubic_sign_changes(double a3, double a2, double a1, double a0, double roots[3]) {
    if (sb_cubic_one_sign(a3, a2, a1, a0)) return 0;
    const double k[4] = {a3, a2, a1, a0};
    /* the ends of the monotone pieces: 0, the derivative's roots in (0, 1), 1 */
    double ends[4] = {0.0}, qa = 3.0 * a3, qb = 2.0 * a2, qc = a1;
    int count = 1;
    if (qa != 0.0) {
        double disc = qb * qb - 4.0 * qa * qc;
        if (disc > 0.0) {
            double sq = sqrt(disc), q = -0.5 * (qb + (qb < 0.0 ? -sq : sq));
            double r1 = q / qa, r2 = q != 0.0 ? qc / q : r1;
            if (r1 > r2) {
                double t = r1;
                r1 = r2, r2 = t;
            }
            if (r1 > 0.0 && r1 < 1.0) ends[count++] = r1;
            if (r2 > 0.0 && r2 < 1.0 && r2 != r1) ends[count++] = r2;
        }
    } else if (qb != 0.0) {
        double r = -qc / qb;
        if (r > 0.0 && r < 1.0) ends[count++] = r;
    }
    ends[count++] = 1.0;
    int found = 0;
    double f_prev = sb_cubic_at(k, 0.0);
    for (int i = 1; i < count; i++) {
        double f_next = sb_cubic_at(k, ends[i]);
        /* a sign change strictly inside, or a zero reached from a nonzero start */
        if ((f_prev < 0.0 && f_next > 0.0) || (f_prev > 0.0 && f_next < 0.0))
            roots[found++] = sb_bisect(k, ends[i - 1], ends[i], f_prev);
        else if (f_next == 0.0 && f_prev != 0.0 && i == count - 1)
            roots[found++] = 1.0;
        if (f_next != 0.0) f_prev = f_next;
    }
    return found;
}

void sb_coplanarity_cubic(const sb_moving_quad* q, double c[4]) {
    sb_vec3 x[3], v[3];
    for (int k = 0; k < 3; k++) {
        x[k] = sb_v3_sub(q->x0[k + 1], q->x0[0]);
        v[k] = sb_v3_sub(sb_v3_sub(q->x1[k + 1], q->x1[0]), x[k]);
    }
    sb_vec3 c0 = sb_v3_cross(x[1], x[2]);
    sb_vec3 c1 = sb_v3_add(sb_v3_cross(x[1], v[2]), sb_v3_cross(v[1], x[2]));
    sb_vec3 c2 = sb_v3_cross(v[1], v[2]);
    c[0] = sb_v3_dot(v[0], c2);
    c[1] = sb_v3_dot(x[0], c2) + sb_v3_dot(v[0], c1);
    c[2] = sb_v3_dot(x[0], c1) + sb_v3_dot(v[0], c0);
    c[3] = sb_v3_dot(x[0], c0);
}

bool sb_vertex_triangle_crossing(const sb_moving_quad* q, double reach, double* t, double w[3]) {
    double c[4], roots[3];
    sb_coplanarity_cubic(q, c);
    int n = sb_cubic_sign_changes(c[0], c[1], c[2], c[3], roots);
    for (int r = 0; r < n; r++) {
        double d = sb_point_triangle_closest(sb_quad_at(q, 0, roots[r]), sb_quad_at(q, 1, roots[r]),
                                             sb_quad_at(q, 2, roots[r]), sb_quad_at(q, 3, roots[r]), w);
        if (d <= reach * reach) {
            *t = roots[r];
            return true;
        }
    }
    return false;
}

bool sb_edge_edge_crossing(const sb_moving_quad* q, double reach, double* t, double* s, double* u) {
    double c[4], roots[3];
    sb_coplanarity_cubic(q, c);
    int n = sb_cubic_sign_changes(c[0], c[1], c[2], c[3], roots);
    for (int r = 0; r < n; r++) {
        double d = sb_segments_closest(sb_quad_at(q, 0, roots[r]), sb_quad_at(q, 1, roots[r]),
                                       sb_quad_at(q, 2, roots[r]), sb_quad_at(q, 3, roots[r]), s, u);
        if (d <= reach * reach) {
            *t = roots[r];
            return true;
        }
    }
    return false;
}

bool sb_quad_may_cross(const sb_moving_quad* q, double end_distance, double reach) {
    double largest = 0.0;
    for (int k = 0; k < 4; k++) {
        sb_vec3 d = sb_v3_sub(q->x1[k], q->x0[k]);
        double move = sb_v3_dot(d, d);
        largest = move > largest ? move : largest;
    }
    return end_distance - 2.0 * sqrt(largest) <= reach;
}
