/* Handles (softbond/handle.h, kernels/interaction/handle.c): a hard handle's vertices
 * are exactly at their targets after every step for every integrator and
 * both kernel choices; released vertices move freely and a re-grab holds
 * them where they are; a pose set by the program is reached to the bit; adaptive stepping counts a hard handle's work;
 * a soft handle's reported force is the sum of its spring-dampers worked out by hand, and it holds a hanging mass at
 * the static stretch m g / k; a one-vertex handle moves to another vertex; 1 and 2 threads give the same state; bad
 * definitions are refused. */
#include "test_util.h"

#include "softbond/handle.h"

#define G 9.81

/* A side × side sheet of width 0.1 m at z = 0, bonds k, corners kt, 0.01 kg per vertex. */
static sb_model* sheet_model(uint32_t side, double k, double kt) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = side;
    sheet.width = sheet.height = 0.1;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    sb_material_def material = sb_default_material_def();
    material.bond_k = k;
    material.angle_k = kt;
    material.mass = 0.01;
    sb_model* m = tu_mesh_model(&mesh, &material);
    sb_mesh_free(&mesh);
    return m;
}

static sb_handle* make_handle(const sb_handle_def* def) {
    sb_error err;
    sb_handle* h = sb_handle_create(def, &err);
    if (!h) fail_msg("%s", err.message);
    return h;
}

/* The first row of the sheet (y = 0), raised 0.02 m in 0.1 s, then held. */
static const sb_keyframe lift[2] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {0.1, {0, 0, 0.02}, {0, 0, 0}}};

static sb_handle* row_handle(uint32_t side, uint32_t* vertices, double stiffness, double damping) {
    for (uint32_t i = 0; i < side; i++) vertices[i] = i;
    sb_handle_def def = sb_default_handle_def();
    def.name = "row";
    def.vertices = vertices;
    def.vertex_count = side;
    def.stiffness = stiffness;
    def.damping = damping;
    def.path = lift;
    def.path_count = 2;
    return make_handle(&def);
}

/* The lift's height at time t, written from the keyframes. */
static double lift_height(double t) { return t >= 0.1 ? 0.02 : (t / 0.1) * 0.02; }

static sb_solver_def handle_def(sb_handle** handles, uint32_t count, sb_integrator integrator, sb_kernels kernels) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.kernels = kernels;
    def.handles = handles;
    def.handle_count = count;
    def.runtime.threads = 1;
    return def;
}

static void test_hard_handle_exact_for_every_integrator(void** state) {
    (void)state;
    const uint32_t side = 6;
    sb_model* m = sheet_model(side, 200.0, 1e-4);
    double rest[3 * 36], x[3 * 36], v[3 * 36];
    for (uint32_t i = 0; i < side * side; i++) sb_model_rest_position(m, i, rest + 3 * i);
    for (int kernels = 0; kernels < 2; kernels++)
        for (int integrator = 0; integrator < SB_INTEGRATOR_COUNT; integrator++) {
            uint32_t vertices[6];
            sb_handle* h = row_handle(side, vertices, 0.0, 0.0);
            sb_solver_def def = handle_def(&h, 1, (sb_integrator)integrator, (sb_kernels)kernels);
            sb_solver* s = tu_solver(m, &def);
            for (int step = 0; step < 150; step++) {
                tu_advance(s, 1e-3, 1);
                sb_solver_get_positions(s, x);
                sb_solver_get_velocities(s, v);
                double t = sb_solver_time(s);
                for (uint32_t i = 0; i < side; i++) {
                    for (int c = 0; c < 2; c++) assert_true(x[3 * i + c] == (double)(sb_real)rest[3 * i + c]);
                    double z = (double)(sb_real)(rest[3 * i + 2] + lift_height(t));
                    if (x[3 * i + 2] != z)
                        fail_msg("%s (%s kernels), step %d: vertex %u at z = %.17g, target %.17g",
                                 sb_integrator_name((sb_integrator)integrator), kernels ? "fast" : "reference", step, i,
                                 x[3 * i + 2], z);
                    /* the target's velocity over the step: 0.2 m/s up while it lifts, 0 after */
                    double expected = t <= 0.1 + 1e-9 ? 0.2 : 0.0;
                    if (t > 0.1 && t < 0.1 + 1.5e-3) continue; /* the step across the last keyframe */
                    TU_ASSERT_NEAR(v[3 * i + 2], expected, 1e-6 + 1e3 * TU_REAL_EPS);
                }
            }
            /* the rest of the sheet hangs from the row: it moved */
            assert_true(x[3 * (side * side - 1) + 2] < -1e-3);
            sb_solver_destroy(s);
            sb_handle_destroy(h);
        }
    sb_model_destroy(m);
}

