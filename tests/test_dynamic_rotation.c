/* Dynamic colliders that turn (kernels/contact/colliders/dynamic.c): the body's
 * angular momentum about its center changes by exactly the torque of what
 * the vertices received at their contact points (worked out here from the
 * moves); friction spins a ball hit off its center the right way and a
 * frictionless hit does not spin it; a free body keeps its angular
 * momentum, and its angular velocity about an axis of symmetry; the same
 * state for 1 and 2 threads; the scene's angular_velocity key. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/test_files.h"

/* side × side free 10 g point masses (no elements) on a grid over
 * [x − w, x + w] × [−w, w] at height z, all moving at velocity. */
static sb_model* points_model(uint32_t side, double w, double x, double z, const double velocity[3]) {
    sb_builder* b = sb_builder_create();
    for (uint32_t i = 0; i < side * side; i++) {
        sb_vertex_def v = sb_default_vertex_def();
        v.position[0] = x - w + 2.0 * w * (i % side) / (side - 1);
        v.position[1] = -w + 2.0 * w * (i / side) / (side - 1);
        v.position[2] = z;
        v.mass = 0.01;
        memcpy(v.velocity, velocity, sizeof v.velocity);
        sb_builder_add_vertex(b, &v);
    }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

static sb_collider* make_collider(const sb_collider_def* def) {
    sb_error err;
    sb_collider* c = sb_collider_create(def, &err);
    if (!c) fail_msg("%s", err.message);
    return c;
}

static sb_collider_def dynamic_def(sb_collider_shape shape, double mass, double friction) {
    sb_collider_def d = sb_default_collider_def();
    d.shape = shape;
    d.name = "body";
    d.mass = mass;
    d.friction = friction;
    return d;
}

static sb_solver_def no_gravity(sb_collider** collider, int threads) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_VERLET;
    def.colliders = collider;
    def.collider_count = 1;
    def.runtime.threads = threads;
    memset(def.gravity, 0, sizeof def.gravity);
    return def;
}

/* L = R diag(inertia) Rᵀ ω (inertia about the body's own axes, R its
 * rotation from the def's frame, whose axes are the world's here). */
static void angular_momentum(const double r[9], const double inertia[3], const double w[3], double L[3]) {
    double local[3];
    for (int j = 0; j < 3; j++) local[j] = inertia[j] * (r[j] * w[0] + r[3 + j] * w[1] + r[6 + j] * w[2]);
    for (int i = 0; i < 3; i++) L[i] = r[3 * i] * local[0] + r[3 * i + 1] * local[1] + r[3 * i + 2] * local[2];
}

/* The box's inertia about its axes: m/3 (h_j² + h_k²). */
static void box_inertia(double m, const double h[3], double inertia[3]) {
    for (int i = 0; i < 3; i++)
        inertia[i] = m / 3.0 * (h[(i + 1) % 3] * h[(i + 1) % 3] + h[(i + 2) % 3] * h[(i + 2) % 3]);
}

/* A 2 kg box at rest, 11 × 11 masses over [−0.15, 0.15]² (off its center:
 * the box is at (0.05, −0.03)) moving at (2, 1, −3) m/s onto its top face
 * with friction 0.3, one step of 0.1 ms. Each mass meets the top face
 * where its move crosses the plane z = top (no thickness), and there it
 * gives the box the opposite of the m Δv it took; the box's angular
 * momentum after the step, I ω from its reported orientation and angular
 * velocity, is the sum of those impulses' moments about its center, and
 * its momentum their sum, to the state's rounding (100 ε relative). */
