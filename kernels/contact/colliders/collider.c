/* Colliders (softbond/collider.h): making them, their poses, and the
 * built-in collide callback.
 *
 * Design. A built-in collider keeps its def as given (its rest frame, in
 * world coordinates) and, when it has a path, a rigid pose per time:
 *
 *   pose(t)(x) = R (x − c) + c + T
 *
 * with c the reference point (plane point, sphere or box center, capsule
 * midpoint of a–b, the center of a mesh's bounding box), R the rotation of `rotate` degrees about x, then y,
 * then z (fixed axes: R = Rz Ry Rx) and T `translate`, both interpolated
 * componentwise between keyframes (linearly, or with the smoothstep weight
 * 3s² − 2s³ of the interval's s); before the first keyframe and after the
 * last the pose holds. Without a path the pose is the identity.
 *
 * begin_step sets pose0 = pose(t0) and pose1 = pose(t1); collide maps the
 * vertex's start through pose0⁻¹ and its end through pose1⁻¹, so the shape
 * sweeps the move relative to itself in its rest frame (a vertex at rest hit
 * by a moving collider is a contact), then maps the answer back: the normal
 * by pose1's rotation; the collider's velocity at the rest-frame contact
 * point p as (pose1(p) − pose0(p)) / (t1 − t0). For a collider that moves
 * during the step, the depth is measured where the solver puts the vertex
 * (from + fraction (to − from), in the world at t1), so that the push out
 * along the normal brings it onto the surface as the collider stands at t1;
 * for one that does not, it is the sweep's depth exactly.
 *
 * collide only reads the collider, so the solver's threads may call it at
 * once; begin_step (the stepping thread, before them) is the only writer.
 * Before the first begin_step both poses are pose(0). A dynamic collider
 * (mass > 0) takes its poses from its state instead (dynamic.c). */
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/contact/colliders/bounds.h"
#include "kernels/contact/colliders/box.h"
#include "kernels/contact/colliders/capsule.h"
#include "kernels/contact/colliders/dynamic.h"
#include "kernels/contact/colliders/mesh_shape.h"
#include "kernels/contact/colliders/plane.h"
#include "kernels/contact/colliders/sphere.h"
#include "kernels/contact/colliders/rotation.h"
#include "kernels/contact/colliders/triangle_point.h"
#include "common/geometry.h"
#include "common/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char* const sb_shape_names[SB_COLLIDER_SHAPE_COUNT] = {"plane", "sphere", "capsule", "box", "mesh"};

sb_collider_def sb_default_collider_def(void) {
    sb_collider_def d;
    memset(&d, 0, sizeof d);
    d.shape = SB_COLLIDER_PLANE;
    d.normal[2] = 1.0;
    d.interpolation = SB_INTERPOLATION_LINEAR;
    return d;
}

const char* sb_collider_shape_name(sb_collider_shape shape) {
    return (unsigned)shape < SB_COLLIDER_SHAPE_COUNT ? sb_shape_names[shape] : "unknown";
}

bool sb_collider_shape_from_name(const char* name, sb_collider_shape* out) {
    if (!name) return false;
    for (int s = 0; s < SB_COLLIDER_SHAPE_COUNT; s++) {
        if (strcmp(name, sb_shape_names[s]) == 0) {
            if (out) *out = (sb_collider_shape)s;
            return true;
        }
    }
    return false;
}

const char* sb_collider_name(const sb_collider* collider) { return collider ? collider->name : NULL; }

/* ---- checking a def ----------------------------------------------------- */

/* The vector must be finite (and, when `positive`, each component > 0). */
static sb_status sb_check_vector(const char* label, const char* field, const double v[3], bool positive,
                                 sb_error* err) {
    bool ok = sb_finite3(v) && (!positive || (v[0] > 0.0 && v[1] > 0.0 && v[2] > 0.0));
    if (ok) return SB_OK;
    return sb_error_set(err, SB_ERR_INVALID, "collider '%s': %s must be %s (got %g, %g, %g)", label, field,
                        positive ? "positive and finite" : "finite", v[0], v[1], v[2]);
}

static sb_status sb_check_radius(const char* label, double radius, sb_error* err) {
    if (isfinite(radius) && radius > 0.0) return SB_OK;
    return sb_error_set(err, SB_ERR_INVALID, "collider '%s': radius must be positive and finite (got %g)", label,
                        radius);
}

