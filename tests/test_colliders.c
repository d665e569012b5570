/* The built-in colliders (softbond/collider.h, kernels/contact/colliders/): each
 * shape's sweep against hand-computed crossings, thickness, resting contact
 * (inside to inside), misses, tangent and zero-length moves, the capsule's
 * pieces and the rotated box; kinematic colliders (poses, interpolation,
 * the collider's velocity and the move relative to it); every validation
 * message; a program's own collider called through the struct. */
#include "tests/test_util.h"
#include "softbond/collider.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/contact/colliders/box.h"
#include "kernels/contact/colliders/capsule.h"
#include "kernels/contact/colliders/plane.h"
#include "kernels/contact/colliders/sphere.h"
#include "kernels/contact/colliders/rotation.h"

#include <stdio.h>

#define EXACT 0.0
#define TIGHT 1e-12

typedef struct sweep_result {
    bool hit;
    double fraction, depth, normal[3];
} sweep_result;

static sweep_result sweep(sb_sweep_fn fn, const sb_collider_def* def, double fx, double fy, double fz, double tx,
                          double ty, double tz, double thickness) {
    sweep_result r = {false, -1.0, -1.0, {0.0, 0.0, 0.0}};
    const double from[3] = {fx, fy, fz}, to[3] = {tx, ty, tz};
    r.hit = fn(def, from, to, thickness, &r.fraction, &r.depth, r.normal);
    return r;
}

static void assert_hit(sweep_result r, double fraction, double depth, double nx, double ny, double nz, double tol) {
    if (!r.hit) fail_msg("expected a hit");
    TU_ASSERT_NEAR(r.fraction, fraction, tol);
    TU_ASSERT_NEAR(r.depth, depth, tol);
    TU_ASSERT_NEAR(r.normal[0], nx, tol);
    TU_ASSERT_NEAR(r.normal[1], ny, tol);
    TU_ASSERT_NEAR(r.normal[2], nz, tol);
}

static sb_collider_def sphere_def(double r) {
    sb_collider_def d = sb_default_collider_def();
    d.shape = SB_COLLIDER_SPHERE;
    d.radius = r;
    return d;
}

/* The capsule along x from −1 to 1, radius 0.5. */
static sb_collider_def capsule_def(void) {
    sb_collider_def d = sb_default_collider_def();
    d.shape = SB_COLLIDER_CAPSULE;
    d.a[0] = -1.0;
    d.b[0] = 1.0;
    d.radius = 0.5;
    return d;
}

static sb_collider_def box_def(double hx, double hy, double hz) {
    sb_collider_def d = sb_default_collider_def();
    d.shape = SB_COLLIDER_BOX;
    d.half_extents[0] = hx;
    d.half_extents[1] = hy;
    d.half_extents[2] = hz;
    return d;
}

static sb_collider* make(const sb_collider_def* def) {
    sb_error err = {{0}};
    sb_collider* c = sb_collider_create(def, &err);
    if (!c) fail_msg("sb_collider_create failed: %s", err.message);
    return c;
}

/* ---- names and defaults ------------------------------------------------- */

static void test_names(void** state) {
    (void)state;
    const char* names[5] = {"plane", "sphere", "capsule", "box", "mesh"};
    for (int s = 0; s < SB_COLLIDER_SHAPE_COUNT; s++) {
        sb_collider_shape out = SB_COLLIDER_SHAPE_COUNT;
        assert_string_equal(sb_collider_shape_name((sb_collider_shape)s), names[s]);
        assert_true(sb_collider_shape_from_name(names[s], &out));
        assert_int_equal(out, s);
    }
    assert_string_equal(sb_collider_shape_name(SB_COLLIDER_SHAPE_COUNT), "unknown");
    sb_collider_shape out = SB_COLLIDER_BOX;
    assert_false(sb_collider_shape_from_name("cube", &out));
    assert_false(sb_collider_shape_from_name(NULL, &out));
    assert_int_equal(out, SB_COLLIDER_BOX);

    sb_collider_def d = sb_default_collider_def();
    assert_int_equal(d.shape, SB_COLLIDER_PLANE);
    assert_true(d.normal[0] == 0.0 && d.normal[1] == 0.0 && d.normal[2] == 1.0);
    assert_true(d.point[0] == 0.0 && d.point[1] == 0.0 && d.point[2] == 0.0);
    assert_true(d.friction == 0.0 && d.static_friction == 0.0 && d.restitution == 0.0 && d.thickness == 0.0);
    assert_null(d.path);
    assert_int_equal(d.path_count, 0);

    /* names: copied, the shape's when NULL or empty, truncated to 63 characters */
    sb_collider* c = make(&d);
    assert_string_equal(sb_collider_name(c), "plane");
    sb_collider_destroy(c);
    char long_name[100];
    memset(long_name, 'n', sizeof long_name - 1);
    long_name[99] = '\0';
    d = sphere_def(1.0);
    d.name = long_name;
    c = make(&d);
    assert_int_equal(strlen(sb_collider_name(c)), 63);
    assert_int_equal(strncmp(sb_collider_name(c), long_name, 63), 0);
    sb_collider_destroy(c);
    char name[8] = "ball";
    d.name = name;
    c = make(&d);
    name[0] = 'X';
    assert_string_equal(sb_collider_name(c), "ball");
    d.name = "";
    sb_collider_destroy(c);
    c = make(&d);
    assert_string_equal(sb_collider_name(c), "sphere");
    sb_collider_destroy(c);
    sb_collider_destroy(NULL);
    assert_null(sb_collider_name(NULL));
}

/* ---- plane ---------------------------------------------------------------- */

