/* The contact of the static built-in planes, spheres (a capsule whose ends
 * coincide among them) and boxes in SIMD over the packed state: the fused Verlet step's answer for resting contact,
 * where every vertex of a body lying on a floor is answered every step.
 *
 * Design. The scalar reference (sb_contact_vertex, kernels/contact/contact.c)
 * asks each collider's callback in double and answers one vertex at a time,
 * about 80 ns a vertex. Here a register holds SB_WIDTH / 4 whole packed
 * vertices (x y z w) and works on them as they lie: a dot product of two
 * packed 3-vectors is their lane-wise product summed over each vertex's
 * four lanes (sb_w_sum4), which leaves the vertex's value in all four, so
 * every per-vertex quantity (a distance, a normal velocity, whether it
 * touches) is a register like the vectors, and a choice is a lane-wise pick
 * of two computed values (no branch, no gather or scatter: each array is
 * read and written once, whole registers). Truths are reals 0 or 1 (and:
 * product, or: maximum), picked with sb_w_pick_greater against one half.
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
 *   sphere  the ball of r = radius + t about c; the line enters at
 *           c / (−b + √(b² − a c)), the form without cancellation;
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
 * order: the same for any thread count, since a run is a fixed block of a
 * fixed chunk. tests/test_fast_contact.c compares the two on random moves.
 * A capsule (a ≠ b) goes to the scalar reference: the lane-wise union of
 * its balls and cylinder matched it on random moves, but let one vertex of
 * a sheet dropped across a thin capsule through in the double build
 * (test_contact's test_fast_sheet_does_not_pass_a_capsule), not yet
 * understood. */
#include "kernels/contact/fast_contact.h"
#include "kernels/contact/colliders/box.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/runtime/wide.h"

#include <math.h>
#include <string.h>

