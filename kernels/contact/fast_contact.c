/* The contact of the static built-in planes, spheres, capsules and boxes
 * in SIMD over the packed state: the fused Verlet step's answer for
 * resting contact, where every vertex of a body lying on a floor is
 * answered every step.
 *
 * Design. The scalar reference (sb_contact_vertex, kernels/contact/contact.c)
 * asks each collider's callback in double and answers one vertex at a time,
 * about 80 ns a vertex. Here a run of SB_WIDTH consecutive packed
 * vertices (x y z w) is read as four whole registers and transposed in
 * their 128-bit lanes (sb_wv_load4_run), so that each lane holds one
 * vertex's x, y and z: every per-vertex quantity (a distance, a normal
 * velocity, whether it touches, a division or a square root) is computed
 * once for SB_WIDTH vertices, and written back by the inverse transpose
 * (the vertices' order in the lanes is the transpose's, sb_w_run_vertex;
 * per-vertex masses are read into the same order). The packed form, a
 * vertex's four lanes summed for a dot product, computed each such value
 * four times and took 2.1 times as long on the floor. A choice is a
 * lane-wise pick of two computed values (no branch, no gather or scatter:
 * each array is read and written once, whole registers). Truths are reals
 * 0 or 1 (and: product, or: maximum), picked with sb_w_pick_greater
 * against one half.
 *
 * The arithmetic is the reference's, in sb_real instead of double, the
 * sweeps' cases written out for a shape standing still in the world
 * (kernels/contact/colliders/sweep.h; the collider's velocity is 0):
 *
 *   plane   f = n·(x − p) − t at both ends of the move; it touches when the
 *           end is in (f1 <= 0): from inside (f0 <= 0) at fraction 1 with
 *           depth −f1, from outside at fraction f0 / (f0 − f1), depth 0;
 *   the others, one answer (sb_fast_sweep) from each end's query (in or
 *   not, depth, outward normal of least penetration) and the interval of
 *   the move's line in the solid: from inside, resting when the end is in
 *   and its outward normal does not face against the start's (fraction 1,
 *   its depth and normal), otherwise at fraction 0 with the start's depth
 *   and normal when the move ends in or heads in; from outside, where the
 *   line enters if that lies within the move, else at the end when the
 *   end is in. The shapes' queries:
 *   sphere  the ball of r = radius + t about c (a capsule whose ends
 *           coincide, as capsule.c decides); the line enters at
 *           c / (−b + √(b² − a c)), the form without cancellation;
 *   capsule from the nearest point of the segment a–b, a clamp of the
 *           place along it (on the axis itself, the normal to it that
 *           capsule.c takes, made once in double); the line the union of
 *           the balls about a and b and the cylinder between them, in
 *           capsule.c's order (a, b, cylinder; an entry no earlier keeps
 *           the normal): the cylinder's roots of A s² + 2 B s + C clipped
 *           to the slab between the ends, all of the line or none of it
 *           along the axis (A = 0), every s of the slab or none across it;
 *   box     in its frame (x' = Rᵀ (x − c), a dot product with each axis):
 *           inside when no room h_k − |x'_k| is negative, the face of
 *           least room; the line by the slab test, the face of the slab
 *           entered last. Whether two faces' normals face away is the sign
 *           of their axes' dot product as the reference rounds it in
 *           double (sb_box_axes_facing; 0 where it is exact), since faces
 *           normal to each other would otherwise be decided by rounding.
 *
 * The earliest contact wins (the first collider on a tie), then the
 * velocity answer (restitution, Coulomb friction: sb_contact_velocity) and
 * the position (sb_contact_position), and the force's starting value
 * m (g − drag v) for the new velocity. A block with a collider this
 * kernel does not answer goes to the scalar reference whole, so one
 * vertex's colliders are always compared by one of the two. The impulses a
 * collider receives are summed lane-wise over a run and reduced in lane
 * order: the same for any thread count, since a run (the consecutive
 * blocks of a chunk with the same colliders in reach) depends on the
 * positions only. tests/test_fast_contact.c compares the two on random moves
 * (a capsule's ends and cylinder, moves along and across its axis among
 * them). */
#include "kernels/contact/fast_contact.h"
#include "kernels/contact/colliders/box.h"
#include "kernels/contact/colliders/capsule.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/runtime/wide.h"

#include <math.h>
#include <string.h>

/* A register must hold a run of several vertices for the answer to pay:
 * the scalar variant (one lane) leaves them to the reference. */
#define SB_FAST_CONTACT (SB_WIDTH > 1)

static void sb_fast_copy3(sb_real out[4], const double v[3]) {
    for (int k = 0; k < 3; k++) out[k] = (sb_real)v[k];
    out[3] = 0;
}

/* The capsule a–b (|b − a| > 0): a, b − a, its unit axis, b, length and
 * squared length, and the unit normal to the axis that its end query takes
 * on the axis itself (sb_capsule_axis_normal, capsule.c's own), all made
 * in double. */