static void test_plane(void** state) {
    (void)state;
    sb_collider_def d = sb_default_collider_def(); /* z = 0, normal +z */
    /* crossing: from z = 1 to z = −1 meets z = 0 halfway */
    assert_hit(sweep(sb_plane_sweep, &d, 0, 0, 1, 0, 0, -1, 0.0), 0.5, 0.0, 0, 0, 1, EXACT);
    /* thickness 0.25 moves the surface to z = 0.25: (1 − 0.25) / 2 */
    assert_hit(sweep(sb_plane_sweep, &d, 0, 0, 1, 0, 0, -1, 0.25), 0.375, 0.0, 0, 0, 1, EXACT);
    /* an oblique move: the fraction is along the move */
    assert_hit(sweep(sb_plane_sweep, &d, 0, 0, 3, 4, 0, -1, 0.0), 0.75, 0.0, 0, 0, 1, EXACT);
    /* inside to inside: keeps the move (fraction 1), pushed out by the depth of `to` */
    assert_hit(sweep(sb_plane_sweep, &d, 0, 0, -0.125, 0.5, 0, -0.25, 0.0), 1.0, 0.25, 0, 0, 1, EXACT);
    assert_hit(sweep(sb_plane_sweep, &d, 0, 0, -0.125, 0.5, 0, -0.25, 0.5), 1.0, 0.75, 0, 0, 1, EXACT);
    /* misses: above all the way; from inside leaving */
    assert_false(sweep(sb_plane_sweep, &d, 0, 0, 1, 0, 0, 0.5, 0.0).hit);
    assert_false(sweep(sb_plane_sweep, &d, 0, 0, -0.5, 0, 0, 1, 0.0).hit);
    /* tangent: parallel above it, no hit; parallel on it, resting contact of depth 0 */
    assert_false(sweep(sb_plane_sweep, &d, 0, 0, 1, 5, 0, 1, 0.0).hit);
    assert_hit(sweep(sb_plane_sweep, &d, 0, 0, 0, 5, 0, 0, 0.0), 1.0, 0.0, 0, 0, 1, EXACT);
    /* zero-length: a point query */
    assert_false(sweep(sb_plane_sweep, &d, 1, 2, 0.5, 1, 2, 0.5, 0.0).hit);
    assert_hit(sweep(sb_plane_sweep, &d, 1, 2, -0.5, 1, 2, -0.5, 0.0), 1.0, 0.5, 0, 0, 1, EXACT);
    /* from exactly on the surface: in is a hit, up is not */
    assert_hit(sweep(sb_plane_sweep, &d, 0, 0, 0, 0, 0, -0.5, 0.0), 1.0, 0.5, 0, 0, 1, EXACT);
    assert_false(sweep(sb_plane_sweep, &d, 0, 0, 0, 0, 0, 0.5, 0.0).hit);
    /* `to` exactly on the surface from outside: fraction 1, depth 0 */
    assert_hit(sweep(sb_plane_sweep, &d, 0, 0, 1, 0, 0, 0, 0.0), 1.0, 0.0, 0, 0, 1, EXACT);
    /* a normal that is not unit and a point off the origin: x = 1, normal −x */
    d.point[0] = 1.0;
    d.normal[0] = -4.0;
    d.normal[2] = 0.0;
    assert_hit(sweep(sb_plane_sweep, &d, -1, 7, 7, 3, 7, 7, 0.0), 0.5, 0.0, -1, 0, 0, EXACT);
    /* a tilted normal: (1, 1, 0) through the origin */
    d = sb_default_collider_def();
    d.normal[0] = d.normal[1] = 1.0;
    d.normal[2] = 0.0;
    double h = sqrt(0.5);
    assert_hit(sweep(sb_plane_sweep, &d, 1, 1, 0, -1, -1, 0, 0.0), 0.5, 0.0, h, h, 0, TIGHT);
}

/* ---- sphere --------------------------------------------------------------- */

static void test_sphere(void** state) {
    (void)state;
    sb_collider_def d = sphere_def(1.0);
    /* through the center: z = 3 → −1 meets z = 1 halfway */
    assert_hit(sweep(sb_sphere_sweep, &d, 0, 0, 3, 0, 0, -1, 0.0), 0.5, 0.0, 0, 0, 1, EXACT);
    /* thickness 0.5: z = 1.5, fraction 1.5 / 4 */
    assert_hit(sweep(sb_sphere_sweep, &d, 0, 0, 3, 0, 0, -1, 0.5), 0.375, 0.0, 0, 0, 1, EXACT);
    /* off the center: x = 0.6 meets the sphere at z = 0.8, normal (0.6, 0, 0.8) */
    assert_hit(sweep(sb_sphere_sweep, &d, 0.6, 0, 3, 0.6, 0, -3, 0.0), 2.2 / 6.0, 0.0, 0.6, 0, 0.8, TIGHT);
    /* a center off the origin */
    d.center[1] = 10.0;
    assert_hit(sweep(sb_sphere_sweep, &d, 0, 13, 0, 0, 9, 0, 0.0), 0.5, 0.0, 0, 1, 0, EXACT);
    d.center[1] = 0.0;
    /* inside to inside: depth of `to`, normal from the center to `to` */
    assert_hit(sweep(sb_sphere_sweep, &d, 0, 0, 0.5, 0.75, 0, 0, 0.0), 1.0, 0.25, 1, 0, 0, EXACT);
    assert_hit(sweep(sb_sphere_sweep, &d, 0, 0, 0.5, 0, 0, 0, 0.0), 1.0, 1.0, 0, 0, 1, EXACT); /* center: +z */
    /* misses: beside it, away from it, leaving it */
    assert_false(sweep(sb_sphere_sweep, &d, 2, 0, 3, 2, 0, -3, 0.0).hit);
    assert_false(sweep(sb_sphere_sweep, &d, 0, 0, 2, 0, 0, 5, 0.0).hit);
    assert_false(sweep(sb_sphere_sweep, &d, 0, 0, 0.5, 0, 0, 3, 0.0).hit);
    /* short of it */
    assert_false(sweep(sb_sphere_sweep, &d, 0, 0, 3, 0, 0, 1.5, 0.0).hit);
    /* tangent: x = 1 touches at one point, no hit (discriminant exactly 0) */
    assert_false(sweep(sb_sphere_sweep, &d, 1, 0, 3, 1, 0, -3, 0.0).hit);
    /* zero-length */
    assert_false(sweep(sb_sphere_sweep, &d, 0, 0, 3, 0, 0, 3, 0.0).hit);
    assert_hit(sweep(sb_sphere_sweep, &d, 0, 0, -0.75, 0, 0, -0.75, 0.0), 1.0, 0.25, 0, 0, -1, EXACT);
    /* from exactly on the surface: in and staying in, a hit; through and out, stopped at once */
    assert_hit(sweep(sb_sphere_sweep, &d, 0, 0, 1, 0, 0, 0.5, 0.0), 1.0, 0.5, 0, 0, 1, EXACT);
    assert_hit(sweep(sb_sphere_sweep, &d, 0, 0, 1, 0, 0, -3, 0.0), 0.0, 0.0, 0, 0, 1, EXACT);
    assert_false(sweep(sb_sphere_sweep, &d, 0, 0, 1, 0, 0, 3, 0.0).hit);
    /* a hair inside, moving through: no tunnelling */
    assert_hit(sweep(sb_sphere_sweep, &d, 0, 0, 0.875, 0, 0, -3, 0.0), 0.0, 0.125, 0, 0, 1, EXACT);
}

