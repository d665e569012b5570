/* Self-contact: the narrow-phase geometry (kernels/contact/proximity.c) against
 * brute force and known answers, and the pass (kernels/contact/self_contact.c) on
 * bodies that fold onto themselves or hit each other, checked with an
 * exact triangle-triangle test written here. */
#include "test_util.h"

#include "kernels/contact/proximity.h"
#include "kernels/contact/triangle_bvh.h"

/* ---- geometry --------------------------------------------------------------- */

static sb_vec3 random_point(tu_rng* r) {
    return (sb_vec3){tu_uniform(r, -1, 1), tu_uniform(r, -1, 1), tu_uniform(r, -1, 1)};
}

static double distance2(sb_vec3 a, sb_vec3 b) {
    sb_vec3 d = sb_v3_sub(a, b);
    return sb_v3_dot(d, d);
}

/* The closest point is in the triangle and no sampled point of the triangle
 * (corners, edges, inside) is closer. */
static void test_point_triangle_closest_is_closest(void** state) {
    (void)state;
    tu_rng r = {1};
    for (int trial = 0; trial < 500; trial++) {
        sb_vec3 p = random_point(&r), a = random_point(&r), b = random_point(&r), c = random_point(&r);
        if (trial % 50 == 0) c = sb_v3_add(a, sb_v3_scale(sb_v3_sub(b, a), 0.3)); /* degenerate: on a line */
        double w[3], d2 = sb_point_triangle_closest(p, a, b, c, w);
        for (int k = 0; k < 3; k++) TU_ASSERT_LE(-1e-12, w[k]);
        TU_ASSERT_NEAR(w[0] + w[1] + w[2], 1.0, 1e-12);
        sb_vec3 q = sb_v3_add(sb_v3_add(sb_v3_scale(a, w[0]), sb_v3_scale(b, w[1])), sb_v3_scale(c, w[2]));
        TU_ASSERT_NEAR(distance2(p, q), d2, 1e-12);
        for (int s = 0; s < 400; s++) {
            double u = tu_uniform(&r, 0, 1), v = tu_uniform(&r, 0, 1);
            if (s % 4 == 1) v = 0; /* on an edge */
            if (u + v > 1) u = 1 - u, v = 1 - v;
            sb_vec3 x = sb_v3_add(a, sb_v3_add(sb_v3_scale(sb_v3_sub(b, a), u), sb_v3_scale(sb_v3_sub(c, a), v)));
            TU_ASSERT_LE(d2, distance2(p, x) + 1e-12);
        }
    }
}

static void test_segments_closest_is_closest(void** state) {
    (void)state;
    tu_rng r = {2};
    for (int trial = 0; trial < 500; trial++) {
        sb_vec3 p0 = random_point(&r), p1 = random_point(&r), q0 = random_point(&r), q1 = random_point(&r);
        if (trial % 50 == 0) q1 = sb_v3_add(q0, sb_v3_sub(p1, p0)); /* parallel */
        double s, u, d2 = sb_segments_closest(p0, p1, q0, q1, &s, &u);
        TU_ASSERT_LE(0.0, s);
        TU_ASSERT_LE(s, 1.0);
        TU_ASSERT_LE(0.0, u);
        TU_ASSERT_LE(u, 1.0);
        for (int k = 0; k < 400; k++) {
            double a = tu_uniform(&r, 0, 1), b = tu_uniform(&r, 0, 1);
            if (k % 5 == 0) a = 0;
            if (k % 7 == 0) b = 1;
            sb_vec3 x = sb_v3_add(p0, sb_v3_scale(sb_v3_sub(p1, p0), a));
            sb_vec3 y = sb_v3_add(q0, sb_v3_scale(sb_v3_sub(q1, q0), b));
            TU_ASSERT_LE(d2, distance2(x, y) + 1e-12);
        }
    }
}

