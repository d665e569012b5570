/* The box's sweep (collider_internal.h): `center`, `half_extents` h and
 * `rotate` (degrees about x, then y, then z: the box's axes are the columns
 * of R), inflated by the thickness t as the box of half extents h + t. That
 * box has square edges and corners where the exact inflated surface (the
 * points within t of the box) has rounded ones: near an edge or a corner a
 * vertex is stopped up to (√3 − 1) t further out than the exact surface
 * would stop it, which for a thickness meant to keep a mesh off a surface
 * is harmless.
 *
 * In the box's frame (x' = Rᵀ (x − center)) the move is clipped against the
 * three slabs |x'_k| <= h_k + t (the slab test): the move's line is inside
 * the box for s in [max of the slabs' entries, min of their exits], and the
 * normal at the entry is that of the face whose slab was entered last. A
 * move parallel to a slab (no division) is inside it for every s or for
 * none. Inside the box the direction of least penetration is the face
 * nearest the point (on a tie the lowest axis, then the + face). */
#include "kernels/contact/colliders/box.h"
#include "kernels/contact/colliders/sweep.h"
#include "kernels/contact/colliders/rotation.h"

#include <math.h>

/* The box's frame: H = half extents + thickness, the rotation and the point. */
typedef struct sb_box_frame {
    double h[3], r[9];
    const double* center;
} sb_box_frame;

static void sb_box_local(const sb_box_frame* b, const double x[3], double out[3]) {
    double v[3] = {x[0] - b->center[0], x[1] - b->center[1], x[2] - b->center[2]};
    for (int i = 0; i < 3; i++) out[i] = b->r[i] * v[0] + b->r[3 + i] * v[1] + b->r[6 + i] * v[2];
}

/* The world normal of the face `sign` e_axis. */
static void sb_box_face(const sb_box_frame* b, int axis, double sign, double normal[3]) {
    for (int k = 0; k < 3; k++) normal[k] = sign * b->r[3 * k + axis];
}

static void sb_box_end(const sb_box_frame* b, const double local[3], sb_sweep_end* end) {
    int axis = 0;
    double least = INFINITY;
    end->inside = true;
    for (int k = 0; k < 3; k++) {
        double room = b->h[k] - fabs(local[k]);
        if (room < 0.0) end->inside = false;
        if (room < least) least = room, axis = k;
    }
    end->depth = end->inside ? least : 0.0;
    sb_box_face(b, axis, local[axis] < 0.0 ? -1.0 : 1.0, end->normal);
}

/* The slab test of the line m + s d (box frame); the normal at the entry. */
static bool sb_box_line(const sb_box_frame* b, const double m[3], const double d[3], double* lo, double* hi,
                        double normal[3]) {
    double s1 = -INFINITY, s2 = INFINITY;
    int axis = -1;
    double sign = 1.0;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0.0) {
            if (fabs(m[k]) > b->h[k]) return false;
            continue;
        }
        double enter = (-copysign(b->h[k], d[k]) - m[k]) / d[k], leave = (copysign(b->h[k], d[k]) - m[k]) / d[k];
        if (enter > s1) s1 = enter, axis = k, sign = d[k] > 0.0 ? -1.0 : 1.0;
        if (leave < s2) s2 = leave;
    }
    if (axis < 0 || !(s1 <= s2)) return false;
    *lo = s1;
    *hi = s2;
    sb_box_face(b, axis, sign, normal);
    return true;
}

bool sb_box_sweep_rotated(const sb_collider_def* def, const double rotation[9], const double from[3],
                          const double to[3], double thickness, double* fraction, double* depth, double normal[3]) {
    sb_box_frame b;
    for (int k = 0; k < 3; k++) b.h[k] = def->half_extents[k] + thickness;
    for (int k = 0; k < 9; k++) b.r[k] = rotation[k];
    b.center = def->center;
    double m[3], t[3], d[3];
    sb_box_local(&b, from, m);
    sb_box_local(&b, to, t);
    sb_sweep_end e0, e1;
    sb_box_end(&b, m, &e0);
    sb_box_end(&b, t, &e1);
    if (e0.inside) return sb_sweep_from_inside(&e0, &e1, from, to, fraction, depth, normal);
    for (int k = 0; k < 3; k++) d[k] = t[k] - m[k];
    double lo = 0.0, hi = 0.0, n[3] = {0.0, 0.0, 0.0};
    bool entered = sb_box_line(&b, m, d, &lo, &hi, n);
    return sb_sweep_from_outside(entered, lo, hi, n, &e1, fraction, depth, normal);
}

bool sb_box_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                  double* fraction, double* depth, double normal[3]) {
    double rotation[9];
    sb_collider_rotation(def->rotate, rotation);
    return sb_box_sweep_rotated(def, rotation, from, to, thickness, fraction, depth, normal);
}

int sb_box_axes_facing(const double rotation[9], int a, int b) {
    const double* r = rotation;
    double dot = r[b] * r[a] + r[3 + b] * r[3 + a] + r[6 + b] * r[6 + a];
    return dot > 0.0 ? 1 : dot < 0.0 ? -1 : 0;
}