/* ---- capsule -------------------------------------------------------------- */

static void test_capsule(void** state) {
    (void)state;
    sb_collider_def d = capsule_def();
    /* the cylinder: straight down onto its middle, z = 0.5 at 1.5 / 2 */
    assert_hit(sweep(sb_capsule_sweep, &d, 0, 0, 2, 0, 0, 0, 0.0), 0.75, 0.0, 0, 0, 1, EXACT);
    assert_hit(sweep(sb_capsule_sweep, &d, 0.5, 2, 0, 0.5, 0, 0, 0.0), 0.75, 0.0, 0, 1, 0, EXACT);
    /* thickness 0.25: radius 0.75, 1.25 / 2 */
    assert_hit(sweep(sb_capsule_sweep, &d, 0, 0, 2, 0, 0, 0, 0.25), 0.625, 0.0, 0, 0, 1, EXACT);
    /* the end caps along the axis: x = ±1.5 at 1.5 / 2 */
    assert_hit(sweep(sb_capsule_sweep, &d, 3, 0, 0, 1, 0, 0, 0.0), 0.75, 0.0, 1, 0, 0, EXACT);
    assert_hit(sweep(sb_capsule_sweep, &d, -3, 0, 0, -1, 0, 0, 0.0), 0.75, 0.0, -1, 0, 0, EXACT);
    /* the caps from above, beyond the ends: x = ±1.3 meets them at z = 0.4 */
    assert_hit(sweep(sb_capsule_sweep, &d, 1.3, 0, 2, 1.3, 0, 0, 0.0), 0.8, 0.0, 0.6, 0, 0.8, TIGHT);
    assert_hit(sweep(sb_capsule_sweep, &d, -1.3, 0, 2, -1.3, 0, 0, 0.0), 0.8, 0.0, -0.6, 0, 0.8, TIGHT);
    /* a diagonal move that reaches the cylinder before the cap's sphere */
    assert_hit(sweep(sb_capsule_sweep, &d, 0.5, 0, 1, 1.5, 0, -1, 0.0), 0.25, 0.0, 0, 0, 1, EXACT);
    /* inside to inside: the cylinder and a cap */
    assert_hit(sweep(sb_capsule_sweep, &d, 0, 0, 0.375, 0.5, 0, 0.25, 0.0), 1.0, 0.25, 0, 0, 1, EXACT);
    assert_hit(sweep(sb_capsule_sweep, &d, 1.25, 0, 0, 1.25, 0, 0, 0.0), 1.0, 0.25, 1, 0, 0, EXACT);
    /* on the axis: a normal across the axis (least along x: y) */
    sweep_result r = sweep(sb_capsule_sweep, &d, 0.5, 0, 0, 0.5, 0, 0, 0.0);
    assert_hit(r, 1.0, 0.5, 0, 1, 0, EXACT);
    /* misses: beside it, beyond an end, short of it, leaving it */
    assert_false(sweep(sb_capsule_sweep, &d, 0, 1, 2, 0, 1, -2, 0.0).hit);
    assert_false(sweep(sb_capsule_sweep, &d, 1.6, 0, 2, 1.6, 0, -2, 0.0).hit);
    assert_false(sweep(sb_capsule_sweep, &d, 0, 0, 2, 0, 0, 1, 0.0).hit);
    assert_false(sweep(sb_capsule_sweep, &d, 0, 0, 0.25, 0, 0, 2, 0.0).hit);
    /* tangent to the cylinder: y = 0.5 touches it along a line, no hit */
    assert_false(sweep(sb_capsule_sweep, &d, 0, 0.5, 2, 0, 0.5, -2, 0.0).hit);
    /* tangent to a cap: x = 1.5 touches the sphere about b at one point */
    assert_false(sweep(sb_capsule_sweep, &d, 1.5, 0, 2, 1.5, 0, -2, 0.0).hit);
    /* zero-length outside */
    assert_false(sweep(sb_capsule_sweep, &d, 0, 0, 2, 0, 0, 2, 0.0).hit);
    /* a tilted capsule: a = (0,0,0), b = (1,1,0); down onto (0.5, 0.5) */
    d.a[0] = 0.0;
    d.b[0] = d.b[1] = 1.0;
    assert_hit(sweep(sb_capsule_sweep, &d, 0.5, 0.5, 2, 0.5, 0.5, 0, 0.0), 0.75, 0.0, 0, 0, 1, TIGHT);
    /* a == b: the sphere about a */
    d = capsule_def();
    d.b[0] = -1.0;
    assert_hit(sweep(sb_capsule_sweep, &d, -1, 0, 2, -1, 0, 0, 0.0), 0.75, 0.0, 0, 0, 1, EXACT);
    assert_hit(sweep(sb_capsule_sweep, &d, -1, 0, 0.25, -1, 0, 0.25, 0.0), 1.0, 0.25, 0, 0, 1, EXACT);
    assert_false(sweep(sb_capsule_sweep, &d, 0, 0, 2, 0, 0, 0, 0.0).hit);
}

/* ---- box ------------------------------------------------------------------ */