static sb_status sb_check_geometry(const char* label, const sb_collider_def* d, sb_error* err) {
    sb_status st = SB_OK;
    switch (d->shape) {
    case SB_COLLIDER_PLANE:
        if ((st = sb_check_vector(label, "point", d->point, false, err))) return st;
        if (sb_finite3(d->normal) && (d->normal[0] != 0.0 || d->normal[1] != 0.0 || d->normal[2] != 0.0)) return SB_OK;
        return sb_error_set(err, SB_ERR_INVALID, "collider '%s': normal must be finite and not zero (got %g, %g, %g)",
                            label, d->normal[0], d->normal[1], d->normal[2]);
    case SB_COLLIDER_SPHERE:
        if ((st = sb_check_vector(label, "center", d->center, false, err))) return st;
        return sb_check_radius(label, d->radius, err);
    case SB_COLLIDER_CAPSULE:
        if ((st = sb_check_vector(label, "a", d->a, false, err))) return st;
        if ((st = sb_check_vector(label, "b", d->b, false, err))) return st;
        return sb_check_radius(label, d->radius, err);
    case SB_COLLIDER_BOX:
        if ((st = sb_check_vector(label, "center", d->center, false, err))) return st;
        if ((st = sb_check_vector(label, "half_extents", d->half_extents, true, err))) return st;
        return sb_check_vector(label, "rotate", d->rotate, false, err);
    case SB_COLLIDER_MESH: return SB_OK; /* its triangles are checked as its hierarchy is built */
    case SB_COLLIDER_SHAPE_COUNT: break;
    }
    return sb_error_set(err, SB_ERR_INVALID,
                        "collider '%s': shape must be plane, sphere, capsule, box or mesh (got %d)", label,
                        (int)d->shape);
}

/* friction, static_friction (after the default), restitution, thickness, footprint. */
static sb_status sb_check_surface(const char* label, const sb_collider_def* d, double static_friction, sb_error* err) {
    if (!(isfinite(d->friction) && d->friction >= 0.0))
        return sb_error_set(err, SB_ERR_INVALID, "collider '%s': friction must be >= 0 and finite (got %g)", label,
                            d->friction);
    if (!(isfinite(static_friction) && static_friction >= d->friction))
        return sb_error_set(err, SB_ERR_INVALID,
                            "collider '%s': static_friction must be >= friction (%g) and finite (got %g)", label,
                            d->friction, static_friction);
    if (!(d->restitution >= 0.0 && d->restitution <= 1.0))
        return sb_error_set(err, SB_ERR_INVALID, "collider '%s': restitution must be in [0, 1] (got %g)", label,
                            d->restitution);
    if (!(isfinite(d->thickness) && d->thickness >= 0.0))
        return sb_error_set(err, SB_ERR_INVALID, "collider '%s': thickness must be >= 0 and finite (got %g)", label,
                            d->thickness);
    if (!(isfinite(d->footprint) && d->footprint >= 0.0))
        return sb_error_set(err, SB_ERR_INVALID, "collider '%s': footprint must be >= 0 and finite (got %g)", label,
                            d->footprint);
    if (d->footprint > 0.0 && d->shape == SB_COLLIDER_PLANE)
        return sb_error_set(err, SB_ERR_INVALID,
                            "collider '%s': a plane stops the vertices only and has no footprint (got %g m)", label,
                            d->footprint);
    return SB_OK;
}

static sb_status sb_check_keyframe(const char* owner, const sb_keyframe* path, uint32_t k, sb_error* err) {
    const sb_keyframe* f = &path[k];
    if (!isfinite(f->time))
        return sb_error_set(err, SB_ERR_INVALID, "%s: path[%u].time must be finite (got %g)", owner, k, f->time);
    if (k > 0 && !(f->time > path[k - 1].time))
        return sb_error_set(err, SB_ERR_INVALID, "%s: path[%u].time must be greater than path[%u].time (%g) (got %g)",
                            owner, k, k - 1, path[k - 1].time, f->time);
    const char* fields[2] = {"translate", "rotate"};
    const double* values[2] = {f->translate, f->rotate};
    for (int q = 0; q < 2; q++)
        if (!sb_finite3(values[q]))
            return sb_error_set(err, SB_ERR_INVALID, "%s: path[%u].%s must be finite (got %g, %g, %g)", owner, k,
                                fields[q], values[q][0], values[q][1], values[q][2]);
    return SB_OK;
}

