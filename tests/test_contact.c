/* Contact: restitution, Coulomb friction, resting contact for every
 * integrator, reaction forces, a program's own collider, determinism. */
#include "test_util.h"

#define G 9.81

/* `count` free point masses of 0.01 kg (no elements) at `height` above the
 * origin, 0.1 m apart along x, moving sideways at vy. */
static sb_model* points_model(uint32_t count, double height, double vy) {
    sb_builder* b = sb_builder_create();
    for (uint32_t i = 0; i < count; i++) {
        sb_vertex_def v = sb_default_vertex_def();
        v.position[0] = 0.1 * i;
        v.position[2] = height;
        v.mass = 0.01;
        v.velocity[1] = vy;
        sb_builder_add_vertex(b, &v);
    }
    sb_error err;
    sb_model* m = sb_builder_compile(b, &err);
    sb_builder_destroy(b);
    if (!m) fail_msg("%s", err.message);
    return m;
}

static sb_collider* floor_plane(double restitution, double friction, double thickness, const double normal[3]) {
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_PLANE;
    def.name = "floor";
    memcpy(def.normal, normal, sizeof def.normal);
    def.restitution = restitution;
    def.friction = def.static_friction = friction;
    def.thickness = thickness;
    sb_error err;
    sb_collider* c = sb_collider_create(&def, &err);
    if (!c) fail_msg("%s", err.message);
    return c;
}

static const double up[3] = {0, 0, 1};

static sb_solver_def contact_def(sb_collider** colliders, uint32_t count, sb_integrator integrator) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.gravity[2] = -G;
    def.colliders = colliders;
    def.collider_count = count;
    def.runtime.threads = 1;
    return def;
}

/* The highest point after the first bounce of a mass dropped from 1 m:
 * e² h, within 1 % of h, for e = 0, 0.5, 0.9, with both kernel choices. */
static void test_restitution_rebound_height(void** state) {
    (void)state;
    const double restitution[3] = {0.0, 0.5, 0.9}, h = 1.0, dt = 1e-4;
    sb_model* m = points_model(1, h, 0.0);
    for (int kernels = 0; kernels < 2; kernels++)
        for (int r = 0; r < 3; r++) {
            sb_collider* plane = floor_plane(restitution[r], 0.0, 0.0, up);
            sb_solver_def def = contact_def(&plane, 1, SB_INTEGRATOR_VERLET);
            def.kernels = kernels ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
            sb_solver* s = tu_solver(m, &def);
            double x[3], v[3], peak = 0.0, lowest = h;
            bool bounced = false;
            for (int step = 0; step < 15000; step++) { /* 1.5 s: the fall takes 0.45 s, the rise as long */
                tu_advance(s, dt, 1);
                sb_solver_get_positions(s, x);
                sb_solver_get_velocities(s, v);
                lowest = fmin(lowest, x[2]);
                if (sb_solver_last_step(s).contacts > 0) bounced = true;
                if (bounced && sb_solver_last_step(s).contacts == 0) peak = fmax(peak, x[2]);
                if (bounced && v[2] < 0 && x[2] < peak - 1e-3) break; /* falling again */
            }
            double want = restitution[r] * restitution[r] * h;
            print_message("e = %.1f (%s): rebound %.5f m, e²h = %.5f m, lowest %.2g m\n", restitution[r],
                          kernels ? "fast" : "reference", peak, want, lowest);
            assert_true(bounced);
            TU_ASSERT_LE(fabs(peak - want), 0.01 * h);
            TU_ASSERT_LE(-lowest, 1e-6); /* never below the plane */
            sb_solver_destroy(s);
            sb_collider_destroy(plane);
        }
    sb_model_destroy(m);
}

/* A 6 x 6 cloth (0.1 m, stiff bonds) lying on an incline of θ, μ = 0.5:
 * it sticks for tan θ < μ and slides with g (sin θ − μ cos θ) otherwise
 * (distance after 0.5 s within 2 %). */