static void test_cubic_sign_changes(void** state) {
    (void)state;
    double roots[3];
    /* (t − 0.2)(t − 0.5)(t − 0.9) = t³ − 1.6 t² + 0.73 t − 0.09 */
    assert_int_equal(sb_cubic_sign_changes(1, -1.6, 0.73, -0.09, roots), 3);
    TU_ASSERT_NEAR(roots[0], 0.2, 1e-12);
    TU_ASSERT_NEAR(roots[1], 0.5, 1e-12);
    TU_ASSERT_NEAR(roots[2], 0.9, 1e-12);
    /* (t − 0.5)² (t + 1): touches zero at 0.5 without changing sign */
    assert_int_equal(sb_cubic_sign_changes(1, 0, -0.75, 0.25, roots), 0);
    assert_int_equal(sb_cubic_sign_changes(0, 0, 0, 0, roots), 0);
    /* a line: 2t − 1 */
    assert_int_equal(sb_cubic_sign_changes(0, 0, 2, -1, roots), 1);
    TU_ASSERT_NEAR(roots[0], 0.5, 1e-15);
    /* (t − 1)(t − 2)(t + 3): zero at the end of the step, reached from above */
    assert_int_equal(sb_cubic_sign_changes(1, 0, -7, 6, roots), 1);
    TU_ASSERT_NEAR(roots[0], 1.0, 0.0);
    /* (t + 1)(t − 2)(t − 3): no root in [0, 1] */
    assert_int_equal(sb_cubic_sign_changes(1, -4, 1, 6, roots), 0);
}

/* (A loop copying the rows here is miscompiled by GCC 12.2 at -O2
 * -march=native on x86-64: its vectorized form reads the constant rows in
 * the wrong order. Hence one assignment per point.) */
static sb_moving_quad quad_of(const double x0[4][3], const double x1[4][3]) {
    sb_moving_quad q = {{sb_v3(x0[0]), sb_v3(x0[1]), sb_v3(x0[2]), sb_v3(x0[3])},
                        {sb_v3(x1[0]), sb_v3(x1[1]), sb_v3(x1[2]), sb_v3(x1[3])}};
    return q;
}

/* A vertex falling through a resting triangle crosses it half way through
 * the step, at its point (0.2, 0.2); one falling beside it does not. */