sb_status sb_path_check(const char* owner, const sb_keyframe* path, uint32_t count, sb_interpolation interpolation,
                        sb_error* err) {
    if (interpolation != SB_INTERPOLATION_LINEAR && interpolation != SB_INTERPOLATION_SMOOTH)
        return sb_error_set(err, SB_ERR_INVALID, "%s: interpolation must be linear or smooth (got %d)", owner,
                            (int)interpolation);
    if (count > 0 && !path)
        return sb_error_set(err, SB_ERR_INVALID, "%s: path_count is %u but path is NULL", owner, count);
    for (uint32_t k = 0; k < count; k++) {
        sb_status st = sb_check_keyframe(owner, path, k, err);
        if (st) return st;
    }
    return SB_OK;
}

static sb_status sb_check_path(const char* label, const sb_collider_def* d, sb_error* err) {
    char owner[80];
    snprintf(owner, sizeof owner, "collider '%s'", label);
    return sb_path_check(owner, d->path, d->path_count, d->interpolation, err);
}

/* mass, velocity and angular velocity: a dynamic collider is a sphere or
 * box without a path. */
static sb_status sb_check_dynamic(const char* label, const sb_collider_def* d, sb_error* err) {
    if (!(isfinite(d->mass) && d->mass >= 0.0))
        return sb_error_set(err, SB_ERR_INVALID, "collider '%s': mass must be >= 0 and finite (got %g)", label,
                            d->mass);
    if (d->mass == 0.0) return SB_OK;
    if (d->shape != SB_COLLIDER_SPHERE && d->shape != SB_COLLIDER_BOX)
        return sb_error_set(err, SB_ERR_INVALID,
                            "collider '%s': a %s cannot be dynamic (mass %g); only a sphere or box", label,
                            sb_collider_shape_name(d->shape), d->mass);
    if (d->path_count > 0)
        return sb_error_set(err, SB_ERR_INVALID, "collider '%s': a dynamic collider (mass %g) cannot have a path",
                            label, d->mass);
    sb_status st = sb_check_vector(label, "velocity", d->velocity, false, err);
    return st ? st : sb_check_vector(label, "angular_velocity", d->angular_velocity, false, err);
}

/* ---- making and destroying ---------------------------------------------- */

/* name, or `fallback` when it is NULL or empty, truncated to fit. */
static void sb_copy_name(char out[64], const char* name, const char* fallback) {
    snprintf(out, 64, "%s", name && name[0] ? name : fallback);
}

static void sb_builtin_begin_step(void* user, double t0, double t1);
static bool sb_builtin_collide(void* user, const sb_contact_query* query, sb_contact* contact);

/* A mesh collider keeps its own copy: def.mesh points at it, and its
 * reference point (def.center) is the center of its bounding box. */
static void sb_mesh_attach(sb_collider* c, sb_mesh_shape* mesh) {
    double box[6];
    c->mesh = mesh;
    c->def.mesh = sb_mesh_shape_mesh(mesh);
    sb_mesh_shape_box(mesh, box);
    for (int k = 0; k < 3; k++) c->def.center[k] = 0.5 * (box[k] + box[3 + k]);
}

sb_collider* sb_collider_create(const sb_collider_def* def, sb_error* err) {
    if (!def) {
        sb_error_set(err, SB_ERR_INVALID, "collider: no definition (def is NULL)");
        return NULL;
    }
    char label[64];
    sb_copy_name(label, def->name, (unsigned)def->shape < SB_COLLIDER_SHAPE_COUNT ? sb_shape_names[def->shape] : "?");
    double static_friction = def->static_friction == 0.0 && def->friction > 0.0 ? def->friction : def->static_friction;
    if (sb_check_geometry(label, def, err) || sb_check_surface(label, def, static_friction, err) ||
        sb_check_path(label, def, err) || sb_check_dynamic(label, def, err))
        return NULL;
    sb_mesh_shape* mesh = NULL;
    if (def->shape == SB_COLLIDER_MESH && !(mesh = sb_mesh_shape_create(label, def->mesh, def->thickness, err)))
        return NULL;
    sb_collider* c = calloc(1, sizeof *c);
    sb_keyframe* path = def->path_count ? malloc(def->path_count * sizeof *path) : NULL;
    if (!c || (def->path_count && !path)) {
        free(c);
        free(path);
        sb_mesh_shape_destroy(mesh);
        sb_error_set(err, SB_ERR_NOMEM, "collider '%s': out of memory", label);
        return NULL;
    }
    if (path) memcpy(path, def->path, def->path_count * sizeof *path);
    memcpy(c->name, label, sizeof c->name);
    c->def = *def;
    c->def.name = c->name;
    c->def.static_friction = static_friction;
    c->def.path = c->path = path;
    c->collide = sb_builtin_collide;
    c->begin_step = sb_builtin_begin_step;
    c->user = c;
    if (def->shape == SB_COLLIDER_BOX) sb_collider_rotation(def->rotate, c->box_rotation);
    if (mesh) sb_mesh_attach(c, mesh);
    c->dynamic = def->mass > 0.0;
    if (c->dynamic) sb_dynamic_init(c);
    sb_builtin_begin_step(c, 0.0, 0.0);
    return c;
}

