/* The SIMD answer of the static planes, spheres, capsules and boxes
 * (kernels/contact/fast_contact.c) against the scalar reference: each
 * collider's own callback in double, the earliest contact, then
 * sb_contact_velocity and sb_contact_position (kernels/contact/contact.c),
 * on random moves near the colliders' surfaces (a rotated box's faces,
 * edges and corners, a capsule's balls and cylinder, moves along and
 * across its axis among them): resting, entering,
 * leaving, missing, sticking and sliding. A move whose reference answer
 * changes its case (which collider, resting or entering, sticking or
 * sliding) under a perturbation of 1e-5 m or 1e-5 m/s lies on a boundary
 * the float kernel may decide the other way, and is left out; every other
 * one must agree to the state's rounding. */
#include "tests/test_util.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/contact/colliders/rotation.h"
#include "kernels/contact/contact.h"
#include "kernels/contact/fast_contact.h"

#include <stdio.h>

#define CANDIDATES 12000
#define COLLIDERS 5
#define THICKNESS 5e-4
#define DT 1e-3

static const double gravity[3] = {0.0, 0.5, -9.81};

static sb_collider* make(sb_collider_def def) {
    sb_error err;
    sb_collider* c = sb_collider_create(&def, &err);
    if (!c) fail_msg("%s", err.message);
    return c;
}

/* A tilted plane and a sphere standing in it, a rotated box, a tilted
 * capsule and one along x (a rod: moves along and across its axis are
 * exactly so) above the plane, with their own surfaces. */
static void make_colliders(sb_collider* c[COLLIDERS]) {
    sb_collider_def plane = sb_default_collider_def();
    plane.shape = SB_COLLIDER_PLANE;
    plane.point[0] = 0.3, plane.point[1] = -0.1, plane.point[2] = 0.05;
    plane.normal[0] = 0.1, plane.normal[1] = -0.2, plane.normal[2] = 1.0;
    plane.restitution = 0.3, plane.friction = 0.4, plane.static_friction = 0.5, plane.thickness = 1e-3;
    sb_collider_def sphere = sb_default_collider_def();
    sphere.shape = SB_COLLIDER_SPHERE;
    sphere.center[0] = 0.2, sphere.center[1] = 0.1, sphere.center[2] = -0.1;
    sphere.radius = 0.35, sphere.restitution = 0.5, sphere.friction = 0.2, sphere.static_friction = 0.25;
    sphere.thickness = 2e-3;
    sb_collider_def capsule = sb_default_collider_def();
    capsule.shape = SB_COLLIDER_CAPSULE;
    capsule.a[0] = 0.9, capsule.a[1] = -0.1, capsule.a[2] = 0.3;
    capsule.b[0] = 1.2, capsule.b[1] = 0.15, capsule.b[2] = 0.45;
    capsule.radius = 0.05, capsule.restitution = 0.2, capsule.friction = 0.3, capsule.static_friction = 0.6;
    capsule.thickness = 1e-3;
    sb_collider_def box = sb_default_collider_def();
    box.shape = SB_COLLIDER_BOX;
    box.center[0] = -0.8, box.center[1] = 0.3, box.center[2] = 0.7;
    box.half_extents[0] = 0.15, box.half_extents[1] = 0.1, box.half_extents[2] = 0.08;
    box.rotate[0] = 20, box.rotate[1] = -35, box.rotate[2] = 50;
    box.restitution = 0.4, box.friction = 0.5, box.static_friction = 0.7, box.thickness = 1.5e-3;
    c[0] = make(plane);
    c[1] = make(sphere);
    sb_collider_def rod = capsule;
    rod.a[0] = -1.1, rod.a[1] = -0.5, rod.a[2] = 0.4;
    rod.b[0] = -0.6, rod.b[1] = -0.5, rod.b[2] = 0.4;
    rod.radius = 0.02, rod.restitution = 0.35, rod.friction = 0.45, rod.static_friction = 0.55;
    c[2] = make(box);
    c[3] = make(capsule);
    c[4] = make(rod);
}

/* One vertex's move: the packed state's values and its mass. */
typedef struct move {
    double x[3], d[3], v[3], mass;
    bool fixed;
} move;

