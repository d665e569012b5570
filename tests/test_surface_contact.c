/* Colliders against the body's surface, not only its vertices
 * (kernels/contact/surface.c). The oracles are geometric and independent
 * of the code under test: the sheet's height under a point from the
 * triangle whose projection holds it, and the distance of a 12 x 12 grid
 * of points on every triangle to the collider (a point-segment distance, a
 * point in a box), computed here.
 * - A 1 cm sphere (radius 5 mm) pressed into a 40 x 40 sheet of 1 m (2.56
 *   cm spacing) at a cell's centre, at an edge's midpoint and over a
 *   vertex: it never passes, and the sheet's reaction at each depth is the
 *   same at the three places within 10 % of their mean. (The spread that
 *   remains, the vertex softest by up to 10 % of the cell's centre, is the
 *   spring net's: a load on one vertex strains its own springs, one
 *   between vertices shares them; friction does not change it, and on a
 *   79 x 79 sheet it is 7 %.)
 * - A 2 mm sphere at 20 m/s (5 mm a step) against a sheet of 1 cm spacing,
 *   between its vertices, with each of the nine integrators: it never
 *   passes.
 * - A dynamic sphere thrown at a free sheet between vertices: the total
 *   momentum is conserved to rounding; the same with 1 and 2 threads,
 *   bitwise.
 * - A sheet of 5 cm spacing falling onto a thin capsule (4 mm) and onto a
 *   box's edge, both lying between two rows of vertices: it rests on
 *   them, and no point of any triangle is inside them.
 * - A program's own collider (a small ball) with a triangle_point callback
 *   holds a falling sheet between its vertices; without one it slips
 *   through. */
#include "test_util.h"

#define PRESS_SIDE 40
#define PRESS_RADIUS 0.005

/* side x side vertices over `width` (m) at height z, bond and angle terms;
 * pinned on the border when `pinned`. */
static sb_model* sheet(uint32_t side, double width, double z, bool pinned) {
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = def.ny = side;
    def.width = def.height = width;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&def, &mesh, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) mesh.positions[3 * i + 2] = z;
    sb_material_def material = sb_default_material_def();
    material.bond_k = 500.0;
    material.angle_k = 0.01;
    sb_builder* b = sb_builder_create();
    assert_int_equal(sb_builder_add_mesh(b, &mesh, &material, &err), SB_OK);
    for (uint32_t i = 0; pinned && i < mesh.vertex_count; i++) {
        uint32_t ix = i % side, iy = i / side;
        sb_builder_vertex(b, i)->fixed = ix == 0 || iy == 0 || ix == side - 1 || iy == side - 1;
    }
    sb_model* m = sb_builder_compile(b, &err);
    sb_builder_destroy(b);
    sb_mesh_free(&mesh);
    if (!m) fail_msg("%s", err.message);
    return m;
}

/* The corners of triangle t at positions x. */
static void corners(const sb_solver* s, const double* x, uint32_t t, const double* p[3]) {
    uint32_t v[3];
    sb_solver_triangle(s, t, v);
    for (int c = 0; c < 3; c++) p[c] = x + 3 * (size_t)v[c];
}

/* The height of the sheet's top layer at (px, py): the highest of the
 * triangles whose projections on z = 0 hold the point (a draped sheet
 * hangs under itself); NAN when none does. */
