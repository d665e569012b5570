/* The plane's sweep (collider_internal.h): the half-space below the plane
 * through `point` with the unit normal n̂ = normal / |normal|, inflated by
 * the thickness t, i.e. the points with f(x) = n̂·(x − point) − t <= 0.
 * f is linear along the move, so a move from outside (f0 > 0) to inside
 * (f1 <= 0) enters at fraction f0 / (f0 − f1), which lies in (0, 1] and
 * needs no division by the move's length; a move with both ends outside
 * never enters a half-space. */
#include "kernels/contact/colliders/plane.h"
#include "kernels/contact/colliders/sweep.h"

#include <math.h>

/* The plane's end of a move, and its signed distance f. */
static double sb_plane_end(const double n[3], const sb_collider_def* def, const double x[3], double thickness,
                           sb_sweep_end* end) {
    double f =
        n[0] * (x[0] - def->point[0]) + n[1] * (x[1] - def->point[1]) + n[2] * (x[2] - def->point[2]) - thickness;
    end->inside = f <= 0.0;
    end->depth = end->inside ? -f : 0.0;
    for (int k = 0; k < 3; k++) end->normal[k] = n[k];
    return f;
}

bool sb_plane_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                    double* fraction, double* depth, double normal[3]) {
    const double* m = def->normal;
    double length = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    double n[3] = {m[0] / length, m[1] / length, m[2] / length};
    sb_sweep_end a, b;
    double f0 = sb_plane_end(n, def, from, thickness, &a), f1 = sb_plane_end(n, def, to, thickness, &b);
    if (a.inside) return sb_sweep_from_inside(&a, &b, from, to, fraction, depth, normal);
    if (!b.inside) return false;
    double lo = f0 / (f0 - f1);
    return sb_sweep_from_outside(true, lo, INFINITY, n, &b, fraction, depth, normal);
}