static void sb_fast_capsule_of(const sb_collider_def* d, double thickness, sb_fast_shape* s) {
    double ab[3] = {d->b[0] - d->a[0], d->b[1] - d->a[1], d->b[2] - d->a[2]};
    double ab2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2], length = sqrt(ab2), u[3], n[3];
    sb_capsule_axis_normal(ab, ab2, n);
    for (int k = 0; k < 3; k++) u[k] = ab[k] / length;
    s->kind = SB_FAST_SHAPE_CAPSULE;
    sb_fast_copy3(s->origin, d->a);
    sb_fast_copy3(s->normal, n);
    sb_fast_copy3(s->axis[0], ab);
    sb_fast_copy3(s->axis[1], u);
    sb_fast_copy3(s->axis[2], d->b);
    s->extent[0] = (sb_real)length;
    s->extent[1] = (sb_real)ab2;
    s->reach = (sb_real)(d->radius + thickness);
}

/* a == b: the ball about a (as capsule.c decides) */
static bool sb_fast_capsule_is_ball(const sb_collider_def* d) {
    double ab[3] = {d->b[0] - d->a[0], d->b[1] - d->a[1], d->b[2] - d->a[2]};
    return ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2] == 0.0;
}

/* The box: its axes are the columns of its rotation; the signs (1, 0, −1)
 * of their dot products as the reference rounds them (in the order 01 02
 * 12). */
static void sb_fast_box_of(const sb_collider* c, double thickness, sb_fast_shape* s) {
    static const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
    for (int p = 0; p < 3; p++) s->facing[p] = (sb_real)sb_box_axes_facing(c->box_rotation, pairs[p][0], pairs[p][1]);
    s->kind = SB_FAST_SHAPE_BOX;
    sb_fast_copy3(s->origin, c->def.center);
    for (int a = 0; a < 3; a++) {
        double column[3] = {c->box_rotation[a], c->box_rotation[3 + a], c->box_rotation[6 + a]};
        sb_fast_copy3(s->axis[a], column);
        s->extent[a] = (sb_real)(c->def.half_extents[a] + thickness);
    }
}

/* One collider as the kernel sees it, from its def. */
static sb_fast_shape sb_fast_shape_of(const sb_collider* c, double contact_thickness) {
    const sb_collider_def* d = &c->def;
    sb_fast_shape s;
    memset(&s, 0, sizeof s);
    if (!SB_FAST_CONTACT || !sb_collider_is_static_builtin(c)) return s;
    double thickness = d->thickness + contact_thickness;
    if (d->shape == SB_COLLIDER_PLANE) {
        double length = sqrt(d->normal[0] * d->normal[0] + d->normal[1] * d->normal[1] + d->normal[2] * d->normal[2]);
        double unit[3] = {d->normal[0] / length, d->normal[1] / length, d->normal[2] / length};
        s.kind = SB_FAST_SHAPE_PLANE;
        sb_fast_copy3(s.origin, d->point);
        sb_fast_copy3(s.normal, unit);
        s.reach = (sb_real)thickness;
    } else if (d->shape == SB_COLLIDER_SPHERE || (d->shape == SB_COLLIDER_CAPSULE && sb_fast_capsule_is_ball(d))) {
        s.kind = SB_FAST_SHAPE_SPHERE;
        sb_fast_copy3(s.origin, d->shape == SB_COLLIDER_SPHERE ? d->center : d->a);
        s.reach = (sb_real)(d->radius + thickness);
    } else if (d->shape == SB_COLLIDER_CAPSULE) {
        sb_fast_capsule_of(d, thickness, &s);
    } else if (d->shape == SB_COLLIDER_BOX) {
        sb_fast_box_of(c, thickness, &s);
    } else {
        return s;
    }
    s.restitution = (sb_real)d->restitution;
    s.friction = (sb_real)d->friction;
    s.static_friction = (sb_real)d->static_friction;
    return s;
}

void sb_fast_colliders_set(sb_fast_colliders* out, sb_collider* const* colliders, uint32_t count,
                           double contact_thickness) {
    out->simd = 0;
    for (uint32_t c = 0; c < count; c++) {
        out->shape[c] = sb_fast_shape_of(colliders[c], contact_thickness);
        if (out->shape[c].kind != SB_FAST_SHAPE_NONE) out->simd |= (uint64_t)1 << c;
    }
}

uint32_t sb_fast_contact_granule(void) { return SB_FAST_CONTACT ? SB_WIDTH : 0; }

#if SB_FAST_CONTACT

/* Truths: 0 or 1 in every lane. */
static inline sb_wide sb_t_pick(sb_wide truth, sb_wide x, sb_wide y) {
    return sb_w_pick_greater(truth, sb_w_set((sb_real)0.5), x, y);
}
static inline sb_wvec3 sb_tv_pick(sb_wide truth, sb_wvec3 x, sb_wvec3 y) {
    return (sb_wvec3){sb_t_pick(truth, x.x, y.x), sb_t_pick(truth, x.y, y.y), sb_t_pick(truth, x.z, y.z)};
}
static inline sb_wide sb_t_greater(sb_wide a, sb_wide b) { return sb_w_pick_greater(a, b, sb_w_set(1), sb_w_set(0)); }
static inline sb_wide sb_t_at_most(sb_wide a, sb_wide b) { return sb_w_pick_greater(a, b, sb_w_set(0), sb_w_set(1)); }
static inline sb_wide sb_t_not(sb_wide a) { return sb_w_sub(sb_w_set(1), a); }
static inline sb_wide sb_t_or(sb_wide a, sb_wide b) { return sb_w_max(a, b); }
static inline sb_wide sb_t_and(sb_wide a, sb_wide b) { return sb_w_mul(a, b); }