static void test_friction_on_an_incline(void** state) {
    (void)state;
    const double mu = 0.5, degrees[2] = {20.0, 40.0}, T = 0.5, dt = 1e-4;
    for (int d = 0; d < 2; d++) {
        double th = degrees[d] * M_PI / 180.0;
        double normal[3] = {-sin(th), 0.0, cos(th)}, slope[3] = {cos(th), 0.0, sin(th)}; /* slope points uphill */
        sb_sheet_def sheet = sb_default_sheet_def();
        sheet.nx = sheet.ny = 6;
        sheet.width = sheet.height = 0.1;
        sb_mesh mesh = {0};
        sb_error err;
        assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
        for (uint32_t i = 0; i < mesh.vertex_count; i++) { /* lay it on the incline: x along the slope */
            double* p = mesh.positions + 3 * i;
            double along = p[0], y = p[1];
            p[0] = along * slope[0];
            p[1] = y;
            p[2] = along * slope[2];
        }
        sb_material_def material = sb_default_material_def();
        material.bond_k = 500.0;
        sb_model* m = tu_mesh_model(&mesh, &material);
        sb_collider* plane = floor_plane(0.0, mu, 0.0, normal);
        sb_solver_def def = contact_def(&plane, 1, SB_INTEGRATOR_VERLET);
        sb_solver* s = tu_solver(m, &def);
        uint32_t n = mesh.vertex_count;
        double* x0 = tu_rest_positions(m);
        double* x = malloc(3 * n * sizeof *x);
        tu_advance(s, dt, (uint64_t)(T / dt));
        sb_solver_get_positions(s, x);
        double moved = 0.0; /* mean displacement along the slope, downhill positive */
        for (uint32_t i = 0; i < n; i++)
            for (int k = 0; k < 3; k++) moved -= (x[3 * i + k] - x0[3 * i + k]) * slope[k] / n;
        double a = G * (sin(th) - mu * cos(th)), want = a > 0 ? 0.5 * a * T * T : 0.0;
        print_message("incline %.0f°: moved %.6f m downhill, Coulomb %.6f m\n", degrees[d], moved, want);
        if (want == 0.0)
            TU_ASSERT_LE(fabs(moved), 1e-5);
        else
            TU_ASSERT_LE(fabs(moved - want), 0.02 * want);
        free(x);
        free(x0);
        sb_solver_destroy(s);
        sb_collider_destroy(plane);
        sb_model_destroy(m);
        sb_mesh_free(&mesh);
    }
}

/* A soft icosphere dropped on a plane of thickness 5 mm, every integrator,
 * both kernels: after every step no vertex is below the inflated surface
 * (z >= 5 mm less float rounding); with drag it comes to rest on it. */
static void test_resting_contact_every_integrator(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_icosphere(1, 0.1, &mesh, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) mesh.positions[3 * i + 2] += 0.12;
    sb_material_def material = sb_default_material_def();
    material.bond_k = 200.0;
    material.angle_k = 0.5;
    sb_model* m = tu_mesh_model(&mesh, &material);
    uint32_t n = mesh.vertex_count;
    double* x = malloc(3 * n * sizeof *x);
    const double thickness = 0.005;
    for (int i = 0; i < SB_INTEGRATOR_COUNT; i++)
        for (int kernels = 0; kernels < 2; kernels++) {
            sb_collider* plane = floor_plane(0.0, 0.3, thickness, up);
            sb_solver_def def = contact_def(&plane, 1, (sb_integrator)i);
            def.kernels = kernels ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
            def.drag = 5.0;
            def.implicit_cg_iterations = 50;
            sb_solver* s = tu_solver(m, &def);
            double lowest = INFINITY;
            uint32_t contacts = 0;
            /* explicit Euler gains energy on any oscillation: a quarter of the step keeps it from blowing
             * up within the run, but it does not settle (its own flaw, not the contact's); the backward
             * Euler ones take steps five times longer, as they are meant to (a step of theirs is a
             * solve, 20 to 100 times the work of an explicit one) */
            bool backward = i == SB_INTEGRATOR_IMPLICIT_EULER || i == SB_INTEGRATOR_VBD;
            double dt = i == SB_INTEGRATOR_EXPLICIT_EULER ? 5e-5 : backward ? 1e-3 : 2e-4;
            for (int step = 0; step < lround(1.2 / dt); step++) { /* 1.2 s */
                tu_advance(s, dt, 1);
                contacts += sb_solver_last_step(s).contacts;
                sb_solver_get_positions(s, x);
                for (uint32_t v = 0; v < n; v++) lowest = fmin(lowest, x[3 * v + 2]);
            }
            sb_energies e = sb_solver_energies(s);
            print_message("%s (%s): %u contacts, lowest z %.6f m, kinetic %.3g J\n",
                          sb_integrator_name((sb_integrator)i), kernels ? "fast" : "reference", contacts, lowest,
                          e.kinetic);
            assert_true(contacts > 0);
            TU_ASSERT_LE(thickness - lowest, 1e-6);
            if (i != SB_INTEGRATOR_EXPLICIT_EULER) TU_ASSERT_LE(e.kinetic, 1e-4);
            sb_solver_destroy(s);
            sb_collider_destroy(plane);
        }
    free(x);
    sb_model_destroy(m);
    sb_mesh_free(&mesh);
}