static void test_angular_momentum_balance(void** state) {
    (void)state;
    const double h[3] = {0.2, 0.25, 0.1}, center[3] = {0.05, -0.03, 0.0}, mass = 2.0, dt = 1e-4;
    const double velocity[3] = {2.0, 1.0, -3.0}, top = center[2] + h[2], z0 = top + 2e-4;
    sb_collider_def d = dynamic_def(SB_COLLIDER_BOX, mass, 0.3);
    memcpy(d.center, center, sizeof d.center);
    memcpy(d.half_extents, h, sizeof d.half_extents);
    sb_collider* box = make_collider(&d);
    sb_model* m = points_model(11, 0.15, 0.0, z0, velocity);
    sb_solver_def sd = no_gravity(&box, 1);
    sb_solver* s = tu_solver(m, &sd);
    uint32_t n = sb_model_vertex_count(m);
    double *x0 = malloc(6 * n * sizeof *x0), *v0 = x0 + 3 * n, *v1 = malloc(3 * n * sizeof *v1);
    sb_solver_get_positions(s, x0);
    sb_solver_get_velocities(s, v0);
    tu_advance(s, dt, 1);
    sb_solver_get_velocities(s, v1);
    double torque[3] = {0, 0, 0}, impulse[3] = {0, 0, 0};
    uint32_t hits = 0;
    for (uint32_t i = 0; i < n; i++) {
        const double *x = x0 + 3 * i, *v = v0 + 3 * i;
        double to_z = x[2] + v[2] * dt;
        if (to_z > top) continue; /* (none: all cross it) */
        double f = (x[2] - top) / (x[2] - to_z), r[3], received[3], moment[3];
        r[0] = x[0] + f * v[0] * dt - center[0];
        r[1] = x[1] + f * v[1] * dt - center[1];
        r[2] = top - center[2];
        for (int k = 0; k < 3; k++) received[k] = -0.01 * (v1[3 * i + k] - v[k]);
        tu_cross(r, received, moment);
        for (int k = 0; k < 3; k++) torque[k] += moment[k], impulse[k] += received[k];
        hits++;
    }
    double rotation[9], w[3], L[3], inertia[3], position[3], vb[3];
    sb_collider_orientation(box, rotation, w);
    sb_collider_state(box, position, vb);
    box_inertia(mass, h, inertia);
    angular_momentum(rotation, inertia, w, L);
    print_message("%u hits; torque received (%.6g, %.6g, %.6g) N m s, the box's L (%.6g, %.6g, %.6g)\n", hits,
                  torque[0], torque[1], torque[2], L[0], L[1], L[2]);
    assert_int_equal(hits, n);
    double size = tu_norm(torque);
    assert_true(size > 1e-3);
    for (int k = 0; k < 3; k++) {
        TU_ASSERT_NEAR(L[k], torque[k], 100 * TU_REAL_EPS * size);
        TU_ASSERT_NEAR(mass * vb[k], impulse[k], 100 * TU_REAL_EPS * tu_norm(impulse));
    }
    free(x0);
    free(v1);
    sb_solver_destroy(s);
    sb_model_destroy(m);
    sb_collider_destroy(box);
}

/* A 1 kg ball of radius 0.1 m at rest, hit by 5 × 5 masses falling at
 * 3 m/s around (0.05, 0) (its +x side, off its center). Friction drags the
 * point they meet along their slide (down and out): the ball turns about
 * +y (ω_y > 0: its +x side moves down), not about x or z (within 1 % of
 * ω_y, the hit being symmetric in y). Without friction the impulses are
 * normal to the sphere, through its center: it does not turn. */