static void test_vertex_triangle_crossing(void** state) {
    (void)state;
    const double x0[4][3] = {{0.2, 0.2, 1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const double x1[4][3] = {{0.2, 0.2, -1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    sb_moving_quad q = quad_of(x0, x1);
    double t, w[3];
    assert_true(sb_vertex_triangle_crossing(&q, 1e-6, &t, w));
    TU_ASSERT_NEAR(t, 0.5, 1e-12);
    TU_ASSERT_NEAR(w[0], 0.6, 1e-12);
    TU_ASSERT_NEAR(w[1], 0.2, 1e-12);
    TU_ASSERT_NEAR(w[2], 0.2, 1e-12);
    q.x0[0] = q.x1[0] = (sb_vec3){2, 2, 0};
    q.x0[0].z = 1, q.x1[0].z = -1;
    assert_false(sb_vertex_triangle_crossing(&q, 1e-6, &t, w));
    /* the triangle moving up through a resting vertex: the same crossing */
    const double y0[4][3] = {{0.2, 0.2, 0}, {0, 0, -1}, {1, 0, -1}, {0, 1, -1}};
    const double y1[4][3] = {{0.2, 0.2, 0}, {0, 0, 3}, {1, 0, 3}, {0, 1, 3}};
    q = quad_of(y0, y1);
    assert_true(sb_vertex_triangle_crossing(&q, 1e-6, &t, w));
    TU_ASSERT_NEAR(t, 0.25, 1e-12);
}

static void test_edge_edge_crossing(void** state) {
    (void)state;
    /* an edge along x falling through one along y, meeting at t = 0.25 */
    const double x0[4][3] = {{-1, 0, 1}, {1, 0, 1}, {0, -1, 0}, {0, 1, 0}};
    const double x1[4][3] = {{-1, 0, -3}, {1, 0, -3}, {0, -1, 0}, {0, 1, 0}};
    sb_moving_quad q = quad_of(x0, x1);
    double t, s, u;
    assert_true(sb_edge_edge_crossing(&q, 1e-6, &t, &s, &u));
    TU_ASSERT_NEAR(t, 0.25, 1e-12);
    TU_ASSERT_NEAR(s, 0.5, 1e-12);
    TU_ASSERT_NEAR(u, 0.5, 1e-12);
    /* shifted past the end of the second edge: it passes beside it */
    for (int k = 0; k < 2; k++) q.x0[k].y = q.x1[k].y = 1.5;
    assert_false(sb_edge_edge_crossing(&q, 1e-6, &t, &s, &u));
}

/* ---- the hierarchy's refit --------------------------------------------------- */

/* Refits the whole hierarchy as the pass does (the cut, then the top). */
static void refit_all(sb_triangle_bvh* bvh, const sb_real* from4, const sb_real* to4, double margin) {
    for (uint32_t k = 0; k < bvh->cut_count; k++) sb_triangle_bvh_refit_subtree(bvh, bvh->cut[k], from4, to4, margin);
    sb_triangle_bvh_refit_top(bvh);
}

/* Every leaf's box holds its triangles' corners at both ends grown by the
 * margin, its normal box holds their unit normals at the end (computed
 * here in double), every parent's boxes hold its children's; a flat sheet
 * is flat at the root, the same sheet folded in half is not. */
static void test_refit_bounds_every_triangle(void** state) {
    (void)state;
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = def.ny = 23;
    def.jitter = 0.3;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&def, &mesh, &err), SB_OK);
    uint32_t n = mesh.vertex_count, t = mesh.triangle_count;
    uint32_t* corners[3];
    for (int c = 0; c < 3; c++) {
        corners[c] = malloc(t * sizeof(uint32_t));
        for (uint32_t k = 0; k < t; k++) corners[c][k] = mesh.triangles[3 * k + c];
    }
    sb_triangle_bvh* bvh = sb_triangle_bvh_create(t, (const uint32_t* const*)corners, mesh.positions);
    assert_non_null(bvh);
    sb_real *from4 = aligned_alloc(64, 4 * 64 * ((n + 63) / 64) * sizeof(sb_real)),
            *to4 = aligned_alloc(64, 4 * 64 * ((n + 63) / 64) * sizeof(sb_real));
    tu_rng r = {7};
    const double margin = 0.01;
    for (int fold = 0; fold < 2; fold++) {
        for (uint32_t i = 0; i < n; i++) {
            double x = mesh.positions[3 * i], y = mesh.positions[3 * i + 1];
            if (fold && x > 0.5) x = 1.0 - x; /* folded over x = 0.5, the right half lifted by 2 cm */
            for (int a = 0; a < 3; a++) from4[4 * i + a] = (sb_real)mesh.positions[3 * i + a];
            to4[4 * i] = (sb_real)(x + (fold ? 0.0 : tu_uniform(&r, -1e-3, 1e-3)));
            to4[4 * i + 1] = (sb_real)y;
            to4[4 * i + 2] = (sb_real)(fold && mesh.positions[3 * i] > 0.5 ? 0.02 : tu_uniform(&r, -1e-3, 1e-3));
            from4[4 * i + 3] = to4[4 * i + 3] = 0;
        }
        refit_all(bvh, from4, to4, margin);
        for (uint32_t i = 0; i < bvh->node_count; i++) {
            const sb_bvh_node* node = &bvh->nodes[i];
            const float *box = bvh->bounds[i].box, *normals = bvh->bounds[i].normals;
            for (uint32_t k = node->first; k < node->first + node->count; k++) {
                uint32_t tri = bvh->order[k];
                double p[3][3];
                for (int c = 0; c < 3; c++)
                    for (int a = 0; a < 3; a++) {
                        uint32_t v = corners[c][tri];
                        TU_ASSERT_LE(box[a], (double)from4[4 * v + a] - margin * 0.999);
                        TU_ASSERT_LE(box[a], (double)to4[4 * v + a] - margin * 0.999);
                        TU_ASSERT_LE((double)from4[4 * v + a] + margin * 0.999, box[3 + a]);
                        TU_ASSERT_LE((double)to4[4 * v + a] + margin * 0.999, box[3 + a]);
                        p[c][a] = to4[4 * v + a];
                    }
                double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
                double w[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]}, normal[3];
                tu_cross(u, w, normal);
                double length = tu_norm(normal);
                for (int a = 0; a < 3; a++) {
                    TU_ASSERT_LE(normals[a], normal[a] / length);
                    TU_ASSERT_LE(normal[a] / length, normals[3 + a]);
                }
            }
        }
        if (fold)
            assert_false(sb_triangle_bvh_flat(bvh, 0));
        else
            assert_true(sb_triangle_bvh_flat(bvh, 0) && bvh->culled[0]);
    }
    free(from4), free(to4);
    for (int c = 0; c < 3; c++) free(corners[c]);
    sb_triangle_bvh_destroy(bvh);
    sb_mesh_free(&mesh);
}

/* ---- an exact triangle-triangle test ----------------------------------------- */

static double orient(const double* a, const double* b, const double* c, const double* d) {
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]}, n[3];
    tu_cross(u, v, n);
    return tu_dot(n, w);
}