static void test_box(void** state) {
    (void)state;
    sb_collider_def d = box_def(1, 2, 3);
    /* each face */
    assert_hit(sweep(sb_box_sweep, &d, 3, 0, 0, -1, 0, 0, 0.0), 0.5, 0.0, 1, 0, 0, EXACT);
    assert_hit(sweep(sb_box_sweep, &d, -3, 0, 0, 1, 0, 0, 0.0), 0.5, 0.0, -1, 0, 0, EXACT);
    assert_hit(sweep(sb_box_sweep, &d, 0, 4, 0, 0, 0, 0, 0.0), 0.5, 0.0, 0, 1, 0, EXACT);
    assert_hit(sweep(sb_box_sweep, &d, 0, 0, -5, 0, 0, -1, 0.0), 0.5, 0.0, 0, 0, -1, EXACT);
    /* thickness 0.5: the face at x = 1.5 */
    assert_hit(sweep(sb_box_sweep, &d, 3, 0, 0, -1, 0, 0, 0.5), 0.375, 0.0, 1, 0, 0, EXACT);
    /* an oblique move: the face entered last (x at 0.5, y already inside) */
    assert_hit(sweep(sb_box_sweep, &d, 3, 1, 0, -1, 0, 0, 0.0), 0.5, 0.0, 1, 0, 0, EXACT);
    /* inside to inside: the face of least penetration at `to` */
    assert_hit(sweep(sb_box_sweep, &d, 0.5, 0, 0, 0.75, 0.5, 0, 0.0), 1.0, 0.25, 1, 0, 0, EXACT);
    assert_hit(sweep(sb_box_sweep, &d, 0, 0, 0, 0, -1.875, 0.5, 0.0), 1.0, 0.125, 0, -1, 0, EXACT);
    /* misses: beside it; through an edge only (one point in common); short; leaving */
    assert_false(sweep(sb_box_sweep, &d, 3, 3, 0, 3, -3, 0, 0.0).hit);
    assert_false(sweep(sb_box_sweep, &d, 2, 1, 0, 0, 3, 0, 0.0).hit);
    assert_false(sweep(sb_box_sweep, &d, 3, 0, 0, 2, 0, 0, 0.0).hit);
    assert_false(sweep(sb_box_sweep, &d, 0.5, 0, 0, 3, 0, 0, 0.0).hit);
    /* tangent: just above the face y = 2, no hit; sliding on it (the closed box), a hit */
    assert_false(sweep(sb_box_sweep, &d, 3, 2.5, 0, -3, 2.5, 0, 0.0).hit);
    assert_hit(sweep(sb_box_sweep, &d, 3, 2, 0, -3, 2, 0, 0.0), 1.0 / 3.0, 0.0, 1, 0, 0, TIGHT);
    /* zero-length */
    assert_false(sweep(sb_box_sweep, &d, 3, 0, 0, 3, 0, 0, 0.0).hit);
    assert_hit(sweep(sb_box_sweep, &d, 0, 0, 2.5, 0, 0, 2.5, 0.0), 1.0, 0.5, 0, 0, 1, EXACT);
    /* from on the face: in is resting contact; through and out, stopped at once */
    assert_hit(sweep(sb_box_sweep, &d, 1, 0, 0, 0.5, 0, 0, 0.0), 1.0, 0.5, 1, 0, 0, EXACT);
    assert_hit(sweep(sb_box_sweep, &d, 1, 0, 0, -3, 0, 0, 0.0), 0.0, 0.0, 1, 0, 0, EXACT);
    /* a center off the origin */
    d.center[2] = 10.0;
    assert_hit(sweep(sb_box_sweep, &d, 0, 0, 15, 0, 0, 11, 0.0), 0.5, 0.0, 0, 0, 1, EXACT);
}

/* Rotated 90 degrees about z, half extents (1, 2, 3) are (2, 1, 3) along the world's axes. */
static void test_box_rotated(void** state) {
    (void)state;
    sb_collider_def turned = box_def(1, 2, 3), swapped = box_def(2, 1, 3);
    turned.rotate[2] = 90.0;
    const double moves[][6] = {{3, 0, 0, -1, 0, 0}, {-3, 0.5, 0, 1, 0.5, 0}, {0, 3, 0, 0, -1, 0},
                               {0, -3, 1, 0, 1, 1}, {1, 0, 5, 1, 0.5, 1},    {1.5, 0.25, 0, 1.75, 0.5, 2.5},
                               {3, 3, 0, 3, -3, 0}, {0, 1.5, 0, 3, 1.5, 0},  {-1, -0.5, 0, -4, 0, 0}};
    for (size_t i = 0; i < sizeof moves / sizeof moves[0]; i++) {
        const double* m = moves[i];
        for (double t = 0.0; t <= 0.25; t += 0.25) {
            sweep_result a = sweep(sb_box_sweep, &turned, m[0], m[1], m[2], m[3], m[4], m[5], t);
            sweep_result b = sweep(sb_box_sweep, &swapped, m[0], m[1], m[2], m[3], m[4], m[5], t);
            assert_int_equal(a.hit, b.hit);
            if (b.hit) assert_hit(a, b.fraction, b.depth, b.normal[0], b.normal[1], b.normal[2], EXACT);
        }
    }
    /* hand-computed: the x face of the turned box is at x = 2 */
    assert_hit(sweep(sb_box_sweep, &turned, 3, 0, 0, -1, 0, 0, 0.0), 0.25, 0.0, 1, 0, 0, EXACT);
    /* 45 degrees: the unit cube's face toward (1, 1)/√2 is x + y = √2 */
    sb_collider_def diamond = box_def(1, 1, 1);
    diamond.rotate[2] = 45.0;
    double h = sqrt(0.5), s = (3.0 - (sqrt(2.0) - 0.1)) / 3.0;
    assert_hit(sweep(sb_box_sweep, &diamond, 3, 0.1, 0, 0, 0.1, 0, 0.0), s, 0.0, h, h, 0, TIGHT);
    /* about x by 90 degrees: the y half extent lies along z */
    sb_collider_def tipped = box_def(1, 2, 3);
    tipped.rotate[0] = 90.0;
    assert_hit(sweep(sb_box_sweep, &tipped, 0, 0, 4, 0, 0, 0, 0.0), 0.5, 0.0, 0, 0, 1, EXACT);
    assert_hit(sweep(sb_box_sweep, &tipped, 0, 6, 0, 0, 0, 0, 0.0), 0.5, 0.0, 0, 1, 0, EXACT);
    /* the rotation: about x, then y, then z (fixed axes) */
    double r[9];
    sb_collider_rotation((const double[3]){90, 90, 0}, r);
    /* Ry(90) Rx(90) e_y: Rx takes y to z, Ry takes z to x */
    TU_ASSERT_NEAR(r[0 * 3 + 1], 1.0, EXACT);
    TU_ASSERT_NEAR(r[1 * 3 + 1], 0.0, EXACT);
    TU_ASSERT_NEAR(r[2 * 3 + 1], 0.0, EXACT);
}

/* ---- random moves against a sampled reference ----------------------------- */

/* An independent signed measure of each inflated shape: < 0 inside, 0 on the surface. */
static double reference_sign(const sb_collider_def* d, const double x[3], double t) {
    double v[3];
    switch (d->shape) {
    case SB_COLLIDER_PLANE: {
        double n = tu_norm(d->normal);
        for (int k = 0; k < 3; k++) v[k] = x[k] - d->point[k];
        return tu_dot(d->normal, v) / n - t;
    }
    case SB_COLLIDER_SPHERE: return tu_dist(x, d->center) - d->radius - t;
    case SB_COLLIDER_CAPSULE: {
        double ab[3], ax[3];
        for (int k = 0; k < 3; k++) ab[k] = d->b[k] - d->a[k], ax[k] = x[k] - d->a[k];
        double tau = fmin(1.0, fmax(0.0, tu_dot(ax, ab) / tu_dot(ab, ab)));
        for (int k = 0; k < 3; k++) v[k] = ax[k] - tau * ab[k];
        return tu_norm(v) - d->radius - t;
    }
    case SB_COLLIDER_BOX: {
        double r[9], worst = -INFINITY;
        sb_collider_rotation(d->rotate, r);
        for (int k = 0; k < 3; k++) v[k] = x[k] - d->center[k];
        for (int i = 0; i < 3; i++) {
            double local = r[i] * v[0] + r[3 + i] * v[1] + r[6 + i] * v[2];
            worst = fmax(worst, fabs(local) - d->half_extents[i] - t);
        }
        return worst;
    }
    default: fail_msg("no shape");
    }
    return 0.0;
}