static inline sb_wvec3 sb_wv_set(const sb_real v[4]) {
    return (sb_wvec3){sb_w_set(v[0]), sb_w_set(v[1]), sb_w_set(v[2])};
}
static inline sb_wvec3 sb_wv_zero(void) { return (sb_wvec3){sb_w_set(0), sb_w_set(0), sb_w_set(0)}; }
static inline sb_wvec3 sb_wv_div(sb_wvec3 v, sb_wide s) {
    return (sb_wvec3){sb_w_div(v.x, s), sb_w_div(v.y, s), sb_w_div(v.z, s)};
}

/* A collider's constants spread over the lanes, made once per run. */
typedef struct sb_fast_wide_shape {
    sb_fast_shape_kind kind;
    sb_wvec3 origin, normal, axis[3];
    sb_wide extent[3], facing[3], reach, restitution, friction, static_friction, index;
} sb_fast_wide_shape;

static sb_fast_wide_shape sb_fast_widen(const sb_fast_shape* s, uint32_t index) {
    return (sb_fast_wide_shape){.kind = s->kind,
                                .axis = {sb_wv_set(s->axis[0]), sb_wv_set(s->axis[1]), sb_wv_set(s->axis[2])},
                                .extent = {sb_w_set(s->extent[0]), sb_w_set(s->extent[1]), sb_w_set(s->extent[2])},
                                .facing = {sb_w_set(s->facing[0]), sb_w_set(s->facing[1]), sb_w_set(s->facing[2])},
                                .origin = sb_wv_set(s->origin),
                                .normal = sb_wv_set(s->normal),
                                .reach = sb_w_set(s->reach),
                                .restitution = sb_w_set(s->restitution),
                                .friction = sb_w_set(s->friction),
                                .static_friction = sb_w_set(s->static_friction),
                                .index = sb_w_set((sb_real)index)};
}

/* One collider's answer for the lanes' vertices: whether each touches it,
 * at which fraction of its move, how deep and along which normal. */
typedef struct sb_fast_hit {
    sb_wide touches, fraction, depth;
    sb_wvec3 normal;
} sb_fast_hit;

/* The vertices' moves: start, end, displacement. */
typedef struct sb_fast_move {
    sb_wvec3 from, to, d;
} sb_fast_move;

static inline __attribute__((always_inline)) sb_fast_hit sb_fast_plane(const sb_fast_wide_shape* s,
                                                                       const sb_fast_move* m) {
    const sb_wide zero = sb_w_set(0), one = sb_w_set(1), t = s->reach;
    sb_fast_hit h;
    h.normal = s->normal;
    sb_wide f0 = sb_w_sub(sb_wv_dot(sb_wv_sub(m->from, s->origin), h.normal), t);
    sb_wide f1 = sb_w_sub(sb_wv_dot(sb_wv_sub(m->to, s->origin), h.normal), t);
    sb_wide from_inside = sb_t_at_most(f0, zero);
    h.touches = sb_t_at_most(f1, zero);
    h.fraction = sb_t_pick(from_inside, one, sb_w_div(f0, sb_w_sub(f0, f1)));
    h.depth = sb_t_pick(from_inside, sb_w_sub(zero, f1), zero);
    return h;
}

/* One end of the move against a shape (sb_sweep_end): in the solid or
 * not, how deep, the outward normal of least penetration. */
typedef struct sb_fast_end {
    sb_wide inside, depth;
    sb_wvec3 normal;
} sb_fast_end;

/* The move's line against a shape: whether it enters, the interval
 * [lo, hi] of it in the solid, the outward normal at lo. */
typedef struct sb_fast_line {
    sb_wide entered, lo, hi;
    sb_wvec3 normal;
} sb_fast_line;

/* The answer every shape's sweep gives (sb_sweep_from_inside and
 * sb_sweep_from_outside, kernels/contact/colliders/sweep.c); `flip` the
 * ends' normals' dot product, or a value of its sign. */
static sb_fast_hit sb_fast_sweep(const sb_fast_end* e0, const sb_fast_end* e1, sb_wide flip, const sb_fast_line* line,
                                 const sb_fast_move* m) {
    const sb_wide zero = sb_w_set(0), one = sb_w_set(1);
    /* from inside: resting, or stopped at the start */
    sb_wide resting = sb_t_and(e1->inside, sb_t_not(sb_t_greater(zero, flip)));
    sb_wide heading_in = sb_t_greater(zero, sb_wv_dot(m->d, e0->normal));
    sb_fast_hit inside = {.touches = sb_t_or(e1->inside, heading_in),
                          .fraction = sb_t_pick(resting, one, zero),
                          .depth = sb_t_pick(resting, e1->depth, e0->depth),
                          .normal = sb_tv_pick(resting, e1->normal, e0->normal)};
    /* from outside: where the line enters, if within the move */
    sb_wide within = sb_t_and(sb_t_and(sb_t_at_most(line->lo, one), sb_t_not(sb_t_greater(zero, line->hi))),
                              sb_t_greater(line->hi, line->lo));
    sb_fast_hit outside = {.touches = sb_t_or(e1->inside, sb_t_and(line->entered, within)),
                           .fraction = sb_t_pick(line->entered, sb_w_min(sb_w_max(line->lo, zero), one), one),
                           .depth = zero,
                           .normal = sb_tv_pick(line->entered, line->normal, e1->normal)};
    sb_fast_hit h;
    h.touches = sb_t_pick(e0->inside, inside.touches, outside.touches);
    h.fraction = sb_t_pick(e0->inside, inside.fraction, outside.fraction);
    h.depth = sb_t_pick(e0->inside, inside.depth, outside.depth);
    h.normal = sb_tv_pick(e0->inside, inside.normal, outside.normal);
    return h;
}