/* Whether segment pq passes through the inside of triangle abc: its ends
 * strictly on both sides of the plane and the line strictly inside the
 * three edges. An orientation below 1e-9 of the largest possible (the
 * product of the lengths involved) counts as zero, so that rounding in two
 * coplanar triangles (a flat part of a sheet) is not taken for a crossing. */
static bool segment_crosses(const double* p, const double* q, const double* a, const double* b, const double* c) {
    double scale = tu_dist(a, b) * tu_dist(a, c) * tu_dist(p, q) * 1e-9;
    double sp = orient(a, b, c, p), sq = orient(a, b, c, q);
    if (!((sp > scale && sq < -scale) || (sp < -scale && sq > scale))) return false;
    double e0 = orient(p, q, a, b), e1 = orient(p, q, b, c), e2 = orient(p, q, c, a);
    return (e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0);
}

/* Two triangles (no shared vertex) intersect when an edge of one passes
 * through the other. */
static bool triangles_intersect(const double* x, const uint32_t a[3], const uint32_t b[3]) {
    for (int e = 0; e < 3; e++) {
        if (segment_crosses(x + 3 * a[e], x + 3 * a[(e + 1) % 3], x + 3 * b[0], x + 3 * b[1], x + 3 * b[2]))
            return true;
        if (segment_crosses(x + 3 * b[e], x + 3 * b[(e + 1) % 3], x + 3 * a[0], x + 3 * a[1], x + 3 * a[2]))
            return true;
    }
    return false;
}

/* A triangle's bounding box, for the sweep below. */
typedef struct tri_box {
    double lo[3], hi[3];
    uint32_t tri;
} tri_box;

static int by_low_x(const void* a, const void* b) {
    double x = ((const tri_box*)a)->lo[0], y = ((const tri_box*)b)->lo[0];
    return (x > y) - (x < y);
}

static bool boxes_overlap(const tri_box* a, const tri_box* b) {
    for (int k = 0; k < 3; k++)
        if (a->hi[k] < b->lo[k] || b->hi[k] < a->lo[k]) return false;
    return true;
}

/* The intersecting pairs of the solver's live triangles (a tearing
 * solver's over its current vertices) that share no vertex; with split > 0,
 * only pairs of a triangle of vertices below split and one at or above.
 * Only pairs whose bounding boxes overlap can intersect: the boxes sorted
 * by their low x, each is tried against those that start before it ends
 * (the same count as trying every pair, a small part of the work). */
