/* The solver (include/softbond/solver.h): both Verlet integrators are second
 * order, conserve energy without drift, bring a damped pinned sheet to rest,
 * integrate gravity and external forces exactly, take a new gravity between
 * steps, catch a blow-up and reject
 * bad time steps.
 *
 * The state is sb_real (float unless SB_DOUBLE), so every tolerance below is
 * chosen well above float rounding; the measured numbers are printed. */
#include "tests/test_util.h"

#include <stdio.h>
#include <stdlib.h>

static const sb_integrator integrators[2] = {SB_INTEGRATOR_VERLET, SB_INTEGRATOR_VELOCITY_VERLET};

static sb_solver* make_solver(const sb_model* m, sb_integrator integrator, double gz, sb_external_force_fn fn,
                              void* user) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.gravity[0] = def.gravity[1] = 0.0;
    def.gravity[2] = gz;
    def.kernels = SB_KERNELS_REFERENCE;
    def.runtime.threads = 0;
    def.external_force = fn;
    def.external_user = user;
    sb_error err;
    memset(&err, 0, sizeof err);
    sb_solver* s = sb_solver_create(m, &def, &err);
    if (!s) fail_msg("sb_solver_create failed: %s", err.message);
    return s;
}

/* ---- order of accuracy -------------------------------------------------------- */

/* Two masses m = 1 on a bond with k = 2π² (reduced mass ½, so ω = 2π, period
 * 1 s), stretched from 1 to 1.3 and released: the separation is exactly
 * r(t) = 1 + 0.3 cos(2π t). */
static double spring_error(sb_integrator integrator, double dt, double T) {
    sb_builder* b = sb_builder_create();
    tu_vertex(b, -0.65, 0, 0, 1.0, false);
    tu_vertex(b, 0.65, 0, 0, 1.0, false);
    tu_bond(b, 0, 1, 1.0, 2 * M_PI * M_PI, 0, 0);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    sb_solver* s = make_solver(m, integrator, 0.0, NULL, NULL);
    uint64_t n = (uint64_t)llround(T / dt);
    tu_advance(s, dt, n);
    assert_true(sb_solver_step_count(s) == n);
    TU_ASSERT_NEAR(sb_solver_time(s), T, 1e-9 * T);
    double x[6];
    sb_solver_get_positions(s, x);
    sb_solver_destroy(s);
    sb_model_destroy(m);
    for (int i = 0; i < 6; ++i)
        if (i != 0 && i != 3) assert_true(x[i] == 0.0); /* it stays on its axis */
    double exact = 1.0 + 0.3 * cos(2 * M_PI * T);
    return fabs((x[3] - x[0]) - exact);
}

/* T = 1.25 periods, where the trajectory crosses its rest length at full
 * speed, so a phase error shows up linearly in the position. dt = 1/20,
 * 1/40, 1/80 of the period: the Verlet phase error ωT(ωdt)²/24 is then
 * 1e-2..6e-4 m, orders of magnitude above float rounding (~1e-6 m over 100
 * steps), and the next term of the error is (ωdt)² ≈ 0.1 times smaller, so
 * a second-order method gives ratios within ±5 % of 4, a first-order one 2. */
static void test_order_spring(void** state) {
    (void)state;
    for (int k = 0; k < 2; ++k) {
        double dt = 0.05, T = 1.25, e[3];
        for (int i = 0; i < 3; ++i) e[i] = spring_error(integrators[k], dt / (1 << i), T);
        double r1 = e[0] / e[1], r2 = e[1] / e[2];
        print_message("order (two-mass spring, analytic), %s: errors %.4g %.4g %.4g m for dt = "
                      "%g, %g, %g s; ratios %.4f %.4f\n",
                      sb_integrator_name(integrators[k]), e[0], e[1], e[2], dt, dt / 2, dt / 4, r1, r2);
        if (!(r1 >= 3.5 && r1 <= 4.5 && r2 >= 3.5 && r2 <= 4.5))
            fail_msg("%s is not second order: error ratios %.4f, %.4f (expected 3.5..4.5)",
                     sb_integrator_name(integrators[k]), r1, r2);
    }
}

/* A triangle of three unequal masses with bond, angle and stretch-bend
 * terms, moving in 3D from a perturbed state: no analytic solution, so the
 * error is measured against a run with dt/256. The reference is a velocity
 * Verlet run for both integrators: the two are the same method in exact
 * arithmetic, and the position form loses precision in float at tiny steps
 * (test_verlet_small_step_precision below). */
