/* The point of a triangle nearest a collider's core (triangle_point.h).
 *
 * Design. A sphere is the points within r of its center, a capsule within
 * r of its segment, an edge of a box within the thickness of the edge:
 * each is a core segment p–q (a point when p == q) inflated by a radius.
 * The point of a triangle nearest the core is the point the core meets
 * first as the two approach, the one whose contact stops the surface; it
 * is the nearest among: where the segment pierces the triangle (distance
 * 0), the nearest points of the triangle to p and to q, and the nearest
 * points between the segment and each of the triangle's three edges
 * (Ericson, Real-Time Collision Detection, 5.1.5 and 5.1.9).
 *
 * Within a step the triangle moves (in the collider's rest frame, where
 * the collider stands still) and may carry its surface past the core: a
 * fast tool passes a thin sheet in one step. The point of the triangle at
 * the end of the step nearest the core is then on the far side; the
 * material point the core went through is where the core's path relative
 * to the triangle (from where it stood from the triangle at the start to
 * where it stands at the end) pierces the triangle at the end of the step. That point's own move then
 * enters the inflated core, and the collider's sweep answers it as it
 * answers a vertex. */
#include "kernels/contact/colliders/triangle_point.h"

#include <math.h>

static double sb_dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void sb_sub(const double a[3], const double b[3], double out[3]) {
    for (int k = 0; k < 3; k++) out[k] = a[k] - b[k];
}

static void sb_set_weights(double w[3], double u, double v, double s) { w[0] = u, w[1] = v, w[2] = s; }

static void sb_weighted(const double t[3][3], const double w[3], double x[3]) {
    for (int k = 0; k < 3; k++) x[k] = w[0] * t[0][k] + w[1] * t[1][k] + w[2] * t[2][k];
}

static double sb_distance2(const double a[3], const double b[3]) {
    double d[3];
    sb_sub(a, b, d);
    return sb_dot(d, d);
}

void sb_triangle_nearest_to_point(const double t[3][3], const double x[3], double w[3]) {
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    sb_sub(t[1], t[0], ab), sb_sub(t[2], t[0], ac), sb_sub(x, t[0], ap);
    double d1 = sb_dot(ab, ap), d2 = sb_dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return sb_set_weights(w, 1, 0, 0);
    sb_sub(x, t[1], bp);
    double d3 = sb_dot(ab, bp), d4 = sb_dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return sb_set_weights(w, 0, 1, 0);
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        double v = d1 / (d1 - d3);
        return sb_set_weights(w, 1 - v, v, 0);
    }
    sb_sub(x, t[2], cp);
    double d5 = sb_dot(ab, cp), d6 = sb_dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return sb_set_weights(w, 0, 0, 1);
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        double s = d2 / (d2 - d6);
        return sb_set_weights(w, 1 - s, 0, s);
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        double s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return sb_set_weights(w, 0, 1 - s, s);
    }
    double denominator = 1.0 / (va + vb + vc), v = vb * denominator, s = vc * denominator;
    sb_set_weights(w, 1 - v - s, v, s);
}

static double sb_clamp01(double x) { return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x; }

/* The parameters s (on p1–q1) and u (on p2–q2) of the segments' nearest
 * points (Ericson 5.1.9; a segment of zero length is its point). */
static void sb_segments_nearest(const double p1[3], const double q1[3], const double p2[3], const double q2[3],
                                double* s, double* u) {
    double d1[3], d2[3], r[3];
    sb_sub(q1, p1, d1), sb_sub(q2, p2, d2), sb_sub(p1, p2, r);
    double a = sb_dot(d1, d1), e = sb_dot(d2, d2), f = sb_dot(d2, r);
    if (a <= 0.0 && e <= 0.0) {
        *s = *u = 0.0;
        return;
    }
    if (a <= 0.0) {
        *s = 0.0, *u = sb_clamp01(f / e);
        return;
    }
    double c = sb_dot(d1, r);
    if (e <= 0.0) {
        *u = 0.0, *s = sb_clamp01(-c / a);
        return;
    }
    double b = sb_dot(d1, d2), denominator = a * e - b * b;
    *s = denominator > 0.0 ? sb_clamp01((b * f - c * e) / denominator) : 0.0;
    *u = (b * *s + f) / e;
    if (*u < 0.0)
        *u = 0.0, *s = sb_clamp01(-c / a);
    else if (*u > 1.0)
        *u = 1.0, *s = sb_clamp01((b - c) / a);
}