static uint32_t intersecting_pairs(const sb_solver* s, uint32_t split) {
    const sb_model* m = sb_solver_model(s);
    uint32_t n = sb_solver_vertex_count(s), t = sb_model_triangle_count(m), found = 0;
    double* x = malloc(3 * (size_t)n * sizeof *x);
    uint32_t* tri = malloc(3 * (size_t)t * sizeof *tri);
    tri_box* boxes = malloc(t * sizeof *boxes);
    sb_solver_get_positions(s, x);
    for (uint32_t i = 0; i < t; i++) {
        sb_solver_triangle(s, i, tri + 3 * i);
        boxes[i].tri = i;
        for (int k = 0; k < 3; k++) {
            const double *p = x + 3 * tri[3 * i], *q = x + 3 * tri[3 * i + 1], *r = x + 3 * tri[3 * i + 2];
            boxes[i].lo[k] = fmin(p[k], fmin(q[k], r[k]));
            boxes[i].hi[k] = fmax(p[k], fmax(q[k], r[k]));
        }
    }
    qsort(boxes, t, sizeof *boxes, by_low_x);
    for (uint32_t i = 0; i < t; i++)
        for (uint32_t j = i + 1; j < t && boxes[j].lo[0] <= boxes[i].hi[0]; j++) {
            if (!boxes_overlap(&boxes[i], &boxes[j])) continue;
            if (!sb_solver_triangle_alive(s, boxes[i].tri) || !sb_solver_triangle_alive(s, boxes[j].tri)) continue;
            const uint32_t *a = tri + 3 * boxes[i].tri, *b = tri + 3 * boxes[j].tri;
            bool shared = false;
            for (int p = 0; p < 3; p++)
                for (int q = 0; q < 3; q++) shared |= a[p] == b[q];
            if (split && (a[0] < split) == (b[0] < split)) continue;
            if (!shared && triangles_intersect(x, a, b)) found++;
        }
    free(x), free(tri), free(boxes);
    return found;
}

/* ---- bodies ----------------------------------------------------------------- */

/* A vertical strip (x across, z up) of nx × nz vertices, w × hgt metres,
 * bottom edge at z0, falling at vz: soft bonds and angles, no bending; its
 * bonds break beyond 1 + break_strain times their rest length (0: never). */
static sb_model* strip_model(uint32_t nx, uint32_t nz, double w, double hgt, double z0, double vz,
                             double break_strain) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = nx, sheet.ny = nz, sheet.width = w, sheet.height = hgt;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) {
        double y = mesh.positions[3 * i + 1];
        mesh.positions[3 * i + 1] = 0.002 * sin(37.0 * mesh.positions[3 * i]); /* a little off plane: it buckles */
        mesh.positions[3 * i + 2] = z0 + y;
    }
    sb_material_def material = sb_default_material_def();
    material.bond_k = 200.0;
    material.angle_k = 0.02;
    material.break_strain = break_strain;
    sb_builder* b = sb_builder_create();
    assert_int_equal(sb_builder_add_mesh(b, &mesh, &material, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) sb_builder_vertex(b, i)->velocity[2] = vz;
    sb_model* m = sb_builder_compile(b, &err);
    sb_builder_destroy(b);
    sb_mesh_free(&mesh);
    if (!m) fail_msg("%s", err.message);
    return m;
}

static sb_collider* floor_collider(void) {
    sb_collider_def def = sb_default_collider_def();
    def.friction = 0.5;
    sb_error err;
    sb_collider* c = sb_collider_create(&def, &err);
    assert_non_null(c);
    return c;
}

static sb_solver_def strip_def(sb_collider* const* floor, sb_integrator integrator, int threads, bool self) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.gravity[2] = -9.81;
    def.drag = 0.5;
    def.colliders = floor;
    def.collider_count = 1;
    def.contact_thickness = 0.002;
    def.self_collision = self;
    def.runtime.threads = threads;
    return def;
}

/* A strip falling onto the floor piles up and folds onto itself: with
 * self-contact no two of its triangles ever intersect; without, they do
 * (so the scene tests something). The state is the same for 1 and 2
 * threads, for the fused Verlet step and for a generic integrator. */