sb_collider* sb_collider_create_custom(const char* name, sb_collide_fn collide, sb_collider_step_fn begin_step,
                                       void* user, sb_error* err) {
    char label[64];
    sb_copy_name(label, name, "custom");
    if (!collide) {
        sb_error_set(err, SB_ERR_INVALID, "collider '%s': collide callback is required (got NULL)", label);
        return NULL;
    }
    sb_collider* c = calloc(1, sizeof *c);
    if (!c) {
        sb_error_set(err, SB_ERR_NOMEM, "collider '%s': out of memory", label);
        return NULL;
    }
    memcpy(c->name, label, sizeof c->name);
    c->collide = collide;
    c->begin_step = begin_step;
    c->user = user;
    sb_collider_set_bounds(c, NULL, NULL);
    c->def = sb_default_collider_def();
    c->def.name = c->name;
    return c;
}

void sb_collider_destroy(sb_collider* collider) {
    if (!collider) return;
    free(collider->path);
    sb_mesh_shape_destroy(collider->mesh);
    free(collider);
}

/* ---- poses --------------------------------------------------------------- */

/* The point the rotations of a path turn about. */
static void sb_reference_point(const sb_collider_def* d, double c[3]) {
    for (int k = 0; k < 3; k++) {
        switch (d->shape) {
        case SB_COLLIDER_PLANE: c[k] = d->point[k]; break;
        case SB_COLLIDER_CAPSULE: c[k] = 0.5 * (d->a[k] + d->b[k]); break;
        default: c[k] = d->center[k]; break;
        }
    }
}

/* The interpolated keyframe of a path at time t. */
static void sb_path_at(const sb_keyframe* p, uint32_t n, sb_interpolation interpolation, double t, double translate[3],
                       double rotate[3]) {
    uint32_t k = 0;
    while (k + 1 < n && p[k + 1].time <= t) k++;
    double w = 0.0;
    if (k + 1 < n && t > p[k].time) {
        double s = (t - p[k].time) / (p[k + 1].time - p[k].time);
        w = interpolation == SB_INTERPOLATION_SMOOTH ? s * s * (3.0 - 2.0 * s) : s;
    }
    const sb_keyframe* q = k + 1 < n ? &p[k + 1] : &p[k];
    for (int i = 0; i < 3; i++) {
        translate[i] = p[k].translate[i] + w * (q->translate[i] - p[k].translate[i]);
        rotate[i] = p[k].rotate[i] + w * (q->rotate[i] - p[k].rotate[i]);
    }
}

void sb_pose_from(const double translate[3], const double rotate[3], const double center[3], double pose[12]) {
    sb_collider_rotation(rotate, pose);
    const double* c = center;
    for (int i = 0; i < 3; i++)
        pose[9 + i] = c[i] - (pose[3 * i] * c[0] + pose[3 * i + 1] * c[1] + pose[3 * i + 2] * c[2]) + translate[i];
}

void sb_path_pose(const sb_keyframe* path, uint32_t count, sb_interpolation interpolation, const double center[3],
                  double t, double pose[12]) {
    static const double identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    memcpy(pose, identity, sizeof identity);
    if (count == 0 || !path) return;
    double translate[3], rotate[3];
    sb_path_at(path, count, interpolation, t, translate, rotate);
    sb_pose_from(translate, rotate, center, pose);
}

void sb_collider_pose(const sb_collider* collider, double t, double pose[12]) {
    const sb_collider_def* d = &collider->def;
    double c[3];
    sb_reference_point(d, c);
    sb_path_pose(d->path, d->path_count, d->interpolation, c, t, pose);
}