static double height_under(const sb_solver* s, const double* x, double px, double py) {
    uint32_t triangles = sb_model_triangle_count(sb_solver_model(s));
    double top = NAN;
    for (uint32_t t = 0; t < triangles; t++) {
        const double* p[3];
        corners(s, x, t, p);
        double d = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        if (d == 0.0) continue;
        double b = ((px - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (py - p[0][1])) / d;
        double c = ((p[1][0] - p[0][0]) * (py - p[0][1]) - (px - p[0][0]) * (p[1][1] - p[0][1])) / d;
        if (b < -1e-12 || c < -1e-12 || b + c > 1.0 + 1e-12) continue;
        double z = (1.0 - b - c) * p[0][2] + b * p[1][2] + c * p[2][2];
        top = isnan(top) || z > top ? z : top;
    }
    return top;
}

/* The distance from x to the segment a–b. */
static double segment_distance(const double x[3], const double a[3], const double b[3]) {
    double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ax[3] = {x[0] - a[0], x[1] - a[1], x[2] - a[2]};
    double s = tu_dot(ab, ab) > 0.0 ? tu_dot(ax, ab) / tu_dot(ab, ab) : 0.0;
    s = s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
    double d[3] = {ax[0] - s * ab[0], ax[1] - s * ab[1], ax[2] - s * ab[2]};
    return tu_norm(d);
}

/* How far a point is inside a solid (> 0 inside). */
typedef double (*depth_fn)(const void* shape, const double x[3]);

/* The deepest any of a 12 x 12 grid of points on every triangle lies in the solid. */
static double deepest_surface_point(const sb_solver* s, depth_fn depth, const void* shape) {
    uint32_t n = sb_solver_vertex_count(s), triangles = sb_model_triangle_count(sb_solver_model(s));
    double* x = malloc(3 * (size_t)n * sizeof *x);
    sb_solver_get_positions(s, x);
    double deepest = -INFINITY;
    const int grid = 12;
    for (uint32_t t = 0; t < triangles; t++) {
        const double* p[3];
        corners(s, x, t, p);
        for (int i = 0; i <= grid; i++)
            for (int j = 0; i + j <= grid; j++) {
                double b = (double)i / grid, c = (double)j / grid, q[3];
                for (int k = 0; k < 3; k++) q[k] = (1.0 - b - c) * p[0][k] + b * p[1][k] + c * p[2][k];
                deepest = fmax(deepest, depth(shape, q));
            }
    }
    free(x);
    return deepest;
}

/* A capsule (and a sphere: a == b) as a solid. */
typedef struct capsule {
    double a[3], b[3], radius;
} capsule;

static double capsule_depth(const void* shape, const double x[3]) {
    const capsule* c = shape;
    return c->radius - segment_distance(x, c->a, c->b);
}

static sb_collider* make_collider(const sb_collider_def* def) {
    sb_error err;
    sb_collider* c = sb_collider_create(def, &err);
    if (!c) fail_msg("%s", err.message);
    return c;
}

/* ---- pressing a sphere in ------------------------------------------------ */

#define PRESS_DEPTHS 4
#define PRESS_HOLD 0.3 /* s at each depth */

/* The sphere, its bottom 1 cm over the pinned sheet at (px, py), pressed
 * down in stages to 2, 3, 4 and 5 cm below the sheet's plane, each reached
 * in 0.1 s and held PRESS_HOLD: the sheet's static reaction on the sphere
 * (N, upwards) at each depth, averaged over the last 50 ms of its hold.
 * Fails if the sphere ever passes: its center below the sheet under it, or
 * a point of the sheet inside it. */
static void press(double px, double py, double footprint, double force[PRESS_DEPTHS]) {
    sb_model* m = sheet(PRESS_SIDE, 1.0, 0.0, true);
    const double dt = 1e-4, start = PRESS_RADIUS + 0.01, stage = 0.1 + PRESS_HOLD;
    sb_keyframe path[1 + 2 * PRESS_DEPTHS] = {{.time = 0.0}};
    for (int d = 0; d < PRESS_DEPTHS; d++)
        for (int e = 0; e < 2; e++) {
            sb_keyframe* k = &path[1 + 2 * d + e];
            k->time = d * stage + 0.1 + e * PRESS_HOLD;
            k->translate[2] = -(0.01 + 0.02 + 0.01 * d);
        }
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_SPHERE;
    def.center[0] = px, def.center[1] = py, def.center[2] = start;
    def.radius = PRESS_RADIUS;
    def.footprint = footprint;
    def.path = path;
    def.path_count = 1 + 2 * PRESS_DEPTHS;
    sb_collider* tool = make_collider(&def);
    sb_solver_def sd = sb_default_solver_def();
    sd.gravity[2] = 0.0;
    sd.drag = 20.0;
    sd.colliders = &tool;
    sd.collider_count = 1;
    sd.contact_thickness = 0.0005;
    sd.runtime.threads = 1;
    sb_solver* s = tu_solver(m, &sd);
    uint32_t n = sb_model_vertex_count(m);
    double* x = malloc(3 * (size_t)n * sizeof *x);
    memset(force, 0, PRESS_DEPTHS * sizeof *force);
    const long per_stage = lround(stage / dt), window = lround(0.05 / dt);
    for (long step = 1; step <= PRESS_DEPTHS * per_stage; step++) {
        tu_advance(s, dt, 1);
        double f[3];
        sb_solver_contact_force(s, 0, f);
        if ((step - 1) % per_stage >= per_stage - window) force[(step - 1) / per_stage] += f[2] / (double)window;
        if (step % 250 != 0) continue;
        double center[3];
        sb_collider_state(tool, center, NULL);
        sb_solver_get_positions(s, x);
        double under = height_under(s, x, px, py);
        if (!(under < center[2]))
            fail_msg("at t = %.3f s the sheet (z %.5f) is over the sphere (z %.5f)", step * dt, under, center[2]);
        capsule ball = {{center[0], center[1], center[2]}, {center[0], center[1], center[2]}, PRESS_RADIUS};
        double deepest = deepest_surface_point(s, capsule_depth, &ball);
        if (deepest > 1e-4)
            fail_msg("at t = %.3f s a point of the sheet is %.3g m inside the sphere", step * dt, deepest);
    }
    free(x);
    sb_solver_destroy(s);
    sb_collider_destroy(tool);
    sb_model_destroy(m);
}

/* The sphere with `footprint` pressed in over a vertex, at an edge's
 * midpoint and at a cell's centre: the reactions at each depth within
 * `spread` of their mean. */
static void press_three_places(double footprint, double spread) {
    const double spacing = 1.0 / (PRESS_SIDE - 1), mid = PRESS_SIDE / 2 * spacing;
    const char* names[3] = {"over a vertex", "at an edge's midpoint", "at a cell's centre"};
    const double places[3][2] = {{mid, mid}, {mid + 0.5 * spacing, mid}, {mid + 0.5 * spacing, mid + 0.5 * spacing}};
    double force[3][PRESS_DEPTHS];
    print_message("footprint %.4f m:\n", footprint);
    for (int p = 0; p < 3; p++) {
        press(places[p][0], places[p][1], footprint, force[p]);
        print_message("%-22s reaction at 2, 3, 4, 5 cm: %.4f %.4f %.4f %.4f N\n", names[p], force[p][0], force[p][1],
                      force[p][2], force[p][3]);
    }
    for (int d = 0; d < PRESS_DEPTHS; d++) {
        double mean = (force[0][d] + force[1][d] + force[2][d]) / 3.0;
        assert_true(mean > 0.1); /* it pressed the sheet */
        for (int p = 0; p < 3; p++) TU_ASSERT_NEAR(force[p][d], mean, spread * mean);
    }
}

static void test_sphere_between_vertices_feels_the_sheet(void** state) {
    (void)state;
    press_three_places(0.0, 0.1);
}

/* With a footprint of 2.5 spacings the sheet answers the same wherever
 * the sphere presses (kernels/contact/footprint.c). */
static void test_sphere_with_a_footprint_feels_the_same_everywhere(void** state) {
    (void)state;
    press_three_places(2.5 / (PRESS_SIDE - 1), 0.05);
}

/* ---- tunnelling ------------------------------------------------------------ */

/* A 2 mm sphere (radius 1 mm) at 20 m/s down through the middle of a cell
 * of a pinned 21 x 21 sheet of 20 cm (1 cm spacing): 2.5 ms steps of 5 mm,
 * two and a half diameters; 2 ms of travel, 4 cm. The sphere without and
 * with a footprint of 2.5 spacings. */
static void small_sphere_does_not_pass_a_sheet(double footprint) {
    const sb_integrator integrators[] = {
        SB_INTEGRATOR_VERLET,
        SB_INTEGRATOR_VELOCITY_VERLET,
        SB_INTEGRATOR_SYMPLECTIC_EULER,
        SB_INTEGRATOR_EXPLICIT_EULER,
        SB_INTEGRATOR_POSITION_VERLET,
        SB_INTEGRATOR_IMPLICIT_EULER,
        SB_INTEGRATOR_PBD,
        SB_INTEGRATOR_XPBD,
        SB_INTEGRATOR_VBD,
    };
    const double r = 0.001, dt = 2.5e-4, px = 0.105, py = 0.105, z0 = 0.01;
    sb_model* m = sheet(21, 0.2, 0.0, true);
    uint32_t n = sb_model_vertex_count(m);
    double* x = malloc(3 * (size_t)n * sizeof *x);
    const sb_keyframe path[2] = {{.time = 0.0}, {.time = 0.002, .translate = {0, 0, -0.04}}};
    for (size_t g = 0; g < sizeof integrators / sizeof *integrators; g++)
        for (int kernels = 0; kernels < 2; kernels++) {
            sb_collider_def def = sb_default_collider_def();
            def.shape = SB_COLLIDER_SPHERE;
            def.center[0] = px, def.center[1] = py, def.center[2] = z0;
            def.radius = r;
            def.footprint = footprint;
            def.path = path;
            def.path_count = 2;
            sb_collider* tool = make_collider(&def);
            sb_solver_def sd = sb_default_solver_def();
            sd.integrator = integrators[g];
            sd.kernels = kernels ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
            sd.gravity[2] = 0.0;
            sd.colliders = &tool;
            sd.collider_count = 1;
            sd.contact_thickness = 1e-4;
            sd.runtime.threads = 1;
            sb_solver* s = tu_solver(m, &sd);
            uint64_t contacts = 0;
            double lowest = INFINITY;
            for (int step = 1; step <= 10; step++) {
                tu_advance(s, dt, 1);
                contacts += sb_solver_last_step(s).contacts;
                double center[3];
                sb_collider_state(tool, center, NULL);
                sb_solver_get_positions(s, x);
                double under = height_under(s, x, px, py);
                lowest = fmin(lowest, under);
                if (!(under < center[2]))
                    fail_msg("%s (%s kernels), step %d: the sheet (z %.4f) is over the sphere (z %.4f)",
                             sb_integrator_name(integrators[g]), kernels ? "fast" : "reference", step, under,
                             center[2]);
            }
            print_message("footprint %.3f m, %-16s %-9s: %3llu contacts, the sheet under the sphere down to z %.4f m\n",
                          footprint, sb_integrator_name(integrators[g]), kernels ? "fast" : "reference",
                          (unsigned long long)contacts, lowest);
            assert_true(lowest < -0.02); /* carried down in front of it */
            sb_solver_destroy(s);
            sb_collider_destroy(tool);
        }
    free(x);
    sb_model_destroy(m);
}

static void test_fast_small_sphere_does_not_pass_a_sheet(void** state) {
    (void)state;
    small_sphere_does_not_pass_a_sheet(0.0);
    small_sphere_does_not_pass_a_sheet(0.025);
}

/* ---- a volume's surface ---------------------------------------------------- */

/* The mass-weighted mean z of the body. */
static double mean_z(const sb_model* m, const double* x) {
    double sum = 0.0, mass = 0.0;
    for (uint32_t i = 0; i < sb_model_vertex_count(m); i++) {
        double mi = sb_model_mass(m, i);
        sum += mi * x[3 * (size_t)i + 2];
        mass += mi;
    }
    return sum / mass;
}

/* A free block of tetrahedra (4 × 4 × 2 cubes of 1 cm, E 100 kPa, no
 * gravity) and a 1 mm sphere driven down at 0.5 m/s onto its top between
 * the surface's vertices (inside a triangle of a cube's top face): the
 * sphere meets the body's boundary faces and carries the body along (its
 * centre of mass moves with the sphere, less the dent), where the
 * vertices alone (1 cm apart) would let it into the body, which would then
 * hardly move. For the edge springs (the tissue factory's faces), the
 * linear elements (a model built tetrahedron by tetrahedron: the faces
 * its tetrahedra do not share) and the quadratic ones (faces split at the
 * middle vertices), fast and reference kernels. */
static void test_small_sphere_stops_at_a_volume_surface(void** state) {
    (void)state;
    const double h = 0.01, r = 0.001, speed = 0.5, dt = 2e-5, travel = 0.01;
    const double px = 1.3 * h, py = 1.6 * h, top = 2 * h;
    const char* names[] = {"springs", "corotated", "quadratic"};
    for (int model = 0; model < 3; model++)
        for (int kernels = 0; kernels < 2; kernels++) {
            sb_model* m = model == 1
                              ? tu_tet_block(4, 4, 2, h, 1e5, 0.3, 0.0, 1, false)
                              : tu_tissue_tet_block(4, 4, 2, h, 1e5, 0.3, 0.0, 1, false,
                                                    model == 0 ? SB_TISSUE_SPRINGS : SB_TISSUE_COROTATED_QUADRATIC);
            uint32_t n = sb_model_vertex_count(m);
            double* x = malloc(3 * (size_t)n * sizeof *x);
            const sb_keyframe path[2] = {{.time = 0.0}, {.time = travel / speed, .translate = {0, 0, -travel}}};
            sb_collider_def def = sb_default_collider_def();
            def.shape = SB_COLLIDER_SPHERE;
            def.center[0] = px, def.center[1] = py, def.center[2] = top + r + 1e-4;
            def.radius = r;
            def.path = path;
            def.path_count = 2;
            sb_collider* tool = make_collider(&def);
            sb_solver_def sd = sb_default_solver_def();
            sd.kernels = kernels ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
            sd.gravity[2] = 0.0;
            sd.colliders = &tool;
            sd.collider_count = 1;
            sd.contact_thickness = 1e-4;
            sd.runtime.threads = 1;
            sb_solver* s = tu_solver(m, &sd);
            sb_solver_get_positions(s, x);
            double before = mean_z(m, x);
            tu_advance(s, dt, (int)lround(travel / speed / dt));
            sb_solver_get_positions(s, x);
            double carried = before - mean_z(m, x);
            print_message("%-9s %-9s: the body carried %.2f mm of the sphere's %.0f mm\n", names[model],
                          kernels ? "fast" : "reference", 1e3 * carried, 1e3 * travel);
            assert_true(carried > 0.5 * travel);
            sb_solver_destroy(s);
            sb_collider_destroy(tool);
            free(x);
            sb_model_destroy(m);
        }
}

/* ---- momentum -------------------------------------------------------------- */

/* Σ m v of the sheet plus the ball's. */
static void total_momentum(const sb_solver* s, const sb_model* m, const sb_collider* ball, double mass, double p[3]) {
    uint32_t n = sb_model_vertex_count(m);
    double *v = malloc(3 * (size_t)n * sizeof *v), ball_v[3];
    sb_solver_get_velocities(s, v);
    sb_collider_state(ball, NULL, ball_v);
    for (int k = 0; k < 3; k++) p[k] = mass * ball_v[k];
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) p[k] += sb_model_mass(m, i) * v[3 * i + k];
    free(v);
}