static void check_random_move(sb_sweep_fn fn, const sb_collider_def* d, const double from[3], const double to[3],
                              double t) {
    enum { samples = 1000 };
    sweep_result r = sweep(fn, d, from[0], from[1], from[2], to[0], to[1], to[2], t);
    double f0 = reference_sign(d, from, t), f1 = reference_sign(d, to, t), x[3];
    if (f0 <= 0.0 && f1 <= 0.0 && r.fraction == 1.0) { /* resting */
        assert_hit(r, 1.0, -f1, r.normal[0], r.normal[1], r.normal[2], 1e-12);
    } else if (f0 <= 0.0) {
        /* `to` inside past the middle of the body is held like a move heading in */ /* leaving, or stopped at once with
                                                                                        the depth of `from` */
        if (r.hit) assert_hit(r, 0.0, -f0, r.normal[0], r.normal[1], r.normal[2], 1e-12);
        if (r.hit) TU_ASSERT_LE(tu_dot(r.normal, (double[3]){to[0] - from[0], to[1] - from[1], to[2] - from[2]}), 0.0);
    } else {
        /* no sample before the fraction (all of them on a miss) is inside beyond rounding */
        double end = r.hit ? r.fraction : 1.0;
        for (int i = 0; i <= samples; i++) {
            double s = end * i / samples;
            for (int k = 0; k < 3; k++) x[k] = from[k] + s * (to[k] - from[k]);
            if (reference_sign(d, x, t) < -1e-9)
                fail_msg("sample %g inside before the answer (hit %d, fraction %.17g)", s, r.hit, r.fraction);
        }
        if (!r.hit) return;
        TU_ASSERT_NEAR(r.depth, 0.0, EXACT);
        TU_ASSERT_NEAR(reference_sign(d, x, t), 0.0, 1e-9); /* x: the contact point, on the surface */
        /* the normal: unit and outward (a step along it leaves, a step against it enters) */
        TU_ASSERT_NEAR(tu_norm(r.normal), 1.0, 1e-12);
        double out[3], in[3];
        for (int k = 0; k < 3; k++) out[k] = x[k] + 1e-6 * r.normal[k], in[k] = x[k] - 1e-6 * r.normal[k];
        TU_ASSERT_LE(0.0, reference_sign(d, out, t));
        TU_ASSERT_LE(reference_sign(d, in, t), 0.0);
    }
    if (r.hit) TU_ASSERT_NEAR(tu_norm(r.normal), 1.0, 1e-12);
}

static void test_random_moves(void** state) {
    (void)state;
    tu_rng rng = {2024};
    sb_collider_def shapes[5] = {sb_default_collider_def(), sphere_def(1.0), capsule_def(), box_def(1, 0.5, 0.75),
                                 capsule_def()};
    shapes[0].normal[0] = 0.3, shapes[0].normal[1] = -0.2, shapes[0].point[2] = 0.1;
    shapes[1].center[0] = 0.2;
    shapes[2].a[1] = 0.3, shapes[2].b[2] = 0.4;
    shapes[3].rotate[0] = 30, shapes[3].rotate[1] = -20, shapes[3].rotate[2] = 75, shapes[3].center[1] = 0.1;
    shapes[4].b[0] = -1.0; /* a == b */
    const sb_sweep_fn fns[5] = {sb_plane_sweep, sb_sphere_sweep, sb_capsule_sweep, sb_box_sweep, sb_capsule_sweep};
    int hits[5] = {0}, rests[5] = {0};
    for (int s = 0; s < 5; s++) {
        for (int i = 0; i < 3000; i++) {
            double from[3], to[3], t = i % 3 == 0 ? 0.0 : tu_uniform(&rng, 0.0, 0.3);
            double reach = i % 2 ? 0.2 : 4.0; /* short moves start resting contacts */
            for (int k = 0; k < 3; k++) {
                from[k] = tu_uniform(&rng, -2.0, 2.0);
                to[k] = from[k] + tu_uniform(&rng, -reach, reach);
            }
            check_random_move(fns[s], &shapes[s], from, to, t);
            double fraction, depth, n[3];
            if (fns[s](&shapes[s], from, to, t, &fraction, &depth, n)) hits[s]++, rests[s] += fraction == 1.0;
        }
        printf("shape %d: %d hits, %d resting of 3000 random moves\n", s, hits[s], rests[s]);
        if (hits[s] < 50 || rests[s] < 10) fail_msg("shape %d: too few hits (%d) or rests (%d)", s, hits[s], rests[s]);
    }
}

/* ---- through the collider: thickness, surface coefficients ----------------- */

static sb_contact_query query(double fx, double fy, double fz, double tx, double ty, double tz, double t0, double t1,
                              double thickness) {
    sb_contact_query q = {.vertex = 7, .t0 = t0, .t1 = t1, .thickness = thickness};
    q.from[0] = fx, q.from[1] = fy, q.from[2] = fz;
    q.to[0] = tx, q.to[1] = ty, q.to[2] = tz;
    return q;
}

