/* Contact as constraints inside the pbd and xpbd sweeps
 * (kernels/contact/contact_pbd.c): a cloth and a ball resting on a plane never sink
 * into it, restitution, Coulomb friction on an incline, the reaction force
 * at rest, momentum with a dynamic collider, fixed vertices inside a
 * collider, and the same state for 1 and 2 threads. Measured numbers are
 * printed. */
#include "test_util.h"

#define G 9.81

static const sb_integrator position_based[2] = {SB_INTEGRATOR_PBD, SB_INTEGRATOR_XPBD};
static const double up[3] = {0, 0, 1};

/* A plane through (0, 0, height) with the given normal and surface constants. */
static sb_collider* plane(double height, const double normal[3], double restitution, double friction,
                          double thickness) {
    sb_collider_def def = sb_default_collider_def();
    def.point[2] = height;
    memcpy(def.normal, normal, sizeof def.normal);
    def.restitution = restitution;
    def.friction = def.static_friction = friction;
    def.thickness = thickness;
    sb_error err;
    sb_collider* c = sb_collider_create(&def, &err);
    if (!c) fail_msg("%s", err.message);
    return c;
}

static sb_solver_def contact_def(sb_collider** colliders, uint32_t count, sb_integrator integrator) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.gravity[2] = -G;
    def.colliders = colliders;
    def.collider_count = count;
    def.runtime.threads = 1;
    return def;
}

/* A side x side sheet `width` wide in the xy plane (x, y in [0, width]) at
 * height z, bonds k, angle terms kt, 0.01 kg per vertex. */
static sb_model* sheet_model(uint32_t side, double width, double z, double k, double kt) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = side;
    sheet.width = sheet.height = width;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) mesh.positions[3 * i + 2] = z;
    sb_material_def material = sb_default_material_def();
    material.bond_k = k;
    material.angle_k = kt;
    material.mass = 0.01;
    sb_model* m = tu_mesh_model(&mesh, &material);
    sb_mesh_free(&mesh);
    return m;
}

/* The lowest z of the solver's vertices. */
static double lowest_z(const sb_solver* s, double* x) {
    uint32_t n = sb_model_vertex_count(sb_solver_model(s));
    sb_solver_get_positions(s, x);
    double lowest = INFINITY;
    for (uint32_t i = 0; i < n; i++) lowest = fmin(lowest, x[3 * i + 2]);
    return lowest;
}

/* The mean z of the solver's vertices (equal masses: the centre of mass). */
static double mean_z(const sb_solver* s, double* x) {
    uint32_t n = sb_model_vertex_count(sb_solver_model(s));
    sb_solver_get_positions(s, x);
    double sum = 0.0;
    for (uint32_t i = 0; i < n; i++) sum += x[3 * i + 2];
    return sum / n;
}

/* A cloth (20 x 20, 0.4 m, tilted 30° so that one edge lands first and it
 * folds down) and a soft ball (icosphere, radius 0.1 m) dropped on a plane
 * of thickness 5 mm, pbd and xpbd (the fast kernels: the sweeps are the
 * same code under both): after every step no vertex is below the inflated
 * surface by more than 1e-6 m (the float state holds 0.005 m to ~1e-9 m),
 * and with drag both come to rest on it. */
static void test_resting_on_a_plane(void** state) {
    (void)state;
    const double thickness = 0.005, tilt = 30.0 * M_PI / 180.0;
    sb_model* cloth = sheet_model(20, 0.4, 0.0, 500.0, 0.05);
    uint32_t nc = sb_model_vertex_count(cloth);
    double* rest = tu_rest_positions(cloth);
    double* start = malloc(3 * (size_t)nc * sizeof *start);
    for (uint32_t i = 0; i < nc; i++) { /* tilted about the x axis, its low edge 2 cm up */
        start[3 * i] = rest[3 * i];
        start[3 * i + 1] = rest[3 * i + 1] * cos(tilt);
        start[3 * i + 2] = 0.02 + rest[3 * i + 1] * sin(tilt);
    }
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_icosphere(2, 0.1, &mesh, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) mesh.positions[3 * i + 2] += 0.15;
    sb_material_def material = sb_default_material_def();
    material.bond_k = 200.0;
    material.angle_k = 0.5;
    sb_model* ball = tu_mesh_model(&mesh, &material);
    sb_mesh_free(&mesh);
    double* x = malloc(3 * (size_t)(nc > 162 ? nc : 162) * sizeof *x);
    for (int body = 0; body < 2; body++)
        for (int k = 0; k < 2; k++) {
            sb_collider* floor = plane(0.0, up, 0.0, 0.3, thickness);
            sb_solver_def def = contact_def(&floor, 1, position_based[k]);
            def.drag = 5.0;
            sb_solver* s = tu_solver(body ? ball : cloth, &def);
            if (!body) assert_int_equal(sb_solver_set_state(s, start, NULL), SB_OK);
            double lowest = INFINITY;
            uint32_t contacts = 0;
            for (int step = 0; step < 2000; step++) { /* 2 s */
                tu_advance(s, 1e-3, 1);
                contacts += sb_solver_last_step(s).contacts;
                lowest = fmin(lowest, lowest_z(s, x));
            }
            sb_energies e = sb_solver_energies(s);
            print_message("%s, %s: %u contacts, lowest z %.9f m, kinetic %.3g J\n", body ? "ball" : "cloth",
                          sb_integrator_name(position_based[k]), contacts, lowest, e.kinetic);
            assert_true(contacts > 0);
            TU_ASSERT_LE(thickness - lowest, 1e-6);
            TU_ASSERT_LE(e.kinetic, 1e-4);
            sb_solver_destroy(s);
            sb_collider_destroy(floor);
        }
    free(x);
    free(start);
    free(rest);
    sb_model_destroy(cloth);
    sb_model_destroy(ball);
}