static void sb_fast_copy3(sb_real out[4], const double v[3]) {
    for (int k = 0; k < 3; k++) out[k] = (sb_real)v[k];
    out[3] = 0;
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
    if (!SB_W_HAS_SUM4 || !sb_collider_is_static_builtin(c)) return s;
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

uint32_t sb_fast_contact_granule(void) { return SB_W_HAS_SUM4 ? SB_WIDTH / 4 : 0; }

#if SB_W_HAS_SUM4

/* Truths: 0 or 1 in every lane. */
static inline sb_wide sb_t_pick(sb_wide truth, sb_wide x, sb_wide y) {
    return sb_w_pick_greater(truth, sb_w_set((sb_real)0.5), x, y);
}
static inline sb_wide sb_t_greater(sb_wide a, sb_wide b) { return sb_w_pick_greater(a, b, sb_w_set(1), sb_w_set(0)); }
static inline sb_wide sb_t_at_most(sb_wide a, sb_wide b) { return sb_w_pick_greater(a, b, sb_w_set(0), sb_w_set(1)); }
static inline sb_wide sb_t_not(sb_wide a) { return sb_w_sub(sb_w_set(1), a); }
static inline sb_wide sb_t_or(sb_wide a, sb_wide b) { return sb_w_max(a, b); }
static inline sb_wide sb_t_and(sb_wide a, sb_wide b) { return sb_w_mul(a, b); }

static inline sb_wide sb_w_dot4(sb_wide a, sb_wide b) { return sb_w_sum4(sb_w_mul(a, b)); }
/* a packed 3-vector (x y z 0, its w already 0) repeated over the
 * register: whole copies of its four lanes, which the compiler makes one
 * broadcast (picking lanes by index made it a gather, a twentieth of the
 * answer's time) */
static inline sb_wide sb_w_repeat4(const sb_real v[4]) {
    sb_real lanes[SB_WIDTH];
    for (int l = 0; l < SB_WIDTH; l += 4) memcpy(lanes + l, v, 4 * sizeof *v);
    return sb_w_load(lanes);
}

/* A collider's constants spread over a register, made once per run. */
typedef struct sb_fast_wide_shape {
    sb_fast_shape_kind kind;
    sb_wide origin, normal, axis[3], extent[3], facing[3], reach, restitution, friction, static_friction, index;
} sb_fast_wide_shape;

static sb_fast_wide_shape sb_fast_widen(const sb_fast_shape* s, uint32_t index) {
    return (sb_fast_wide_shape){.kind = s->kind,
                                .axis = {sb_w_repeat4(s->axis[0]), sb_w_repeat4(s->axis[1]), sb_w_repeat4(s->axis[2])},
                                .extent = {sb_w_set(s->extent[0]), sb_w_set(s->extent[1]), sb_w_set(s->extent[2])},
                                .facing = {sb_w_set(s->facing[0]), sb_w_set(s->facing[1]), sb_w_set(s->facing[2])},
                                .origin = sb_w_repeat4(s->origin),
                                .normal = sb_w_repeat4(s->normal),
                                .reach = sb_w_set(s->reach),
                                .restitution = sb_w_set(s->restitution),
                                .friction = sb_w_set(s->friction),
                                .static_friction = sb_w_set(s->static_friction),
                                .index = sb_w_set((sb_real)index)};
}

/* One collider's answer for the vertices of a register: whether each
 * touches it, at which fraction of its move, how deep and along which
 * normal. */
typedef struct sb_fast_hit {
    sb_wide touches, fraction, depth, normal;
} sb_fast_hit;

/* The vertices' moves: start, end, displacement. */
typedef struct sb_fast_move {
    sb_wide from, to, d;
} sb_fast_move;

static sb_fast_hit sb_fast_plane(const sb_fast_wide_shape* s, const sb_fast_move* m) {
    const sb_wide zero = sb_w_set(0), one = sb_w_set(1), p = s->origin, t = s->reach;
    sb_fast_hit h;
    h.normal = s->normal;
    sb_wide f0 = sb_w_sub(sb_w_dot4(sb_w_sub(m->from, p), h.normal), t);
    sb_wide f1 = sb_w_sub(sb_w_dot4(sb_w_sub(m->to, p), h.normal), t);
    sb_wide from_inside = sb_t_at_most(f0, zero);
    h.touches = sb_t_at_most(f1, zero);
    h.fraction = sb_t_pick(from_inside, one, sb_w_div(f0, sb_w_sub(f0, f1)));
    h.depth = sb_t_pick(from_inside, sb_w_sub(zero, f1), zero);
    return h;
}

/* One end of the move against a shape (sb_sweep_end): in the solid or
 * not, how deep, the outward normal of least penetration. */
typedef struct sb_fast_end {
    sb_wide inside, depth, normal;
} sb_fast_end;

/* The move's line against a shape: whether it enters, the interval
 * [lo, hi] of it in the solid, the outward normal at lo. */
typedef struct sb_fast_line {
    sb_wide entered, lo, hi, normal;
} sb_fast_line;

/* The answer every shape's sweep gives (sb_sweep_from_inside and
 * sb_sweep_from_outside, kernels/contact/colliders/sweep.c); `flip` the
 * ends' normals' dot product, or a value of its sign. */
static sb_fast_hit sb_fast_sweep(const sb_fast_end* e0, const sb_fast_end* e1, sb_wide flip, const sb_fast_line* line,
                                 const sb_fast_move* m) {
    const sb_wide zero = sb_w_set(0), one = sb_w_set(1);
    /* from inside: resting, or stopped at the start */
    sb_wide resting = sb_t_and(e1->inside, sb_t_not(sb_t_greater(zero, flip)));
    sb_wide heading_in = sb_t_greater(zero, sb_w_dot4(m->d, e0->normal));
    sb_fast_hit inside = {.touches = sb_t_or(e1->inside, heading_in),
                          .fraction = sb_t_pick(resting, one, zero),
                          .depth = sb_t_pick(resting, e1->depth, e0->depth),
                          .normal = sb_t_pick(resting, e1->normal, e0->normal)};
    /* from outside: where the line enters, if within the move */
    sb_wide within = sb_t_and(sb_t_and(sb_t_at_most(line->lo, one), sb_t_not(sb_t_greater(zero, line->hi))),
                              sb_t_greater(line->hi, line->lo));
    sb_fast_hit outside = {.touches = sb_t_or(e1->inside, sb_t_and(line->entered, within)),
                           .fraction = sb_t_pick(line->entered, sb_w_min(sb_w_max(line->lo, zero), one), one),
                           .depth = zero,
                           .normal = sb_t_pick(line->entered, line->normal, e1->normal)};
    sb_fast_hit h;
    h.touches = sb_t_pick(e0->inside, inside.touches, outside.touches);
    h.fraction = sb_t_pick(e0->inside, inside.fraction, outside.fraction);
    h.depth = sb_t_pick(e0->inside, inside.depth, outside.depth);
    h.normal = sb_t_pick(e0->inside, inside.normal, outside.normal);
    return h;
}

/* The end at offset v from the nearest point of the shape's core (a
 * point, a segment) within r: `fallback` where v is 0. */
static sb_fast_end sb_fast_round_end(sb_wide v, sb_wide r, sb_wide fallback) {
    sb_wide distance = sb_w_sqrt(sb_w_dot4(v, v));
    return (sb_fast_end){.inside = sb_t_at_most(distance, r),
                         .depth = sb_w_sub(r, distance),
                         .normal = sb_w_pick_greater(distance, sb_w_set(0), sb_w_div(v, distance), fallback)};
}

static sb_wide sb_fast_up(void) {
    static const sb_real up[4] = {0, 0, 1, 0};
    return sb_w_repeat4(up);
}

/* The line of the move in the ball of radius r about center
 * (sb_ball_line, sphere.c): it enters heading to the center (b < 0) with a
 * positive discriminant, at c / (−b + √(b² − a c)). */
static sb_fast_line sb_fast_ball_line(sb_wide center, sb_wide r, const sb_fast_move* mv) {
    const sb_wide zero = sb_w_set(0);
    sb_wide m0 = sb_w_sub(mv->from, center);
    sb_wide a = sb_w_dot4(mv->d, mv->d), b = sb_w_dot4(m0, mv->d), c = sb_w_sub(sb_w_dot4(m0, m0), sb_w_mul(r, r));
    sb_wide disc = sb_w_sub(sb_w_mul(b, b), sb_w_mul(a, c));
    sb_wide q = sb_w_add(sb_w_sub(zero, b), sb_w_sqrt(sb_w_max(disc, zero)));
    sb_fast_line line = {.entered = sb_t_and(sb_t_greater(zero, b), sb_t_greater(disc, zero)),
                         .lo = sb_w_div(c, q),
                         .hi = sb_w_div(q, a)};
    sb_wide at = sb_w_add(m0, sb_w_mul(line.lo, mv->d));
    line.normal = sb_w_div(at, sb_w_sqrt(sb_w_dot4(at, at)));
    return line;
}

static sb_fast_hit sb_fast_sphere(const sb_fast_wide_shape* s, const sb_fast_move* m) {
    sb_fast_end e0 = sb_fast_round_end(sb_w_sub(m->from, s->origin), s->reach, sb_fast_up());
    sb_fast_end e1 = sb_fast_round_end(sb_w_sub(m->to, s->origin), s->reach, sb_fast_up());
    sb_fast_line line = sb_fast_ball_line(s->origin, s->reach, m);
    return sb_fast_sweep(&e0, &e1, sb_w_dot4(e1.normal, e0.normal), &line, m);
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
        e.inside = sb_t_and(e.inside, sb_t_at_most(zero, room));
        sb_wide least = k == 0 ? one : sb_t_greater(e.depth, room);
        e.depth = k == 0 ? room : sb_t_pick(least, room, e.depth);
        e.normal = k == 0 ? sb_w_mul(sign, s->axis[k]) : sb_t_pick(least, sb_w_mul(sign, s->axis[k]), e.normal);
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
        .entered = zero, .lo = sb_w_set(-(sb_real)INFINITY), .hi = sb_w_set((sb_real)INFINITY), .normal = zero};
    sb_wide inside_parallels = sb_w_set(1);
    for (int k = 0; k < 3; k++) {
        sb_wide h = s->extent[k], m = b->from[k], d = b->d[k];
        sb_wide moving = sb_t_greater(sb_w_abs(d), zero), forward = sb_t_greater(d, zero);
        sb_wide near = sb_t_pick(forward, sb_w_sub(zero, h), h), far = sb_w_sub(zero, near);
        sb_wide enter = sb_w_div(sb_w_sub(near, m), d), leave = sb_w_div(sb_w_sub(far, m), d);
        sb_wide later = sb_t_and(moving, sb_t_greater(enter, line.lo));
        sb_wide sooner = sb_t_and(moving, sb_t_greater(line.hi, leave));
        line.lo = sb_t_pick(later, enter, line.lo);
        line.normal = sb_t_pick(later, sb_t_pick(forward, sb_w_sub(zero, s->axis[k]), s->axis[k]), line.normal);
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
    sb_wide from = sb_w_sub(m->from, s->origin), to = sb_w_sub(m->to, s->origin);
    for (int k = 0; k < 3; k++) {
        b.from[k] = sb_w_dot4(from, s->axis[k]);
        b.to[k] = sb_w_dot4(to, s->axis[k]);
        b.d[k] = sb_w_sub(b.to[k], b.from[k]);
    }
    sb_wide axis0, side0, axis1, side1;
    sb_fast_end e0 = sb_fast_box_end(s, b.from, &axis0, &side0), e1 = sb_fast_box_end(s, b.to, &axis1, &side1);
    sb_fast_line line = sb_fast_box_line(s, &b);
    return sb_fast_sweep(&e0, &e1, sb_fast_box_flip(s, axis0, side0, axis1, side1), &line, m);
}

/* The earliest contact of a register's vertices among the colliders of
 * `near`, with the collider's index and surface constants per vertex. */
typedef struct sb_fast_contact {
    sb_fast_hit hit;
    sb_wide collider, restitution, friction, static_friction;
} sb_fast_contact;

static sb_fast_hit sb_fast_shape_hit(const sb_fast_wide_shape* s, const sb_fast_move* m) {
    switch (s->kind) {
    case SB_FAST_SHAPE_PLANE: return sb_fast_plane(s, m);
    case SB_FAST_SHAPE_SPHERE: return sb_fast_sphere(s, m);
    default: return sb_fast_box(s, m);
    }
}

static sb_fast_contact sb_fast_earliest(const sb_fast_wide_shape* shapes, uint32_t count, const sb_fast_move* m) {
    const sb_wide zero = sb_w_set(0);
    if (count == 1) /* one collider in reach (most blocks): nothing to compare */
        return (sb_fast_contact){sb_fast_shape_hit(shapes, m), shapes->index, shapes->restitution, shapes->friction,
                                 shapes->static_friction};
    sb_fast_contact best = {.hit = {zero, zero, zero, zero}, zero, zero, zero, zero};
    for (uint32_t c = 0; c < count; c++) {
        const sb_fast_wide_shape* s = &shapes[c];
        sb_fast_hit h = sb_fast_shape_hit(s, m);
        sb_wide take =
            sb_t_and(h.touches, sb_t_or(sb_t_not(best.hit.touches), sb_t_greater(best.hit.fraction, h.fraction)));
        best.hit.touches = sb_t_or(best.hit.touches, h.touches);
        best.hit.fraction = sb_t_pick(take, h.fraction, best.hit.fraction);
        best.hit.depth = sb_t_pick(take, h.depth, best.hit.depth);
        best.hit.normal = sb_t_pick(take, h.normal, best.hit.normal);
        best.collider = sb_t_pick(take, s->index, best.collider);
        best.restitution = sb_t_pick(take, s->restitution, best.restitution);
        best.friction = sb_t_pick(take, s->friction, best.friction);
        best.static_friction = sb_t_pick(take, s->static_friction, best.static_friction);
    }
    return best;
}

/* The velocity answer (sb_contact_velocity, the collider at rest). */
static sb_wide sb_fast_velocity(const sb_fast_contact* c, sb_wide v) {
    const sb_wide zero = sb_w_set(0), n = c->hit.normal;
    sb_wide vn = sb_w_dot4(v, n), jn = sb_w_mul(sb_w_sub(zero, sb_w_add(sb_w_set(1), c->restitution)), vn);
    sb_wide vt = sb_w_sub(v, sb_w_mul(vn, n)), vt_length = sb_w_sqrt(sb_w_dot4(vt, vt));
    sb_wide slide = sb_w_max(sb_w_sub(sb_w_set(1), sb_w_div(sb_w_mul(c->friction, jn), vt_length)), zero);
    sb_wide keep = sb_w_pick_greater(vt_length, sb_w_mul(c->static_friction, jn), slide, zero);
    sb_wide answered = sb_w_add(sb_w_mul(sb_w_mul(sb_w_sub(zero, c->restitution), vn), n), sb_w_mul(keep, vt));
    return sb_w_pick_greater(zero, vn, answered, v);
}

/* The position after the contact (sb_contact_position). */
static sb_wide sb_fast_position(const sb_fast_contact* c, const sb_fast_move* m, sb_wide v, sb_wide dt) {
    const sb_wide n = c->hit.normal, vn = sb_w_dot4(v, n);
    sb_wide normal_move = sb_w_add(sb_w_add(sb_w_mul(c->hit.fraction, sb_w_dot4(m->d, n)), c->hit.depth),
                                   sb_w_mul(sb_w_mul(sb_w_sub(sb_w_set(1), c->hit.fraction), dt), vn));
    return sb_w_add(sb_w_add(m->from, sb_w_mul(dt, sb_w_sub(v, sb_w_mul(vn, n)))), sb_w_mul(normal_move, n));
}

/* The colliders of a run and its lane-wise sums: the impulses m Δv per
 * collider, the vertices answered (their x y z lanes: three each). */
typedef struct sb_fast_run_state {
    uint32_t count;
    sb_fast_wide_shape shape[SB_MAX_COLLIDERS];
    sb_wide impulse[SB_MAX_COLLIDERS], lanes;
} sb_fast_run_state;

static void sb_fast_add_impulse(sb_fast_run_state* r, const sb_fast_contact* c, sb_wide impulse) {
    if (r->count == 1) {
        r->impulse[0] = sb_w_add(r->impulse[0], impulse);
        return;
    }
    for (uint32_t k = 0; k < r->count; k++) {
        sb_wide mine = sb_w_pick_greater(sb_w_abs(sb_w_sub(c->collider, r->shape[k].index)), sb_w_set((sb_real)0.5),
                                         sb_w_set(0), impulse);
        r->impulse[k] = sb_w_add(r->impulse[k], mine);
    }
}

/* Into the colliders' sums: lane l of a register belongs to axis l % 4
 * (the w lanes hold 0). */
static void sb_fast_reduce(const sb_fast_run_state* r, uint64_t near, double* out, double* contacts) {
    sb_real lanes[SB_WIDTH];
    uint32_t k = 0;
    for (uint32_t c = 0; near >> c; c++)
        if (near >> c & 1) {
            sb_w_store(lanes, r->impulse[k++]);
            for (int l = 0; l < SB_WIDTH; l++)
                if ((l & 3) < 3) out[3 * c + (l & 3)] -= lanes[l];
        }
    *contacts += sb_w_sum(r->lanes, SB_WIDTH) / 3;
}

/* The register's answered vertices (vertex q / 4 on) to step->touch. */
static void sb_fast_report(const sb_fast_contact_step* step, size_t q, const sb_fast_contact* c, sb_wide answered,
                           sb_wide x_new, sb_wide impulse) {
    sb_real lanes[5][SB_WIDTH];
    const sb_wide from[5] = {answered, c->hit.normal, x_new, impulse, c->collider};
    for (int a = 0; a < 5; a++) sb_w_store(lanes[a], from[a]);
    sb_real restitution[SB_WIDTH];
    sb_w_store(restitution, c->restitution);
    for (int j = 0; j < SB_WIDTH; j += 4) {
        if (!(lanes[0][j] > (sb_real)0.5)) continue;
        sb_contact contact = {.restitution = restitution[j]};
        double impulse_j[3];
        for (int k = 0; k < 3; k++) {
            contact.normal[k] = lanes[1][j + k];
            contact.point[k] = lanes[2][j + k];
            impulse_j[k] = lanes[3][j + k];
        }
        step->touch(step->user, step->first + (uint32_t)(q + (size_t)j) / 4, (int)lanes[4][j], &contact, impulse_j);
    }
}

uint32_t sb_fast_contact_answer(const sb_fast_colliders* colliders, uint64_t near, const sb_packed_run* run,
                                const sb_fast_contact_step* step, double* out, double* contacts) {
    const uint32_t granule = SB_WIDTH / 4, whole = run->count / granule * granule;
    const sb_wide zero = sb_w_set(0), dt = sb_w_set((sb_real)step->dt), drag = sb_w_set((sb_real)step->drag);
    const sb_real gravity[4] = {(sb_real)step->gravity[0], (sb_real)step->gravity[1], (sb_real)step->gravity[2], 0};
    const sb_wide g = sb_w_repeat4(gravity);
    sb_fast_run_state r; /* not zeroed whole: only its first r.count shapes and sums are used */
    r.count = 0;
    r.lanes = zero;
    for (uint32_t c = 0; near >> c; c++)
        if (near >> c & 1) {
            r.impulse[r.count] = zero;
            r.shape[r.count++] = sb_fast_widen(&colliders->shape[c], c);
        }
    for (size_t q = 0; q < 4 * (size_t)whole; q += SB_WIDTH) {
        sb_wide x = sb_w_load(run->x + q), v = sb_w_load(run->v + q), d = sb_w_load(run->d + q);
        sb_fast_move m = {sb_w_sub(x, d), x, d};
        sb_fast_contact c = sb_fast_earliest(r.shape, r.count, &m);
        sb_wide free = sb_t_greater(sb_w_spread4(run->inv_mass, q), zero); /* x y z lanes of the free vertices */
        sb_wide answered = sb_t_and(c.hit.touches, free);
        if (!sb_w_any(sb_w_less(sb_w_set((sb_real)0.5), answered), SB_WIDTH)) continue;
        sb_wide mass = sb_w_spread4(run->mass, q), v_new = sb_fast_velocity(&c, v);
        sb_wide x_new = sb_fast_position(&c, &m, v_new, dt);
        sb_w_store(run->x + q, sb_t_pick(answered, x_new, x));
        sb_w_store(run->v + q, sb_t_pick(answered, v_new, v));
        sb_w_store(run->d + q, sb_t_pick(answered, sb_w_mul(v_new, dt), d));
        sb_wide f_new = sb_w_mul(mass, sb_w_sub(g, sb_w_mul(drag, v_new)));
        sb_w_store(run->f + q, sb_t_pick(answered, f_new, sb_w_load(run->f + q)));
        sb_wide impulse = sb_t_pick(answered, sb_w_mul(mass, sb_w_sub(v_new, v)), zero);
        sb_fast_add_impulse(&r, &c, impulse);
        r.lanes = sb_w_add(r.lanes, answered);
        if (step->touch) sb_fast_report(step, q, &c, answered, x_new, impulse);
    }
    sb_fast_reduce(&r, near, out, contacts);
    return whole;
}

#else /* no register holds whole packed vertices: the scalar reference answers */

uint32_t sb_fast_contact_answer(const sb_fast_colliders* colliders, uint64_t near, const sb_packed_run* run,
                                const sb_fast_contact_step* step, double* out, double* contacts) {
    (void)colliders, (void)near, (void)run, (void)step, (void)out, (void)contacts;
    return 0;
}

#endif