/* y = pose(x) */
void sb_pose_apply(const double pose[12], const double x[3], double y[3]) {
    for (int i = 0; i < 3; i++)
        y[i] = pose[3 * i] * x[0] + pose[3 * i + 1] * x[1] + pose[3 * i + 2] * x[2] + pose[9 + i];
}

/* x = pose⁻¹(y) = Rᵀ (y − translation) */
static void sb_pose_invert(const double pose[12], const double y[3], double x[3]) {
    double r[3] = {y[0] - pose[9], y[1] - pose[10], y[2] - pose[11]};
    for (int i = 0; i < 3; i++) x[i] = pose[i] * r[0] + pose[3 + i] * r[1] + pose[6 + i] * r[2];
}

/* ---- the built-in callbacks --------------------------------------------- */

static void sb_builtin_begin_step(void* user, double t0, double t1) {
    sb_collider* c = user;
    if (c->dynamic) {
        sb_dynamic_begin_step(c, t0, t1);
    } else if (c->driven) { /* from where the last step left it to where the program put it */
        memcpy(c->pose0, c->pose1, sizeof c->pose0);
        memcpy(c->pose1, c->driven_pose, sizeof c->pose1);
    } else {
        sb_collider_pose(c, t0, c->pose0);
        sb_collider_pose(c, t1, c->pose1);
    }
    c->t0 = t0;
    c->t1 = t1;
    sb_collider_step_bounds(c);
}

bool sb_collider_is_static_builtin(const sb_collider* c) {
    /* its own user: a program's collider that wraps a built-in one's
     * callback (user: that collider) is answered through the callback, not
     * by its own def, which is the default's */
    return c->collide == sb_builtin_collide && c->user == c && !c->path && !c->driven && !c->dynamic;
}

/* The shape's sweep in its rest frame. */
static bool sb_shape_sweep(const sb_collider* c, const double from[3], const double to[3], double thickness,
                           double* fraction, double* depth, double normal[3]) {
    const sb_collider_def* d = &c->def;
    switch (d->shape) {
    case SB_COLLIDER_PLANE: return sb_plane_sweep(d, from, to, thickness, fraction, depth, normal);
    case SB_COLLIDER_SPHERE: return sb_sphere_sweep(d, from, to, thickness, fraction, depth, normal);
    case SB_COLLIDER_CAPSULE: return sb_capsule_sweep(d, from, to, thickness, fraction, depth, normal);
    case SB_COLLIDER_BOX: return sb_box_sweep_rotated(d, c->box_rotation, from, to, thickness, fraction, depth, normal);
    case SB_COLLIDER_MESH: return sb_mesh_sweep(c->mesh, from, to, thickness, fraction, depth, normal);
    case SB_COLLIDER_SHAPE_COUNT: break;
    }
    return false;
}

/* How far a rest-frame point lies inside the inflated surface (0 outside). */
static double sb_point_depth(const sb_collider* c, const double x[3], double thickness) {
    double fraction, depth, normal[3];
    return sb_shape_sweep(c, x, x, thickness, &fraction, &depth, normal) ? depth : 0.0;
}

/* The answer's surface constants. */
static void sb_surface(const sb_collider* c, double fraction, double depth, sb_contact* contact) {
    contact->fraction = fraction;
    contact->depth = depth;
    contact->restitution = c->def.restitution;
    contact->friction = c->def.friction;
    contact->static_friction = c->def.static_friction;
}