/* Point masses at rest on the floor: the floor's reaction force is their
 * weight (within 0.1 %), pointing down into the floor. */
static void test_reaction_force_is_the_weight(void** state) {
    (void)state;
    sb_model* m = points_model(10, 0.01, 0.0);
    sb_collider* plane = floor_plane(0.0, 0.0, 0.0, up);
    sb_solver_def def = contact_def(&plane, 1, SB_INTEGRATOR_VELOCITY_VERLET);
    def.kernels = SB_KERNELS_FAST;
    sb_solver* s = tu_solver(m, &def);
    tu_advance(s, 1e-4, 3000); /* fallen and at rest */
    double force[3], sum[3] = {0, 0, 0};
    for (int step = 0; step < 1000; step++) {
        tu_advance(s, 1e-4, 1);
        sb_solver_contact_force(s, 0, force);
        for (int k = 0; k < 3; k++) sum[k] += force[k] / 1000;
    }
    double weight = 10 * 0.01 * G;
    print_message("mean reaction (%.6f, %.6f, %.6f) N, weight %.6f N\n", sum[0], sum[1], sum[2], weight);
    TU_ASSERT_LE(fabs(sum[2] + weight), 1e-3 * weight);
    TU_ASSERT_LE(fabs(sum[0]) + fabs(sum[1]), 1e-9);
    sb_solver_contact_force(s, 1, force); /* no such collider */
    assert_true(force[0] == 0 && force[1] == 0 && force[2] == 0);
    sb_solver_destroy(s);
    sb_collider_destroy(plane);
    sb_model_destroy(m);
}

/* A program's own collider: the plane z = 0 as a callback. */
static bool own_plane(void* user, const sb_contact_query* q, sb_contact* c) {
    int* calls = user;
    (*calls)++;
    double to = q->to[2] - q->thickness, from = q->from[2] - q->thickness;
    if (to >= 0.0) return false;
    *c = (sb_contact){.normal = {0, 0, 1}, .restitution = 0.5, .friction = 0.2, .static_friction = 0.2};
    if (from > 0.0)
        c->fraction = from / (from - to);
    else {
        c->fraction = 1.0;
        c->depth = -to;
    }
    return true;
}

/* It is answered exactly as the built-in plane with the same constants. */
static void test_own_collider_matches_the_builtin(void** state) {
    (void)state;
    sb_model* m = points_model(5, 0.3, 0.5); /* sliding: friction acts */
    int calls = 0;
    sb_error err;
    sb_collider* own = sb_collider_create_custom("own", own_plane, NULL, &calls, &err);
    assert_non_null(own);
    assert_string_equal(sb_collider_name(own), "own");
    sb_collider_def def = sb_default_collider_def();
    def.restitution = 0.5;
    def.friction = def.static_friction = 0.2;
    sb_collider* builtin = sb_collider_create(&def, &err);
    assert_non_null(builtin);
    uint64_t hash[2];
    sb_collider* which[2] = {own, builtin};
    for (int k = 0; k < 2; k++) {
        sb_solver_def sd = contact_def(&which[k], 1, SB_INTEGRATOR_VERLET);
        sd.contact_thickness = 0.001;
        sb_solver* s = tu_solver(m, &sd);
        tu_advance(s, 1e-4, 5000);
        hash[k] = tu_state_hash(s);
        sb_solver_destroy(s);
    }
    assert_true(calls > 0);
    assert_true(hash[0] == hash[1]);
    sb_collider_destroy(own);
    sb_collider_destroy(builtin);
    sb_model_destroy(m);
}

/* The icosphere on the plane with friction: 1, 2 and 3 threads give bitwise
 * the same state and the same reaction force. */
static void test_contact_is_deterministic(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_icosphere(3, 0.1, &mesh, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) mesh.positions[3 * i + 2] += 0.11;
    sb_material_def material = sb_default_material_def();
    material.bond_k = 200.0;
    sb_model* m = tu_mesh_model(&mesh, &material);
    uint64_t first = 0;
    double first_force[3] = {0, 0, 0};
    for (int threads = 1; threads <= 3; threads++) {
        sb_collider* plane = floor_plane(0.3, 0.4, 0.001, up);
        sb_solver_def def = contact_def(&plane, 1, SB_INTEGRATOR_VERLET);
        def.kernels = SB_KERNELS_FAST;
        def.runtime.threads = threads;
        sb_solver* s = tu_solver(m, &def);
        tu_advance(s, 1e-4, 2000);
        double force[3];
        sb_solver_contact_force(s, 0, force);
        uint64_t h = tu_state_hash(s);
        if (threads == 1) {
            first = h;
            memcpy(first_force, force, sizeof force);
            assert_true(sb_solver_last_step(s).contacts > 0 || force[2] != 0.0);
        } else {
            assert_true(h == first);
            assert_memory_equal(force, first_force, sizeof force);
        }
        sb_solver_destroy(s);
        sb_collider_destroy(plane);
    }
    sb_model_destroy(m);
    sb_mesh_free(&mesh);
}

