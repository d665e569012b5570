/* The capsule's sweep (collider_internal.h): the points within
 * r = radius + thickness of the segment a–b.
 *
 * The capsule is the union of three convex pieces: the two balls about a
 * and b and the cylinder around a–b between the planes through a and b
 * normal to the axis. The capsule itself is convex, so the part of the
 * move's line inside it is one interval, the union of the pieces'
 * intervals: it starts at the earliest entry among them. On a tie the ball
 * is taken (the cylinder's flat ends lie inside the balls, so a cylinder
 * entry through an end is never earlier). The outward normal anywhere is
 * the direction from the nearest point of the segment.
 *
 * Cylinder: with u the axis, m = from − a, d = to − from and ⊥ the parts
 * normal to u, |m⊥ + s d⊥|² = r² gives A s² + 2 B s + C = 0 (A = d⊥·d⊥,
 * B = m⊥·d⊥, C = m⊥·m⊥ − r²), clipped to 0 <= (m + s d)·u <= |b − a|. A
 * move along the axis (A = 0) is inside the infinite cylinder for every s
 * or for none. a == b is the ball about a. */
#include "kernels/contact/colliders/capsule.h"
#include "kernels/contact/colliders/sphere.h"
#include "kernels/contact/colliders/sweep.h"

#include <math.h>

static double sb_dot3(const double x[3], const double y[3]) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }

void sb_capsule_axis_normal(const double ab[3], double ab2, double normal[3]) {
    int e = fabs(ab[0]) <= fabs(ab[1]) && fabs(ab[0]) <= fabs(ab[2]) ? 0 : fabs(ab[1]) <= fabs(ab[2]) ? 1 : 2;
    double n[3] = {0.0, 0.0, 0.0};
    n[e] = 1.0;
    double along = n[e] * ab[e] / ab2;
    for (int k = 0; k < 3; k++) n[k] -= along * ab[k];
    double length = sqrt(sb_dot3(n, n));
    for (int k = 0; k < 3; k++) normal[k] = n[k] / length;
}

/* The capsule at x; ab = b − a, ab2 = |ab|² > 0. */
static void sb_capsule_end(const double a[3], const double ab[3], double ab2, double r, const double x[3],
                           sb_sweep_end* end) {
    double ax[3] = {x[0] - a[0], x[1] - a[1], x[2] - a[2]};
    double tau = sb_dot3(ax, ab) / ab2;
    tau = tau < 0.0 ? 0.0 : tau > 1.0 ? 1.0 : tau;
    double v[3] = {ax[0] - tau * ab[0], ax[1] - tau * ab[1], ax[2] - tau * ab[2]};
    double distance = sqrt(sb_dot3(v, v));
    end->inside = distance <= r;
    end->depth = end->inside ? r - distance : 0.0;
    if (distance > 0.0) {
        for (int k = 0; k < 3; k++) end->normal[k] = v[k] / distance;
        return;
    }
    sb_capsule_axis_normal(ab, ab2, end->normal);
}

/* The roots s1 <= s2 of A s² + 2 B s + C (A > 0); false when they are not
 * two distinct reals. */
static bool sb_quadratic(double A, double B, double C, double* s1, double* s2) {
    double disc = B * B - A * C;
    if (!(disc > 0.0)) return false;
    double q = B <= 0.0 ? -B + sqrt(disc) : -B - sqrt(disc);
    *s1 = B <= 0.0 ? C / q : q / A;
    *s2 = B <= 0.0 ? q / A : C / q;
    return true;
}

/* The interval of the move's line inside the cylinder piece, and the
 * outward normal where it enters. */