/* A small stiff body (a 5 x 5 sheet 2 cm wide, k = 10⁴ N/m, held flat)
 * dropped flat from h = 0.5 m: its centre of mass rises to e² h after the
 * first bounce, for e = 0, 0.5 and 0.9, within 0.1 % of h. */
static void test_restitution_rebound_height(void** state) {
    (void)state;
    const double restitution[3] = {0.0, 0.5, 0.9}, h = 0.5, dt = 1e-4;
    sb_model* m = sheet_model(5, 0.02, h, 1e4, 0.05);
    double x[3 * 25];
    for (int k = 0; k < 2; k++)
        for (int r = 0; r < 3; r++) {
            sb_collider* floor = plane(0.0, up, restitution[r], 0.0, 0.0);
            sb_solver_def def = contact_def(&floor, 1, position_based[k]);
            sb_solver* s = tu_solver(m, &def);
            double peak = 0.0;
            bool bounced = false;
            for (int step = 0; step < 15000; step++) { /* 1.5 s: the fall takes 0.32 s, the rise as long */
                tu_advance(s, dt, 1);
                double z = mean_z(s, x);
                if (sb_solver_last_step(s).contacts > 0) bounced = true;
                if (bounced && sb_solver_last_step(s).contacts == 0) peak = fmax(peak, z);
                if (bounced && z < peak - 1e-3) break; /* falling again */
            }
            double want = restitution[r] * restitution[r] * h;
            print_message("%s, e = %.1f: rebound %.5f m, e²h = %.5f m\n", sb_integrator_name(position_based[k]),
                          restitution[r], peak, want);
            assert_true(bounced);
            TU_ASSERT_LE(fabs(peak - want), 1e-3 * h);
            sb_solver_destroy(s);
            sb_collider_destroy(floor);
        }
    sb_model_destroy(m);
}

/* A 6 x 6 cloth (0.1 m, stiff bonds) lying on an incline of θ, μ = 0.5,
 * pbd and xpbd: it sticks for tan θ < μ (moves less than 10 µm in 0.5 s)
 * and slides with g (sin θ − μ cos θ) otherwise (distance after 0.5 s
 * within 2 %). */
static void test_friction_on_an_incline(void** state) {
    (void)state;
    const double mu = 0.5, degrees[2] = {20.0, 40.0}, T = 0.5, dt = 1e-4;
    sb_model* m = sheet_model(6, 0.1, 0.0, 500.0, 0.05);
    uint32_t n = sb_model_vertex_count(m);
    double *rest = tu_rest_positions(m), *x0 = malloc(3 * n * sizeof *x0), *x = malloc(3 * n * sizeof *x);
    for (int k = 0; k < 2; k++)
        for (int d = 0; d < 2; d++) {
            double th = degrees[d] * M_PI / 180.0;
            double normal[3] = {-sin(th), 0.0, cos(th)}, slope[3] = {cos(th), 0.0, sin(th)}; /* uphill */
            for (uint32_t i = 0; i < n; i++) /* laid on the incline: x along the slope */
                for (int c = 0; c < 3; c++) x0[3 * i + c] = c == 1 ? rest[3 * i + 1] : rest[3 * i] * slope[c];
            sb_collider* incline = plane(0.0, normal, 0.0, mu, 0.0);
            sb_solver_def def = contact_def(&incline, 1, position_based[k]);
            sb_solver* s = tu_solver(m, &def);
            assert_int_equal(sb_solver_set_state(s, x0, NULL), SB_OK);
            tu_advance(s, dt, (uint64_t)(T / dt));
            sb_solver_get_positions(s, x);
            double moved = 0.0; /* mean displacement along the slope, downhill positive */
            for (uint32_t i = 0; i < n; i++)
                for (int c = 0; c < 3; c++) moved -= (x[3 * i + c] - x0[3 * i + c]) * slope[c] / n;
            double a = G * (sin(th) - mu * cos(th)), want = a > 0 ? 0.5 * a * T * T : 0.0;
            print_message("%s, incline %.0f°: moved %.7f m downhill, Coulomb %.7f m\n",
                          sb_integrator_name(position_based[k]), degrees[d], moved, want);
            if (want == 0.0)
                TU_ASSERT_LE(fabs(moved), 1e-5);
            else
                TU_ASSERT_LE(fabs(moved - want), 0.02 * want);
            sb_solver_destroy(s);
            sb_collider_destroy(incline);
        }
    free(x);
    free(x0);
    free(rest);
    sb_model_destroy(m);
}