static sb_model* triangle_model(void) {
    sb_builder* b = sb_builder_create();
    tu_vertex(b, -0.4, -0.3, 0, 1.0, false);
    tu_vertex(b, 0.6, -0.3, 0, 1.5, false);
    tu_vertex(b, -0.1, 0.5, 0, 0.8, false);
    tu_bond(b, 0, 1, -1, 30.0, 0, 0);
    tu_bond(b, 1, 2, -1, 30.0, 0, 0);
    tu_bond(b, 2, 0, -1, 30.0, 0, 0);
    tu_triangle(b, 0, 1, 2, 2.0, 1.0);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

static void triangle_run(const sb_model* m, sb_integrator integrator, double dt, double T, double out[9]) {
    sb_solver* s = make_solver(m, integrator, 0.0, NULL, NULL);
    /* Perturbed and spinning: every term and all three dimensions act. */
    double x[9] = {-0.45, -0.3, 0.05, 0.7, -0.28, -0.02, -0.1, 0.55, 0.0};
    double v[9] = {0.0, 0.1, 0.3, 0.0, 0.0, -0.2, -0.2, 0.1, 0.0};
    assert_int_equal(sb_solver_set_state(s, x, v), SB_OK);
    tu_advance(s, dt, (uint64_t)llround(T / dt));
    sb_solver_get_positions(s, out);
    sb_solver_destroy(s);
}

static double max_diff(const double* a, const double* b, int n) {
    double d = 0;
    for (int i = 0; i < n; ++i) d = fmax(d, fabs(a[i] - b[i]));
    return d;
}

static void test_order_triangle(void** state) {
    (void)state;
    sb_model* m = triangle_model();
    /* Fastest mode ω ≈ √(3·30/0.6) ≈ 12 rad/s: dt = 0.04 s is ωdt ≈ 0.5,
     * errors ~1e-2..1e-3 m at T = 1 s; the reference (dt/256) is 65536 times
     * more accurate in exact arithmetic. */
    double dt = 0.04, T = 1.0;
    for (int k = 0; k < 2; ++k) {
        double ref[9], x[3][9], e[3];
        triangle_run(m, SB_INTEGRATOR_VELOCITY_VERLET, dt / 256, T, ref);
        for (int i = 0; i < 3; ++i) {
            triangle_run(m, integrators[k], dt / (1 << i), T, x[i]);
            e[i] = max_diff(x[i], ref, 9);
        }
        double r1 = e[0] / e[1], r2 = e[1] / e[2];
        print_message("order (triangle, bonds+angles+stretch-bend, vs dt/256), %s: errors %.4g "
                      "%.4g %.4g m; ratios %.4f %.4f\n",
                      sb_integrator_name(integrators[k]), e[0], e[1], e[2], r1, r2);
        if (!(r1 >= 3.5 && r1 <= 4.5 && r2 >= 3.5 && r2 <= 4.5))
            fail_msg("%s is not second order on the triangle: ratios %.4f, %.4f", sb_integrator_name(integrators[k]),
                     r1, r2);
    }
    sb_model_destroy(m);
}

/* ---- energy conservation ------------------------------------------------------ */

/* An nx × ny sheet with spacing h, origin at (x0, y0), in the z = 0 plane
 * (or, when vertical, in the y = 0 plane hanging down: row r at z = −h r):
 * a bond along every edge (right, up and the up-right diagonal of each
 * quad), triangles (a,b,c) and (a,c,d) per quad. */
typedef struct sheet_consts {
    double bond_k, spring_k, damping, angle_k, sb_k, mass;
} sheet_consts;

static sb_model* sheet_model(int nx, int ny, double h, double x0, double y0, sheet_consts c, const int* fixed,
                             int nfixed, bool vertical) {
    sb_builder* b = sb_builder_create();
    for (int r = 0; r < ny; ++r)
        for (int col = 0; col < nx; ++col) {
            if (vertical)
                tu_vertex(b, x0 + h * col, 0, y0 - h * r, c.mass, false);
            else
                tu_vertex(b, x0 + h * col, y0 + h * r, 0, c.mass, false);
        }
    for (int f = 0; f < nfixed; ++f) sb_builder_vertex(b, (uint32_t)fixed[f])->fixed = true;
    for (int r = 0; r < ny; ++r)
        for (int col = 0; col < nx; ++col) {
            uint32_t a = (uint32_t)(r * nx + col);
            if (col + 1 < nx) tu_bond(b, a, a + 1, -1, c.bond_k, c.spring_k, c.damping);
            if (r + 1 < ny) tu_bond(b, a, a + nx, -1, c.bond_k, c.spring_k, c.damping);
            if (col + 1 < nx && r + 1 < ny) tu_bond(b, a, a + nx + 1, -1, c.bond_k, c.spring_k, c.damping);
        }
    for (int r = 0; r + 1 < ny; ++r)
        for (int col = 0; col + 1 < nx; ++col) {
            uint32_t a = (uint32_t)(r * nx + col), bb = a + 1, cc = a + nx + 1, d = a + nx;
            tu_triangle(b, a, bb, cc, c.angle_k, c.sb_k);
            tu_triangle(b, a, cc, d, c.angle_k, c.sb_k);
        }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

static void test_energy_conservation(void** state) {
    (void)state;
    enum { NX = 5, NY = 5, N = NX * NY, STEPS = 100000 };
    const sheet_consts c = {100.0, 0.0, 0.0, 0.2, 0.5, 0.04};
    sb_model* m = sheet_model(NX, NY, 0.25, -0.5, -0.5, c, NULL, 0, false);
    /* The fastest mode: Gershgorin gives ω² ≤ 2 Σk / m over the six bonds of
     * an interior vertex; the angle (kθ/L² ≈ 3 N/m) and stretch-bend
     * (ksb/L ≈ 2 N/m) stiffnesses add a few percent, covered by 1.2×. */
    double omega_max = 1.2 * sqrt(2.0 * 6 * c.bond_k / c.mass);
    double dt = 2 * M_PI / omega_max / 100; /* 100 steps per fastest period */
    /* Verlet conserves a shadow energy; the computed energy oscillates
     * around it with relative amplitude (ω dt)²/4 in a mode of frequency ω,
     * here at most (2π/100)²/4 ≈ 1e-3 for the fastest mode and less for the
     * rest, with no secular drift (symplectic). Float rounding adds a random
     * walk of ~ε·√STEPS ≈ 4e-5. So: bound 1e-3 on the deviation and on the
     * drift of the mean. */
    const double bound = 1e-3;
    tu_rng r = {2024};
    double x[3 * N];
    for (int v = 0; v < N; ++v) {
        double p[3];
        sb_model_rest_position(m, (uint32_t)v, p);
        for (int d = 0; d < 3; ++d) x[3 * v + d] = p[d] + tu_uniform(&r, -0.02, 0.02);
    }
    int failed = 0;
    for (int k = 0; k < 2; ++k) {
        sb_solver* s = make_solver(m, integrators[k], 0.0, NULL, NULL);
        assert_int_equal(sb_solver_set_state(s, x, NULL), SB_OK);
        sb_energies en = sb_solver_energies(s);
        double e0 = sb_energies_total(&en);
        assert_true(e0 > 0);
        TU_ASSERT_NEAR(en.kinetic, 0.0, 1e-12 * e0);
        TU_ASSERT_NEAR(en.gravity, 0.0, 1e-12 * e0);
        double max_dev = 0, first = 0, last = 0;
        const int tenth = STEPS / 10;
        for (int i = 1; i <= STEPS; ++i) {
            sb_status st = sb_solver_advance(s, dt);
            if (st != SB_OK) fail_msg("step %d: %s", i, sb_solver_error(s));
            en = sb_solver_energies(s);
            double e = sb_energies_total(&en);
            max_dev = fmax(max_dev, fabs(e - e0) / e0);
            if (i <= tenth) first += e / tenth;
            if (i > STEPS - tenth) last += e / tenth;
        }
        double drift = fabs(last - first) / e0;
        print_message("energy (5x5 sheet, %d steps, dt = %.3g s = T_min/100), %s: E0 = %.6g J, "
                      "max |E - E0|/E0 = %.3g, drift of the mean (last vs first 10%%) = %.3g, "
                      "bound %.0e\n",
                      STEPS, dt, sb_integrator_name(integrators[k]), e0, max_dev, drift, bound);
        if (!(max_dev <= bound && drift <= bound)) failed |= 1 << k;
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
    /* Both integrators run before failing, so both numbers are printed. */
    for (int k = 0; k < 2; ++k)
        if (failed & (1 << k))
            fail_msg("%s: total energy left the bound %.0e (see the numbers above)", sb_integrator_name(integrators[k]),
                     bound);
}

/* ---- a damped sheet pinned at two corners comes to rest ------------------------ *
 * The sheet starts vertical, in the y = 0 plane, pinned at its two top
 * corners, and sags under gravity. Why not horizontal: the only damping is
 * along the bonds (Eq. 2), and a horizontal sheet falls into a swing about
 * the axis through its two pins, a nearly rigid motion that changes no bond
 * length and so is hardly damped (measured: kinetic energy still ~1e-3 J of
 * a 5 J potential drop after 600 s, beating between modes). Started in
 * the plane of the pins and gravity, the motion stays in that plane
 * (every force has y = 0) and every in-plane motion of a triangulated
 * sheet pinned at two points stretches bonds, so all of it is damped. */
static void test_pinned_sheet_comes_to_rest(void** state) {
    (void)state;
    enum { NX = 5, NY = 5, N = NX * NY };
    /* Corners (0,0,0) and (1,0,0): coordinates exact in float, so "did not
     * move" can be checked bitwise. */
    const int pins[2] = {0, NX - 1};
    const sheet_consts c = {0.0, 100.0, 1.0, 0.0, 0.0, 0.04};
    sb_model* m = sheet_model(NX, NY, 0.25, 0.0, 0.0, c, pins, 2, true);
    double rest[3 * N], mean_z0 = 0;
    for (int v = 0; v < N; ++v) {
        sb_model_rest_position(m, (uint32_t)v, rest + 3 * v);
        mean_z0 += rest[3 * v + 2] / N;
    }
    const double dt = 1e-3; /* ω_max ≈ √(2·6·100/0.04) ≈ 173 rad/s: ωdt ≈ 0.17 */
    for (int k = 0; k < 2; ++k) {
        sb_solver* s = make_solver(m, integrators[k], -9.81, NULL, NULL);
        sb_energies en = sb_solver_energies(s);
        double u0 = sb_energies_internal(&en) + en.gravity;
        double ke = 0, drop = 0, x[3 * N], t_end = 0;
        /* Up to 60 s; stop early once far below the bound. */
        for (int second = 1; second <= 60; ++second) {
            tu_advance(s, dt, 1000);
            en = sb_solver_energies(s);
            ke = en.kinetic;
            drop = u0 - (sb_energies_internal(&en) + en.gravity);
            t_end = second;
            if (second >= 5 && ke < 1e-8 * drop) break;
        }
        sb_solver_get_positions(s, x);
        double mean_z = 0;
        for (int v = 0; v < N; ++v) mean_z += x[3 * v + 2] / N;
        print_message("pinned sheet, %s: after %.0f s kinetic %.3g J, potential drop %.4g J, "
                      "mean z %.4f m (start %.4f m)\n",
                      sb_integrator_name(integrators[k]), t_end, ke, drop, mean_z, mean_z0);
        assert_true(drop > 0);
        TU_ASSERT_LE(ke, 1e-6 * drop);
        for (int f = 0; f < 2; ++f)
            for (int d = 0; d < 3; ++d)
                if (x[3 * pins[f] + d] != rest[3 * pins[f] + d])
                    fail_msg("fixed vertex %d moved: coordinate %d is %.17g, rest %.17g", pins[f], d,
                             x[3 * pins[f] + d], rest[3 * pins[f] + d]);
        /* It hangs below its start, and stays in its plane. */
        TU_ASSERT_LE(mean_z, mean_z0 - 0.01);
        for (int v = 0; v < N; ++v) assert_true(x[3 * v + 1] == 0.0);
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

/* A horizontal sheet pinned at two corners settles too once the medium
 * around it has a little drag (−drag·m·v on every free vertex): the swing
 * about the pin axis that bond damping cannot reach is damped by it. */
static void test_horizontal_sheet_settles_with_drag(void** state) {
    (void)state;
    enum { NX = 5, NY = 5, N = NX * NY };
    const int pins[2] = {0, NX - 1};
    const sheet_consts c = {0.0, 100.0, 1.0, 0.0, 0.0, 0.04};
    sb_model* m = sheet_model(NX, NY, 0.25, 0.0, 0.0, c, pins, 2, false);
    for (int k = 0; k < 2; ++k) {
        sb_solver_def def = sb_default_solver_def();
        def.integrator = integrators[k];
        def.drag = 0.5;
        sb_error err;
        sb_solver* s = sb_solver_create(m, &def, &err);
        assert_non_null(s);
        sb_energies en = sb_solver_energies(s);
        double u0 = sb_energies_internal(&en) + en.gravity;
        tu_advance(s, 1e-3, 60000); /* 60 s: the drag time constant is 2 s */
        en = sb_solver_energies(s);
        double drop = u0 - (sb_energies_internal(&en) + en.gravity);
        print_message("horizontal pinned sheet with drag 0.5/s, %s: kinetic %.3g J after 60 s, potential drop %.4g J\n",
                      sb_integrator_name(integrators[k]), en.kinetic, drop);
        assert_true(drop > 0);
        TU_ASSERT_LE(en.kinetic, 1e-6 * drop);
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

/* ---- exact cases: gravity and an external force on a free particle ------------- */

/* Verlet integrates a constant acceleration exactly, so the only error is
 * rounding: a few ε of the state per step, bounded by 4·n·ε·|value|. A
 * first-order start or a lagging velocity would be off by ~g·dt/2. */
static void test_free_fall(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    tu_vertex(b, 0, 0, 0, 1.5, false);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    const double g = 9.81, dt = 0.01;
    const int n = 100;
    for (int k = 0; k < 2; ++k) {
        sb_solver* s = make_solver(m, integrators[k], -g, NULL, NULL);
        for (int i = 1; i <= n; ++i) {
            tu_advance(s, dt, 1);
            double t = i * dt, x[3], v[3];
            sb_solver_get_positions(s, x);
            sb_solver_get_velocities(s, v);
            double z = -0.5 * g * t * t, vz = -g * t;
            double tol = 4.0 * i * TU_REAL_EPS * 5.0; /* |z| ≤ 5 m, |vz| ≤ 10 m/s */
            if (!(fabs(x[2] - z) <= tol && fabs(v[2] - vz) <= 2 * tol))
                fail_msg("%s, step %d: z = %.9g (exact %.9g), vz = %.9g (exact %.9g), tol %.3g",
                         sb_integrator_name(integrators[k]), i, x[2], z, v[2], vz, tol);
            assert_true(x[0] == 0.0 && x[1] == 0.0 && v[0] == 0.0 && v[1] == 0.0);
        }
        TU_ASSERT_NEAR(sb_solver_time(s), n * dt, 1e-12);
        /* The energies see it: kinetic ½mv², gravity −m g·x = m g z, total 0. */
        sb_energies en = sb_solver_energies(s);
        double z = -0.5 * g, vz = -g;
        TU_ASSERT_NEAR(en.kinetic, 0.5 * 1.5 * vz * vz, 1e-4 * 0.5 * 1.5 * vz * vz);
        TU_ASSERT_NEAR(en.gravity, 1.5 * g * z, 1e-4 * 1.5 * g * fabs(z));
        TU_ASSERT_NEAR(sb_energies_total(&en), 0.0, 1e-4 * 1.5 * g * fabs(z));
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

/* The mean vertical velocity of a free 4 x 4 sheet of equal masses: its
 * centre of mass's, which only gravity changes (internal forces cancel). */
static double mean_vz(const sb_solver* s, uint32_t n) {
    double v[3 * 16], sum = 0.0;
    sb_solver_get_velocities(s, v);
    for (uint32_t i = 0; i < n; i++) sum += v[3 * i + 2];
    return sum / n;
}

/* sb_solver_set_gravity between steps: off, the centre of mass keeps its
 * velocity; reversed, it gains g t upward (within one step's g dt: the
 * position form's velocity is a difference across the step of the change); for the fast and the reference
 * kernels, Verlet's two forms and pbd. A non-finite gravity is refused and
 * changes nothing. */
static void test_set_gravity(void** state) {
    (void)state;
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = 4;
    sheet.width = sheet.height = 0.1;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    sb_material_def material = sb_default_material_def();
    material.mass = 0.01;
    sb_model* m = tu_mesh_model(&mesh, &material);
    sb_mesh_free(&mesh);
    const sb_integrator chosen[3] = {SB_INTEGRATOR_VERLET, SB_INTEGRATOR_VELOCITY_VERLET, SB_INTEGRATOR_PBD};
    const double g = 9.81, dt = 1e-3, T = 0.05;
    for (int k = 0; k < 6; k++) {
        sb_solver_def def = sb_default_solver_def();
        def.integrator = chosen[k % 3];
        def.kernels = k < 3 ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
        def.runtime.threads = 1;
        sb_solver* s = tu_solver(m, &def);
        tu_advance(s, dt, 50);
        double falling = mean_vz(s, 16);
        TU_ASSERT_NEAR(falling, -g * T, 1e-3 * g * T);
        const double off[3] = {0, 0, 0}, up[3] = {0, 0, g}, bad[3] = {0, NAN, 0};
        assert_int_equal(sb_solver_set_gravity(s, off), SB_OK);
        tu_advance(s, dt, 50);
        TU_ASSERT_NEAR(mean_vz(s, 16), falling, 1.5 * g * dt);
        assert_int_equal(sb_solver_set_gravity(s, up), SB_OK);
        tu_advance(s, dt, 50);
        TU_ASSERT_NEAR(mean_vz(s, 16), falling + g * T, 1.5 * g * dt);
        assert_int_equal(sb_solver_set_gravity(s, bad), SB_ERR_INVALID);
        tu_advance(s, dt, 50);
        TU_ASSERT_NEAR(mean_vz(s, 16), falling + 2 * g * T, 1.5 * g * dt);
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

typedef struct force_log {
    double F[3];
    uint32_t only_vertex; /* UINT32_MAX: every vertex */
    long calls;
    bool bad_vertex, bad_time;
    uint32_t forbidden; /* a vertex the callback must never see */
    double t_max;
} force_log;

static void constant_force(void* user, uint32_t vertex, double time, const double position[3], const double velocity[3],
                           double force[3]) {
    force_log* log = (force_log*)user;
    (void)position;
    (void)velocity;
    log->calls++;
    if (vertex == log->forbidden) log->bad_vertex = true;
    if (!(time >= 0.0 && time <= log->t_max + 1e-9)) log->bad_time = true;
    if (log->only_vertex != UINT32_MAX && vertex != log->only_vertex) return;
    for (int d = 0; d < 3; ++d) force[d] += log->F[d];
}

static void test_external_force(void** state) {
    (void)state;
    const double mass = 2.0, F[3] = {3.0, -1.0, 0.5}, x0[3] = {0.5, -0.25, 1.0};
    sb_builder* b = sb_builder_create();
    tu_vertex(b, x0[0], x0[1], x0[2], mass, false);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    const int n = 64;
    const double dt = 1.0 / 64;
    for (int k = 0; k < 2; ++k) {
        force_log log = {{F[0], F[1], F[2]}, UINT32_MAX, 0, false, false, UINT32_MAX, n * dt};
        sb_solver* s = make_solver(m, integrators[k], 0.0, constant_force, &log);
        tu_advance(s, dt, (uint64_t)n);
        double x[3], v[3], t = n * dt;
        sb_solver_get_positions(s, x);
        sb_solver_get_velocities(s, v);
        for (int d = 0; d < 3; ++d) {
            double a = F[d] / mass;
            /* Exact for Verlet up to rounding: 4·n·ε·(|x| ≤ 2). */
            TU_ASSERT_NEAR(x[d], x0[d] + 0.5 * a * t * t, 4.0 * n * TU_REAL_EPS * 2.0);
            TU_ASSERT_NEAR(v[d], a * t, 4.0 * n * TU_REAL_EPS * 2.0);
        }
        assert_true(log.calls >= n);
        assert_false(log.bad_time);
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);

    /* A pinned vertex and a free one: the callback is for free vertices only,
     * and a force on vertex 1 does not move vertex 0. */
    b = sb_builder_create();
    tu_vertex(b, 0, 0, 0, 1.0, true);
    tu_vertex(b, 0.25, 0.5, 0, mass, false);
    m = tu_compile(b);
    sb_builder_destroy(b);
    for (int k = 0; k < 2; ++k) {
        force_log log = {{F[0], F[1], F[2]}, 1, 0, false, false, 0, n * dt};
        sb_solver* s = make_solver(m, integrators[k], 0.0, constant_force, &log);
        tu_advance(s, dt, (uint64_t)n);
        double x[6];
        sb_solver_get_positions(s, x);
        assert_true(x[0] == 0.0 && x[1] == 0.0 && x[2] == 0.0);
        TU_ASSERT_NEAR(x[3], 0.25 + 0.5 * F[0] / mass, 4.0 * n * TU_REAL_EPS * 2.0);
        assert_false(log.bad_vertex);
        assert_true(log.calls >= n);
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

/* ---- failure modes ------------------------------------------------------------ */

/* k = 1e6 N/m between unit masses: ω ≈ 1414 rad/s, so dt = 0.01 s is
 * ωdt ≈ 14, far beyond Verlet's stability limit of 2: the amplitude grows
 * ~200× per step and must be caught, not returned as inf/NaN. */
static void test_blow_up_is_caught(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    tu_vertex(b, 0, 0, 0, 1.0, false);
    tu_vertex(b, 1, 0.1, 0, 1.0, false);
    tu_bond(b, 0, 1, 0.5, 1e6, 0, 0);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    for (int k = 0; k < 2; ++k) {
        sb_solver* s = make_solver(m, integrators[k], 0.0, NULL, NULL);
        sb_status st = SB_OK;
        int i;
        for (i = 0; i < 10000 && st == SB_OK; ++i) st = sb_solver_advance(s, 0.01);
        print_message("blow-up, %s: %s after %d steps: %s\n", sb_integrator_name(integrators[k]), sb_status_name(st), i,
                      sb_solver_error(s));
        assert_int_equal(st, SB_ERR_UNSTABLE);
        TU_ASSERT_CONTAINS(sb_solver_error(s), "step");
        TU_ASSERT_CONTAINS(sb_solver_error(s), "vertex");
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

static void test_invalid_dt(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    tu_vertex(b, 0, 0, 0, 1.0, false);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    sb_solver* s = make_solver(m, SB_INTEGRATOR_VERLET, -9.81, NULL, NULL);
    tu_advance(s, 0.01, 3);
    const double bad[5] = {0.0, -0.0, -1e-3, NAN, INFINITY};
    for (int i = 0; i < 5; ++i) {
        sb_status st = sb_solver_advance(s, bad[i]);
        if (st != SB_ERR_INVALID) fail_msg("dt = %g: status %s, expected invalid", bad[i], sb_status_name(st));
        /* Rejected before anything moved. */
        assert_true(sb_solver_step_count(s) == 3);
        TU_ASSERT_NEAR(sb_solver_time(s), 0.03, 1e-15);
    }
    /* The solver still works after a rejected call. */
    tu_advance(s, 0.01, 1);
    assert_true(sb_solver_step_count(s) == 4);
    sb_solver_destroy(s);
    sb_model_destroy(m);
}

/* At a small step both integrators must follow the same trajectory (they
 * are the same method in exact arithmetic): 6400 steps of 1.5625e-4 s on the
 * triangle. In double they agree to ~1e-12 m; velocity Verlet in float is
 * within ~1e-6 m of double. Bound 1e-4 m: float rounding with room, yet
 * 1/10 of the dt = 0.01 s discretisation error of the order test. A position
 * form that stores only x_n and x_{n−1} in float loses the increment
 * x_n − x_{n−1} (~5e-5 m) to rounding of x (~6e-8 m) every step. */
static void test_verlet_small_step_precision(void** state) {
    (void)state;
    sb_model* m = triangle_model();
    double a[9], b[9];
    triangle_run(m, SB_INTEGRATOR_VERLET, 0.04 / 256, 1.0, a);
    triangle_run(m, SB_INTEGRATOR_VELOCITY_VERLET, 0.04 / 256, 1.0, b);
    double d = max_diff(a, b, 9);
    sb_model_destroy(m);
    print_message("verlet vs velocity_verlet at dt = 1.5625e-4 s after 1 s: max difference %.3g m\n", d);
    TU_ASSERT_LE(d, 1e-4);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_order_spring),
        cmocka_unit_test(test_order_triangle),
        cmocka_unit_test(test_verlet_small_step_precision),
        cmocka_unit_test(test_energy_conservation),
        cmocka_unit_test(test_pinned_sheet_comes_to_rest),
        cmocka_unit_test(test_horizontal_sheet_settles_with_drag),
        cmocka_unit_test(test_free_fall),
        cmocka_unit_test(test_set_gravity),
        cmocka_unit_test(test_external_force),
        cmocka_unit_test(test_blow_up_is_caught),
        cmocka_unit_test(test_invalid_dt),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