/* The reference's answer and its case. */
typedef struct answer {
    int hit; /* the collider, -1 for none */
    double x[3], v[3], impulse[3];
    int kind; /* fraction 0, between, 1; 3 more when the velocity changed, 3 more again when it stuck */
} answer;

/* The colliders in reach of the answer and of the reference (a bit each):
 * all five, or the plane alone (a run on a floor, which the kernel answers
 * by its inline plane). */
static uint64_t in_reach = 31;

static answer reference(sb_collider* const c[COLLIDERS], const move* m) {
    answer a = {.hit = -1};
    for (int k = 0; k < 3; k++) a.x[k] = m->x[k], a.v[k] = m->v[k];
    if (m->fixed) return a;
    sb_contact_query q = {.t0 = 0.0, .t1 = DT, .thickness = THICKNESS};
    for (int k = 0; k < 3; k++) q.from[k] = m->x[k] - m->d[k], q.to[k] = m->x[k];
    sb_contact best = {0};
    for (int i = 0; i < COLLIDERS; i++) {
        sb_contact contact;
        if ((in_reach >> i & 1) && c[i]->collide(c[i]->user, &q, &contact) &&
            (a.hit < 0 || contact.fraction < best.fraction)) {
            best = contact;
            a.hit = i;
        }
    }
    if (a.hit < 0) return a;
    sb_contact_velocity(&best, a.v);
    sb_contact_position(&best, DT, q.from, q.to, a.v, a.x);
    double vn = 0.0, vt = 0.0;
    for (int k = 0; k < 3; k++) vn += a.v[k] * best.normal[k];
    for (int k = 0; k < 3; k++) vt += pow(a.v[k] - vn * best.normal[k], 2);
    bool changed = a.v[0] != m->v[0] || a.v[1] != m->v[1] || a.v[2] != m->v[2];
    a.kind = (best.fraction == 0.0 ? 0 : best.fraction == 1.0 ? 2 : 1) + (changed ? 3 : 0) + (vt < 1e-20 ? 3 : 0);
    for (int k = 0; k < 3; k++) a.impulse[k] = m->mass * (a.v[k] - m->v[k]);
    return a;
}

static void normalize(double v[3]) {
    double length = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + 1e-12;
    for (int k = 0; k < 3; k++) v[k] /= length;
}

/* A random point p of the plane's surface and its normal n. */
static void near_plane(tu_rng* r, const sb_collider_def* d, double p[3], double n[3]) {
    for (int k = 0; k < 3; k++) n[k] = d->normal[k], p[k] = d->point[k] + tu_uniform(r, -0.5, 0.5);
    normalize(n);
    double off = (p[0] - d->point[0]) * n[0] + (p[1] - d->point[1]) * n[1] + (p[2] - d->point[2]) * n[2];
    for (int k = 0; k < 3; k++) p[k] -= off * n[k];
}

/* A point at `radius` from a random point of the segment a–b (a ball when
 * a = b). */
static void near_segment(tu_rng* r, const double a[3], const double b[3], double radius, double p[3], double n[3]) {
    double tau = tu_uniform(r, -0.6, 1.6), core[3];
    tau = tau < 0 ? 0 : tau > 1 ? 1 : tau;
    for (int k = 0; k < 3; k++) core[k] = a[k] + tau * (b[k] - a[k]), n[k] = tu_uniform(r, -1, 1);
    normalize(n);
    for (int k = 0; k < 3; k++) p[k] = core[k] + radius * n[k];
}

/* A point of the rotated box's surface: from a random point about the box,
 * the nearest of the box where it lies outside (a face, an edge or a
 * corner), or of the nearest face where inside; n the direction out. */