/* A 0.5 kg ball of radius 3 mm at 2 m/s down onto the middle of a cell of
 * a free 21 x 21 sheet of 20 cm (4.4 kg), no gravity, 10 ms: it carries the
 * sheet along without passing it, slowing down, and the total momentum
 * after equals the ball's before to rounding; 1 and 2 threads bitwise
 * alike. The ball without and with a footprint of 2.5 spacings. */
static void ball_on_a_free_sheet_conserves_momentum(double footprint) {
    const double mass = 0.5, r = 0.003;
    sb_model* m = sheet(21, 0.2, 0.0, false);
    uint64_t hashes[2];
    for (int threads = 1; threads <= 2; threads++) {
        sb_collider_def def = sb_default_collider_def();
        def.shape = SB_COLLIDER_SPHERE;
        def.center[0] = def.center[1] = 0.105;
        def.center[2] = r + 0.002;
        def.radius = r;
        def.mass = mass;
        def.footprint = footprint;
        def.velocity[2] = -2.0;
        sb_collider* ball = make_collider(&def);
        sb_solver_def sd = sb_default_solver_def();
        sd.gravity[2] = 0.0;
        sd.colliders = &ball;
        sd.collider_count = 1;
        sd.runtime.threads = threads;
        sb_solver* s = tu_solver(m, &sd);
        double before[3], after[3], v[3], p[3];
        total_momentum(s, m, ball, mass, before);
        tu_advance(s, 1e-4, 100);
        total_momentum(s, m, ball, mass, after);
        sb_collider_state(ball, p, v);
        double* x = malloc(3 * (size_t)sb_model_vertex_count(m) * sizeof *x);
        sb_solver_get_positions(s, x);
        double under = height_under(s, x, p[0], p[1]);
        free(x);
        double error = 0.0;
        for (int k = 0; k < 3; k++) error = fmax(error, fabs(after[k] - before[k]));
        print_message(
            "footprint %.3f m, %d thread(s): the ball 2 -> %.4f m/s down, the sheet %.2f mm under its centre; "
            "momentum %.6g -> %.6g kg m/s, error %.3g\n",
            footprint, threads, -v[2], 1e3 * (p[2] - under), before[2], after[2], error);
        assert_true(v[2] > -1.9);  /* the sheet slowed it */
        assert_true(under < p[2]); /* under it, not passed */
        TU_ASSERT_LE(error, 1e3 * TU_REAL_EPS * fabs(before[2]));
        hashes[threads - 1] = tu_state_hash(s);
        sb_solver_destroy(s);
        sb_collider_destroy(ball);
    }
    assert_true(hashes[0] == hashes[1]);
    sb_model_destroy(m);
}