/* The end at offset v from the nearest point of the shape's core (a
 * point, a segment) within r: `fallback` where v is 0. */
static sb_fast_end sb_fast_round_end(sb_wvec3 v, sb_wide r, sb_wvec3 fallback) {
    sb_wide distance = sb_w_sqrt(sb_wv_dot(v, v));
    sb_wide outward = sb_t_greater(distance, sb_w_set(0));
    return (sb_fast_end){.inside = sb_t_at_most(distance, r),
                         .depth = sb_w_sub(r, distance),
                         .normal = sb_tv_pick(outward, sb_wv_div(v, distance), fallback)};
}

static sb_wvec3 sb_fast_up(void) { return (sb_wvec3){sb_w_set(0), sb_w_set(0), sb_w_set(1)}; }

/* The line of the move in the ball of radius r about center
 * (sb_ball_line, sphere.c): it enters heading to the center (b < 0) with a
 * positive discriminant, at c / (−b + √(b² − a c)). */
static sb_fast_line sb_fast_ball_line(sb_wvec3 center, sb_wide r, const sb_fast_move* mv) {
    const sb_wide zero = sb_w_set(0);
    sb_wvec3 m0 = sb_wv_sub(mv->from, center);
    sb_wide a = sb_wv_dot(mv->d, mv->d), b = sb_wv_dot(m0, mv->d), c = sb_w_sub(sb_wv_dot(m0, m0), sb_w_mul(r, r));
    sb_wide disc = sb_w_sub(sb_w_mul(b, b), sb_w_mul(a, c));
    sb_wide q = sb_w_add(sb_w_sub(zero, b), sb_w_sqrt(sb_w_max(disc, zero)));
    sb_fast_line line = {.entered = sb_t_and(sb_t_greater(zero, b), sb_t_greater(disc, zero)),
                         .lo = sb_w_div(c, q),
                         .hi = sb_w_div(q, a)};
    sb_wvec3 at = sb_wv_add(m0, sb_wv_scale(mv->d, line.lo));
    line.normal = sb_wv_div(at, sb_w_sqrt(sb_wv_dot(at, at)));
    return line;
}

static sb_fast_hit sb_fast_sphere(const sb_fast_wide_shape* s, const sb_fast_move* m) {
    sb_fast_end e0 = sb_fast_round_end(sb_wv_sub(m->from, s->origin), s->reach, sb_fast_up());
    sb_fast_end e1 = sb_fast_round_end(sb_wv_sub(m->to, s->origin), s->reach, sb_fast_up());
    sb_fast_line line = sb_fast_ball_line(s->origin, s->reach, m);
    return sb_fast_sweep(&e0, &e1, sb_wv_dot(e1.normal, e0.normal), &line, m);
}

/* The capsule at x (sb_capsule_end): from the nearest point of the
 * segment, a clamp of x's place along it. */
static sb_fast_end sb_fast_capsule_end(const sb_fast_wide_shape* s, sb_wvec3 x) {
    const sb_wvec3 ab = s->axis[0], ax = sb_wv_sub(x, s->origin);
    sb_wide tau = sb_w_min(sb_w_max(sb_w_div(sb_wv_dot(ax, ab), s->extent[1]), sb_w_set(0)), sb_w_set(1));
    return sb_fast_round_end(sb_wv_sub(ax, sb_wv_scale(ab, tau)), s->reach, s->normal);
}

/* The line of the move in the cylinder piece (sb_cylinder_line,
 * capsule.c): the roots of A s² + 2 B s + C, clipped to the slab between
 * the ends; all of the line or none of it when the move is along the axis
 * (A = 0), every s of the slab or none when it is across (d·u = 0). */