/* Ten point masses and a 6 x 6 cloth at rest on a plane, pbd and xpbd: the
 * plane's mean reaction force over 1000 steps is their weight (within
 * 0.1 %), straight down into it. */
static void test_reaction_force_is_the_weight(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    for (int i = 0; i < 10; i++) tu_vertex(b, 0.1 * i, 0, 0.001, 0.01, false);
    sb_model* points = tu_compile(b);
    sb_builder_destroy(b);
    sb_model* cloth = sheet_model(6, 0.1, 0.001, 500.0, 0.05);
    sb_model* models[2] = {points, cloth};
    for (int body = 0; body < 2; body++)
        for (int k = 0; k < 2; k++) {
            sb_collider* floor = plane(0.0, up, 0.0, 0.5, 0.0);
            sb_solver_def def = contact_def(&floor, 1, position_based[k]);
            sb_solver* s = tu_solver(models[body], &def);
            tu_advance(s, 1e-4, 1000); /* fallen (1 mm) and at rest */
            double force[3], sum[3] = {0, 0, 0};
            for (int step = 0; step < 1000; step++) {
                tu_advance(s, 1e-4, 1);
                sb_solver_contact_force(s, 0, force);
                for (int c = 0; c < 3; c++) sum[c] += force[c] / 1000;
            }
            uint32_t n = sb_model_vertex_count(models[body]);
            double weight = n * 0.01 * G;
            print_message("%s, %s: mean reaction (%.3g, %.3g, %.6f) N, weight %.6f N\n", body ? "cloth" : "points",
                          sb_integrator_name(position_based[k]), sum[0], sum[1], sum[2], weight);
            TU_ASSERT_LE(fabs(sum[2] + weight), 1e-3 * weight);
            TU_ASSERT_LE(fabs(sum[0]) + fabs(sum[1]), 1e-6 * weight);
            sb_solver_destroy(s);
            sb_collider_destroy(floor);
        }
    sb_model_destroy(points);
    sb_model_destroy(cloth);
}

/* A dynamic ball (0.5 kg, radius 5 cm, friction 0.3) thrown at 5 m/s at a
 * free 21 x 21 cloth, no gravity, pbd and xpbd: the ball slows down and
 * the momentum of ball and cloth together is kept (to the float state's
 * rounding: 1e-5 of the throw's). */
static void test_dynamic_ball_keeps_momentum(void** state) {
    (void)state;
    sb_model* m = sheet_model(21, 0.4, 0.0, 500.0, 0.05);
    uint32_t n = sb_model_vertex_count(m);
    double* v = malloc(3 * (size_t)n * sizeof *v);
    for (int k = 0; k < 2; k++) {
        sb_collider_def def = sb_default_collider_def();
        def.shape = SB_COLLIDER_SPHERE;
        def.radius = 0.05;
        def.mass = 0.5;
        def.friction = def.static_friction = 0.3;
        def.center[0] = def.center[1] = 0.2;
        def.center[2] = 0.06;
        def.velocity[2] = -5.0;
        sb_error err;
        sb_collider* ball = sb_collider_create(&def, &err);
        assert_non_null(ball);
        sb_solver_def sd = contact_def(&ball, 1, position_based[k]);
        sd.gravity[2] = 0.0;
        sb_solver* s = tu_solver(m, &sd);
        tu_advance(s, 1e-4, 300);
        double ball_v[3], p[3];
        sb_collider_state(ball, NULL, ball_v);
        sb_solver_get_velocities(s, v);
        for (int c = 0; c < 3; c++) {
            p[c] = 0.5 * ball_v[c];
            for (uint32_t i = 0; i < n; i++) p[c] += sb_model_mass(m, i) * v[3 * i + c];
        }
        print_message("%s: ball -5 -> %.4f m/s, momentum (%.3g, %.3g, %.6f) N s, thrown with -2.5 N s\n",
                      sb_integrator_name(position_based[k]), ball_v[2], p[0], p[1], p[2]);
        assert_true(ball_v[2] > -4.0); /* it met the cloth and slowed */
        for (int c = 0; c < 3; c++) TU_ASSERT_NEAR(p[c], c == 2 ? -2.5 : 0.0, 1e-5 * 2.5);
        sb_solver_destroy(s);
        sb_collider_destroy(ball);
    }
    free(v);
    sb_model_destroy(m);
}

