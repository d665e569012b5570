/* Bounds of the built-in shapes over a step: the axis-aligned box around
 * the shape at its pose at t0 and at t1, inflated by its thickness. The
 * contact pass (kernels/contact/contact.c) skips every chunk of vertices, and then
 * every vertex, whose move lies outside it, so a collider costs nothing
 * where nothing is near it. A plane bounds a half-space: only one whose
 * normal lies along an axis is bounded (on that axis); a tilted plane is
 * infinite, and every vertex is asked about. The inner radius, last, is
 * how far a shape may move in a step (softbond/collider.h). */
#include "kernels/contact/colliders/bounds.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/contact/colliders/mesh_shape.h"

#include <math.h>

void sb_collider_set_bounds(sb_collider* c, const double lo[3], const double hi[3]) {
    for (int k = 0; k < 3; k++) {
        c->bounds[k] = lo ? lo[k] : -INFINITY;
        c->bounds[3 + k] = hi ? hi[k] : INFINITY;
    }
}

/* The rest-frame box around a shape (infinite where unbounded). */
static void sb_rest_box(const sb_collider* c, double lo[3], double hi[3]) {
    const sb_collider_def* d = &c->def;
    for (int k = 0; k < 3; k++) lo[k] = -INFINITY, hi[k] = INFINITY;
    switch (d->shape) {
    case SB_COLLIDER_PLANE: {
        int axis = -1;
        for (int k = 0; k < 3; k++)
            if (d->normal[k] != 0.0) axis = axis == -1 ? k : 3; /* 3: more than one: tilted */
        if (axis >= 0 && axis < 3) {                            /* the solid lies below the point along n */
            if (d->normal[axis] > 0.0)
                hi[axis] = d->point[axis];
            else
                lo[axis] = d->point[axis];
        }
        break;
    }
    case SB_COLLIDER_SPHERE:
        for (int k = 0; k < 3; k++) lo[k] = d->center[k] - d->radius, hi[k] = d->center[k] + d->radius;
        break;
    case SB_COLLIDER_CAPSULE:
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(d->a[k], d->b[k]) - d->radius;
            hi[k] = fmax(d->a[k], d->b[k]) + d->radius;
        }
        break;
    case SB_COLLIDER_BOX: /* the rotated box's extent along each axis: Σ |R_kj| h_j */
        for (int k = 0; k < 3; k++) {
            double e = 0.0;
            for (int j = 0; j < 3; j++) e += fabs(c->box_rotation[3 * k + j]) * d->half_extents[j];
            lo[k] = d->center[k] - e;
            hi[k] = d->center[k] + e;
        }
        break;
    case SB_COLLIDER_MESH: { /* the box around its vertices */
        double box[6];
        sb_mesh_shape_box(c->mesh, box);
        for (int k = 0; k < 3; k++) lo[k] = box[k], hi[k] = box[3 + k];
        break;
    }
    case SB_COLLIDER_SHAPE_COUNT: break;
    }
}

static bool sb_finite_box(const double a[3], const double b[3]) {
    return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]) && isfinite(b[0]) && isfinite(b[1]) && isfinite(b[2]);
}

static bool sb_no_rotation(const double pose[12]) {
    static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    for (int k = 0; k < 9; k++)
        if (pose[k] != identity[k]) return false;
    return true;
}

/* Grows [lo, hi] by the world box of the rest box [a, b] under a pose: a
 * finite box by its rotated extent; a half-space's box only when the pose
 * does not rotate it (else it is everywhere). */
static void sb_grow_by_pose(const double pose[12], const double a[3], const double b[3], double lo[3], double hi[3]) {
    bool finite = sb_finite_box(a, b), shifted = sb_no_rotation(pose);
    for (int i = 0; i < 3; i++) {
        double l = -INFINITY, h = INFINITY;
        if (finite) {
            double center = pose[9 + i], extent = 0.0;
            for (int j = 0; j < 3; j++) {
                center += pose[3 * i + j] * 0.5 * (a[j] + b[j]);
                extent += fabs(pose[3 * i + j]) * 0.5 * (b[j] - a[j]);
            }
            l = center - extent;
            h = center + extent;
        } else if (shifted) {
            l = a[i] + pose[9 + i];
            h = b[i] + pose[9 + i];
        }
        lo[i] = fmin(lo[i], l);
        hi[i] = fmax(hi[i], h);
    }
}

void sb_collider_step_bounds(sb_collider* c) {
    double a[3], b[3], lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    sb_rest_box(c, a, b);
    sb_grow_by_pose(c->pose0, a, b, lo, hi);
    sb_grow_by_pose(c->pose1, a, b, lo, hi);
    for (int k = 0; k < 3; k++) lo[k] -= c->def.thickness, hi[k] += c->def.thickness;
    sb_collider_set_bounds(c, lo, hi);
}

double sb_collider_inner_radius(const sb_collider* c) {
    const sb_collider_def* d = &c->def;
    double inner = INFINITY;
    switch (d->shape) {
    case SB_COLLIDER_SPHERE:
    case SB_COLLIDER_CAPSULE: inner = d->radius; break;
    case SB_COLLIDER_BOX: inner = fmin(d->half_extents[0], fmin(d->half_extents[1], d->half_extents[2])); break;
    case SB_COLLIDER_MESH: {
        double box[6];
        sb_mesh_shape_box(c->mesh, box);
        inner = 0.5 * fmin(box[3] - box[0], fmin(box[4] - box[1], box[5] - box[2]));
        break;
    }
    case SB_COLLIDER_PLANE: /* also a program's own collider, whose def is the default plane */
    case SB_COLLIDER_SHAPE_COUNT: return INFINITY;
    }
    return inner + d->thickness;
}