/* A sheet of `side` x `side` vertices, 1 m wide, centred on the origin at
 * height z, bond and angle terms, moving at vz; pinned on its border when
 * `pinned`. */
static sb_model* sheet_model(uint32_t side, double z, double vz, bool pinned) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = side;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) {
        mesh.positions[3 * i] -= 0.5;
        mesh.positions[3 * i + 1] -= 0.5;
        mesh.positions[3 * i + 2] = z;
    }
    sb_material_def material = sb_default_material_def();
    material.bond_k = 500.0;
    material.angle_k = 0.1;
    sb_builder* b = sb_builder_create();
    assert_int_equal(sb_builder_add_mesh(b, &mesh, &material, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) {
        uint32_t ix = i % side, iy = i / side;
        sb_vertex_def* v = sb_builder_vertex(b, i);
        v->velocity[2] = vz;
        v->fixed = pinned && (ix == 0 || iy == 0 || ix == side - 1 || iy == side - 1);
    }
    sb_model* m = sb_builder_compile(b, &err);
    sb_builder_destroy(b);
    sb_mesh_free(&mesh);
    if (!m) fail_msg("%s", err.message);
    return m;
}

/* The sheet of a test below, falling onto a capsule of radius r along x,
 * its axis at height z and sideways offset y, for 30 steps of 1 ms with
 * either kernel choice: the vertex-steps inside the capsule, and those over
 * it (within its radius of the axis sideways) a step before that are under
 * it a step later. */
typedef struct capsule_drop {
    uint32_t stopped, inside, through;
} capsule_drop;

static capsule_drop drop_on_capsule(sb_model* m, double r, double y, double z, sb_kernels kernels) {
    uint32_t n = sb_model_vertex_count(m);
    double *x = malloc(3 * (size_t)n * sizeof *x), *before = malloc(3 * (size_t)n * sizeof *before);
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_CAPSULE;
    def.a[0] = -0.3, def.b[0] = 0.3;
    def.a[1] = def.b[1] = y;
    def.a[2] = def.b[2] = z;
    def.radius = r;
    sb_error err;
    sb_collider* capsule = sb_collider_create(&def, &err);
    assert_non_null(capsule);
    sb_solver_def sd = contact_def(&capsule, 1, SB_INTEGRATOR_VERLET);
    sd.kernels = kernels;
    sb_solver* s = tu_solver(m, &sd);
    capsule_drop out = {0, 0, 0};
    sb_solver_get_positions(s, before);
    for (int step = 0; step < 30; step++) {
        tu_advance(s, 1e-3, 1);
        out.stopped += sb_solver_last_step(s).contacts;
        sb_solver_get_positions(s, x);
        for (uint32_t i = 0; i < n; i++) {
            double p[3] = {x[3 * i], x[3 * i + 1] - y, x[3 * i + 2] - z};
            double q[3] = {before[3 * i], before[3 * i + 1] - y, before[3 * i + 2] - z};
            bool over_it = fabs(p[0]) < 0.3 && fabs(p[1]) < r && fabs(q[1]) < r;
            out.inside += fabs(p[0]) < 0.3 && p[1] * p[1] + p[2] * p[2] < (r - 1e-6) * (r - 1e-6);
            out.through += over_it && q[2] > 0.0 && p[2] < 0.0;
        }
        memcpy(before, x, 3 * (size_t)n * sizeof *x);
    }
    sb_solver_destroy(s);
    sb_collider_destroy(capsule);
    free(x);
    free(before);
    return out;
}

/* A sheet falling at 20 m/s onto a capsule of radius 5 mm (a needle, a hook)
 * at 1 ms steps, each twice as long as the capsule is thick, never passes
 * it (the swept test; an end-point test would miss it): no vertex is ever
 * inside the capsule, and none that was over it is under it a step later,
 * with either kernel choice, for 16 places of the capsule under the sheet
 * (a grid of 0.41 mm sideways by 0.7 mm in height, the vertices 25 mm
 * apart: each a different wrapping of the sheet). The sheet may wrap round
 * the capsule and slide off it sideways; it may not go through. */