static void test_friction_spins_a_ball_hit_off_center(void** state) {
    (void)state;
    /* the post-step answer, and pbd's constraints inside its sweeps */
    const sb_integrator integrators[] = {SB_INTEGRATOR_VERLET, SB_INTEGRATOR_PBD};
    for (int variant = 0; variant < 4; variant++) {
        double friction = variant % 2 == 0 ? 0.5 : 0.0;
        sb_collider_def d = dynamic_def(SB_COLLIDER_SPHERE, 1.0, friction);
        d.radius = 0.1;
        sb_collider* ball = make_collider(&d);
        sb_model* m = points_model(5, 0.01, 0.05, 0.15, (double[3]){0, 0, -3.0});
        sb_solver_def sd = no_gravity(&ball, 1);
        sd.integrator = integrators[variant / 2];
        sb_solver* s = tu_solver(m, &sd);
        tu_advance(s, 1e-4, 400);
        double rotation[9], w[3];
        sb_collider_orientation(ball, rotation, w);
        print_message("%s, friction %.1f: ω = (%.6g, %.6g, %.6g) rad/s\n", sb_integrator_name(sd.integrator), friction,
                      w[0], w[1], w[2]);
        if (friction > 0.0) {
            assert_true(w[1] > 0.1);
            TU_ASSERT_LE(fabs(w[0]), 0.01 * w[1]);
            TU_ASSERT_LE(fabs(w[2]), 0.01 * w[1]);
        } else {
            TU_ASSERT_LE(tu_norm(w), 1e-6);
        }
        sb_solver_destroy(s);
        sb_model_destroy(m);
        sb_collider_destroy(ball);
    }
}

/* Free bodies far from the masses, for 1 s at 1 ms: a ball spinning at
 * (1, 2, 3) rad/s and a box spinning at 5 rad/s about its own z axis keep
 * ω (to 1e-12), and the box has turned by 5 rad about z (its rotation
 * within 1e-9 of Rz(5)); a box spinning about no axis of its own keeps its
 * angular momentum I ω (to 1e-9 relative) while ω itself precesses. */
static void test_free_bodies_keep_their_spin(void** state) {
    (void)state;
    const double h[3] = {0.3, 0.2, 0.1};
    const double spins[3][3] = {{1, 2, 3}, {0, 0, 5}, {3, -1, 2}};
    for (int variant = 0; variant < 3; variant++) {
        sb_collider_def d = dynamic_def(variant == 0 ? SB_COLLIDER_SPHERE : SB_COLLIDER_BOX, 1.5, 0.5);
        d.radius = 0.2;
        memcpy(d.half_extents, h, sizeof d.half_extents);
        d.center[2] = 5.0;
        memcpy(d.angular_velocity, spins[variant], sizeof d.angular_velocity);
        sb_collider* body = make_collider(&d);
        sb_model* m = points_model(3, 0.1, 0.0, 0.0, (double[3]){0, 0, 0});
        sb_solver_def sd = no_gravity(&body, 1);
        sb_solver* s = tu_solver(m, &sd);
        tu_advance(s, 1e-3, 1000);
        double rotation[9], w[3], inertia[3], L[3], L0[3];
        sb_collider_orientation(body, rotation, w);
        if (variant == 0)
            inertia[0] = inertia[1] = inertia[2] = 0.4 * 1.5 * 0.2 * 0.2;
        else
            box_inertia(1.5, h, inertia);
        angular_momentum(rotation, inertia, w, L);
        const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        angular_momentum(identity, inertia, spins[variant], L0);
        print_message("ω now (%.12g, %.12g, %.12g), L now (%.9g, %.9g, %.9g), at the start (%.9g, %.9g, %.9g)\n", w[0],
                      w[1], w[2], L[0], L[1], L[2], L0[0], L0[1], L0[2]);
        for (int k = 0; k < 3; k++) TU_ASSERT_NEAR(L[k], L0[k], 1e-9 * tu_norm(L0));
        if (variant < 2)
            for (int k = 0; k < 3; k++) TU_ASSERT_NEAR(w[k], spins[variant][k], 1e-12 * tu_norm(spins[variant]));
        if (variant == 1) {
            const double rz[9] = {cos(5.0), -sin(5.0), 0, sin(5.0), cos(5.0), 0, 0, 0, 1};
            for (int k = 0; k < 9; k++) TU_ASSERT_NEAR(rotation[k], rz[k], 1e-9);
        }
        if (variant == 2) assert_true(fabs(w[0] - spins[2][0]) > 1e-3); /* it precessed */
        sb_solver_destroy(s);
        sb_model_destroy(m);
        sb_collider_destroy(body);
    }
}