static sb_fast_line sb_fast_cylinder_line(const sb_fast_wide_shape* s, const sb_fast_move* mv) {
    const sb_wide zero = sb_w_set(0), length = s->extent[0], r = s->reach;
    const sb_wide below = sb_w_set(-(sb_real)INFINITY), above = sb_w_set((sb_real)INFINITY);
    const sb_wvec3 u = s->axis[1], m = sb_wv_sub(mv->from, s->origin);
    sb_wide mu = sb_wv_dot(m, u), du = sb_wv_dot(mv->d, u);
    sb_wvec3 mp = sb_wv_sub(m, sb_wv_scale(u, mu)), dp = sb_wv_sub(mv->d, sb_wv_scale(u, du));
    sb_wide A = sb_wv_dot(dp, dp), B = sb_wv_dot(mp, dp), C = sb_w_sub(sb_wv_dot(mp, mp), sb_w_mul(r, r));
    sb_wide disc = sb_w_sub(sb_w_mul(B, B), sb_w_mul(A, C)), root = sb_w_sqrt(sb_w_max(disc, zero));
    sb_wide falling = sb_t_at_most(B, zero), q = sb_w_sub(sb_t_pick(falling, root, sb_w_sub(zero, root)), B);
    sb_wide along = sb_t_not(sb_t_greater(A, zero));
    sb_wide s1 = sb_t_pick(along, below, sb_t_pick(falling, sb_w_div(C, q), sb_w_div(q, A)));
    sb_wide s2 = sb_t_pick(along, above, sb_t_pick(falling, sb_w_div(q, A), sb_w_div(C, q)));
    sb_wide entered = sb_t_pick(along, sb_t_at_most(C, zero), sb_t_greater(disc, zero));
    sb_wide across = sb_t_not(sb_t_greater(sb_w_abs(du), zero));
    sb_wide sa = sb_w_div(sb_w_sub(zero, mu), du), sb = sb_w_div(sb_w_sub(length, mu), du);
    s1 = sb_t_pick(across, s1, sb_w_max(s1, sb_w_min(sa, sb)));
    s2 = sb_t_pick(across, s2, sb_w_min(s2, sb_w_max(sa, sb)));
    sb_wide in_slab = sb_t_and(sb_t_at_most(zero, mu), sb_t_at_most(mu, length));
    entered = sb_t_and(entered, sb_t_or(sb_t_not(across), in_slab));
    entered = sb_t_and(entered, sb_t_at_most(s1, s2));
    sb_wide at = sb_w_pick_greater(s1, below, s1, zero); /* -inf: a zero move on the axis */
    sb_fast_end there = sb_fast_capsule_end(s, sb_wv_add(mv->from, sb_wv_scale(mv->d, at)));
    return (sb_fast_line){.entered = entered, .lo = s1, .hi = s2, .normal = there.normal};
}

/* Adds a piece's interval to the union (sb_capsule_union_add): an entry no
 * earlier than the current keeps its normal. */
static void sb_fast_union_add(sb_fast_line* line, const sb_fast_line* piece) {
    sb_wide first = sb_t_not(line->entered);
    sb_wide earlier = sb_t_and(piece->entered, sb_t_or(first, sb_t_greater(line->lo, piece->lo)));
    sb_wide later = sb_t_and(piece->entered, sb_t_or(first, sb_t_greater(piece->hi, line->hi)));
    line->lo = sb_t_pick(earlier, piece->lo, line->lo);
    line->normal = sb_tv_pick(earlier, piece->normal, line->normal);
    line->hi = sb_t_pick(later, piece->hi, line->hi);
    line->entered = sb_t_or(line->entered, piece->entered);
}

/* The capsule: the union of the balls about a and b and the cylinder
 * between them (sb_capsule_line), in that order. */
static sb_fast_hit sb_fast_capsule(const sb_fast_wide_shape* s, const sb_fast_move* m) {
    sb_fast_end e0 = sb_fast_capsule_end(s, m->from), e1 = sb_fast_capsule_end(s, m->to);
    sb_fast_line line = sb_fast_ball_line(s->origin, s->reach, m);
    sb_fast_line ball_b = sb_fast_ball_line(s->axis[2], s->reach, m);
    sb_fast_line cylinder = sb_fast_cylinder_line(s, m);
    sb_fast_union_add(&line, &ball_b);
    sb_fast_union_add(&line, &cylinder);
    return sb_fast_sweep(&e0, &e1, sb_wv_dot(e1.normal, e0.normal), &line, m);
}

/* The box's frame at the move's ends: x' = Rᵀ (x − center), its axes
 * one by one, and the face normals ±R e_k. */
typedef struct sb_fast_box_frame {
    sb_wide from[3], to[3], d[3];
} sb_fast_box_frame;

/* The box at a point of local coordinates x (sb_box_end, box.c): inside
 * when no room h_k − |x_k| is negative; the face of least room (the lowest
 * axis on a tie), on the side of x: its axis and side (±1) as well. */
static sb_fast_end sb_fast_box_end(const sb_fast_wide_shape* s, const sb_wide x[3], sb_wide* axis, sb_wide* side) {
    const sb_wide zero = sb_w_set(0), one = sb_w_set(1);
    sb_fast_end e = {.inside = one};
    for (int k = 0; k < 3; k++) {
        sb_wide room = sb_w_sub(s->extent[k], sb_w_abs(x[k]));
        sb_wide negative = sb_t_greater(zero, x[k]), sign = sb_t_pick(negative, sb_w_set(-1), one);
        sb_wvec3 face = sb_wv_scale(s->axis[k], sign);
        e.inside = sb_t_and(e.inside, sb_t_at_most(zero, room));
        sb_wide least = k == 0 ? one : sb_t_greater(e.depth, room);
        e.depth = k == 0 ? room : sb_t_pick(least, room, e.depth);
        e.normal = k == 0 ? face : sb_tv_pick(least, face, e.normal);
        *axis = k == 0 ? zero : sb_t_pick(least, sb_w_set((sb_real)k), *axis);
        *side = k == 0 ? sign : sb_t_pick(least, sign, *side);
    }
    return e;
}