static void test_fast_sheet_does_not_pass_a_capsule(void** state) {
    (void)state;
    sb_model* m = sheet_model(41, 0.05, -20.0, false);
    for (int place = 0; place < 16; place++)
        for (int fast = 0; fast < 2; fast++) {
            double y = (place % 8) * 0.41e-3, z = (place / 8) * 0.7e-3;
            capsule_drop d = drop_on_capsule(m, 0.005, y, z, fast ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE);
            if (place == 0 || d.inside || d.through)
                print_message("capsule at y %.2f mm z %.1f mm, %s: %u contacts, %u vertex-steps inside, %u through\n",
                              1e3 * y, 1e3 * z, fast ? "fast" : "reference", d.stopped, d.inside, d.through);
            assert_true(d.stopped > 0);
            assert_int_equal(d.inside, 0);
            assert_int_equal(d.through, 0);
        }
    sb_model_destroy(m);
}

/* A sphere of radius 5 cm thrown at 20 m/s (a keyframed path) through a
 * sheet pinned on its border: the vertices in its way are swept ahead of it
 * (none is ever behind its centre within 3 cm of its axis). */
static void test_thrown_sphere_does_not_pass_a_sheet(void** state) {
    (void)state;
    sb_model* m = sheet_model(41, 0.0, 0.0, true);
    uint32_t n = sb_model_vertex_count(m);
    double* x = malloc(3 * (size_t)n * sizeof *x);
    sb_keyframe path[2] = {{.time = 0.0, .translate = {0, 0, 0}}, {.time = 0.01, .translate = {0, 0, -0.2}}};
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_SPHERE;
    def.center[2] = 0.1; /* from 10 cm above the sheet to 10 cm below it in 10 ms */
    def.radius = 0.05;
    def.path = path;
    def.path_count = 2;
    sb_error err;
    sb_collider* ball = sb_collider_create(&def, &err);
    assert_non_null(ball);
    sb_solver_def sd = contact_def(&ball, 1, SB_INTEGRATOR_VERLET);
    sd.gravity[2] = 0.0;
    sb_solver* s = tu_solver(m, &sd);
    uint32_t behind = 0;
    double lowest = 0.0;
    for (int step = 1; step <= 100; step++) {
        tu_advance(s, 1e-4, 1);
        double cz = 0.1 - 20.0 * 1e-4 * step; /* the ball's centre */
        sb_solver_get_positions(s, x);
        for (uint32_t i = 0; i < n; i++) {
            const double* p = x + 3 * i;
            behind += p[0] * p[0] + p[1] * p[1] < 0.03 * 0.03 && p[2] > cz;
            lowest = fmin(lowest, p[2]);
        }
    }
    print_message("lowest vertex %.4f m, %u vertex-steps behind the ball's centre\n", lowest, behind);
    assert_int_equal(behind, 0);
    TU_ASSERT_LE(lowest, -0.1); /* the sheet went down with the ball */
    sb_solver_destroy(s);
    sb_collider_destroy(ball);
    free(x);
    sb_model_destroy(m);
}

/* A sphere driven by sb_collider_set_pose, 1 mm a step along +x, pushes a
 * point mass at rest ahead of it at its own speed (10 m/s) and never lets it
 * inside. */
static void test_driven_sphere_pushes(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    sb_vertex_def v = sb_default_vertex_def();
    v.position[0] = 0.06;
    v.mass = 0.01;
    sb_builder_add_vertex(b, &v);
    sb_error err;
    sb_model* m = sb_builder_compile(b, &err);
    sb_builder_destroy(b);
    assert_non_null(m);
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_SPHERE;
    def.radius = 0.05;
    sb_collider* ball = sb_collider_create(&def, &err);
    assert_non_null(ball);
    sb_solver_def sd = contact_def(&ball, 1, SB_INTEGRATOR_VERLET);
    sd.gravity[2] = 0.0;
    sb_solver* s = tu_solver(m, &sd);
    double x[3], vel[3];
    for (int step = 1; step <= 50; step++) {
        sb_collider_set_pose(ball, (double[3]){0.001 * step, 0, 0}, (double[3]){0, 0, 0});
        tu_advance(s, 1e-4, 1);
        sb_solver_get_positions(s, x);
        TU_ASSERT_LE(0.05 - (x[0] - 0.001 * step), 1e-7); /* outside the ball, up to float rounding */
    }
    sb_solver_get_velocities(s, vel);
    print_message("pushed to x = %.4f m at %.3f m/s\n", x[0], vel[0]);
    assert_true(x[0] > 0.09);
    TU_ASSERT_LE(fabs(vel[0] - 10.0), 1e-3);
    sb_solver_destroy(s);
    sb_collider_destroy(ball);
    sb_model_destroy(m);
}