/* A chain whose first vertex is fixed 1 cm inside the floor, pbd and xpbd:
 * the fixed vertex never moves (inverse mass 0), the free ones are kept
 * out. */
static void test_fixed_vertex_inside_a_collider(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    for (int i = 0; i < 5; i++) tu_vertex(b, 0.02 * i, 0, i == 0 ? -0.01 : 0.01, 0.01, i == 0);
    for (uint32_t i = 0; i + 1 < 5; i++) tu_bond(b, i, i + 1, -1, 200, 0, 0);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    for (int k = 0; k < 2; k++) {
        sb_collider* floor = plane(0.0, up, 0.0, 0.3, 0.0);
        sb_solver_def def = contact_def(&floor, 1, position_based[k]);
        sb_solver* s = tu_solver(m, &def);
        double x[15], v[15];
        for (int step = 0; step < 500; step++) {
            tu_advance(s, 1e-3, 1);
            sb_solver_get_positions(s, x);
            sb_solver_get_velocities(s, v);
            assert_true(x[0] == 0.0 && x[1] == 0.0 && x[2] == (double)(sb_real)-0.01);
            assert_true(v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0);
            for (int i = 1; i < 5; i++) TU_ASSERT_LE(-x[3 * i + 2], 1e-6);
        }
        sb_solver_destroy(s);
        sb_collider_destroy(floor);
    }
    sb_model_destroy(m);
}

/* A 100 x 100 sheet (1 m) falling onto a sphere with friction and
 * restitution above a floor, 40 steps of 2 ms: thousands of constraints a
 * color, so both threads project, and 40 chunks of contacts. The state and
 * both reaction forces are bitwise the same for 1 and 2 threads. */
static void test_threads_deterministic(void** state) {
    (void)state;
    sb_model* m = sheet_model(100, 1.0, 0.0, 500.0, 0.05);
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_SPHERE;
    def.center[0] = def.center[1] = 0.5;
    def.center[2] = -0.3;
    def.radius = 0.3;
    def.friction = def.static_friction = 0.4;
    def.restitution = 0.3;
    sb_error err;
    sb_collider* colliders[2] = {sb_collider_create(&def, &err), NULL};
    assert_non_null(colliders[0]);
    for (int k = 0; k < 2; k++) {
        uint64_t hashes[2];
        double forces[2][6];
        uint32_t contacts = 0;
        for (int t = 0; t < 2; t++) {
            colliders[1] = plane(-0.05, up, 0.2, 0.6, 0.002);
            sb_solver_def sd = contact_def(colliders, 2, position_based[k]);
            sd.runtime.threads = t + 1;
            sb_solver* s = tu_solver(m, &sd);
            for (int step = 0; step < 40; step++) {
                tu_advance(s, 2e-3, 1);
                contacts += sb_solver_last_step(s).contacts;
            }
            hashes[t] = tu_state_hash(s);
            sb_solver_contact_force(s, 0, forces[t]);
            sb_solver_contact_force(s, 1, forces[t] + 3);
            sb_solver_destroy(s);
            sb_collider_destroy(colliders[1]);
        }
        print_message(
            "%s: %u contacts; state hash %016llx (1 thread), %016llx (2 threads); force on the sphere %.6f N\n",
            sb_integrator_name(position_based[k]), contacts, (unsigned long long)hashes[0],
            (unsigned long long)hashes[1], forces[0][2]);
        assert_true(contacts > 0 && forces[0][2] != 0.0);
        assert_true(hashes[0] == hashes[1]);
        assert_memory_equal(forces[0], forces[1], sizeof forces[0]);
    }
    sb_collider_destroy(colliders[0]);
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_resting_on_a_plane),          cmocka_unit_test(test_restitution_rebound_height),
        cmocka_unit_test(test_friction_on_an_incline),      cmocka_unit_test(test_reaction_force_is_the_weight),
        cmocka_unit_test(test_dynamic_ball_keeps_momentum), cmocka_unit_test(test_fixed_vertex_inside_a_collider),
        cmocka_unit_test(test_threads_deterministic),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