/* A 41 × 41 sheet dropped on a ball spinning at (0, 4, 1) rad/s with
 * friction, 30 ms: bitwise the same sheet, ball position, velocity,
 * orientation and angular velocity with 1 and 2 threads. */
static void test_spinning_ball_is_deterministic(void** state) {
    (void)state;
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = 41;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) {
        mesh.positions[3 * i] -= 0.5;
        mesh.positions[3 * i + 1] -= 0.5;
        mesh.positions[3 * i + 2] = 0.12;
    }
    sb_material_def material = sb_default_material_def();
    material.bond_k = 500.0;
    material.angle_k = 0.1;
    sb_model* m = tu_mesh_model(&mesh, &material);
    sb_mesh_free(&mesh);
    uint64_t first_hash = 0;
    double first[18];
    for (int threads = 1; threads <= 2; threads++) {
        sb_collider_def d = dynamic_def(SB_COLLIDER_SPHERE, 0.5, 0.6);
        d.radius = 0.1;
        d.angular_velocity[1] = 4.0;
        d.angular_velocity[2] = 1.0;
        d.velocity[2] = 1.0;
        sb_collider* ball = make_collider(&d);
        sb_solver_def sd = no_gravity(&ball, threads);
        sd.gravity[2] = -9.81;
        sb_solver* s = tu_solver(m, &sd);
        tu_advance(s, 1e-4, 300);
        double body[18];
        sb_collider_state(ball, body, body + 3);
        sb_collider_orientation(ball, body + 6, body + 15);
        uint64_t hash = tu_state_hash(s);
        print_message("%d thread(s): ball z %.17g, ω (%.17g, %.17g, %.17g), hash %016llx\n", threads, body[2], body[15],
                      body[16], body[17], (unsigned long long)hash);
        assert_true(fabs(body[15]) + fabs(body[17]) > 0.0 && body[16] != 4.0); /* the sheet changed its spin */
        if (threads == 1) {
            first_hash = hash;
            memcpy(first, body, sizeof first);
        } else {
            assert_true(hash == first_hash);
            assert_memory_equal(body, first, sizeof first);
        }
        sb_solver_destroy(s);
        sb_collider_destroy(ball);
    }
    sb_model_destroy(m);
}

/* ---- the scene key -------------------------------------------------------------- */

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_dynamic_rotation");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

/* angular_velocity is read with a mass (the run starts and the log has the
 * ball's force), unknown without one and to a plane. */
static void test_scene_angular_velocity(void** state) {
    (void)state;
    const char* cases[3][2] = {
        {"  - {type: sphere, center: [0, 0, -0.2], radius: 0.1, mass: 1, angular_velocity: [0, 0, 3]}\n", NULL},
        {"  - {type: sphere, center: [0, 0, -0.2], radius: 0.1, angular_velocity: [0, 0, 3]}\n",
         "softbond: spin.yaml:3: unknown key 'colliders[0].angular_velocity'\n"},
        {"  - {type: plane, angular_velocity: [0, 0, 3]}\n", "softbond: spin.yaml:3: unknown key "
                                                             "'colliders[0].angular_velocity'\n"},
    };
    for (int c = 0; c < 3; c++) {
        char text[400];
        snprintf(text, sizeof text, "mesh: {nx: 4, ny: 3}\ncolliders:\n%sduration: 0.001\n", cases[c][0]);
        tu_write_file("spin.yaml", text);
        tu_result r = tu_run((const char*[]){"run", "spin.yaml", "--output", "spin_out", NULL});
        if (cases[c][1]) {
            assert_int_equal(r.code, 2);
            assert_string_equal(r.err, cases[c][1]);
        } else if (r.code != 0) {
            fail_msg("exit %d: %s", r.code, r.err);
        }
        tu_result_free(&r);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_angular_momentum_balance),    cmocka_unit_test(test_friction_spins_a_ball_hit_off_center),
        cmocka_unit_test(test_free_bodies_keep_their_spin), cmocka_unit_test(test_spinning_ball_is_deterministic),
        cmocka_unit_test(test_scene_angular_velocity),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