/* The sign of the ends' faces' normals' dot product as the reference
 * computes it in double: ±1 on one axis; on two, their axes' (made once,
 * s->facing), which rounding decides, the axes being normal to each other. */
static sb_wide sb_fast_box_flip(const sb_fast_wide_shape* s, sb_wide axis0, sb_wide side0, sb_wide axis1,
                                sb_wide side1) {
    const sb_wide half = sb_w_set((sb_real)0.5);
    sb_wide sum = sb_w_add(axis0, axis1), same = sb_t_greater(half, sb_w_abs(sb_w_sub(axis0, axis1)));
    sb_wide pair =
        sb_w_pick_greater(sum, sb_w_set((sb_real)1.5),
                          sb_w_pick_greater(sum, sb_w_set((sb_real)2.5), s->facing[2], s->facing[1]), s->facing[0]);
    return sb_w_mul(sb_w_mul(side0, side1), sb_t_pick(same, sb_w_set(1), pair));
}

/* The slab test of the move's line (sb_box_line): a slab the move is
 * parallel to holds all of it or none; the normal of the face whose slab
 * is entered last (the lowest axis on a tie). */
static sb_fast_line sb_fast_box_line(const sb_fast_wide_shape* s, const sb_fast_box_frame* b) {
    const sb_wide zero = sb_w_set(0);
    sb_fast_line line = {
        .entered = zero, .lo = sb_w_set(-(sb_real)INFINITY), .hi = sb_w_set((sb_real)INFINITY), .normal = sb_wv_zero()};
    sb_wide inside_parallels = sb_w_set(1);
    for (int k = 0; k < 3; k++) {
        sb_wide h = s->extent[k], m = b->from[k], d = b->d[k];
        sb_wide moving = sb_t_greater(sb_w_abs(d), zero), forward = sb_t_greater(d, zero);
        sb_wide near = sb_t_pick(forward, sb_w_sub(zero, h), h), far = sb_w_sub(zero, near);
        sb_wide enter = sb_w_div(sb_w_sub(near, m), d), leave = sb_w_div(sb_w_sub(far, m), d);
        sb_wide later = sb_t_and(moving, sb_t_greater(enter, line.lo));
        sb_wide sooner = sb_t_and(moving, sb_t_greater(line.hi, leave));
        line.lo = sb_t_pick(later, enter, line.lo);
        line.normal = sb_tv_pick(later, sb_tv_pick(forward, sb_wv_neg(s->axis[k]), s->axis[k]), line.normal);
        line.hi = sb_t_pick(sooner, leave, line.hi);
        line.entered = sb_t_or(line.entered, moving);
        inside_parallels = sb_t_and(inside_parallels, sb_t_or(moving, sb_t_at_most(sb_w_abs(m), h)));
    }
    line.entered = sb_t_and(sb_t_and(line.entered, inside_parallels), sb_t_at_most(line.lo, line.hi));
    return line;
}

/* The box (sb_box_sweep_rotated): the move in the box's frame, the local
 * displacement the difference of the ends' coordinates as there. */
static sb_fast_hit sb_fast_box(const sb_fast_wide_shape* s, const sb_fast_move* m) {
    sb_fast_box_frame b;
    sb_wvec3 from = sb_wv_sub(m->from, s->origin), to = sb_wv_sub(m->to, s->origin);
    for (int k = 0; k < 3; k++) {
        b.from[k] = sb_wv_dot(from, s->axis[k]);
        b.to[k] = sb_wv_dot(to, s->axis[k]);
        b.d[k] = sb_w_sub(b.to[k], b.from[k]);
    }
    sb_wide axis0, side0, axis1, side1;
    sb_fast_end e0 = sb_fast_box_end(s, b.from, &axis0, &side0), e1 = sb_fast_box_end(s, b.to, &axis1, &side1);
    sb_fast_line line = sb_fast_box_line(s, &b);
    return sb_fast_sweep(&e0, &e1, sb_fast_box_flip(s, axis0, side0, axis1, side1), &line, m);
}

/* The earliest contact of the lanes' vertices among the colliders of
 * `near`, with the collider's index and surface constants per vertex. */
typedef struct sb_fast_contact {
    sb_fast_hit hit;
    sb_wide collider, restitution, friction, static_friction;
} sb_fast_contact;

static sb_fast_hit sb_fast_shape_hit(const sb_fast_wide_shape* s, const sb_fast_move* m) {
    switch (s->kind) {
    case SB_FAST_SHAPE_PLANE: return sb_fast_plane(s, m);
    case SB_FAST_SHAPE_SPHERE: return sb_fast_sphere(s, m);
    case SB_FAST_SHAPE_CAPSULE: return sb_fast_capsule(s, m);
    default: return sb_fast_box(s, m);
    }
}