static void test_release_and_grab(void** state) {
    (void)state;
    const uint32_t side = 6;
    sb_model* m = sheet_model(side, 200.0, 1e-4);
    for (int integrator = 0; integrator < SB_INTEGRATOR_COUNT; integrator++) {
        /* explicit Euler gains energy every step: the free sheet blows up within 0.3 s, handle or not */
        if (integrator == SB_INTEGRATOR_EXPLICIT_EULER) continue;
        uint32_t vertices[6];
        sb_handle* h = row_handle(side, vertices, 0.0, 0.0);
        sb_solver_def def = handle_def(&h, 1, (sb_integrator)integrator, SB_KERNELS_FAST);
        sb_solver* s = tu_solver(m, &def);
        double x[3 * 36], v[3 * 36], held[3 * 36];
        tu_advance(s, 1e-3, 50); /* mid-lift: the row rises at 0.2 m/s */
        sb_handle_release(h);
        assert_false(sb_handle_held(h));
        sb_solver_get_velocities(s, v);
        TU_ASSERT_NEAR(v[2], 0.2, 1e-6 + 1e3 * TU_REAL_EPS); /* it keeps the velocity it had */
        sb_solver_get_positions(s, held);
        tu_advance(s, 1e-3, 200);
        sb_solver_get_positions(s, x);
        /* free again: the row rose on its momentum, then fell with the sheet */
        for (uint32_t i = 0; i < side; i++) assert_true(x[3 * i + 2] < held[3 * i + 2] - 1e-3);
        /* re-grabbed where it is now: it stays there */
        assert_int_equal(sb_handle_grab(h), SB_OK);
        sb_solver_get_positions(s, held);
        tu_advance(s, 1e-3, 20);
        sb_solver_get_positions(s, x);
        for (uint32_t i = 0; i < side; i++)
            for (int c = 0; c < 3; c++) TU_ASSERT_NEAR(x[3 * i + c], held[3 * i + c], 1e-12 + 4 * TU_REAL_EPS * 0.1);
        sb_solver_destroy(s);
        sb_handle_destroy(h);
    }
    sb_model_destroy(m);
}

/* Adaptive stepping counts a hard handle's work: lifting the row does not
 * look like energy made from nothing, so (almost) no sub-step is rejected;
 * without the count every one is, down to min_dt, and the advance fails. */
static void test_adaptive_counts_the_handle_work(void** state) {
    (void)state;
    const uint32_t side = 6;
    sb_model* m = sheet_model(side, 200.0, 1e-4);
    const sb_integrator integrators[2] = {SB_INTEGRATOR_VERLET, SB_INTEGRATOR_VELOCITY_VERLET};
    for (int kernels = 0; kernels < 2; kernels++)
        for (int q = 0; q < 2; q++) {
            uint32_t vertices[6];
            sb_handle* h = row_handle(side, vertices, 0.0, 0.0);
            sb_solver_def def = handle_def(&h, 1, integrators[q], (sb_kernels)kernels);
            def.adaptive = true;
            def.adaptive_tolerance = 1e-5; /* float's rounding level in both precisions: the count, not the
                                              trapezoid rule's own error, is what is tested */
            sb_solver* s = tu_solver(m, &def);
            uint32_t rejected = 0;
            for (int step = 0; step < 150; step++) {
                tu_advance(s, 1e-3, 1);
                rejected += sb_solver_last_step(s).rejected;
            }
            /* a few at most (the reference path's rounding), of 150 steps */
            if (rejected > 5) fail_msg("%s: %u sub-steps rejected", sb_integrator_name(integrators[q]), rejected);
            sb_solver_destroy(s);
            sb_handle_destroy(h);
        }
    sb_model_destroy(m);
}

/* A program drives the row (sb_handle_set_pose before each step): after
 * each step it is where the program put it, to the bit. */
