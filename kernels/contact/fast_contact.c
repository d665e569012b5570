/* The contact of the static built-in planes and spheres in SIMD over the
 * packed state: the fused Verlet step's answer for resting contact, where
 * every vertex of a body lying on a floor is answered every step.
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
 *   sphere  the ball of r = radius + t about c: from inside, resting when
 *           the end is in and its outward normal does not face against the
 *           start's (fraction 1, its depth and normal), otherwise at
 *           fraction 0 with the start's depth and normal when the move
 *           ends in or heads in; from outside, where the line enters
 *           (c / (−b + √(b² − a c)), the form without cancellation) if that
 *           lies within the move, else at the end when the end is in.
 *
 * The earliest contact wins (the first collider on a tie), then the
 * velocity answer (restitution, Coulomb friction: sb_contact_velocity) and
 * the position (sb_contact_position), and the force's starting value
 * m (g − drag v) for the new velocity. A block with a collider this
 * kernel does not answer goes to the scalar reference whole, so one
 * vertex's colliders are always compared by one of the two. The impulses a
 * collider receives are summed lane-wise over a run and reduced in lane
 * order: the same for any thread count, since a run is a fixed block of a
 * fixed chunk. tests/test_fast_contact.c compares the two on random moves. */
#include "kernels/contact/fast_contact.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/runtime/wide.h"

#include <math.h>
#include <string.h>

/* One collider as the kernel sees it, from its def. */
static sb_fast_shape sb_fast_shape_of(const sb_collider* c, double contact_thickness) {
    const sb_collider_def* d = &c->def;
    sb_fast_shape s = {.kind = SB_FAST_SHAPE_NONE};
    if (!SB_W_HAS_SUM4 || !sb_collider_is_static_builtin(c)) return s;
    double thickness = d->thickness + contact_thickness;
    if (d->shape == SB_COLLIDER_PLANE) {
        double length = sqrt(d->normal[0] * d->normal[0] + d->normal[1] * d->normal[1] + d->normal[2] * d->normal[2]);
        s.kind = SB_FAST_SHAPE_PLANE;
        for (int k = 0; k < 3; k++) {
            s.origin[k] = (sb_real)d->point[k];
            s.normal[k] = (sb_real)(d->normal[k] / length);
        }
        s.reach = (sb_real)thickness;
    } else if (d->shape == SB_COLLIDER_SPHERE) {
        s.kind = SB_FAST_SHAPE_SPHERE;
        for (int k = 0; k < 3; k++) s.origin[k] = (sb_real)d->center[k];
        s.reach = (sb_real)(d->radius + thickness);
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
    sb_wide origin, normal, reach, restitution, friction, static_friction, index;
} sb_fast_wide_shape;

static sb_fast_wide_shape sb_fast_widen(const sb_fast_shape* s, uint32_t index) {
    return (sb_fast_wide_shape){.kind = s->kind,
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

/* The outward normal of the ball at offset m from its center of length
 * `distance` (+z at the center). */
static sb_wide sb_fast_ball_normal(sb_wide m, sb_wide distance) {
    static const sb_real up[4] = {0, 0, 1, 0};
    return sb_w_pick_greater(distance, sb_w_set(0), sb_w_div(m, distance), sb_w_repeat4(up));
}

static sb_fast_hit sb_fast_sphere(const sb_fast_wide_shape* s, const sb_fast_move* mv) {
    const sb_wide zero = sb_w_set(0), one = sb_w_set(1), r = s->reach;
    sb_wide center = s->origin, m0 = sb_w_sub(mv->from, center), m1 = sb_w_sub(mv->to, center);
    sb_wide s0 = sb_w_dot4(m0, m0), d0 = sb_w_sqrt(s0), d1 = sb_w_sqrt(sb_w_dot4(m1, m1));
    sb_wide in0 = sb_t_at_most(d0, r), in1 = sb_t_at_most(d1, r);
    sb_wide n0 = sb_fast_ball_normal(m0, d0), n1 = sb_fast_ball_normal(m1, d1);
    /* from inside: resting, or stopped at the start */
    sb_wide resting = sb_t_and(in1, sb_t_not(sb_t_greater(zero, sb_w_dot4(n1, n0))));
    sb_wide heading_in = sb_t_greater(zero, sb_w_dot4(mv->d, n0));
    sb_fast_hit inside = {.touches = sb_t_or(in1, heading_in),
                          .fraction = sb_t_pick(resting, one, zero),
                          .depth = sb_t_pick(resting, sb_w_sub(r, d1), sb_w_sub(r, d0)),
                          .normal = sb_t_pick(resting, n1, n0)};
    /* from outside: where the line enters, if within the move */
    sb_wide a = sb_w_dot4(mv->d, mv->d), b = sb_w_dot4(m0, mv->d), c = sb_w_sub(s0, sb_w_mul(r, r));
    sb_wide disc = sb_w_sub(sb_w_mul(b, b), sb_w_mul(a, c));
    sb_wide entered = sb_t_and(sb_t_greater(zero, b), sb_t_greater(disc, zero));
    sb_wide q = sb_w_add(sb_w_sub(zero, b), sb_w_sqrt(sb_w_max(disc, zero)));
    sb_wide lo = sb_w_div(c, q), hi = sb_w_div(q, a), at = sb_w_add(m0, sb_w_mul(lo, mv->d));
    sb_wide within = sb_t_and(sb_t_and(sb_t_at_most(lo, one), sb_t_not(sb_t_greater(zero, hi))), sb_t_greater(hi, lo));
    sb_fast_hit outside = {.touches = sb_t_or(in1, sb_t_and(entered, within)),
                           .fraction = sb_t_pick(entered, sb_w_min(sb_w_max(lo, zero), one), one),
                           .depth = zero,
                           .normal = sb_t_pick(entered, sb_w_div(at, sb_w_sqrt(sb_w_dot4(at, at))), n1)};
    sb_fast_hit h;
    h.touches = sb_t_pick(in0, inside.touches, outside.touches);
    h.fraction = sb_t_pick(in0, inside.fraction, outside.fraction);
    h.depth = sb_t_pick(in0, inside.depth, outside.depth);
    h.normal = sb_t_pick(in0, inside.normal, outside.normal);
    return h;
}

/* The earliest contact of a register's vertices among the colliders of
 * `near`, with the collider's index and surface constants per vertex. */
typedef struct sb_fast_contact {
    sb_fast_hit hit;
    sb_wide collider, restitution, friction, static_friction;
} sb_fast_contact;

static sb_fast_hit sb_fast_shape_hit(const sb_fast_wide_shape* s, const sb_fast_move* m) {
    return s->kind == SB_FAST_SHAPE_PLANE ? sb_fast_plane(s, m) : sb_fast_sphere(s, m);
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