static sb_fast_contact sb_fast_earliest(const sb_fast_wide_shape* shapes, uint32_t count, const sb_fast_move* m) {
    const sb_wide zero = sb_w_set(0);
    if (count == 1) { /* one collider in reach (most blocks): nothing to compare; a plane (a floor) inline */
        sb_fast_hit h = shapes->kind == SB_FAST_SHAPE_PLANE ? sb_fast_plane(shapes, m) : sb_fast_shape_hit(shapes, m);
        return (sb_fast_contact){h, shapes->index, shapes->restitution, shapes->friction, shapes->static_friction};
    }
    sb_fast_contact best = {.hit = {zero, zero, zero, sb_wv_zero()}, zero, zero, zero, zero};
    for (uint32_t c = 0; c < count; c++) {
        const sb_fast_wide_shape* s = &shapes[c];
        sb_fast_hit h = sb_fast_shape_hit(s, m);
        sb_wide take =
            sb_t_and(h.touches, sb_t_or(sb_t_not(best.hit.touches), sb_t_greater(best.hit.fraction, h.fraction)));
        best.hit.touches = sb_t_or(best.hit.touches, h.touches);
        best.hit.fraction = sb_t_pick(take, h.fraction, best.hit.fraction);
        best.hit.depth = sb_t_pick(take, h.depth, best.hit.depth);
        best.hit.normal = sb_tv_pick(take, h.normal, best.hit.normal);
        best.collider = sb_t_pick(take, s->index, best.collider);
        best.restitution = sb_t_pick(take, s->restitution, best.restitution);
        best.friction = sb_t_pick(take, s->friction, best.friction);
        best.static_friction = sb_t_pick(take, s->static_friction, best.static_friction);
    }
    return best;
}

/* The velocity answer (sb_contact_velocity, the collider at rest). */
static sb_wvec3 sb_fast_velocity(const sb_fast_contact* c, sb_wvec3 v) {
    const sb_wide zero = sb_w_set(0);
    const sb_wvec3 n = c->hit.normal;
    sb_wide vn = sb_wv_dot(v, n), jn = sb_w_mul(sb_w_sub(zero, sb_w_add(sb_w_set(1), c->restitution)), vn);
    sb_wvec3 vt = sb_wv_sub(v, sb_wv_scale(n, vn));
    sb_wide vt_length = sb_w_sqrt(sb_wv_dot(vt, vt));
    sb_wide slide = sb_w_max(sb_w_sub(sb_w_set(1), sb_w_div(sb_w_mul(c->friction, jn), vt_length)), zero);
    sb_wide keep = sb_w_pick_greater(vt_length, sb_w_mul(c->static_friction, jn), slide, zero);
    sb_wvec3 answered = sb_wv_add(sb_wv_scale(n, sb_w_mul(sb_w_sub(zero, c->restitution), vn)), sb_wv_scale(vt, keep));
    return sb_tv_pick(sb_t_greater(zero, vn), answered, v);
}

/* The position after the contact (sb_contact_position). */
static sb_wvec3 sb_fast_position(const sb_fast_contact* c, const sb_fast_move* m, sb_wvec3 v, sb_wide dt) {
    const sb_wvec3 n = c->hit.normal;
    const sb_wide vn = sb_wv_dot(v, n);
    sb_wide normal_move = sb_w_add(sb_w_add(sb_w_mul(c->hit.fraction, sb_wv_dot(m->d, n)), c->hit.depth),
                                   sb_w_mul(sb_w_mul(sb_w_sub(sb_w_set(1), c->hit.fraction), dt), vn));
    return sb_wv_add(sb_wv_add(m->from, sb_wv_scale(sb_wv_sub(v, sb_wv_scale(n, vn)), dt)),
                     sb_wv_scale(n, normal_move));
}

/* The colliders of a run and its lane-wise sums: the impulses m Δv per
 * collider, the vertices answered. */
typedef struct sb_fast_run_state {
    uint32_t count;
    sb_fast_wide_shape shape[SB_MAX_COLLIDERS];
    sb_wvec3 impulse[SB_MAX_COLLIDERS];
    sb_wide answered;
} sb_fast_run_state;

static void sb_fast_add_impulse(sb_fast_run_state* r, const sb_fast_contact* c, sb_wvec3 impulse) {
    if (r->count == 1) {
        r->impulse[0] = sb_wv_add(r->impulse[0], impulse);
        return;
    }
    for (uint32_t k = 0; k < r->count; k++) {
        sb_wide mine = sb_t_greater(sb_w_set((sb_real)0.5), sb_w_abs(sb_w_sub(c->collider, r->shape[k].index)));
        r->impulse[k] = sb_wv_add(r->impulse[k], sb_wv_scale(impulse, mine));
    }
}

/* Into the colliders' sums, each lane-wise sum reduced in lane order. */
static void sb_fast_reduce(const sb_fast_run_state* r, uint64_t near, double* out, double* contacts) {
    uint32_t k = 0;
    for (uint32_t c = 0; near >> c; c++)
        if (near >> c & 1) {
            const sb_wvec3* sum = &r->impulse[k++];
            out[3 * c + 0] -= sb_w_sum(sum->x, SB_WIDTH);
            out[3 * c + 1] -= sb_w_sum(sum->y, SB_WIDTH);
            out[3 * c + 2] -= sb_w_sum(sum->z, SB_WIDTH);
        }
    *contacts += sb_w_sum(r->answered, SB_WIDTH);
}