/* ---- dynamic (two-way) colliders ----------------------------------------- */

/* A dynamic sphere of `mass` and `radius` with its center at `center`,
 * moving at `velocity`. */
static sb_collider* dynamic_ball(double mass, double radius, const double center[3], const double velocity[3],
                                 double friction) {
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_SPHERE;
    def.name = "ball";
    def.radius = radius;
    def.mass = mass;
    def.friction = friction;
    memcpy(def.center, center, sizeof def.center);
    memcpy(def.velocity, velocity, sizeof def.velocity);
    sb_error err;
    sb_collider* c = sb_collider_create(&def, &err);
    if (!c) fail_msg("%s", err.message);
    return c;
}

/* The throw of the momentum test: a 0.5 kg ball of radius 5 cm at 5 m/s
 * down onto a 41 x 41 sheet pinned on its border, no gravity, 20 ms at
 * 0.1 ms steps. Returns the sum of the impulses the ball received (the
 * reaction force times the step) and the lowest the sheet's center went. */
static void throw_ball(sb_collider* ball, sb_solver* s, uint32_t center, double received[3], double* sag) {
    uint32_t n = sb_model_vertex_count(sb_solver_model(s));
    double* x = malloc(3 * (size_t)n * sizeof *x);
    assert_non_null(x);
    memset(received, 0, 3 * sizeof *received);
    *sag = 0.0;
    for (int step = 0; step < 200; step++) {
        tu_advance(s, 1e-4, 1);
        double force[3];
        sb_solver_contact_force(s, 0, force);
        for (int k = 0; k < 3; k++) received[k] += force[k] * 1e-4;
        sb_solver_get_positions(s, x);
        *sag = fmin(*sag, x[3 * center + 2]);
    }
    (void)ball;
    free(x);
}

/* Two-way momentum: the ball's momentum changes by exactly the impulses it
 * received, the opposite of what the sheet's vertices took (to rounding),
 * with both kernel choices and with adaptive steps; the ball slows down and
 * the net sags along the throw. */
static void test_dynamic_ball_momentum_balance(void** state) {
    (void)state;
    const uint32_t side = 41, center = side * (side / 2) + side / 2;
    sb_model* m = sheet_model(side, 0.0, 0.0, true);
    for (int variant = 0; variant < 3; variant++) {
        sb_collider* ball = dynamic_ball(0.5, 0.05, (double[3]){0, 0, 0.06}, (double[3]){0, 0, -5.0}, 0.0);
        sb_solver_def sd = contact_def(&ball, 1, SB_INTEGRATOR_VERLET);
        sd.gravity[2] = 0.0;
        sd.kernels = variant == 1 ? SB_KERNELS_REFERENCE : SB_KERNELS_FAST;
        sd.adaptive = variant == 2;
        /* the push out of a vertex met inside the ball is not energy-exact: above double's rounding level */
        sd.adaptive_tolerance = 1e-5;
        sb_solver* s = tu_solver(m, &sd);
        double p0[3], v0[3], p1[3], v1[3], received[3], sag;
        sb_collider_state(ball, p0, v0);
        throw_ball(ball, s, center, received, &sag);
        sb_collider_state(ball, p1, v1);
        double error = 0.0, size = 0.0;
        for (int k = 0; k < 3; k++) {
            error = fmax(error, fabs(0.5 * (v1[k] - v0[k]) - received[k]));
            size = fmax(size, fabs(received[k]));
        }
        print_message("%s: ball %.4f -> %.4f m/s, at z %.4f m, impulse received %.6f N s, momentum error %.3g (%.3g "
                      "relative), sheet center down to %.4f m\n",
                      variant == 0   ? "fast"
                      : variant == 1 ? "reference"
                                     : "adaptive",
                      v0[2], v1[2], p1[2], received[2], error, error / size, sag);
        assert_true(size > 0.1);
        TU_ASSERT_LE(error, 1e-9 * size);
        assert_true(fabs(v1[2]) < fabs(v0[2])); /* slowed down */
        TU_ASSERT_LE(sag, -0.02);               /* the net sagged along the throw (−z) */
        sb_solver_destroy(s);
        sb_collider_destroy(ball);
    }
    sb_model_destroy(m);
}

/* A 50 g ball of radius 10 cm (friction 0.5) laid on a 21 x 21 sheet
 * pinned on its border at 0.3 m/s across it, under gravity with drag on
 * the sheet, for 3 s: it rests on the sheet (no vertex inside it, its
 * bottom in the dip it made, never through the net), and while it moves
 * across the dip friction makes it roll, not slide: its lowest point moves
 * at under a tenth of the ball's speed (summed over the times it moves
 * faster than 2 cm/s). */