static void test_ball_on_a_free_sheet_conserves_momentum(void** state) {
    (void)state;
    ball_on_a_free_sheet_conserves_momentum(0.0);
    ball_on_a_free_sheet_conserves_momentum(0.025);
}

/* ---- resting on a thin capsule and a box's edge ---------------------------- */

/* A box as a solid: center, rotation (columns: its axes), half extents. */
typedef struct box {
    double center[3], rotation[9], half[3];
} box;

static double box_depth(const void* shape, const double x[3]) {
    const box* b = shape;
    double v[3] = {x[0] - b->center[0], x[1] - b->center[1], x[2] - b->center[2]}, depth = INFINITY;
    for (int a = 0; a < 3; a++) {
        double local = b->rotation[a] * v[0] + b->rotation[3 + a] * v[1] + b->rotation[6 + a] * v[2];
        depth = fmin(depth, b->half[a] - fabs(local));
    }
    return depth;
}

/* A 21 x 21 sheet of 1 m (5 cm spacing) over [0, 1]², 2 cm up,
 * falls under gravity for 1 s onto the collider (its top along x at z = 0,
 * y = 52.5 cm: between two rows of vertices): the sheet's height over the
 * top is at or above it, and no point of it lies inside the solid. */
static void drape(const sb_collider_def* def, depth_fn depth, const void* shape, const char* name) {
    sb_model* m = sheet(21, 1.0, 0.02, false);
    uint32_t n = sb_model_vertex_count(m);
    sb_collider* c = make_collider(def);
    sb_solver_def sd = sb_default_solver_def();
    sd.drag = 5.0;
    sd.colliders = &c;
    sd.collider_count = 1;
    sd.contact_thickness = 0.0005;
    sd.runtime.threads = 1;
    sb_solver* s = tu_solver(m, &sd);
    double* x = malloc(3 * (size_t)n * sizeof *x);
    double deepest = -INFINITY;
    for (int step = 1; step <= 10000; step++) {
        tu_advance(s, 1e-4, 1);
        if (step % 500 == 0) deepest = fmax(deepest, deepest_surface_point(s, depth, shape));
    }
    sb_solver_get_positions(s, x);
    double over = height_under(s, x, 0.5, 0.525), edge_z = 0.0;
    print_message("%s: the sheet over its top at z %.5f m, deepest point of the sheet %.3g m inside\n", name, over,
                  deepest);
    assert_true(over >= edge_z - 1e-4 && over < 0.01); /* on it, not through, not flying off */
    TU_ASSERT_LE(deepest, 1e-4);
    free(x);
    sb_solver_destroy(s);
    sb_collider_destroy(c);
    sb_model_destroy(m);
}