static void near_box(tu_rng* r, const sb_collider_def* d, double p[3], double n[3]) {
    double rotation[9], local[3], surface[3], out[3];
    sb_collider_rotation(d->rotate, rotation);
    int nearest = 0;
    for (int k = 0; k < 3; k++) {
        double h = d->half_extents[k];
        local[k] = tu_uniform(r, -1.4 * h, 1.4 * h);
        surface[k] = local[k] < -h ? -h : local[k] > h ? h : local[k];
        if (h - fabs(local[k]) < d->half_extents[nearest] - fabs(local[nearest])) nearest = k;
    }
    for (int k = 0; k < 3; k++) out[k] = local[k] - surface[k];
    if (out[0] == 0 && out[1] == 0 && out[2] == 0) { /* inside: onto the nearest face */
        surface[nearest] = copysign(d->half_extents[nearest], local[nearest]);
        out[nearest] = copysign(1.0, local[nearest]);
    }
    normalize(out);
    for (int k = 0; k < 3; k++) {
        p[k] = d->center[k], n[k] = 0;
        for (int j = 0; j < 3; j++) p[k] += rotation[3 * k + j] * surface[j], n[k] += rotation[3 * k + j] * out[j];
    }
}

/* A capsule's move d: as it is, along the axis a–b or across it (its part
 * along the axis taken away), a third of the time each. */
static void axis_move(tu_rng* r, const sb_collider_def* d, double move[3]) {
    double u[3] = {d->b[0] - d->a[0], d->b[1] - d->a[1], d->b[2] - d->a[2]}, choice = tu_uniform(r, 0, 3);
    double length = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]); /* the rod's u is exactly (1, 0, 0) */
    for (int k = 0; k < 3; k++) u[k] /= length;
    double along = move[0] * u[0] + move[1] * u[1] + move[2] * u[2];
    for (int k = 0; k < 3; k++)
        if (choice >= 1) move[k] = choice < 2 ? along * u[k] : move[k] - along * u[k];
}

/* A random move near one collider's surface, in the state's precision. */
static move random_move(tu_rng* r, sb_collider* const c[COLLIDERS]) {
    move m = {.mass = tu_uniform(r, 0.5e-3, 2e-3), .fixed = tu_uniform(r, 0, 1) < 0.05};
    double p[3], n[3];
    int which = (int)tu_uniform(r, 0, COLLIDERS);
    const sb_collider_def* d = &c[which < COLLIDERS ? which : 0]->def;
    if (d->shape == SB_COLLIDER_PLANE)
        near_plane(r, d, p, n);
    else if (d->shape == SB_COLLIDER_SPHERE)
        near_segment(r, d->center, d->center, d->radius, p, n);
    else if (d->shape == SB_COLLIDER_CAPSULE)
        near_segment(r, d->a, d->b, d->radius, p, n);
    else
        near_box(r, d, p, n);
    double height = tu_uniform(r, -6e-3, 8e-3), reach = tu_uniform(r, 0, 1) < 0.3 ? 2e-2 : 4e-3;
    double speed = tu_uniform(r, 0, 1) < 0.5 ? 0.05 : 2.0, inward = speed * tu_uniform(r, 0, 2);
    double move[3] = {tu_uniform(r, -reach, reach), tu_uniform(r, -reach, reach), tu_uniform(r, -reach, reach)};
    if (d->shape == SB_COLLIDER_CAPSULE) axis_move(r, d, move);
    for (int k = 0; k < 3; k++) {
        m.x[k] = (sb_real)(p[k] + height * n[k]);
        m.d[k] = (sb_real)move[k];
        m.v[k] = (sb_real)(speed * tu_uniform(r, -1, 1) - inward * n[k]);
    }
    m.mass = (sb_real)m.mass;
    return m;
}

/* Whether the reference's case holds under small perturbations. */
static bool stable(sb_collider* const c[COLLIDERS], const move* m, tu_rng* r) {
    answer a = reference(c, m);
    for (int trial = 0; trial < 8; trial++) {
        move p = *m;
        for (int k = 0; k < 3; k++) {
            p.x[k] += tu_uniform(r, -1e-5, 1e-5);
            p.d[k] += tu_uniform(r, -1e-5, 1e-5);
            p.v[k] += tu_uniform(r, -1e-5, 1e-5);
        }
        answer b = reference(c, &p);
        if (b.hit != a.hit || b.kind != a.kind) return false;
    }
    return true;
}

/* The packed state of the stable moves, a whole number of registers. */
typedef struct packed {
    sb_real *x, *v, *d, *f, *mass, *inv_mass;
    move* moves;
    uint32_t count;
} packed;