static void test_collide_static(void** state) {
    (void)state;
    sb_collider_def d = sb_default_collider_def();
    d.thickness = 0.125;
    d.friction = 0.5;
    d.restitution = 0.25;
    sb_collider* c = make(&d);
    assert_ptr_equal(c->user, c);
    assert_non_null(c->begin_step);
    c->begin_step(c->user, 2.0, 2.5);
    /* total thickness 0.125 + 0.125: z = 0.25 */
    sb_contact_query q = query(0, 0, 1, 0, 0, -1, 2.0, 2.5, 0.125);
    sb_contact k;
    memset(&k, 0xff, sizeof k);
    assert_true(c->collide(c->user, &q, &k));
    TU_ASSERT_NEAR(k.fraction, 0.375, EXACT);
    TU_ASSERT_NEAR(k.depth, 0.0, EXACT);
    TU_ASSERT_NEAR(k.normal[2], 1.0, EXACT);
    assert_true(k.velocity[0] == 0.0 && k.velocity[1] == 0.0 && k.velocity[2] == 0.0);
    TU_ASSERT_NEAR(k.restitution, 0.25, EXACT);
    TU_ASSERT_NEAR(k.friction, 0.5, EXACT);
    TU_ASSERT_NEAR(k.static_friction, 0.5, EXACT); /* left 0: becomes friction */
    q = query(0, 0, 1, 0, 0, 0.5, 2.0, 2.5, 0.125);
    assert_false(c->collide(c->user, &q, &k));
    sb_collider_destroy(c);
    d.static_friction = 0.75;
    c = make(&d);
    q = query(0, 0, 0.1, 0, 0, 0.1, 2.0, 2.0, 0.0);
    assert_true(c->collide(c->user, &q, &k));
    TU_ASSERT_NEAR(k.depth, 0.025, 1e-15);
    TU_ASSERT_NEAR(k.static_friction, 0.75, EXACT);
    sb_collider_destroy(c);
}

/* ---- kinematic colliders ------------------------------------------------- */

/* A sphere of radius 1 at the origin translating 1 m along x in 1 s. */
static void test_kinematic_sphere(void** state) {
    (void)state;
    const sb_keyframe path[2] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {1.0, {1, 0, 0}, {0, 0, 0}}};
    sb_collider_def d = sphere_def(1.0);
    d.path = path;
    d.path_count = 2;
    sb_collider* c = make(&d);
    c->begin_step(c->user, 0.0, 1.0);
    /* a vertex at rest at x = 1.5: relative to the sphere it moves from 1.5 to 0.5 and meets x = 1 halfway */
    sb_contact_query q = query(1.5, 0, 0, 1.5, 0, 0, 0.0, 1.0, 0.0);
    sb_contact k;
    assert_true(c->collide(c->user, &q, &k));
    TU_ASSERT_NEAR(k.fraction, 0.5, TIGHT);
    TU_ASSERT_NEAR(k.normal[0], 1.0, TIGHT);
    TU_ASSERT_NEAR(k.velocity[0], 1.0, TIGHT);
    TU_ASSERT_NEAR(k.velocity[1], 0.0, TIGHT);
    TU_ASSERT_NEAR(k.velocity[2], 0.0, TIGHT);
    /* the vertex stays at 1.5, which the sphere at t1 (center x = 1) covers 0.5 deep: pushed out to x = 2 */
    TU_ASSERT_NEAR(k.depth, 0.5, TIGHT);
    /* a vertex moving with the sphere: no contact */
    q = query(1.5, 0, 0, 2.5, 0, 0, 0.0, 1.0, 0.0);
    assert_false(c->collide(c->user, &q, &k));
    /* a vertex ahead at 3: the sphere's front reaches 2 only */
    q = query(3, 0, 0, 3, 0, 0, 0.0, 1.0, 0.0);
    assert_false(c->collide(c->user, &q, &k));
    /* after the last keyframe the sphere stands still at x = 1 */
    c->begin_step(c->user, 2.0, 3.0);
    q = query(1, 0, 3, 1, 0, -1, 2.0, 3.0, 0.0);
    assert_true(c->collide(c->user, &q, &k));
    TU_ASSERT_NEAR(k.fraction, 0.5, TIGHT);
    TU_ASSERT_NEAR(k.velocity[0], 0.0, EXACT);
    TU_ASSERT_NEAR(k.depth, 0.0, EXACT);
    /* a step of zero length: no velocity */
    c->begin_step(c->user, 0.5, 0.5);
    q = query(1.5, 0, 0, 1.5, 0, 0, 0.5, 0.5, 0.0);
    assert_true(c->collide(c->user, &q, &k));
    TU_ASSERT_NEAR(k.velocity[0], 0.0, EXACT);
    TU_ASSERT_NEAR(k.depth, 0.0, TIGHT); /* x = 1.5 is on the sphere at t = 0.5 */
    sb_collider_destroy(c);
}

/* The plane z = 0 turning 90 degrees about x (about its point) in 1 s. */
static void test_kinematic_rotation(void** state) {
    (void)state;
    const sb_keyframe path[2] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {1.0, {0, 0, 0}, {90, 0, 0}}};
    sb_collider_def d = sb_default_collider_def();
    d.path = path;
    d.path_count = 2;
    sb_collider* c = make(&d);
    c->begin_step(c->user, 0.0, 1.0);
    /* a vertex at rest at (0, 1, 1): in the plane's frame it goes from (0, 1, 1) to (0, 1, −1), meeting it
     * halfway at p = (0, 1, 0), which the turn carries from (0, 1, 0) to (0, 0, 1) */
    sb_contact_query q = query(0, 1, 1, 0, 1, 1, 0.0, 1.0, 0.0);
    sb_contact k;
    assert_true(c->collide(c->user, &q, &k));
    TU_ASSERT_NEAR(k.fraction, 0.5, TIGHT);
    TU_ASSERT_NEAR(k.normal[0], 0.0, TIGHT);
    TU_ASSERT_NEAR(k.normal[1], -1.0, TIGHT);
    TU_ASSERT_NEAR(k.normal[2], 0.0, TIGHT);
    TU_ASSERT_NEAR(k.velocity[0], 0.0, TIGHT);
    TU_ASSERT_NEAR(k.velocity[1], -1.0, TIGHT);
    TU_ASSERT_NEAR(k.velocity[2], 1.0, TIGHT);
    TU_ASSERT_NEAR(k.depth, 1.0, TIGHT); /* at t1 the solid is y >= 0: the vertex is 1 deep */
    sb_collider_destroy(c);
}

static void assert_pose(const sb_collider* c, double t, const double expected[12], double tol) {
    double pose[12];
    sb_collider_pose(c, t, pose);
    for (int i = 0; i < 12; i++) {
        if (!(fabs(pose[i] - expected[i]) <= tol))
            fail_msg("pose(%g)[%d]: expected %.17g, got %.17g", t, i, expected[i], pose[i]);
    }
}