static void test_sheet_rests_on_a_thin_capsule(void** state) {
    (void)state;
    const double r = 0.004;
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_CAPSULE;
    def.a[0] = 0.2, def.b[0] = 0.8;
    def.a[1] = def.b[1] = 0.525;
    def.a[2] = def.b[2] = -r;
    def.radius = r;
    def.friction = 0.5;
    capsule shape = {{0.2, 0.525, -r}, {0.8, 0.525, -r}, r};
    drape(&def, capsule_depth, &shape, "capsule");
}

static void test_sheet_rests_on_a_box_edge(void** state) {
    (void)state;
    const double h = 0.03, c45 = sqrt(0.5);
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_BOX;
    def.center[0] = 0.5, def.center[1] = 0.525, def.center[2] = -h * sqrt(2.0);
    def.half_extents[0] = 0.3, def.half_extents[1] = def.half_extents[2] = h;
    def.rotate[0] = 45.0; /* about x: an edge on top, along x */
    def.friction = 0.5;
    box shape = {{0.5, 0.525, -h * sqrt(2.0)}, {1, 0, 0, 0, c45, -c45, 0, c45, c45}, {0.3, h, h}};
    drape(&def, box_depth, &shape, "box edge");
}

/* A mesh collider's ridge: a closed prism 60 cm long along x, its top
 * edge at z = 0, y = 52.5 cm (between two rows of the sheet's vertices),
 * its sides at 45° down to a base 8 cm wide. Vertex contact alone lets
 * the sheet's vertices slide 2.5 cm down its sides and the ridge through
 * the triangles between them. */