static void test_driven_pose(void** state) {
    (void)state;
    const uint32_t side = 6;
    sb_model* m = sheet_model(side, 200.0, 1e-4);
    uint32_t vertices[6];
    for (uint32_t i = 0; i < side; i++) vertices[i] = i;
    sb_handle_def hd = sb_default_handle_def();
    hd.vertices = vertices;
    hd.vertex_count = side;
    sb_handle* h = make_handle(&hd);
    const double zero[3] = {0, 0, 0};
    sb_handle_set_pose(h, zero, zero); /* before the solver exists: fine */
    sb_solver_def def = handle_def(&h, 1, SB_INTEGRATOR_VERLET, SB_KERNELS_FAST);
    sb_solver* s = tu_solver(m, &def);
    double rest[3 * 36], x[3 * 36];
    for (uint32_t i = 0; i < side * side; i++) sb_model_rest_position(m, i, rest + 3 * i);
    for (int step = 1; step <= 50; step++) {
        const double shift[3] = {0.001 * step, 0.0, -0.002 * step};
        sb_handle_set_pose(h, shift, zero);
        tu_advance(s, 1e-3, 1);
        sb_solver_get_positions(s, x);
        for (uint32_t i = 0; i < side; i++)
            for (int c = 0; c < 3; c++) assert_true(x[3 * i + c] == (double)(sb_real)(rest[3 * i + c] + shift[c]));
    }
    sb_solver_destroy(s);
    sb_handle_destroy(h);
    sb_model_destroy(m);
}

/* Three free vertices in a row joined by bonds. */
static sb_model* three_masses(double mass) {
    sb_builder* b = sb_builder_create();
    for (int i = 0; i < 3; i++) tu_vertex(b, 0.1 * i, 0.0, 0.0, mass, false);
    tu_bond(b, 0, 1, -1, 50.0, 0, 0);
    tu_bond(b, 1, 2, -1, 50.0, 0, 0);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

/* The reported force is Σ k (target − x) + c (target velocity − v) at the
 * state the last force evaluation saw: explicit Euler evaluates the forces
 * at the final state of its step. */
static void test_soft_force_is_the_sum_of_its_springs(void** state) {
    (void)state;
    sb_model* m = three_masses(0.05);
    const double k = 40.0, c = 0.3;
    const sb_keyframe path[2] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {1.0, {0.5, 0, 1.0}, {0, 0, 0}}};
    uint32_t vertices[2] = {0, 2};
    sb_handle_def hd = sb_default_handle_def();
    hd.name = "grasper";
    hd.vertices = vertices;
    hd.vertex_count = 2;
    hd.stiffness = k;
    hd.damping = c;
    hd.path = path;
    hd.path_count = 2;
    sb_handle* h = make_handle(&hd);
    sb_solver_def def = handle_def(&h, 1, SB_INTEGRATOR_EXPLICIT_EULER, SB_KERNELS_REFERENCE);
    sb_solver* s = tu_solver(m, &def);
    double x[9], v[9], rest[9];
    for (uint32_t i = 0; i < 3; i++) sb_model_rest_position(m, i, rest + 3 * i);
    for (int step = 0; step < 100; step++) {
        tu_advance(s, 1e-3, 1);
        sb_solver_get_positions(s, x);
        sb_solver_get_velocities(s, v);
        double t = sb_solver_time(s);
        const double shift[3] = {0.5 * t, 0.0, t}, speed[3] = {0.5, 0.0, 1.0};
        double expected[3] = {0, 0, 0}, reported[3];
        for (int j = 0; j < 2; j++)
            for (int a = 0; a < 3; a++) {
                uint32_t i = vertices[j];
                expected[a] += k * (rest[3 * i + a] + shift[a] - x[3 * i + a]) + c * (speed[a] - v[3 * i + a]);
            }
        sb_handle_force(h, reported);
        for (int a = 0; a < 3; a++) TU_ASSERT_NEAR(reported[a], expected[a], 1e-9 + 1e-6 * fabs(expected[a]));
    }
    double reported[3];
    sb_handle_force(h, reported);
    assert_true(reported[2] > 0.01); /* it pulls up: the masses lag the target */
    sb_handle_release(h);
    sb_handle_force(h, reported);
    assert_true(reported[0] == 0.0 && reported[1] == 0.0 && reported[2] == 0.0);
    sb_solver_destroy(s);
    sb_handle_destroy(h);
    sb_model_destroy(m);
}

