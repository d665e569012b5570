/* The triangle-mesh collider (SB_COLLIDER_MESH, kernels/contact/colliders/mesh.c):
 * a cube mesh answers every move as the analytic box does, static and
 * kinematic; an icosphere's answers lie between the spheres through its
 * faces and its corners; an open sheet is a shell of its thickness, the
 * box of that half height over its middle; point masses rest on a mesh
 * floor and fast ones do not pass a thin closed or open mesh; bad meshes
 * are refused with their messages; a scene's `type: mesh` reads its file,
 * names its line when the file is missing or empty, and runs. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/test_files.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/contact/colliders/sphere.h"

/* ---- meshes made here ------------------------------------------------------ */

/* The vertex at p, added unless an equal one is there (exact comparison:
 * the faces compute a shared point with the same arithmetic). */
static uint32_t vertex_at(sb_mesh* m, const double p[3]) {
    for (uint32_t v = 0; v < m->vertex_count; v++)
        if (memcmp(m->positions + 3 * (size_t)v, p, 3 * sizeof *p) == 0) return v;
    memcpy(m->positions + 3 * (size_t)m->vertex_count, p, 3 * sizeof *p);
    return m->vertex_count++;
}

/* Coordinate i of n + 1 from c − h to c + h, the ends exactly so (they are
 * other faces' planes). */
static double grid_coordinate(double c, double h, uint32_t i, uint32_t n) {
    return i == 0 ? c - h : i == n ? c + h : c - h + 2.0 * h * i / n;
}

/* The closed surface of the box [center − h, center + h], each face an
 * n × n grid of quads split in two, wound outward. */
static sb_mesh box_mesh(const double center[3], const double h[3], uint32_t n) {
    sb_mesh m = {0};
    m.positions = malloc(6 * (size_t)(n + 1) * (n + 1) * 3 * sizeof *m.positions);
    m.triangles = malloc(6 * (size_t)n * n * 6 * sizeof *m.triangles);
    assert_non_null(m.positions);
    assert_non_null(m.triangles);
    for (int axis = 0; axis < 3; axis++)
        for (int side = -1; side <= 1; side += 2) {
            int b = (axis + 1) % 3, c = (axis + 2) % 3;
            uint32_t corner[4];
            for (uint32_t i = 0; i < n; i++)
                for (uint32_t j = 0; j < n; j++) {
                    for (int q = 0; q < 4; q++) { /* (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1) */
                        uint32_t u = i + (q == 1 || q == 2), v = j + (q >= 2);
                        double p[3];
                        p[axis] = center[axis] + side * h[axis];
                        p[b] = grid_coordinate(center[b], h[b], u, n);
                        p[c] = grid_coordinate(center[c], h[c], v, n);
                        corner[q] = vertex_at(&m, p);
                    }
                    /* e_b × e_c = e_axis: counterclockwise in (b, c) faces +axis */
                    const int order[2][6] = {{0, 1, 2, 0, 2, 3}, {0, 2, 1, 0, 3, 2}};
                    for (int k = 0; k < 6; k++)
                        m.triangles[3 * (size_t)m.triangle_count + (size_t)k] = corner[order[side < 0][k]];
                    m.triangle_count += 2;
                }
        }
    return m;
}

/* The open square [−L, L]² at z = 0 as an n × n grid of quads split in two. */
static sb_mesh square_mesh(double L, uint32_t n) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = n + 1;
    sheet.width = sheet.height = 2.0 * L;
    sheet.jitter = 0.0;
    sb_mesh m = {0};
    sb_error err;
    if (sb_mesh_generate_sheet(&sheet, &m, &err)) fail_msg("%s", err.message);
    for (uint32_t v = 0; v < m.vertex_count; v++) m.positions[3 * v] -= L, m.positions[3 * v + 1] -= L;
    return m;
}

static sb_collider* make_collider(const sb_collider_def* def) {
    sb_error err;
    sb_collider* c = sb_collider_create(def, &err);
    if (!c) fail_msg("%s", err.message);
    return c;
}

static sb_collider_def mesh_def(const sb_mesh* mesh, double thickness) {
    sb_collider_def d = sb_default_collider_def();
    d.shape = SB_COLLIDER_MESH;
    d.name = "mesh";
    d.mesh = mesh;
    d.thickness = thickness;
    return d;
}