typedef struct prism {
    double x0, x1, y, half, height;
} prism;

static double prism_depth(const void* shape, const double x[3]) {
    const prism* p = shape;
    double across = x[1] - p->y, r = sqrt(0.5);
    double depth = fmin(x[0] - p->x0, p->x1 - x[0]);
    depth = fmin(depth, x[2] + p->height);      /* the base */
    depth = fmin(depth, -(-across + x[2]) * r); /* the side facing -y */
    return fmin(depth, -(across + x[2]) * r);   /* the side facing +y */
}

static void test_sheet_rests_on_a_mesh_ridge(void** state) {
    (void)state;
    const prism shape = {0.2, 0.8, 0.525, 0.04, 0.04};
    double positions[18];
    for (int end = 0; end < 2; end++) { /* apex, the -y and the +y foot */
        double x = end ? shape.x1 : shape.x0, *p = positions + 9 * end;
        const double corner[3][3] = {
            {x, shape.y, 0.0}, {x, shape.y - shape.half, -shape.height}, {x, shape.y + shape.half, -shape.height}};
        memcpy(p, corner, sizeof corner);
    }
    uint32_t triangles[] = {0, 2, 1, 3, 4, 5,  /* the ends */
                            0, 1, 4, 0, 4, 3,  /* the side facing -y */
                            0, 3, 5, 0, 5, 2,  /* the side facing +y */
                            1, 2, 5, 1, 5, 4}; /* the base */
    sb_mesh mesh = {.vertex_count = 6, .positions = positions, .triangle_count = 8, .triangles = triangles};
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_MESH;
    def.mesh = &mesh;
    def.friction = 0.5;
    drape(&def, prism_depth, &shape, "mesh ridge");
}