/* A one-vertex soft handle moved to another vertex (a mouse's pick): it
 * holds the new vertex where it was, pulls it toward its moved target, and
 * a handle of two vertices, one not attached, or a
 * vertex outside the model is refused. */
static void test_grab_another_vertex(void** state) {
    (void)state;
    sb_model* m = three_masses(0.05);
    const double k = 40.0;
    uint32_t first = 0;
    sb_handle_def hd = sb_default_handle_def();
    hd.vertices = &first;
    hd.vertex_count = 1;
    hd.stiffness = k;
    sb_handle* h = make_handle(&hd);
    assert_int_equal(sb_handle_grab_vertex(h, 2), SB_ERR_INVALID); /* not attached */
    sb_solver_def def = handle_def(&h, 1, SB_INTEGRATOR_EXPLICIT_EULER, SB_KERNELS_REFERENCE);
    def.gravity[2] = 0.0;
    sb_solver* s = tu_solver(m, &def);
    assert_int_equal(sb_handle_grab_vertex(h, 3), SB_ERR_INVALID);
    assert_int_equal(sb_handle_grab_vertex(h, 2), SB_OK);
    double grabbed[3], x[9];
    sb_handle_target(h, 0, grabbed);
    sb_solver_get_positions(s, x);
    for (int c = 0; c < 3; c++) assert_true(grabbed[c] == x[6 + c]);
    const double lift[3] = {0, 0, 0.01}, none[3] = {0, 0, 0};
    sb_handle_set_pose(h, lift, none);
    tu_advance(s, 1e-3, 3); /* explicit Euler moves by the velocity before the step: the pull shows at the third */
    double force[3];
    sb_handle_force(h, force);
    sb_solver_get_positions(s, x);
    TU_ASSERT_NEAR(force[2], k * (grabbed[2] + 0.01 - x[8]), 1e-6);
    assert_true(force[2] > 0.3 && x[8] > 0.0); /* vertex 2 alone is pulled up */
    uint32_t two[2] = {0, 1};
    hd.vertices = two;
    hd.vertex_count = 2;
    sb_handle* pair = make_handle(&hd);
    assert_int_equal(sb_handle_grab_vertex(pair, 2), SB_ERR_INVALID);
    sb_handle_destroy(pair);
    sb_solver_destroy(s);
    sb_handle_destroy(h);
    sb_model_destroy(m);
}

/* A 0.1 kg mass hanging from a soft handle of k = 100 N/m settles m g / k
 * = 9.81 mm below it, and the handle holds it with m g. */
static void test_soft_handle_holds_a_hanging_mass(void** state) {
    (void)state;
    const double mass = 0.1, k = 100.0;
    for (int integrator = 0; integrator < SB_INTEGRATOR_COUNT; integrator++) {
        sb_builder* b = sb_builder_create();
        tu_vertex(b, 0, 0, 0, mass, false);
        tu_vertex(b, 1, 0, 0, 1.0, true);
        tu_bond(b, 0, 1, -1, 1.0, 0, 0); /* a fixed end keeps the model valid; horizontal and slack at most */
        sb_model* m = tu_compile(b);
        sb_builder_destroy(b);
        uint32_t vertex = 0;
        sb_handle_def hd = sb_default_handle_def();
        hd.vertices = &vertex;
        hd.vertex_count = 1;
        hd.stiffness = k;
        hd.damping = 2.0;
        sb_handle* h = make_handle(&hd);
        sb_solver_def def = handle_def(&h, 1, (sb_integrator)integrator, SB_KERNELS_FAST);
        sb_solver* s = tu_solver(m, &def);
        tu_advance(s, 1e-3, 3000);
        double x[6], f[3];
        sb_solver_get_positions(s, x);
        sb_handle_force(h, f);
        /* the horizontal bond (1 N/m, 1 m long), stretched by z²/2, pulls up by ~5e-7 N: far below 0.1 % */
        double stretch = mass * G / k;
        TU_ASSERT_NEAR(-x[2], stretch, 1e-3 * stretch);
        TU_ASSERT_NEAR(f[2], mass * G, 1e-3 * mass * G);
        sb_solver_destroy(s);
        sb_handle_destroy(h);
        sb_model_destroy(m);
    }
}