static sb_collider_def box_def(const double center[3], const double h[3], double thickness) {
    sb_collider_def d = sb_default_collider_def();
    d.shape = SB_COLLIDER_BOX;
    d.name = "box";
    memcpy(d.center, center, sizeof d.center);
    memcpy(d.half_extents, h, sizeof d.half_extents);
    d.thickness = thickness;
    return d;
}

typedef struct answer {
    bool hit;
    sb_contact contact;
} answer;

static answer ask(const sb_collider* c, const double from[3], const double to[3], double t0, double t1) {
    sb_contact_query q = {.vertex = 0, .t0 = t0, .t1 = t1, .thickness = 0.0};
    memcpy(q.from, from, sizeof q.from);
    memcpy(q.to, to, sizeof q.to);
    answer a = {false, {0}};
    a.hit = c->collide(c->user, &q, &a.contact);
    return a;
}

static void random_point(tu_rng* rng, const double lo[3], const double hi[3], double p[3]) {
    for (int k = 0; k < 3; k++) p[k] = tu_uniform(rng, lo[k], hi[k]);
}

/* What kind of move an answer was: missed, entered from outside, or from
 * inside; counted so that a test sees each kind. */
typedef struct kinds {
    int missed, entered, inside;
} kinds;

static void count_kind(kinds* k, const answer* a) {
    if (!a->hit)
        k->missed++;
    else if (a->contact.depth == 0.0)
        k->entered++;
    else
        k->inside++;
}

/* Both answers the same within tol: hit or not, fraction, depth, normal,
 * the collider's velocity. */
static void assert_same(const answer* mesh, const answer* box, double tol, const double from[3], const double to[3]) {
    if (mesh->hit != box->hit)
        fail_msg("mesh %s, box %s: from (%.17g, %.17g, %.17g) to (%.17g, %.17g, %.17g)", mesh->hit ? "hit" : "missed",
                 box->hit ? "hit" : "missed", from[0], from[1], from[2], to[0], to[1], to[2]);
    if (!mesh->hit) return;
    TU_ASSERT_NEAR(mesh->contact.fraction, box->contact.fraction, tol);
    TU_ASSERT_NEAR(mesh->contact.depth, box->contact.depth, tol);
    for (int k = 0; k < 3; k++) {
        TU_ASSERT_NEAR(mesh->contact.normal[k], box->contact.normal[k], tol);
        TU_ASSERT_NEAR(mesh->contact.velocity[k], box->contact.velocity[k], tol);
    }
}

/* ---- a closed mesh against the analytic shapes ------------------------------- */

static const double cube_center[3] = {0.2, -0.1, 0.3}, cube_h[3] = {0.5, 0.35, 0.25};

/* 20 000 random moves in and around the box [center ± h] (a third of them
 * short, from near its surface): the cube mesh (each face a 3 × 3 grid)
 * answers as the box collider within 1e-9 (m, and unit normals). */
static void test_cube_mesh_is_the_box(void** state) {
    (void)state;
    sb_mesh cube = box_mesh(cube_center, cube_h, 3);
    sb_collider_def md = mesh_def(&cube, 0.0), bd = box_def(cube_center, cube_h, 0.0);
    sb_collider *mesh = make_collider(&md), *box = make_collider(&bd);
    sb_mesh_free(&cube); /* the collider keeps its own copy */
    tu_rng rng = {42};
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = cube_center[k] - 1.6 * cube_h[k], hi[k] = cube_center[k] + 1.6 * cube_h[k];
    kinds seen = {0};
    for (int i = 0; i < 20000; i++) {
        double from[3], to[3];
        random_point(&rng, lo, hi, from);
        random_point(&rng, lo, hi, to);
        if (i % 3 == 0)
            for (int k = 0; k < 3; k++) to[k] = from[k] + tu_uniform(&rng, -0.05, 0.05);
        answer a = ask(mesh, from, to, 0.0, 0.0), b = ask(box, from, to, 0.0, 0.0);
        assert_same(&a, &b, 1e-9, from, to);
        count_kind(&seen, &b);
    }
    print_message("missed %d, entered %d, from inside %d\n", seen.missed, seen.entered, seen.inside);
    assert_true(seen.missed > 1000 && seen.entered > 1000 && seen.inside > 1000);
    sb_collider_destroy(mesh);
    sb_collider_destroy(box);
}