static void test_poses(void** state) {
    (void)state;
    /* a sphere about (1, 0, 0): keyframes at 2, 6 and 8 s */
    const sb_keyframe path[3] = {
        {2.0, {0, 0, 1}, {0, 0, 0}}, {6.0, {4, 0, 1}, {0, 0, 360}}, {8.0, {4, 2, 1}, {0, 0, 360}}};
    sb_collider_def d = sphere_def(0.5);
    d.center[0] = 1.0;
    d.path = path;
    d.path_count = 3;
    sb_collider* linear = make(&d);
    d.interpolation = SB_INTERPOLATION_SMOOTH;
    sb_collider* smooth = make(&d);
    const double held_first[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1};
    const double held_last[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 4, 2, 1};
    /* before the first keyframe and after the last the pose holds */
    assert_pose(linear, -5.0, held_first, EXACT);
    assert_pose(linear, 2.0, held_first, EXACT);
    assert_pose(smooth, 0.0, held_first, EXACT);
    assert_pose(linear, 8.0, held_last, EXACT);
    assert_pose(linear, 100.0, held_last, EXACT);
    assert_pose(smooth, 100.0, held_last, EXACT);
    /* t = 3, a quarter of the first interval. Linear: translate (1, 0, 1), Rz(90) about (1, 0, 0):
     * x ↦ R (x − c) + c + T, so the translation is c − R c + T = (1,0,0) − (0,1,0) + (1,0,1) */
    const double at_quarter[12] = {0, -1, 0, 1, 0, 0, 0, 0, 1, 2, -1, 1};
    assert_pose(linear, 3.0, at_quarter, EXACT);
    /* smooth: weight 3/16 − 2/64 = 0.15625: translate 0.625, rotate 56.25 degrees */
    double a = 56.25 * M_PI / 180.0, co = cos(a), si = sin(a);
    const double smooth_quarter[12] = {co, -si, 0, si, co, 0, 0, 0, 1, 1 - co + 0.625, -si, 1};
    assert_pose(smooth, 3.0, smooth_quarter, TIGHT);
    /* the second interval: translate (4, 1, 1) halfway, rotation 360 = identity (exact) */
    const double second[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 4, 1, 1};
    assert_pose(linear, 7.0, second, EXACT);
    assert_pose(smooth, 7.0, second, EXACT);
    /* begin_step stores the poses of t0 and t1 */
    linear->begin_step(linear->user, 3.0, 7.0);
    for (int i = 0; i < 12; i++) {
        TU_ASSERT_NEAR(linear->pose0[i], at_quarter[i], EXACT);
        TU_ASSERT_NEAR(linear->pose1[i], second[i], EXACT);
    }
    sb_collider_destroy(linear);
    sb_collider_destroy(smooth);
    /* one keyframe: that pose at every time; no path: the identity */
    const sb_keyframe one = {1.0, {0, 0, 5}, {0, 0, 0}};
    d.path = &one;
    d.path_count = 1;
    sb_collider* c = make(&d);
    const double five[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 5};
    assert_pose(c, 0.0, five, EXACT);
    assert_pose(c, 9.0, five, EXACT);
    sb_collider_destroy(c);
    d.path = NULL;
    d.path_count = 0;
    c = make(&d);
    const double identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    assert_pose(c, 3.0, identity, EXACT);
    c->begin_step(c->user, 0.0, 1.0);
    for (int i = 0; i < 12; i++) TU_ASSERT_NEAR(c->pose1[i], identity[i], EXACT);
    sb_collider_destroy(c);
}

/* ---- validation ------------------------------------------------------------ */

static void expect_error(const sb_collider_def* d, const char* message) {
    sb_error err = {{0}};
    sb_collider* c = sb_collider_create(d, &err);
    if (c) {
        sb_collider_destroy(c);
        fail_msg("expected \"%s\", but the collider was made", message);
    }
    assert_string_equal(err.message, message);
    assert_null(sb_collider_create(d, NULL)); /* err may be NULL */
}

static void test_validation(void** state) {
    (void)state;
    sb_error err = {{0}};
    assert_null(sb_collider_create(NULL, &err));
    assert_string_equal(err.message, "collider: no definition (def is NULL)");

    sb_collider_def d = sb_default_collider_def();
    d.name = "floor";
    d.shape = (sb_collider_shape)7;
    expect_error(&d, "collider 'floor': shape must be plane, sphere, capsule, box or mesh (got 7)");
    d.name = NULL;
    expect_error(&d, "collider '?': shape must be plane, sphere, capsule, box or mesh (got 7)");
    d = sb_default_collider_def();
    d.name = "floor";
    d.point[0] = NAN;
    expect_error(&d, "collider 'floor': point must be finite (got nan, 0, 0)");
    d.point[0] = 0.0;
    d.normal[2] = 0.0;
    expect_error(&d, "collider 'floor': normal must be finite and not zero (got 0, 0, 0)");
    d.normal[2] = INFINITY;
    expect_error(&d, "collider 'floor': normal must be finite and not zero (got 0, 0, inf)");
    d.normal[2] = 1.0;
    d.friction = -0.1;
    expect_error(&d, "collider 'floor': friction must be >= 0 and finite (got -0.1)");
    d.friction = 0.5;
    d.static_friction = 0.2;
    expect_error(&d, "collider 'floor': static_friction must be >= friction (0.5) and finite (got 0.2)");
    d.friction = 0.0;
    d.static_friction = -1.0;
    expect_error(&d, "collider 'floor': static_friction must be >= friction (0) and finite (got -1)");
    d.static_friction = 0.0;
    d.restitution = 1.5;
    expect_error(&d, "collider 'floor': restitution must be in [0, 1] (got 1.5)");
    d.restitution = NAN;
    expect_error(&d, "collider 'floor': restitution must be in [0, 1] (got nan)");
    d.restitution = 1.0;
    d.thickness = -0.01;
    expect_error(&d, "collider 'floor': thickness must be >= 0 and finite (got -0.01)");
    d.thickness = 0.0;
    d.interpolation = (sb_interpolation)5;
    expect_error(&d, "collider 'floor': interpolation must be linear or smooth (got 5)");
    d.interpolation = SB_INTERPOLATION_SMOOTH;
    d.path_count = 2;
    expect_error(&d, "collider 'floor': path_count is 2 but path is NULL");
    sb_keyframe path[3] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {1.0, {0, 0, 0}, {0, 0, 0}}, {1.0, {0, 0, 0}, {0, 0, 0}}};
    d.path = path;
    d.path_count = 3;
    expect_error(&d, "collider 'floor': path[2].time must be greater than path[1].time (1) (got 1)");
    path[2].time = 0.5;
    expect_error(&d, "collider 'floor': path[2].time must be greater than path[1].time (1) (got 0.5)");
    path[2].time = 2.0;
    path[0].time = NAN;
    expect_error(&d, "collider 'floor': path[0].time must be finite (got nan)");
    path[0].time = 0.0;
    path[1].translate[0] = INFINITY;
    expect_error(&d, "collider 'floor': path[1].translate must be finite (got inf, 0, 0)");
    path[1].translate[0] = 0.0;
    path[2].rotate[1] = NAN;
    expect_error(&d, "collider 'floor': path[2].rotate must be finite (got 0, nan, 0)");
    path[2].rotate[1] = 0.0;
    sb_collider* c = make(&d); /* now valid */
    sb_collider_destroy(c);

    d = sphere_def(-1.0);
    d.name = "ball";
    expect_error(&d, "collider 'ball': radius must be positive and finite (got -1)");
    d.radius = INFINITY;
    expect_error(&d, "collider 'ball': radius must be positive and finite (got inf)");
    d.name = NULL; /* the shape names it */
    d.radius = 0.0;
    expect_error(&d, "collider 'sphere': radius must be positive and finite (got 0)");
    d.radius = 1.0;
    d.center[1] = -INFINITY;
    expect_error(&d, "collider 'sphere': center must be finite (got 0, -inf, 0)");

    d = capsule_def();
    d.name = "rod";
    d.a[2] = NAN;
    expect_error(&d, "collider 'rod': a must be finite (got -1, 0, nan)");
    d.a[2] = 0.0;
    d.b[0] = INFINITY;
    expect_error(&d, "collider 'rod': b must be finite (got inf, 0, 0)");
    d.b[0] = 1.0;
    d.radius = -0.5;
    expect_error(&d, "collider 'rod': radius must be positive and finite (got -0.5)");

    d = box_def(1, 0, 1);
    d.name = "crate";
    expect_error(&d, "collider 'crate': half_extents must be positive and finite (got 1, 0, 1)");
    d.half_extents[1] = -2.0;
    expect_error(&d, "collider 'crate': half_extents must be positive and finite (got 1, -2, 1)");
    d.half_extents[1] = 2.0;
    d.center[0] = NAN;
    expect_error(&d, "collider 'crate': center must be finite (got nan, 0, 0)");
    d.center[0] = 0.0;
    d.rotate[2] = INFINITY;
    expect_error(&d, "collider 'crate': rotate must be finite (got 0, 0, inf)");

    /* a custom collider needs its collide callback */
    assert_null(sb_collider_create_custom("probe", NULL, NULL, NULL, &err));
    assert_string_equal(err.message, "collider 'probe': collide callback is required (got NULL)");
    assert_null(sb_collider_create_custom(NULL, NULL, NULL, NULL, &err));
    assert_string_equal(err.message, "collider 'custom': collide callback is required (got NULL)");
    assert_null(sb_collider_create_custom(NULL, NULL, NULL, NULL, NULL));
}