/* ---- a program's own collider ---------------------------------------------- */

/* A static ball as a program's own collider: the end of a move inside it is
 * pushed out (the moves here are slow), and a triangle's point is the
 * centre's projection on its plane when that falls inside it. */
typedef struct own_ball {
    double center[3], radius;
} own_ball;

static bool own_ball_collide(void* user, const sb_contact_query* q, sb_contact* c) {
    const own_ball* b = user;
    double d[3] = {q->to[0] - b->center[0], q->to[1] - b->center[1], q->to[2] - b->center[2]}, r = tu_norm(d);
    if (!(r < b->radius + q->thickness) || r == 0.0) return false;
    *c = (sb_contact){.fraction = 1.0, .depth = b->radius + q->thickness - r};
    for (int k = 0; k < 3; k++) c->normal[k] = d[k] / r, c->point[k] = b->center[k] + c->normal[k] * b->radius;
    return true;
}

static bool own_ball_triangle_point(void* user, const double from[3][3], const double to[3][3], double w[3]) {
    (void)from;
    const own_ball* b = user;
    double e1[3], e2[3], x[3], n[3];
    for (int k = 0; k < 3; k++)
        e1[k] = to[1][k] - to[0][k], e2[k] = to[2][k] - to[0][k], x[k] = b->center[k] - to[0][k];
    tu_cross(e1, e2, n);
    double n2 = tu_dot(n, n), c1[3], c2[3];
    if (!(n2 > 0.0)) return false;
    tu_cross(x, e2, c1);
    tu_cross(e1, x, c2);
    w[1] = tu_dot(c1, n) / n2, w[2] = tu_dot(c2, n) / n2, w[0] = 1.0 - w[1] - w[2];
    return w[0] >= 0.0 && w[1] >= 0.0 && w[2] >= 0.0;
}

/* An 11 x 11 sheet of 10 cm (1 cm spacing) falls 1 cm under gravity onto
 * a program's own ball of radius 2 mm under the middle of a cell: with its
 * triangle_point callback the sheet rests on the ball (its top layer over
 * the centre on the ball's top), without it the ball slips between the
 * vertices. */