/* The same cube and box on the same path (turning and moving over the
 * step) and then driven by sb_collider_set_pose: the same answers,
 * velocities included, within 1e-9. */
static void test_kinematic_cube_mesh_is_the_kinematic_box(void** state) {
    (void)state;
    sb_mesh cube = box_mesh(cube_center, cube_h, 2);
    const sb_keyframe path[2] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {1.0, {0.3, -0.2, 0.1}, {20, -10, 35}}};
    sb_collider_def md = mesh_def(&cube, 0.0), bd = box_def(cube_center, cube_h, 0.0);
    md.path = bd.path = path;
    md.path_count = bd.path_count = 2;
    sb_collider *mesh = make_collider(&md), *box = make_collider(&bd);
    sb_mesh_free(&cube);
    tu_rng rng = {7};
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = cube_center[k] - 2.0 * cube_h[k], hi[k] = cube_center[k] + 2.0 * cube_h[k];
    kinds seen = {0};
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1) { /* driven: from the path's last pose to this one */
            const double translate[3] = {0.1, 0.2, -0.1}, rotate[3] = {5, 40, -15};
            sb_collider_set_pose(mesh, translate, rotate);
            sb_collider_set_pose(box, translate, rotate);
        }
        mesh->begin_step(mesh->user, 0.4, 0.45);
        box->begin_step(box->user, 0.4, 0.45);
        for (int i = 0; i < 10000; i++) {
            double from[3], to[3];
            random_point(&rng, lo, hi, from);
            random_point(&rng, lo, hi, to);
            answer a = ask(mesh, from, to, 0.4, 0.45), b = ask(box, from, to, 0.4, 0.45);
            assert_same(&a, &b, 1e-9, from, to);
            count_kind(&seen, &b);
        }
    }
    print_message("missed %d, entered %d, from inside %d\n", seen.missed, seen.entered, seen.inside);
    assert_true(seen.missed > 1000 && seen.entered > 1000 && seen.inside > 1000);
    sb_collider_destroy(mesh);
    sb_collider_destroy(box);
}

/* An icosphere of radius 1 (3 subdivisions) lies between the sphere
 * through its corners (radius 1) and the one touching its faces (radius
 * r_in, the least distance of a face's plane from the center, computed
 * here). Inflated by t, between 1 + t and r_in + t. For random moves from
 * outside the outer sphere: a move that enters the inner sphere hits the
 * mesh, no earlier than it enters the outer one and no later than the
 * inner one; a move that misses the outer one misses the mesh; the normal
 * is within the facets' angle (edge / radius) of the radial direction at
 * the contact point, which lies between the spheres. Points inside: depth
 * between the spheres' depths. For t = 0 and t = 0.05. */