static bool sb_builtin_collide(void* user, const sb_contact_query* q, sb_contact* contact) {
    const sb_collider* c = user;
    double from[3], to[3], normal[3], fraction, depth, thickness = c->def.thickness + q->thickness;
    if (sb_collider_is_static_builtin(c)) { /* the rest frame is the world */
        if (!sb_shape_sweep(c, q->from, q->to, thickness, &fraction, &depth, contact->normal)) return false;
        memset(contact->velocity, 0, sizeof contact->velocity);
        for (int k = 0; k < 3; k++)
            contact->point[k] = q->from[k] + fraction * (q->to[k] - q->from[k]) + depth * contact->normal[k];
        sb_surface(c, fraction, depth, contact);
        return true;
    }
    sb_pose_invert(c->pose0, q->from, from);
    sb_pose_invert(c->pose1, q->to, to);
    if (!sb_shape_sweep(c, from, to, thickness, &fraction, &depth, normal)) return false;
    bool moving = c->t1 > c->t0 && memcmp(c->pose0, c->pose1, sizeof c->pose0) != 0;
    double p[3], at0[3], at1[3], surface[3];
    for (int k = 0; k < 3; k++) {
        p[k] = from[k] + fraction * (to[k] - from[k]);
        surface[k] = p[k] + depth * normal[k]; /* the point of the surface met, in the rest frame */
    }
    sb_pose_apply(c->pose0, p, at0);
    sb_pose_apply(c->pose1, p, at1);
    sb_pose_apply(c->pose1, surface, contact->point);
    for (int k = 0; k < 3; k++) {
        contact->normal[k] =
            c->pose1[3 * k] * normal[0] + c->pose1[3 * k + 1] * normal[1] + c->pose1[3 * k + 2] * normal[2];
        contact->velocity[k] = moving ? (at1[k] - at0[k]) / (c->t1 - c->t0) : 0.0;
    }
    if (moving) { /* the depth where the solver puts the vertex, against the collider at t1 */
        double w[3], rest[3];
        for (int k = 0; k < 3; k++) w[k] = q->from[k] + fraction * (q->to[k] - q->from[k]);
        sb_pose_invert(c->pose1, w, rest);
        depth = sb_point_depth(c, rest, thickness);
    }
    sb_surface(c, fraction, depth, contact);
    return true;
}

/* The nearest material point of a triangle (rest frame) to the box's
 * edges: each edge is a core of the thickness's radius; the nearest of
 * the twelve. */
static void sb_box_triangle_point(const sb_collider* c, const double from[3][3], const double to[3][3], double w[3]) {
    const double *h = c->def.half_extents, *r = c->box_rotation;
    double corner[8][3], best = INFINITY, cw[3];
    for (int i = 0; i < 8; i++) {
        double local[3] = {i & 1 ? h[0] : -h[0], i & 2 ? h[1] : -h[1], i & 4 ? h[2] : -h[2]};
        for (int k = 0; k < 3; k++)
            corner[i][k] = c->def.center[k] + r[3 * k] * local[0] + r[3 * k + 1] * local[1] + r[3 * k + 2] * local[2];
    }
    for (int i = 0; i < 8; i++)
        for (int axis = 1; axis < 8; axis <<= 1) { /* the edges from each corner along +x, +y, +z */
            if (i & axis) continue;
            double d2 = sb_triangle_swept_nearest(from, to, corner[i], corner[i | axis], cw);
            if (!(d2 < best)) continue;
            best = d2;
            for (int k = 0; k < 3; k++) w[k] = cw[k];
        }
}

/* How far from a triangle (its corners at the end of the step) a mesh's
 * ridge is asked about: its longest edge and the shell's thickness (the
 * collider's answer then says whether the point is in contact). */
static double sb_ridge_reach(const sb_collider* c, const double t[3][3]) {
    double longest = 0.0;
    for (int i = 0; i < 3; i++) {
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) d2 += (t[(i + 1) % 3][k] - t[i][k]) * (t[(i + 1) % 3][k] - t[i][k]);
        longest = fmax(longest, sqrt(d2));
    }
    return longest + c->def.thickness;
}

/* Whether a program's callback gave usable weights. */
static bool sb_weights_valid(const double w[3]) {
    double sum = 0.0;
    for (int k = 0; k < 3; k++) {
        if (!(isfinite(w[k]) && w[k] >= 0.0)) return false;
        sum += w[k];
    }
    return fabs(sum - 1.0) <= 1e-6;
}

bool sb_collider_triangle_point(const sb_collider* c, const double from[3][3], const double to[3][3], double w[3]) {
    if (c->begin_step != sb_builtin_begin_step)
        return c->triangle_point && c->triangle_point(c->user, from, to, w) && sb_weights_valid(w);
    const sb_collider_def* d = &c->def;
    if (!sb_collider_meets_surface(c)) return false;
    double a[3][3], b[3][3];
    for (int i = 0; i < 3; i++) {
        sb_pose_invert(c->pose0, from[i], a[i]);
        sb_pose_invert(c->pose1, to[i], b[i]);
    }
    if (d->shape == SB_COLLIDER_SPHERE) sb_triangle_swept_nearest(a, b, d->center, d->center, w);
    if (d->shape == SB_COLLIDER_CAPSULE) sb_triangle_swept_nearest(a, b, d->a, d->b, w);
    if (d->shape == SB_COLLIDER_BOX) sb_box_triangle_point(c, a, b, w);
    if (d->shape == SB_COLLIDER_MESH) return sb_mesh_triangle_point(c->mesh, a, b, sb_ridge_reach(c, b), w);
    return true;
}