/* ---- a program's own collider ------------------------------------------- */

typedef struct probe {
    int steps, calls;
    double t0, t1;
    uint32_t vertex;
} probe;

static void probe_step(void* user, double t0, double t1) {
    probe* p = user;
    p->steps++;
    p->t0 = t0;
    p->t1 = t1;
}

static bool probe_collide(void* user, const sb_contact_query* q, sb_contact* contact) {
    probe* p = user;
    p->calls++;
    p->vertex = q->vertex;
    memset(contact, 0, sizeof *contact);
    contact->fraction = 0.25;
    contact->normal[1] = 1.0;
    return q->to[1] < 0.0;
}

static void test_custom(void** state) {
    (void)state;
    probe p = {0, 0, 0.0, 0.0, 0};
    sb_error err = {{0}};
    sb_collider* c = sb_collider_create_custom("probe", probe_collide, probe_step, &p, &err);
    assert_non_null(c);
    assert_string_equal(sb_collider_name(c), "probe");
    assert_ptr_equal(c->user, &p);
    c->begin_step(c->user, 1.0, 1.5);
    assert_int_equal(p.steps, 1);
    TU_ASSERT_NEAR(p.t0, 1.0, EXACT);
    TU_ASSERT_NEAR(p.t1, 1.5, EXACT);
    sb_contact_query q = query(0, 1, 0, 0, -1, 0, 1.0, 1.5, 0.0);
    sb_contact k;
    assert_true(c->collide(c->user, &q, &k));
    assert_int_equal(p.calls, 1);
    assert_int_equal(p.vertex, 7);
    TU_ASSERT_NEAR(k.fraction, 0.25, EXACT);
    q.to[1] = 2.0;
    assert_false(c->collide(c->user, &q, &k));
    assert_int_equal(p.calls, 2);
    sb_collider_destroy(c);
    /* begin_step may be NULL; the name defaults to "custom" */
    c = sb_collider_create_custom("", probe_collide, NULL, &p, &err);
    assert_non_null(c);
    assert_null(c->begin_step);
    assert_string_equal(sb_collider_name(c), "custom");
    sb_collider_destroy(c);
}

/* How far each shape may move in a step: its inner radius plus the thickness. */
static void test_inner_radius(void** state) {
    (void)state;
    sb_collider_def d = sb_default_collider_def();
    sb_collider* c = make(&d);
    assert_true(isinf(sb_collider_inner_radius(c))); /* a plane */
    sb_collider_destroy(c);
    d.thickness = 0.001;
    d.shape = SB_COLLIDER_SPHERE;
    d.radius = 0.005;
    c = make(&d);
    TU_ASSERT_NEAR(sb_collider_inner_radius(c), 0.006, 1e-15);
    sb_collider_destroy(c);
    d.shape = SB_COLLIDER_CAPSULE;
    d.b[0] = 0.1;
    c = make(&d);
    TU_ASSERT_NEAR(sb_collider_inner_radius(c), 0.006, 1e-15);
    sb_collider_destroy(c);
    d.shape = SB_COLLIDER_BOX;
    d.half_extents[0] = 0.03, d.half_extents[1] = 0.002, d.half_extents[2] = 0.01;
    c = make(&d);
    TU_ASSERT_NEAR(sb_collider_inner_radius(c), 0.003, 1e-15);
    sb_collider_destroy(c);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_inner_radius),
        cmocka_unit_test(test_plane),
        cmocka_unit_test(test_sphere),
        cmocka_unit_test(test_capsule),
        cmocka_unit_test(test_box),
        cmocka_unit_test(test_box_rotated),
        cmocka_unit_test(test_random_moves),
        cmocka_unit_test(test_collide_static),
        cmocka_unit_test(test_kinematic_sphere),
        cmocka_unit_test(test_kinematic_rotation),
        cmocka_unit_test(test_poses),
        cmocka_unit_test(test_validation),
        cmocka_unit_test(test_custom),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