static void test_icosphere_lies_between_spheres(void** state) {
    (void)state;
    sb_mesh ico = {0};
    sb_error err;
    if (sb_mesh_generate_icosphere(3, 1.0, &ico, &err)) fail_msg("%s", err.message);
    double r_in = 1.0, edge = 0.0;
    for (uint32_t t = 0; t < ico.triangle_count; t++) {
        const double* p[3];
        for (int k = 0; k < 3; k++) p[k] = ico.positions + 3 * (size_t)ico.triangles[3 * t + (uint32_t)k];
        double ab[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        double ac[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]}, n[3];
        tu_cross(ab, ac, n);
        r_in = fmin(r_in, fabs(tu_dot(n, p[0])) / tu_norm(n));
        edge = fmax(edge, fmax(tu_dist(p[0], p[1]), fmax(tu_dist(p[1], p[2]), tu_dist(p[2], p[0]))));
    }
    const double thickness[2] = {0.0, 0.05}, origin[3] = {0, 0, 0};
    for (int variant = 0; variant < 2; variant++) {
        double t = thickness[variant], outer = 1.0 + t, inner = r_in + t;
        sb_collider_def md = mesh_def(&ico, t);
        sb_collider* mesh = make_collider(&md);
        tu_rng rng = {99 + (uint64_t)variant};
        const double lo[3] = {-1.6, -1.6, -1.6}, hi[3] = {1.6, 1.6, 1.6};
        int hits = 0, inside = 0;
        for (int i = 0; i < 20000; i++) {
            double from[3], to[3], fraction_inner, fraction_outer, depth, normal[3];
            random_point(&rng, lo, hi, from);
            random_point(&rng, lo, hi, to);
            answer a = ask(mesh, from, to, 0.0, 0.0);
            double r_from = tu_norm(from);
            if (r_from < inner) { /* inside (asked as a point): depth between the spheres' */
                answer point = ask(mesh, from, from, 0.0, 0.0);
                if (!point.hit) fail_msg("a point %.6f from the center is inside", r_from);
                TU_ASSERT_LE(inner - r_from - 1e-12, point.contact.depth);
                TU_ASSERT_LE(point.contact.depth, outer - r_from + 1e-12);
                inside++;
                continue;
            }
            if (r_from <= outer) continue; /* between the spheres: either answer holds */
            bool enters_inner = sb_ball_sweep(origin, inner, from, to, &fraction_inner, &depth, normal);
            bool enters_outer = sb_ball_sweep(origin, outer, from, to, &fraction_outer, &depth, normal);
            if (!enters_outer) {
                assert_false(a.hit);
                continue;
            }
            if (!enters_inner) continue;
            assert_true(a.hit);
            hits++;
            TU_ASSERT_LE(fraction_outer - 1e-12, a.contact.fraction);
            TU_ASSERT_LE(a.contact.fraction, fraction_inner + 1e-12);
            double p[3];
            for (int k = 0; k < 3; k++) p[k] = from[k] + a.contact.fraction * (to[k] - from[k]);
            double r = tu_norm(p);
            TU_ASSERT_LE(inner - 1e-9, r);
            TU_ASSERT_LE(r, outer + 1e-9);
            TU_ASSERT_LE(cos(edge), tu_dot(p, a.contact.normal) / r);
        }
        print_message("t = %g: r_in %.5f, edge %.4f; %d entries checked, %d points inside\n", t, r_in, edge, hits,
                      inside);
        assert_true(hits > 1000 && inside > 100);
        sb_collider_destroy(mesh);
    }
    sb_mesh_free(&ico);
}

/* ---- an open mesh: a shell --------------------------------------------------- */

/* The open square [−1, 1]² (a 4 × 4 grid) with thickness 0.02 is, over its
 * middle, the box of half extents (1, 1, 0.02): random moves with both ends
 * over [−0.9, 0.9]² answer the same within 1e-9, from above (normal +z)
 * and from below (−z). */
static void test_open_square_is_a_shell(void** state) {
    (void)state;
    sb_mesh square = square_mesh(1.0, 4);
    const double center[3] = {0, 0, 0}, h[3] = {1.0, 1.0, 0.02};
    sb_collider_def md = mesh_def(&square, 0.02), bd = box_def(center, h, 0.0);
    sb_collider *mesh = make_collider(&md), *box = make_collider(&bd);
    sb_mesh_free(&square);
    tu_rng rng = {5};
    const double lo[3] = {-0.9, -0.9, -0.1}, hi[3] = {0.9, 0.9, 0.1};
    kinds seen = {0};
    int up = 0, down = 0;
    for (int i = 0; i < 20000; i++) {
        double from[3], to[3];
        random_point(&rng, lo, hi, from);
        random_point(&rng, lo, hi, to);
        answer a = ask(mesh, from, to, 0.0, 0.0), b = ask(box, from, to, 0.0, 0.0);
        assert_same(&a, &b, 1e-9, from, to);
        count_kind(&seen, &b);
        if (a.hit) up += a.contact.normal[2] > 0.5, down += a.contact.normal[2] < -0.5;
    }
    print_message("missed %d, entered %d, from inside %d; normals up %d, down %d\n", seen.missed, seen.entered,
                  seen.inside, up, down);
    assert_true(seen.missed > 1000 && seen.entered > 1000 && seen.inside > 100 && up > 1000 && down > 1000);
    sb_collider_destroy(mesh);
    sb_collider_destroy(box);
}