static void test_dynamic_ball_rests_and_rolls_on_a_sheet(void** state) {
    (void)state;
    const uint32_t side = 21;
    const double radius = 0.1, dt = 1e-4;
    sb_model* m = sheet_model(side, 0.0, 0.0, true);
    uint32_t n = sb_model_vertex_count(m);
    double* x = malloc(3 * (size_t)n * sizeof *x);
    sb_collider* ball = dynamic_ball(0.05, radius, (double[3]){0, 0, radius + 0.01}, (double[3]){0.3, 0, 0}, 0.5);
    sb_solver_def sd = contact_def(&ball, 1, SB_INTEGRATOR_VERLET);
    sd.drag = 20.0;
    sb_solver* s = tu_solver(m, &sd);
    double p[3], v[3], rotation[9], w[3], deepest = 0.0, lowest = INFINITY, speeds = 0.0, slips = 0.0;
    for (int step = 0; step < 30000; step++) {
        tu_advance(s, dt, 1);
        if (step % 100 != 99) continue;
        sb_collider_state(ball, p, v);
        sb_collider_orientation(ball, rotation, w);
        sb_solver_get_positions(s, x);
        lowest = fmin(lowest, p[2] - radius);
        for (uint32_t i = 0; i < n; i++) {
            double d[3] = {x[3 * i] - p[0], x[3 * i + 1] - p[1], x[3 * i + 2] - p[2]};
            deepest = fmax(deepest, radius - sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        }
        /* its lowest point, (0, 0, −radius) from the center, moves at v + ω × (0, 0, −radius) */
        double speed = hypot(v[0], v[1]), slip = hypot(v[0] - radius * w[1], v[1] + radius * w[0]);
        if (speed < 0.02) continue;
        speeds += speed;
        slips += slip;
    }
    print_message("after 3 s: ball at (%.4f, %.4f, %.4f) m; while moving: mean slip / speed %.3g; deepest vertex %.3g "
                  "m inside; lowest bottom %.4f m\n",
                  p[0], p[1], p[2], slips / speeds, deepest, lowest);
    TU_ASSERT_LE(deepest, 1e-4);                       /* nothing inside it */
    assert_true(lowest < 0.0 && lowest > -0.5);        /* it sagged the net, stayed on it */
    assert_true(fabs(p[0]) < 0.4 && fabs(p[1]) < 0.4); /* within the pinned border */
    assert_true(speeds > 1.0);                         /* it moved (50 samples at 2 cm/s) */
    TU_ASSERT_LE(slips, 0.1 * speeds);                 /* it rolls */
    sb_solver_destroy(s);
    sb_collider_destroy(ball);
    free(x);
    sb_model_destroy(m);
}

/* The throw with 1 and 2 threads: bitwise the same ball and sheet. */
static void test_dynamic_ball_is_deterministic(void** state) {
    (void)state;
    const uint32_t side = 41, center = side * (side / 2) + side / 2;
    sb_model* m = sheet_model(side, 0.0, 0.0, true);
    uint64_t first_hash = 0;
    double first[6];
    for (int threads = 1; threads <= 2; threads++) {
        sb_collider* ball = dynamic_ball(0.5, 0.05, (double[3]){0, 0, 0.06}, (double[3]){0, 0, -5.0}, 0.0);
        sb_solver_def sd = contact_def(&ball, 1, SB_INTEGRATOR_VERLET);
        sd.gravity[2] = -G;
        sd.runtime.threads = threads;
        sb_solver* s = tu_solver(m, &sd);
        double received[3], sag, ball_state[6];
        throw_ball(ball, s, center, received, &sag);
        sb_collider_state(ball, ball_state, ball_state + 3);
        uint64_t h = tu_state_hash(s);
        print_message("%d thread(s): ball z %.17g, vz %.17g, hash %016llx\n", threads, ball_state[2], ball_state[5],
                      (unsigned long long)h);
        if (threads == 1) {
            first_hash = h;
            memcpy(first, ball_state, sizeof first);
        } else {
            assert_true(h == first_hash);
            assert_memory_equal(ball_state, first, sizeof first);
        }
        sb_solver_destroy(s);
        sb_collider_destroy(ball);
    }
    sb_model_destroy(m);
}

static void expect_refused(const sb_collider_def* def, const char* message) {
    sb_error err;
    memset(&err, 0, sizeof err);
    sb_collider* c = sb_collider_create(def, &err);
    if (c) sb_collider_destroy(c);
    assert_null(c);
    assert_string_equal(err.message, message);
}

/* mass < 0, a dynamic collider with a path, a dynamic plane or capsule: each
 * refused with its message. */
static void test_dynamic_collider_validation(void** state) {
    (void)state;
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_SPHERE;
    def.name = "ball";
    def.radius = 0.05;
    def.mass = -1.0;
    expect_refused(&def, "collider 'ball': mass must be >= 0 and finite (got -1)");
    def.mass = 0.5;
    sb_keyframe path[1] = {{.time = 0.0}};
    def.path = path;
    def.path_count = 1;
    expect_refused(&def, "collider 'ball': a dynamic collider (mass 0.5) cannot have a path");
    def.path = NULL;
    def.path_count = 0;
    def.velocity[0] = NAN;
    expect_refused(&def, "collider 'ball': velocity must be finite (got nan, 0, 0)");
    sb_collider_def plane = sb_default_collider_def();
    plane.name = "floor";
    plane.mass = 1.0;
    expect_refused(&plane, "collider 'floor': a plane cannot be dynamic (mass 1); only a sphere or box");
    sb_collider_def capsule = sb_default_collider_def();
    capsule.shape = SB_COLLIDER_CAPSULE;
    capsule.b[0] = 1.0;
    capsule.radius = 0.1;
    capsule.mass = 2.0;
    expect_refused(&capsule, "collider 'capsule': a capsule cannot be dynamic (mass 2); only a sphere or box");
    /* a dynamic box is accepted and reports its center and velocity */
    sb_collider_def box = sb_default_collider_def();
    box.shape = SB_COLLIDER_BOX;
    box.half_extents[0] = box.half_extents[1] = box.half_extents[2] = 0.1;
    box.center[2] = 1.0;
    box.mass = 1.0;
    box.velocity[0] = 2.0;
    sb_error err;
    sb_collider* c = sb_collider_create(&box, &err);
    assert_non_null(c);
    double p[3], v[3];
    sb_collider_state(c, p, v);
    assert_true(p[0] == 0.0 && p[1] == 0.0 && p[2] == 1.0 && v[0] == 2.0 && v[1] == 0.0 && v[2] == 0.0);
    sb_collider_destroy(c);
}

/* A dynamic box in free fall beside a sheet it never touches: symplectic
 * Euler under gravity, v = g t and z = z0 + g dt² n(n − 1)/2 after n steps. */
static void test_dynamic_box_falls(void** state) {
    (void)state;
    sb_model* m = points_model(1, 0.0, 0.0);
    sb_collider_def def = sb_default_collider_def();
    def.shape = SB_COLLIDER_BOX;
    def.half_extents[0] = def.half_extents[1] = def.half_extents[2] = 0.1;
    def.center[0] = 5.0;
    def.center[2] = 1.0;
    def.mass = 2.0;
    sb_error err;
    sb_collider* box = sb_collider_create(&def, &err);
    assert_non_null(box);
    sb_solver_def sd = contact_def(&box, 1, SB_INTEGRATOR_VERLET);
    sd.gravity[2] = -G;
    sb_solver* s = tu_solver(m, &sd);
    const double dt = 1e-3;
    const int steps = 100;
    tu_advance(s, dt, steps);
    double p[3], v[3];
    sb_collider_state(box, p, v);
    TU_ASSERT_NEAR(v[2], -G * dt * steps, 1e-12);
    TU_ASSERT_NEAR(p[2], 1.0 - G * dt * dt * steps * (steps - 1) / 2.0, 1e-12);
    sb_solver_destroy(s);
    sb_collider_destroy(box);
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_restitution_rebound_height),
        cmocka_unit_test(test_friction_on_an_incline),
        cmocka_unit_test(test_resting_contact_every_integrator),
        cmocka_unit_test(test_reaction_force_is_the_weight),
        cmocka_unit_test(test_own_collider_matches_the_builtin),
        cmocka_unit_test(test_contact_is_deterministic),
        cmocka_unit_test(test_fast_sheet_does_not_pass_a_capsule),
        cmocka_unit_test(test_thrown_sphere_does_not_pass_a_sheet),
        cmocka_unit_test(test_driven_sphere_pushes),
        cmocka_unit_test(test_dynamic_ball_momentum_balance),
        cmocka_unit_test(test_dynamic_ball_rests_and_rolls_on_a_sheet),
        cmocka_unit_test(test_dynamic_ball_is_deterministic),
        cmocka_unit_test(test_dynamic_collider_validation),
        cmocka_unit_test(test_dynamic_box_falls),
    };
    return TU_RUN_TESTS(tests);
}