void sb_collider_set_triangle_point(sb_collider* c, sb_triangle_point_fn triangle_point) {
    if (c && c->begin_step != sb_builtin_begin_step) c->triangle_point = triangle_point;
}

/* The ball around points p[0..count) grown by `grow`. */
static void sb_ball_around(const double (*p)[3], int count, double grow, double center[3], double* radius) {
    double far = 0.0;
    for (int k = 0; k < 3; k++) {
        center[k] = 0.0;
        for (int i = 0; i < count; i++) center[k] += p[i][k] / count;
    }
    for (int i = 0; i < count; i++) {
        double d[3] = {p[i][0] - center[0], p[i][1] - center[1], p[i][2] - center[2]};
        far = fmax(far, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
    }
    *radius = far + grow;
}

/* The ball around a program's own collider's bounds (infinite where they are). */
static void sb_bounds_ball(const sb_collider* c, double center[3], double* radius) {
    double corners[2][3];
    for (int k = 0; k < 3; k++) corners[0][k] = c->bounds[k], corners[1][k] = c->bounds[3 + k];
    sb_ball_around((const double(*)[3])corners, 2, 0.0, center, radius);
    if (!isfinite(*radius)) center[0] = center[1] = center[2] = 0.0, *radius = INFINITY;
}

void sb_collider_surface_ball(const sb_collider* c, double center[3], double* radius) {
    const sb_collider_def* d = &c->def;
    double core[8][3], at[16][3];
    int count = 0;
    if (c->begin_step != sb_builtin_begin_step) {
        sb_bounds_ball(c, center, radius);
        return;
    }
    if (d->shape == SB_COLLIDER_SPHERE) {
        for (int k = 0; k < 3; k++) core[0][k] = d->center[k];
        count = 1;
    } else if (d->shape == SB_COLLIDER_CAPSULE) {
        for (int k = 0; k < 3; k++) core[0][k] = d->a[k], core[1][k] = d->b[k];
        count = 2;
    } else if (d->shape == SB_COLLIDER_MESH) { /* the corners of its box */
        double box[6];
        sb_mesh_shape_box(c->mesh, box);
        for (int i = 0; i < 8; i++)
            for (int k = 0; k < 3; k++) core[i][k] = box[(i >> k & 1) ? 3 + k : k];
        count = 8;
    } else {
        const double *h = d->half_extents, *r = c->box_rotation;
        for (int i = 0; i < 8; i++) {
            double local[3] = {i & 1 ? h[0] : -h[0], i & 2 ? h[1] : -h[1], i & 4 ? h[2] : -h[2]};
            for (int k = 0; k < 3; k++)
                core[i][k] = d->center[k] + r[3 * k] * local[0] + r[3 * k + 1] * local[1] + r[3 * k + 2] * local[2];
        }
        count = 8;
    }
    for (int i = 0; i < count; i++) {
        sb_pose_apply(c->pose0, core[i], at[i]);
        sb_pose_apply(c->pose1, core[i], at[count + i]);
    }
    bool rounded = d->shape == SB_COLLIDER_SPHERE || d->shape == SB_COLLIDER_CAPSULE;
    sb_ball_around((const double(*)[3])at, 2 * count, (rounded ? d->radius : 0.0) + d->thickness, center, radius);
}

/* Not a plane: a flat triangle's points against a plane are the blend of
 * its corners' (the signed distance is linear across it), so its deepest
 * point is a corner, which the vertex pass answers; the face pass would
 * find nothing to do for it (and a floor under a whole body would make it
 * visit every triangle). */
double sb_collider_footprint(const sb_collider* c) { return c->def.footprint; }

bool sb_collider_meets_surface(const sb_collider* c) {
    sb_collider_shape shape = c->def.shape;
    if (c->begin_step != sb_builtin_begin_step) return c->triangle_point != NULL;
    return shape == SB_COLLIDER_SPHERE || shape == SB_COLLIDER_CAPSULE || shape == SB_COLLIDER_BOX ||
           shape == SB_COLLIDER_MESH;
}

void sb_collider_set_pose(sb_collider* c, const double translate[3], const double rotate[3]) {
    /* a program's own collider moves itself; the solver moves a dynamic one */
    if (c->begin_step != sb_builtin_begin_step || c->dynamic) return;
    double center[3];
    sb_reference_point(&c->def, center);
    sb_pose_from(translate, rotate, center, c->driven_pose);
    c->driven = true;
}

/* The fields that change as the collider runs: its bounds, the poses of
 * the step, the pose the program drove it to, and a dynamic one's body. */
static int sb_collider_moving(sb_collider* c, double* fields[], size_t counts[]) {
    double* list[] = {c->bounds,           c->pose0,           c->pose1,    &c->t0,           &c->t1,
                      c->driven_pose,      c->position,        c->velocity, c->next_position, c->orientation,
                      c->next_orientation, c->angular_momentum};
    size_t sizes[] = {6, 12, 12, 1, 1, 12, 3, 3, 3, 4, 4, 3};
    int n = (int)(sizeof sizes / sizeof *sizes);
    for (int k = 0; k < n; k++) fields[k] = list[k], counts[k] = sizes[k];
    return n;
}

void sb_collider_save(const sb_collider* c, sb_sections_writer* w) {
    double* fields[16];
    size_t counts[16];
    int n = sb_collider_moving((sb_collider*)c, fields, counts); /* reads only */
    for (int k = 0; k < n; k++) sb_sections_put(w, fields[k], counts[k] * sizeof(double));
    uint8_t driven = c->driven;
    sb_sections_put(w, &driven, 1);
}

void sb_collider_load(sb_collider* c, sb_cursor* r) {
    double* fields[16];
    size_t counts[16];
    int n = sb_collider_moving(c, fields, counts);
    for (int k = 0; k < n; k++) sb_cursor_take(r, fields[k], counts[k] * sizeof(double));
    uint8_t driven = 0;
    sb_cursor_take(r, &driven, 1);
    c->driven = driven != 0;
}

void sb_collider_state(const sb_collider* c, double position[3], double velocity[3]) {
    double p[3] = {0, 0, 0}, v[3] = {0, 0, 0};
    if (c && c->dynamic) {
        memcpy(p, c->position, sizeof p);
        memcpy(v, c->velocity, sizeof v);
    } else if (c && c->begin_step == sb_builtin_begin_step) {
        double reference[3], at0[3];
        sb_reference_point(&c->def, reference);
        sb_pose_apply(c->pose1, reference, p);
        sb_pose_apply(c->pose0, reference, at0);
        if (c->t1 > c->t0)
            for (int k = 0; k < 3; k++) v[k] = (p[k] - at0[k]) / (c->t1 - c->t0);
    }
    if (position) memcpy(position, p, sizeof p);
    if (velocity) memcpy(velocity, v, sizeof v);
}

/* The rotation R1 R0ᵀ of a step as an angular velocity: its axis times its
 * angle, over dt. */
static void sb_step_spin(const double r0[9], const double r1[9], double dt, double w[3]) {
    double turn[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            turn[3 * i + j] = r1[3 * i] * r0[3 * j] + r1[3 * i + 1] * r0[3 * j + 1] + r1[3 * i + 2] * r0[3 * j + 2];
    double axis[3] = {0.5 * (turn[7] - turn[5]), 0.5 * (turn[2] - turn[6]), 0.5 * (turn[3] - turn[1])};
    double sine = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    double angle = atan2(sine, 0.5 * (turn[0] + turn[4] + turn[8] - 1.0));
    double per_sine = sine > 0.0 ? angle / sine : 1.0; /* axis sin(angle) → axis angle */
    for (int k = 0; k < 3; k++) w[k] = axis[k] * per_sine / dt;
}

void sb_collider_orientation(const sb_collider* c, double rotation[9], double angular_velocity[3]) {
    double r[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, w[3] = {0, 0, 0};
    if (c && c->dynamic) {
        sb_dynamic_spin(c, r, w);
    } else if (c && c->begin_step == sb_builtin_begin_step) {
        memcpy(r, c->pose1, sizeof r);
        if (c->t1 > c->t0) sb_step_spin(c->pose0, c->pose1, c->t1 - c->t0, w);
    }
    if (rotation) memcpy(rotation, r, sizeof r);
    if (angular_velocity) memcpy(angular_velocity, w, sizeof w);
}