/* ---- with the solver ----------------------------------------------------------- */

#define G 9.81

/* `count` free 10 g point masses (no elements) at random places over
 * [−0.8, 0.8]² at height z, moving at velocity. */
static sb_model* points_model(uint32_t count, double z, const double velocity[3], uint64_t seed) {
    sb_builder* b = sb_builder_create();
    tu_rng rng = {seed};
    for (uint32_t i = 0; i < count; i++) {
        sb_vertex_def v = sb_default_vertex_def();
        v.position[0] = tu_uniform(&rng, -0.8, 0.8);
        v.position[1] = tu_uniform(&rng, -0.8, 0.8);
        v.position[2] = z;
        v.mass = 0.01;
        memcpy(v.velocity, velocity, sizeof v.velocity);
        sb_builder_add_vertex(b, &v);
    }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

static sb_solver_def points_solver_def(sb_collider** collider) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_VERLET;
    def.gravity[2] = -G;
    def.colliders = collider;
    def.collider_count = 1;
    def.runtime.threads = 1;
    return def;
}

/* Lowest and highest z of the vertices now. */
static void z_range(const sb_solver* s, double* x, uint32_t n, double* lowest, double* highest) {
    sb_solver_get_positions(s, x);
    *lowest = INFINITY, *highest = -INFINITY;
    for (uint32_t i = 0; i < n; i++) *lowest = fmin(*lowest, x[3 * i + 2]), *highest = fmax(*highest, x[3 * i + 2]);
}

/* 20 masses dropped from 0.3 m onto a mesh floor (the top, z = 0, of a
 * closed slab, each face a 5 × 5 grid) with thickness 2 mm, friction 0.6:
 * in every step no vertex is below the thickness by more than 1e-5 m
 * (float rounding at that height), and after 1 s all rest on it (at the
 * thickness within 1e-5 m, below 1 mm/s) while the floor carries their
 * weight. */
static void test_resting_on_a_mesh_floor(void** state) {
    (void)state;
    const double center[3] = {0, 0, -0.05}, h[3] = {1, 1, 0.05}, t = 0.002, dt = 1e-4;
    sb_mesh slab = box_mesh(center, h, 5);
    sb_collider_def md = mesh_def(&slab, t);
    md.friction = 0.6;
    sb_collider* floor = make_collider(&md);
    sb_model* m = points_model(20, 0.3, (double[3]){0.3, -0.2, 0}, 3);
    sb_solver_def sd = points_solver_def(&floor);
    sb_solver* s = tu_solver(m, &sd);
    uint32_t n = 20;
    double x[60], v[60], lowest_ever = INFINITY, lowest, highest;
    for (int step = 0; step < 10000; step++) {
        tu_advance(s, dt, 1);
        z_range(s, x, n, &lowest, &highest);
        lowest_ever = fmin(lowest_ever, lowest);
    }
    sb_solver_get_velocities(s, v);
    double speed = 0.0, force[3];
    for (uint32_t i = 0; i < 3 * n; i++) speed = fmax(speed, fabs(v[i]));
    sb_solver_contact_force(s, 0, force);
    print_message("lowest ever %.7f m, now %.7f to %.7f m, fastest %.3g m/s, floor force %.5f N (weight %.5f N)\n",
                  lowest_ever, lowest, highest, speed, force[2], n * 0.01 * G);
    TU_ASSERT_LE(t - 1e-5, lowest_ever);
    TU_ASSERT_NEAR(lowest, t, 1e-5);
    TU_ASSERT_NEAR(highest, t, 1e-5);
    TU_ASSERT_LE(speed, 1e-3);
    TU_ASSERT_NEAR(-force[2], n * 0.01 * G, 1e-3 * n * 0.01 * G); /* pushed down by their weight */
    sb_solver_destroy(s);
    sb_model_destroy(m);
    sb_collider_destroy(floor);
    sb_mesh_free(&slab);
}