static packed pack(sb_collider* const c[COLLIDERS], uint32_t granule) {
    tu_rng rng = {12345};
    packed p = {.moves = calloc(CANDIDATES, sizeof(move))};
    for (int i = 0; i < CANDIDATES; i++) {
        move m = random_move(&rng, c);
        if (stable(c, &m, &rng)) p.moves[p.count++] = m;
    }
    p.count = p.count / granule * granule;
    sb_real** arrays[4] = {&p.x, &p.v, &p.d, &p.f};
    for (int a = 0; a < 4; a++) *arrays[a] = calloc(4 * (size_t)p.count + 64, sizeof(sb_real));
    p.mass = calloc(p.count + 16, sizeof(sb_real));
    p.inv_mass = calloc(p.count + 16, sizeof(sb_real));
    for (uint32_t i = 0; i < p.count; i++) {
        const move* m = &p.moves[i];
        for (int k = 0; k < 3; k++) {
            p.x[4 * i + k] = (sb_real)m->x[k];
            p.v[4 * i + k] = (sb_real)m->v[k];
            p.d[4 * i + k] = (sb_real)m->d[k];
            p.f[4 * i + k] = (sb_real)(m->mass * gravity[k]); /* the drift's value, to be replaced */
        }
        p.mass[i] = (sb_real)m->mass;
        p.inv_mass[i] = m->fixed ? 0 : (sb_real)(1.0 / m->mass);
    }
    return p;
}

static void unpack_free(packed* p) {
    free(p->x), free(p->v), free(p->d), free(p->f), free(p->mass), free(p->inv_mass), free(p->moves);
}

/* The tolerance of a value of magnitude `size` computed in the state's
 * precision from the state's values. */
static double tolerance(double size) { return 16.0 * TU_REAL_EPS * (1.0 + size); }

/* How much a curved surface's normal amplifies the rounding of the state's
 * coordinates: 1 + |x| / r about a ball's or a capsule's radius r (the
 * offset from the core, of length r, is rounded as |x| is), 1 on flat
 * faces. */
static double bend(sb_collider* const c[COLLIDERS], int hit, const move* m) {
    if (hit < 0) return 1.0;
    const sb_collider_def* d = &c[hit]->def;
    double size = fabs(m->x[0]) + fabs(m->x[1]) + fabs(m->x[2]);
    return d->shape == SB_COLLIDER_SPHERE || d->shape == SB_COLLIDER_CAPSULE ? 1.0 + size / d->radius : 1.0;
}

/* The SIMD answer against the reference under a drag (the answered
 * vertices' starting forces m (g − drag v) renewed), or none (the drift's
 * m g left as it is), with the colliders of `near` in reach. */