static void test_folding_strip_never_intersects(void** state) {
    (void)state;
    sb_model* m = strip_model(30, 8, 0.3, 0.07, 0.01, -1.0, 0.0);
    sb_collider* floor = floor_collider();
    const sb_integrator integrators[] = {SB_INTEGRATOR_VERLET, SB_INTEGRATOR_SYMPLECTIC_EULER};
    for (int run = 0; run < 5; run++) {
        bool self = run < 4;
        sb_solver_def def = strip_def(&floor, integrators[run / 2 % 2], run % 2 + 1, self);
        sb_solver* s = tu_solver(m, &def);
        uint32_t worst = 0, contacts = 0;
        for (int frame = 0; frame < 16; frame++) {
            for (int k = 0; k < 20; k++) {
                tu_advance(s, 2.5e-4, 1);
                contacts += sb_solver_last_step(s).self_contacts;
                assert_int_equal(sb_solver_last_step(s).self_dropped, 0);
            }
            uint32_t pairs = intersecting_pairs(s, 0);
            worst = pairs > worst ? pairs : worst;
        }
        static uint64_t hashes[2];
        if (self) {
            if (worst)
                fail_msg("run %d (%s, %d threads): %u intersecting pairs", run, sb_integrator_name(def.integrator),
                         def.runtime.threads, worst);
            assert_true(contacts > 0);
            uint64_t hash = tu_state_hash(s);
            if (run % 2 == 0)
                hashes[run / 2] = hash;
            else
                assert_true(hash == hashes[run / 2]); /* 2 threads as 1 */
        } else {
            assert_true(worst > 0);
        }
        sb_solver_destroy(s);
    }
    sb_collider_destroy(floor);
    sb_model_destroy(m);
}

/* The strip of the test above thrown at the floor at 3 m/s, its bonds
 * breaking beyond 2 % strain: it tears as it piles up and folds, and with
 * self-contact its live triangles never intersect, across the breaks and
 * the splits; the state is the same for 1 and 2 threads, and a solver
 * loaded with the state saved half-way (torn already) ends bitwise where
 * the first did. */
static void test_tearing_strip_never_intersects(void** state) {
    (void)state;
    sb_model* m = strip_model(30, 8, 0.3, 0.07, 0.01, -3.0, 0.02);
    sb_collider* floor = floor_collider();
    uint64_t hashes[2];
    void* saved = NULL;
    size_t size = 0;
    for (int threads = 1; threads <= 2; threads++) {
        sb_solver_def def = strip_def(&floor, SB_INTEGRATOR_VERLET, threads, true);
        sb_solver* s = tu_solver(m, &def);
        for (int frame = 0; frame < 16; frame++) {
            if (frame == 8 && threads == 1) {
                sb_error err;
                saved = malloc(size = sb_solver_state_size(s));
                assert_int_equal(sb_solver_save_state(s, saved, size, &err), SB_OK);
            }
            tu_advance(s, 2.5e-4, 20);
            assert_int_equal(sb_solver_last_step(s).self_dropped, 0);
            assert_int_equal(intersecting_pairs(s, 0), 0);
        }
        print_message("%d threads: %u bonds broken, %u vertices split off\n", threads, sb_solver_broken_count(s),
                      sb_solver_vertex_count(s) - sb_model_vertex_count(m));
        assert_true(sb_solver_vertex_count(s) > sb_model_vertex_count(m)); /* it tore */
        hashes[threads - 1] = tu_state_hash(s);
        sb_solver_destroy(s);
    }
    assert_true(hashes[1] == hashes[0]);
    sb_solver_def def = strip_def(&floor, SB_INTEGRATOR_VERLET, 1, true);
    sb_solver* s = tu_solver(m, &def);
    sb_error err;
    assert_int_equal(sb_solver_load_state(s, saved, size, &err), SB_OK);
    tu_advance(s, 2.5e-4, 8 * 20);
    assert_true(tu_state_hash(s) == hashes[0]);
    sb_solver_destroy(s);
    free(saved);
    sb_collider_destroy(floor);
    sb_model_destroy(m);
}

/* Two bodies of one model: a small sheet thrown at 20 m/s at a sheet pinned
 * on its border, 5 mm a step against a 2 mm contact thickness (only the
 * continuous test can see it). With every integrator, the small sheet never
 * passes through: no triangle of one ever intersects one of the other, and
 * it ends above the big sheet's middle. */