/* 50 masses thrown down at 20 m/s with 1 ms steps (20 mm a step) at a
 * mesh 2 mm thin: a closed slab (thickness 0) and an open square (a shell
 * of 1 mm either side), each face a grid of 6 × 6 so that moves cross its
 * triangles' edges too. In every step every vertex is on or above its top
 * (within 1e-6 m), none below it. */
static void test_fast_vertices_do_not_tunnel(void** state) {
    (void)state;
    const double center[3] = {0, 0, 0}, h[3] = {1, 1, 0.001}, dt = 1e-3;
    for (int variant = 0; variant < 2; variant++) {
        sb_mesh mesh = variant == 0 ? box_mesh(center, h, 6) : square_mesh(1.0, 6);
        sb_collider_def md = mesh_def(&mesh, variant == 0 ? 0.0 : 0.001);
        sb_collider* wall = make_collider(&md);
        sb_model* m = points_model(50, 0.1, (double[3]){1.0, 0.5, -20.0}, 11 + (uint64_t)variant);
        sb_solver_def sd = points_solver_def(&wall);
        sb_solver* s = tu_solver(m, &sd);
        double x[150], lowest_ever = INFINITY, lowest, highest;
        for (int step = 0; step < 100; step++) {
            tu_advance(s, dt, 1);
            z_range(s, x, 50, &lowest, &highest);
            lowest_ever = fmin(lowest_ever, lowest);
        }
        print_message("%s: lowest ever %.7f m (top at %.4f m)\n", variant == 0 ? "closed slab" : "open square",
                      lowest_ever, h[2]);
        TU_ASSERT_LE(h[2] - 1e-6, lowest_ever);
        sb_solver_destroy(s);
        sb_model_destroy(m);
        sb_collider_destroy(wall);
        sb_mesh_free(&mesh);
    }
}

/* ---- bad input ---------------------------------------------------------------- */

static void expect_refused(const sb_collider_def* def, const char* message) {
    sb_error err;
    memset(&err, 0, sizeof err);
    sb_collider* c = sb_collider_create(def, &err);
    if (c) sb_collider_destroy(c);
    assert_null(c);
    assert_string_equal(err.message, message);
}

/* No mesh, no triangles, an index out of range, a vertex not finite, a
 * triangle of no area, an open mesh without thickness, a closed mesh with
 * one triangle turned: each refused with its message. A closed mesh wound
 * inward is turned outward: a point inside it is inside. */
static void test_bad_meshes_are_refused(void** state) {
    (void)state;
    sb_collider_def d = mesh_def(NULL, 0.0);
    expect_refused(&d, "collider 'mesh': a mesh collider needs a mesh (mesh is NULL)");
    sb_mesh cube = box_mesh(cube_center, cube_h, 1);
    sb_mesh empty = cube;
    empty.triangle_count = 0;
    d.mesh = &empty;
    expect_refused(&d, "collider 'mesh': the mesh has no triangles");
    d.mesh = &cube;
    uint32_t saved = cube.triangles[4];
    cube.triangles[4] = 8;
    expect_refused(&d, "collider 'mesh': mesh triangle 1 has vertex 8 but the mesh has 8 vertices");
    cube.triangles[4] = cube.triangles[3];
    expect_refused(&d, "collider 'mesh': mesh triangle 1 (vertices 0, 0, 2) has no area");
    cube.triangles[4] = saved;
    cube.positions[5] = NAN;
    char message[200];
    snprintf(message, sizeof message, "collider 'mesh': mesh vertex 1 is not finite (%g, %g, nan)", cube.positions[3],
             cube.positions[4]);
    expect_refused(&d, message);
    cube.positions[5] = cube_center[2] - cube_h[2];
    sb_mesh square = square_mesh(1.0, 2);
    d.mesh = &square;
    expect_refused(&d, "collider 'mesh': the mesh is open (8 boundary and 0 non-manifold edge uses), so it is a shell "
                       "of the collider's thickness around its surface: thickness must be > 0 (got 0)");
    /* one triangle turned over */
    d.mesh = &cube;
    uint32_t* tri = cube.triangles + 3 * 5;
    uint32_t swap = tri[1];
    tri[1] = tri[2], tri[2] = swap;
    sb_error err = {{0}};
    assert_null(sb_collider_create(&d, &err));
    TU_ASSERT_CONTAINS(err.message, "collider 'mesh': the mesh is closed but not consistently oriented: edge ");
    /* every triangle turned over: it faces in, and is turned outward */
    for (uint32_t t = 0; t < cube.triangle_count; t++)
        if (t != 5)
            swap = cube.triangles[3 * t + 1], cube.triangles[3 * t + 1] = cube.triangles[3 * t + 2],
            cube.triangles[3 * t + 2] = swap;
    sb_collider* inward = make_collider(&d);
    answer a = ask(inward, cube_center, cube_center, 0.0, 0.0);
    assert_true(a.hit);
    TU_ASSERT_NEAR(a.contact.depth, cube_h[2], 1e-12); /* its least half extent */
    TU_ASSERT_NEAR(fabs(a.contact.normal[2]), 1.0, 1e-12);
    sb_collider_destroy(inward);
    sb_mesh_free(&square);
    sb_mesh_free(&cube);
}