static void test_own_collider_meets_the_surface(void** state) {
    (void)state;
    own_ball ball = {{0.045, 0.055, -0.002}, 0.002};
    for (int surface = 0; surface < 2; surface++) {
        sb_model* m = sheet(11, 0.1, 0.01, false);
        sb_error err;
        sb_collider* c = sb_collider_create_custom("own ball", own_ball_collide, NULL, &ball, &err);
        assert_non_null(c);
        double lo[3] = {0.043, 0.053, -0.004}, hi[3] = {0.047, 0.057, 0.0};
        sb_collider_set_bounds(c, lo, hi);
        if (surface) sb_collider_set_triangle_point(c, own_ball_triangle_point);
        sb_solver_def sd = sb_default_solver_def();
        sd.drag = 5.0;
        sd.colliders = &c;
        sd.collider_count = 1;
        sd.contact_thickness = 0.0002;
        sd.runtime.threads = 1;
        sb_solver* s = tu_solver(m, &sd);
        tu_advance(s, 1e-4, 1500);
        double* x = malloc(3 * (size_t)sb_model_vertex_count(m) * sizeof *x);
        sb_solver_get_positions(s, x);
        double over = height_under(s, x, ball.center[0], ball.center[1]);
        print_message("%s: the sheet over the ball's centre at z %.4f m\n",
                      surface ? "with triangle_point" : "vertices only", over);
        if (surface)
            assert_true(over > ball.center[2] + ball.radius - 1e-4); /* on it, not in it */
        else
            assert_true(over < ball.center[2]);
        free(x);
        sb_solver_destroy(s);
        sb_collider_destroy(c);
        sb_model_destroy(m);
    }
}

/* ---- refused footprints -------------------------------------------------- */

/* The solver's message for `tool` on the 1 cm sheet (longest edge √2 cm),
 * or fails when the solver is made. */
static void solver_refuses(sb_collider* tool, int32_t max_splits, const char* says) {
    sb_model* m = sheet(21, 0.2, 0.0, true);
    sb_solver_def sd = sb_default_solver_def();
    sd.colliders = &tool;
    sd.collider_count = 1;
    sd.max_splits = max_splits;
    sb_error err = {{0}};
    sb_solver* s = sb_solver_create(m, &sd, &err);
    if (s) fail_msg("a solver was made; it should say \"%s\"", says);
    print_message("refused: %s\n", err.message);
    assert_non_null(strstr(err.message, says));
    assert_non_null(strstr(err.message, "'tool'"));
    sb_model_destroy(m);
}

/* A footprint on a plane, negative or not finite is refused by the
 * collider; one shorter than the surface's longest edge, or with tearing,
 * by the solver, each with a message naming the collider. */
static void test_footprint_refusals(void** state) {
    (void)state;
    sb_collider_def def = sb_default_collider_def();
    def.name = "tool";
    sb_error err = {{0}};
    const double bad[] = {-0.01, NAN, INFINITY};
    def.footprint = 0.02; /* the default shape: a plane */
    assert_null(sb_collider_create(&def, &err));
    assert_non_null(strstr(err.message, "plane"));
    def.shape = SB_COLLIDER_SPHERE;
    def.radius = 0.001;
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        def.footprint = bad[k];
        assert_null(sb_collider_create(&def, &err));
        assert_non_null(strstr(err.message, "footprint must be >= 0"));
    }
    def.footprint = 0.01;
    sb_collider* tool = make_collider(&def);
    solver_refuses(tool, 0, "shorter than the longest edge");
    sb_collider_destroy(tool);
    def.footprint = 0.025;
    tool = make_collider(&def);
    solver_refuses(tool, 100, "tearing");
    sb_collider_destroy(tool);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_between_vertices_feels_the_sheet),
        cmocka_unit_test(test_sphere_with_a_footprint_feels_the_same_everywhere),
        cmocka_unit_test(test_fast_small_sphere_does_not_pass_a_sheet),
        cmocka_unit_test(test_small_sphere_stops_at_a_volume_surface),
        cmocka_unit_test(test_ball_on_a_free_sheet_conserves_momentum),
        cmocka_unit_test(test_sheet_rests_on_a_thin_capsule),
        cmocka_unit_test(test_sheet_rests_on_a_box_edge),
        cmocka_unit_test(test_sheet_rests_on_a_mesh_ridge),
        cmocka_unit_test(test_own_collider_meets_the_surface),
        cmocka_unit_test(test_footprint_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