static void check_against_reference(double drag, uint64_t near) {
    in_reach = near;
    uint32_t granule = sb_fast_contact_granule();
    if (granule == 0) skip(); /* the scalar SIMD variant answers by the reference only */
    sb_collider* c[COLLIDERS];
    make_colliders(c);
    sb_fast_colliders fast;
    sb_fast_colliders_set(&fast, c, COLLIDERS, THICKNESS);
    assert_int_equal(fast.simd, 31);
    packed p = pack(c, granule);
    assert_true(p.count > CANDIDATES * 8 / 10); /* few moves lie on a boundary */
    sb_packed_run run = {p.x, p.v, p.d, p.f, p.mass, p.inv_mass, p.count};
    sb_fast_contact_step step = {.dt = DT, .drag = drag, .gravity = {gravity[0], gravity[1], gravity[2]}};
    double sums[3 * COLLIDERS] = {0}, contacts = 0.0, want[3 * COLLIDERS] = {0}, scale[COLLIDERS] = {0};
    assert_int_equal(sb_fast_contact_answer(&fast, near, &run, &step, sums, &contacts), p.count);
    int kinds[COLLIDERS][9] = {{0}}, answered = 0, missed = 0;
    for (uint32_t i = 0; i < p.count; i++) {
        answer a = reference(c, &p.moves[i]);
        double v_size =
            (fabs(a.v[0]) + fabs(a.v[1]) + fabs(a.v[2]) + fabs(p.moves[i].v[0])) * bend(c, a.hit, &p.moves[i]);
        for (int k = 0; k < 3; k++) {
            if (fabs(p.x[4 * i + k] - a.x[k]) > tolerance(fabs(a.x[k])) ||
                fabs(p.v[4 * i + k] - a.v[k]) > tolerance(v_size))
                fail_msg("vertex %u axis %d (collider %d, case %d): x %.9g, want %.9g; v %.9g, want %.9g", i, k, a.hit,
                         a.kind, (double)p.x[4 * i + k], a.x[k], (double)p.v[4 * i + k], a.v[k]);
            double mass = p.moves[i].mass, f = mass * (gravity[k] - (a.hit < 0 ? 0.0 : drag * a.v[k]));
            double d = a.hit < 0 ? p.moves[i].d[k] : a.v[k] * DT;
            assert_true(fabs(p.f[4 * i + k] - f) <= tolerance(10.0 + drag * v_size) * mass);
            assert_true(fabs(p.d[4 * i + k] - d) <= tolerance(v_size) * DT);
        }
        if (a.hit < 0) {
            missed++;
            continue;
        }
        answered++;
        kinds[a.hit][a.kind]++;
        for (int k = 0; k < 3; k++) want[3 * a.hit + k] -= a.impulse[k];
        scale[a.hit] += p.moves[i].mass * v_size;
    }
    assert_int_equal((int)contacts, answered);
    for (int h = 0; h < COLLIDERS; h++)
        for (int k = 0; k < 3; k++) assert_true(fabs(sums[3 * h + k] - want[3 * h + k]) <= tolerance(0) * scale[h]);
    print_message("%u moves: %d answered, %d missed\n", p.count, answered, missed);
    for (int h = 0; h < COLLIDERS; h++)
        print_message("collider %d: resting %d, entering %d; bounced %d %d; stuck %d %d\n", h, kinds[h][2], kinds[h][1],
                      kinds[h][5], kinds[h][4], kinds[h][8], kinds[h][7]);
    /* every case was tried: resting and entering, each unchanged, sliding
     * and sticking, against every collider, and moves that miss */
    assert_true(missed > 0);
    for (int h = 0; h < COLLIDERS; h++)
        for (int kind = 1; kind <= 8; kind++)
            if ((near >> h & 1) && kind != 3 && kind != 6) assert_true(kinds[h][kind] > 0);
    unpack_free(&p);
    for (int h = 0; h < COLLIDERS; h++) sb_collider_destroy(c[h]);
}

static void test_fast_contact_matches_reference(void** state) {
    (void)state;
    check_against_reference(0.2, 31);
}

static void test_fast_contact_without_drag_matches_reference(void** state) {
    (void)state;
    check_against_reference(0.0, 31);
}

static void test_fast_contact_on_one_plane_matches_reference(void** state) {
    (void)state;
    check_against_reference(0.2, 1);
    check_against_reference(0.0, 1);
}

/* A program's own collider that wraps a built-in one's callback (its user
 * that collider) is answered through the callback, not taken for a
 * built-in shape: its own def is the default's, a plane through the
 * origin, which the SIMD answer would have answered instead. */
static void test_wrapped_builtin_is_not_answered_in_simd(void** state) {
    (void)state;
    sb_collider* c[COLLIDERS];
    make_colliders(c);
    sb_error err;
    sb_collider* wrapped = sb_collider_create_custom("wrapped sphere", c[1]->collide, NULL, c[1]->user, &err);
    assert_non_null(wrapped);
    sb_collider* both[2] = {c[1], wrapped};
    sb_fast_colliders fast;
    sb_fast_colliders_set(&fast, both, 2, THICKNESS);
    assert_int_equal(fast.simd, sb_fast_contact_granule() ? 1 : 0); /* the built-in sphere only */
    sb_collider_destroy(wrapped);
    for (int h = 0; h < COLLIDERS; h++) sb_collider_destroy(c[h]);
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_fast_contact_matches_reference),
                                       cmocka_unit_test(test_fast_contact_without_drag_matches_reference),
                                       cmocka_unit_test(test_fast_contact_on_one_plane_matches_reference),
                                       cmocka_unit_test(test_wrapped_builtin_is_not_answered_in_simd)};
    return TU_RUN_TESTS(tests);
}