/* ---- scenes ---------------------------------------------------------------------- */

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_mesh_collider");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

static void assert_input_error(const tu_result* r, const char* message) {
    assert_int_equal(r->code, 2);
    char expected[600];
    snprintf(expected, sizeof expected, "softbond: %s", message);
    TU_ASSERT_CONTAINS(r->err, expected);
}

/* A mesh collider whose file is missing, has no triangles, or is open
 * with no thickness: exit 2 and the line of the entry's key. */
static void test_scene_mesh_errors(void** state) {
    (void)state;
    tu_write_file("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    tu_write_file("square.obj", "v -1 -1 0\nv 1 -1 0\nv -1 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
    const char* cases[3][2] = {
        {"    file: nowhere.obj\n", "bad_mesh.yaml:5: 'colliders[0].file': "},
        {"    file: points.obj\n", "bad_mesh.yaml:5: 'colliders[0].file': "},
        {"    file: square.obj\n", "bad_mesh.yaml:3: collider 'mesh0': the mesh is open"},
    };
    for (int c = 0; c < 3; c++) {
        char text[400];
        snprintf(text, sizeof text, "mesh: {nx: 4, ny: 3}\ncolliders:\n  - type: mesh\n    scale: 2\n%s", cases[c][0]);
        tu_write_file("bad_mesh.yaml", text);
        tu_result r = tu_run((const char*[]){"run", "bad_mesh.yaml", "--output", "never", NULL});
        assert_input_error(&r, cases[c][1]);
        tu_result_free(&r);
    }
    tu_write_file("no_file.yaml", "mesh: {nx: 4, ny: 3}\ncolliders:\n  - type: mesh\n    thickness: 0.01\n");
    tu_result r = tu_run((const char*[]){"run", "no_file.yaml", "--output", "never", NULL});
    assert_input_error(&r, "no_file.yaml:3: 'colliders[0].file' is not set (a mesh needs file)");
    tu_result_free(&r);
}

/* scenes/mesh_bowl.yaml runs (a short part of it) and logs the bowl's force. */
static void test_mesh_bowl_scene_runs(void** state) {
    (void)state;
    tu_result r = tu_run((const char*[]){"run", SB_SOURCE_DIR "/scenes/mesh_bowl.yaml", "--set", "duration=0.05",
                                         "--output", "bowl_out", NULL});
    if (r.code != 0) fail_msg("exit %d: %s", r.code, r.err);
    char* log = tu_read_file(tu_tmp_path("bowl_out/log.csv"));
    assert_non_null(log);
    TU_ASSERT_CONTAINS(log, "bowl_fz");
    free(log);
    tu_result_free(&r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube_mesh_is_the_box),
        cmocka_unit_test(test_kinematic_cube_mesh_is_the_kinematic_box),
        cmocka_unit_test(test_icosphere_lies_between_spheres),
        cmocka_unit_test(test_open_square_is_a_shell),
        cmocka_unit_test(test_resting_on_a_mesh_floor),
        cmocka_unit_test(test_fast_vertices_do_not_tunnel),
        cmocka_unit_test(test_bad_meshes_are_refused),
        cmocka_unit_test(test_scene_mesh_errors),
        cmocka_unit_test(test_mesh_bowl_scene_runs),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