bool sb_triangle_pierced(const double t[3][3], const double from[3], const double to[3], double w[3]) {
    double ab[3], ac[3], n[3], af[3], at[3];
    sb_sub(t[1], t[0], ab), sb_sub(t[2], t[0], ac), sb_sub(from, t[0], af), sb_sub(to, t[0], at);
    n[0] = ab[1] * ac[2] - ab[2] * ac[1], n[1] = ab[2] * ac[0] - ab[0] * ac[2], n[2] = ab[0] * ac[1] - ab[1] * ac[0];
    double side_from = sb_dot(af, n), side_to = sb_dot(at, n), n2 = sb_dot(n, n);
    if (!(n2 > 0.0) || (side_from > 0.0 && side_to > 0.0) || (side_from < 0.0 && side_to < 0.0) || side_from == side_to)
        return false;
    double s = side_from / (side_from - side_to), x[3], ax[3], cross[3];
    for (int k = 0; k < 3; k++) x[k] = from[k] + s * (to[k] - from[k]);
    sb_sub(x, t[0], ax);
    /* the weights of b and c: the areas of a x c and a b x over a b c */
    cross[0] = ax[1] * ac[2] - ax[2] * ac[1], cross[1] = ax[2] * ac[0] - ax[0] * ac[2],
    cross[2] = ax[0] * ac[1] - ax[1] * ac[0];
    double wb = sb_dot(cross, n) / n2;
    cross[0] = ab[1] * ax[2] - ab[2] * ax[1], cross[1] = ab[2] * ax[0] - ab[0] * ax[2],
    cross[2] = ab[0] * ax[1] - ab[1] * ax[0];
    double wc = sb_dot(cross, n) / n2, wa = 1.0 - wb - wc;
    if (wa < 0.0 || wb < 0.0 || wc < 0.0) return false;
    sb_set_weights(w, wa, wb, wc);
    return true;
}

/* A candidate nearer than the best so far replaces it. */
static void sb_keep_nearer(double d2, const double w[3], const double core[3], double* best, double best_w[3],
                           double best_core[3]) {
    if (!(d2 < *best)) return;
    *best = d2;
    for (int k = 0; k < 3; k++) best_w[k] = w[k], best_core[k] = core[k];
}

double sb_triangle_nearest_to_segment(const double t[3][3], const double p[3], const double q[3], double w[3],
                                      double core[3]) {
    double best = INFINITY, cw[3], x[3];
    if (sb_triangle_pierced(t, p, q, w)) { /* a point (p == q) never pierces */
        sb_weighted(t, w, core);
        return 0.0;
    }
    const double* ends[2] = {p, q};
    for (int e = 0; e < 2; e++) {
        sb_triangle_nearest_to_point(t, ends[e], cw);
        sb_weighted(t, cw, x);
        sb_keep_nearer(sb_distance2(x, ends[e]), cw, ends[e], &best, w, core);
    }
    for (int e = 0; e < 3; e++) {
        int i = e, j = (e + 1) % 3;
        double s, u, on_edge[3], on_core[3];
        sb_segments_nearest(t[i], t[j], p, q, &s, &u);
        for (int k = 0; k < 3; k++) {
            on_edge[k] = t[i][k] + s * (t[j][k] - t[i][k]);
            on_core[k] = p[k] + u * (q[k] - p[k]);
        }
        cw[0] = cw[1] = cw[2] = 0.0;
        cw[i] = 1.0 - s, cw[j] = s;
        sb_keep_nearer(sb_distance2(on_edge, on_core), cw, on_core, &best, w, core);
    }
    return best;
}

/* Whether the path of x relative to the triangle pierces it at the end of
 * the step: x stood at x − p0 from the triangle's point p0 at weights w at
 * the start, which is x + (p1 − p0) seen from the same point p1 at the
 * end. */
static bool sb_passed_through(const double from[3][3], const double to[3][3], const double x[3], const double w[3],
                              double pierced[3]) {
    double start[3];
    for (int k = 0; k < 3; k++)
        start[k] =
            x[k] + (w[0] * (to[0][k] - from[0][k]) + w[1] * (to[1][k] - from[1][k]) + w[2] * (to[2][k] - from[2][k]));
    return sb_triangle_pierced(to, start, x, pierced);
}

double sb_triangle_swept_nearest(const double from[3][3], const double to[3][3], const double p[3], const double q[3],
                                 double w[3]) {
    double core[3], pierced[3];
    double d2 = sb_triangle_nearest_to_segment(to, p, q, w, core);
    if (d2 == 0.0) return 0.0;
    const double* points[3] = {core, p, q};
    int count = p[0] == q[0] && p[1] == q[1] && p[2] == q[2] ? 1 : 3;
    for (int k = 0; k < count; k++) {
        if (!sb_passed_through(from, to, points[k], w, pierced)) continue;
        for (int c = 0; c < 3; c++) w[c] = pierced[c];
        return 0.0;
    }
    return d2;
}