static bool sb_cylinder_line(const double a[3], const double ab[3], double ab2, double r, const double from[3],
                             const double to[3], double* lo, double* hi, double normal[3]) {
    double length = sqrt(ab2), u[3] = {ab[0] / length, ab[1] / length, ab[2] / length}, m[3], d[3];
    for (int k = 0; k < 3; k++) {
        m[k] = from[k] - a[k];
        d[k] = to[k] - from[k];
    }
    double mu = sb_dot3(m, u), du = sb_dot3(d, u), mp[3], dp[3];
    for (int k = 0; k < 3; k++) {
        mp[k] = m[k] - mu * u[k];
        dp[k] = d[k] - du * u[k];
    }
    double A = sb_dot3(dp, dp), B = sb_dot3(mp, dp), C = sb_dot3(mp, mp) - r * r;
    double s1 = -INFINITY, s2 = INFINITY;
    if (A > 0.0 ? !sb_quadratic(A, B, C, &s1, &s2) : C > 0.0) return false;
    if (du != 0.0) { /* clip to the slab 0 <= (m + s d)·u <= length */
        double sa = -mu / du, sb = (length - mu) / du;
        s1 = fmax(s1, fmin(sa, sb));
        s2 = fmin(s2, fmax(sa, sb));
    } else if (mu < 0.0 || mu > length) {
        return false;
    }
    if (!(s1 <= s2)) return false;
    double p[3], s = isfinite(s1) ? s1 : 0.0; /* -inf: a zero move on the axis, which rounding left outside */
    for (int k = 0; k < 3; k++) p[k] = from[k] + s * d[k];
    sb_sweep_end at;
    sb_capsule_end(a, ab, ab2, r, p, &at);
    for (int k = 0; k < 3; k++) normal[k] = at.normal[k];
    *lo = s1;
    *hi = s2;
    return true;
}

/* The union of the pieces' intervals so far, and the normal at its start. */
typedef struct sb_capsule_union {
    bool entered;
    double lo, hi, normal[3];
} sb_capsule_union;

/* Adds a piece's interval; an entry no earlier than the current keeps its normal. */
static void sb_capsule_union_add(sb_capsule_union* line, double lo, double hi, const double normal[3]) {
    if (!line->entered || lo < line->lo) {
        line->lo = lo;
        for (int k = 0; k < 3; k++) line->normal[k] = normal[k];
    }
    if (!line->entered || hi > line->hi) line->hi = hi;
    line->entered = true;
}

bool sb_capsule_line(const double a[3], const double b[3], double r, const double from[3], const double to[3],
                     double* lo, double* hi, double normal[3]) {
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ab2 = sb_dot3(ab, ab);
    if (ab2 == 0.0) return sb_ball_line(a, r, from, to, lo, hi, normal);
    sb_capsule_union line = {false, 0.0, 0.0, {0.0, 0.0, 0.0}};
    double l, h, n[3];
    if (sb_ball_line(a, r, from, to, &l, &h, n)) sb_capsule_union_add(&line, l, h, n);
    if (sb_ball_line(b, r, from, to, &l, &h, n)) sb_capsule_union_add(&line, l, h, n);
    if (sb_cylinder_line(a, ab, ab2, r, from, to, &l, &h, n)) sb_capsule_union_add(&line, l, h, n);
    if (!line.entered) return false;
    *lo = line.lo;
    *hi = line.hi;
    for (int k = 0; k < 3; k++) normal[k] = line.normal[k];
    return true;
}

bool sb_capsule_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                      double* fraction, double* depth, double normal[3]) {
    double r = def->radius + thickness;
    double ab[3] = {def->b[0] - def->a[0], def->b[1] - def->a[1], def->b[2] - def->a[2]}, ab2 = sb_dot3(ab, ab);
    if (ab2 == 0.0) return sb_ball_sweep(def->a, r, from, to, fraction, depth, normal);
    sb_sweep_end e0, e1;
    sb_capsule_end(def->a, ab, ab2, r, from, &e0);
    sb_capsule_end(def->a, ab, ab2, r, to, &e1);
    if (e0.inside) return sb_sweep_from_inside(&e0, &e1, from, to, fraction, depth, normal);
    double lo = 0.0, hi = 0.0, n[3] = {0.0, 0.0, 0.0};
    bool entered = sb_capsule_line(def->a, def->b, r, from, to, &lo, &hi, n);
    return sb_sweep_from_outside(entered, lo, hi, n, &e1, fraction, depth, normal);
}