/* The lanes' answered vertices (the run's vertex i on) to step->touch. */
static void sb_fast_report(const sb_fast_contact_step* step, uint32_t i, const sb_fast_contact* c, sb_wide answered,
                           sb_wvec3 x_new, sb_wvec3 impulse) {
    enum { ANSWERED, RESTITUTION, COLLIDER, NORMAL, POINT = NORMAL + 3, IMPULSE = POINT + 3, VALUES = IMPULSE + 3 };
    const sb_wide from[VALUES] = {answered,        c->restitution,  c->collider, c->hit.normal.x,
                                  c->hit.normal.y, c->hit.normal.z, x_new.x,     x_new.y,
                                  x_new.z,         impulse.x,       impulse.y,   impulse.z};
    sb_real lanes[VALUES][SB_WIDTH];
    for (int a = 0; a < VALUES; a++) sb_w_store(lanes[a], from[a]);
    for (int l = 0; l < SB_WIDTH; l++) {
        if (!(lanes[ANSWERED][l] > (sb_real)0.5)) continue;
        sb_contact contact = {.restitution = lanes[RESTITUTION][l]};
        double impulse_l[3];
        for (int k = 0; k < 3; k++) {
            contact.normal[k] = lanes[NORMAL + k][l];
            contact.point[k] = lanes[POINT + k][l];
            impulse_l[k] = lanes[IMPULSE + k][l];
        }
        step->touch(step->user, step->first + i + (uint32_t)sb_w_run_vertex(l), (int)lanes[COLLIDER][l], &contact,
                    impulse_l);
    }
}

uint32_t sb_fast_contact_answer(const sb_fast_colliders* colliders, uint64_t near, const sb_packed_run* run,
                                const sb_fast_contact_step* step, double* out, double* contacts) {
    const uint32_t whole = run->count / SB_WIDTH * SB_WIDTH;
    const sb_wide zero = sb_w_set(0), half = sb_w_set((sb_real)0.5), dt = sb_w_set((sb_real)step->dt);
    const sb_wide drag = sb_w_set((sb_real)step->drag);
    const sb_real gravity[4] = {(sb_real)step->gravity[0], (sb_real)step->gravity[1], (sb_real)step->gravity[2], 0};
    const sb_wvec3 g = sb_wv_set(gravity);
    sb_fast_run_state r; /* not zeroed whole: only its first r.count shapes and sums are used */
    r.count = 0;
    r.answered = zero;
    for (uint32_t c = 0; near >> c; c++)
        if (near >> c & 1) {
            r.impulse[r.count] = sb_wv_zero();
            r.shape[r.count++] = sb_fast_widen(&colliders->shape[c], c);
        }
    for (uint32_t i = 0; i < whole; i += SB_WIDTH) {
        sb_real *x4 = run->x + 4 * (size_t)i, *v4 = run->v + 4 * (size_t)i, *d4 = run->d + 4 * (size_t)i;
        sb_wide x_w, v_w, d_w;
        sb_wvec3 x = sb_wv_load4_run(x4, &x_w), v = sb_wv_load4_run(v4, &v_w), d = sb_wv_load4_run(d4, &d_w);
        sb_fast_move m = {sb_wv_sub(x, d), x, d};
        sb_fast_contact c = sb_fast_earliest(r.shape, r.count, &m);
        sb_wide answered = sb_t_and(c.hit.touches, sb_t_greater(sb_w_load_run(run->inv_mass + i), zero));
        if (!sb_w_any(sb_w_less(half, answered), SB_WIDTH)) continue;
        sb_wide mass = sb_w_load_run(run->mass + i);
        sb_wvec3 v_new = sb_fast_velocity(&c, v), x_new = sb_fast_position(&c, &m, v_new, dt);
        sb_wv_store4_run(x4, sb_tv_pick(answered, x_new, x), x_w);
        sb_wv_store4_run(v4, sb_tv_pick(answered, v_new, v), v_w);
        sb_wv_store4_run(d4, sb_tv_pick(answered, sb_wv_scale(v_new, dt), d), d_w);
        if (step->drag != 0.0) { /* without drag the drift's m g is the new velocity's starting force too */
            sb_real* f4 = run->f + 4 * (size_t)i;
            sb_wide f_w;
            sb_wvec3 f = sb_wv_load4_run(f4, &f_w), f_new = sb_wv_scale(sb_wv_sub(g, sb_wv_scale(v_new, drag)), mass);
            sb_wv_store4_run(f4, sb_tv_pick(answered, f_new, f), f_w);
        }
        sb_wvec3 impulse = sb_tv_pick(answered, sb_wv_scale(sb_wv_sub(v_new, v), mass), sb_wv_zero());
        sb_fast_add_impulse(&r, &c, impulse);
        r.answered = sb_w_add(r.answered, answered);
        if (step->touch) sb_fast_report(step, i, &c, answered, x_new, impulse);
    }
    sb_fast_reduce(&r, near, out, contacts);
    return whole;
}

#else /* one lane: the scalar reference answers */

uint32_t sb_fast_contact_answer(const sb_fast_colliders* colliders, uint64_t near, const sb_packed_run* run,
                                const sb_fast_contact_step* step, double* out, double* contacts) {
    (void)colliders, (void)near, (void)run, (void)step, (void)out, (void)contacts;
    return 0;
}

#endif