/* A hard handle turning a row of the sheet and a soft one pulling a corner:
 * the same bits for 1 and 2 threads. */
static void test_threads_deterministic(void** state) {
    (void)state;
    const uint32_t side = 24;
    sb_model* m = sheet_model(side, 200.0, 1e-4);
    const sb_keyframe turn[2] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {0.05, {0, 0, 0.01}, {30, 0, 0}}};
    uint32_t row[24], corner = side * side - 1;
    for (uint32_t i = 0; i < side; i++) row[i] = i;
    const sb_integrator integrators[3] = {SB_INTEGRATOR_VERLET, SB_INTEGRATOR_XPBD, SB_INTEGRATOR_SYMPLECTIC_EULER};
    for (int q = 0; q < 3; q++) {
        uint64_t hashes[2];
        double forces[2][3];
        for (int threads = 1; threads <= 2; threads++) {
            sb_handle_def hard = sb_default_handle_def(), soft = sb_default_handle_def();
            hard.vertices = row;
            hard.vertex_count = side;
            hard.path = turn;
            hard.path_count = 2;
            soft.vertices = &corner;
            soft.vertex_count = 1;
            soft.stiffness = 5.0;
            soft.damping = 0.05;
            soft.path = turn;
            soft.path_count = 2;
            sb_handle* h[2] = {make_handle(&hard), make_handle(&soft)};
            sb_solver_def def = handle_def(h, 2, integrators[q], SB_KERNELS_FAST);
            def.runtime.threads = threads;
            sb_solver* s = tu_solver(m, &def);
            tu_advance(s, 5e-4, 200);
            hashes[threads - 1] = tu_state_hash(s);
            sb_handle_force(h[1], forces[threads - 1]);
            sb_solver_destroy(s);
            sb_handle_destroy(h[0]);
            sb_handle_destroy(h[1]);
        }
        assert_true(hashes[0] == hashes[1]);
        assert_memory_equal(forces[0], forces[1], sizeof forces[0]);
    }
    sb_model_destroy(m);
}

static void test_refusals(void** state) {
    (void)state;
    sb_error err;
    uint32_t vertices[2] = {0, 7};
    sb_handle_def def = sb_default_handle_def();
    def.name = "hook";
    assert_null(sb_handle_create(&def, &err));
    TU_ASSERT_CONTAINS(err.message, "handle 'hook': no vertices");
    def.vertices = vertices;
    def.vertex_count = 2;
    def.stiffness = -1;
    assert_null(sb_handle_create(&def, &err));
    TU_ASSERT_CONTAINS(err.message, "stiffness and damping must be finite and >= 0");
    def.stiffness = 0;
    const sb_keyframe backwards[2] = {{1.0, {0, 0, 0}, {0, 0, 0}}, {0.5, {0, 0, 0}, {0, 0, 0}}};
    def.path = backwards;
    def.path_count = 2;
    assert_null(sb_handle_create(&def, &err));
    TU_ASSERT_CONTAINS(err.message, "handle 'hook': path[1].time must be greater than path[0].time");
    def.path = NULL;
    def.path_count = 0;
    sb_handle* h = make_handle(&def);
    sb_model* m = three_masses(0.1); /* 3 vertices: vertex 7 is not there */
    sb_solver_def sd = handle_def(&h, 1, SB_INTEGRATOR_VERLET, SB_KERNELS_FAST);
    assert_null(sb_solver_create(m, &sd, &err));
    TU_ASSERT_CONTAINS(err.message, "handle 'hook': vertex 7 (entry 1) is not in the model (3 vertices)");
    assert_int_equal(sb_handle_grab(h), SB_ERR_INVALID); /* not attached */
    sb_handle_destroy(h);
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hard_handle_exact_for_every_integrator),
        cmocka_unit_test(test_release_and_grab),
        cmocka_unit_test(test_adaptive_counts_the_handle_work),
        cmocka_unit_test(test_driven_pose),
        cmocka_unit_test(test_soft_force_is_the_sum_of_its_springs),
        cmocka_unit_test(test_soft_handle_holds_a_hanging_mass),
        cmocka_unit_test(test_threads_deterministic),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_grab_another_vertex),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