static void test_thrown_sheet_does_not_pass_a_sheet(void** state) {
    (void)state;
    sb_sheet_def def = sb_default_sheet_def();
    sb_mesh meshes[2] = {{0}, {0}}, both = {0};
    sb_error err;
    def.nx = def.ny = 21;
    assert_int_equal(sb_mesh_generate_sheet(&def, &meshes[0], &err), SB_OK);
    def.nx = def.ny = 6;
    def.width = def.height = 0.2;
    assert_int_equal(sb_mesh_generate_sheet(&def, &meshes[1], &err), SB_OK);
    for (uint32_t i = 0; i < meshes[1].vertex_count; i++) {
        meshes[1].positions[3 * i] += 0.4;
        meshes[1].positions[3 * i + 1] += 0.4;
        meshes[1].positions[3 * i + 2] = 0.05;
    }
    assert_int_equal(sb_mesh_concatenate(meshes, 2, &both, &err), SB_OK);
    sb_material_def material = sb_default_material_def();
    material.bond_k = 500.0;
    material.angle_k = 0.1;
    sb_builder* b = sb_builder_create();
    assert_int_equal(sb_builder_add_mesh(b, &both, &material, &err), SB_OK);
    uint32_t big = meshes[0].vertex_count;
    for (uint32_t i = 0; i < both.vertex_count; i++) {
        uint32_t ix = i % 21, iy = i / 21;
        if (i >= big)
            sb_builder_vertex(b, i)->velocity[2] = -20.0;
        else
            sb_builder_vertex(b, i)->fixed = ix == 0 || iy == 0 || ix == 20 || iy == 20;
    }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    const sb_integrator integrators[] = {SB_INTEGRATOR_VERLET,
                                         SB_INTEGRATOR_VELOCITY_VERLET,
                                         SB_INTEGRATOR_EXPLICIT_EULER,
                                         SB_INTEGRATOR_SYMPLECTIC_EULER,
                                         SB_INTEGRATOR_POSITION_VERLET,
                                         SB_INTEGRATOR_IMPLICIT_EULER,
                                         SB_INTEGRATOR_PBD,
                                         SB_INTEGRATOR_XPBD};
    for (size_t k = 0; k < sizeof integrators / sizeof *integrators; k++) {
        sb_solver_def sdef = sb_default_solver_def();
        sdef.integrator = integrators[k];
        sdef.contact_thickness = 0.002;
        sdef.self_collision = true;
        sdef.drag = 1.0;
        sb_solver* s = tu_solver(m, &sdef);
        for (int step = 0; step < 60; step++) {
            tu_advance(s, 2.5e-4, 1);
            if (step % 4 == 3) assert_int_equal(intersecting_pairs(s, big), 0);
        }
        double x[3 * 500];
        sb_solver_get_positions(s, x);
        uint32_t middle = 10 * 21 + 10, small_middle = big + 2 * 6 + 2;
        if (!(x[3 * small_middle + 2] > x[3 * middle + 2]))
            fail_msg("%s: the thrown sheet passed (%g below %g)", sb_integrator_name(integrators[k]),
                     x[3 * small_middle + 2], x[3 * middle + 2]);
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
    sb_mesh_free(&both);
    sb_mesh_free(&meshes[0]);
    sb_mesh_free(&meshes[1]);
}

/* Self-contact needs a thickness. */
static void test_self_contact_needs_a_thickness(void** state) {
    (void)state;
    sb_model* m = strip_model(4, 4, 0.1, 0.1, 0.0, 0.0, 0.0);
    sb_solver_def def = sb_default_solver_def();
    def.self_collision = true;
    sb_error err;
    assert_null(sb_solver_create(m, &def, &err));
    TU_ASSERT_CONTAINS(err.message, "self_collision needs a contact thickness > 0");
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_point_triangle_closest_is_closest),
        cmocka_unit_test(test_segments_closest_is_closest),
        cmocka_unit_test(test_cubic_sign_changes),
        cmocka_unit_test(test_vertex_triangle_crossing),
        cmocka_unit_test(test_edge_edge_crossing),
        cmocka_unit_test(test_refit_bounds_every_triangle),
        cmocka_unit_test(test_folding_strip_never_intersects),
        cmocka_unit_test(test_tearing_strip_never_intersects),
        cmocka_unit_test(test_thrown_sheet_does_not_pass_a_sheet),
        cmocka_unit_test(test_self_contact_needs_a_thickness),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
