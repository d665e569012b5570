/* The sphere's sweep (collider_internal.h): the ball of radius
 * r = radius + thickness about `center`.
 *
 * A move from + s d (d = to − from, m = from − center) meets the sphere
 * where |m + s d|² = r², i.e. a s² + 2 b s + c = 0 with a = d·d, b = m·d,
 * c = m·m − r². From outside (c > 0) the move can only enter while it
 * heads toward the center (b < 0) and the discriminant b² − a c is
 * positive (zero: a tangent move, which only touches). The entry root is
 * computed as c / (−b + √(b² − a c)), the form without cancellation; it
 * needs no division by a, so a zero-length move is safe (it returns
 * before: b = 0). */
#include "kernels/contact/colliders/sphere.h"
#include "kernels/contact/colliders/sweep.h"

#include <math.h>

/* The ball of radius r about center at x: inside or not, how deep, and the
 * outward normal (+z at the center itself, where every direction is as
 * short). */
static void sb_ball_end(const double center[3], double r, const double x[3], sb_sweep_end* end) {
    double v[3] = {x[0] - center[0], x[1] - center[1], x[2] - center[2]};
    double distance = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    end->inside = distance <= r;
    end->depth = end->inside ? r - distance : 0.0;
    for (int k = 0; k < 3; k++) end->normal[k] = distance > 0.0 ? v[k] / distance : (k == 2 ? 1.0 : 0.0);
}

bool sb_ball_line(const double center[3], double r, const double from[3], const double to[3], double* lo, double* hi,
                  double normal[3]) {
    double d[3], m[3];
    for (int k = 0; k < 3; k++) {
        d[k] = to[k] - from[k];
        m[k] = from[k] - center[k];
    }
    double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], b = m[0] * d[0] + m[1] * d[1] + m[2] * d[2];
    double c = m[0] * m[0] + m[1] * m[1] + m[2] * m[2] - r * r, disc = b * b - a * c;
    if (!(b < 0.0 && disc > 0.0)) return false;
    double q = -b + sqrt(disc);
    *lo = c / q;
    *hi = q / a;
    double p[3];
    for (int k = 0; k < 3; k++) p[k] = m[k] + *lo * d[k];
    double length = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    for (int k = 0; k < 3; k++) normal[k] = p[k] / length;
    return true;
}

bool sb_ball_sweep(const double center[3], double r, const double from[3], const double to[3], double* fraction,
                   double* depth, double normal[3]) {
    sb_sweep_end a, b;
    sb_ball_end(center, r, from, &a);
    sb_ball_end(center, r, to, &b);
    if (a.inside) return sb_sweep_from_inside(&a, &b, from, to, fraction, depth, normal);
    double lo = 0.0, hi = 0.0, n[3] = {0.0, 0.0, 0.0};
    bool entered = sb_ball_line(center, r, from, to, &lo, &hi, n);
    return sb_sweep_from_outside(entered, lo, hi, n, &b, fraction, depth, normal);
}

bool sb_sphere_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                     double* fraction, double* depth, double normal[3]) {
    return sb_ball_sweep(def->center, def->radius + thickness, from, to, fraction, depth, normal);
}
