/* The position-based integrators pbd and xpbd (kernels/integrators/pbd.c): names and
 * scene keys, fixed vertices, convergence of the projection with the
 * iteration count, xpbd's static stretch of a hanging chain (k Δx = m g),
 * the same state for 1, 2 and 3 threads, few barriers a step, and the blow-up rule on bond lengths
 * (softbond/solver.h) under pbd too. Measured numbers are printed. */
#include "tests/test_util.h"
#include "scenes/scene.h"
#include "scenes/scene_model.h"
#include "kernels/integrators/fast_pbd.h"

#include <stdio.h>

static const sb_integrator position_based[2] = {SB_INTEGRATOR_PBD, SB_INTEGRATOR_XPBD};

static sb_solver_def pbd_def(sb_integrator integrator, sb_kernels kernels) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.kernels = kernels;
    return def;
}

static void test_names_and_keys(void** state) {
    (void)state;
    const char* names[2] = {"pbd", "xpbd"};
    for (int i = 0; i < 2; ++i) {
        sb_integrator out = SB_INTEGRATOR_COUNT;
        assert_true(sb_integrator_from_name(names[i], &out));
        assert_int_equal(out, position_based[i]);
        assert_string_equal(sb_integrator_name(position_based[i]), names[i]);
    }
    assert_int_equal(sb_default_solver_def().pbd_iterations, 10);
    sb_scene scene;
    sb_error err;
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    assert_int_equal(sb_scene_solver_def(&scene).pbd_iterations, 10);
    assert_int_equal(sb_scene_set(&scene, "integrator=xpbd", &err), SB_OK);
    assert_int_equal(sb_scene_set(&scene, "pbd.iterations=25", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    sb_solver_def def = sb_scene_solver_def(&scene);
    assert_int_equal(def.integrator, SB_INTEGRATOR_XPBD);
    assert_int_equal(def.pbd_iterations, 25);
    assert_int_equal(sb_scene_set(&scene, "pbd.iterations=0", &err), SB_OK);
    assert_int_not_equal(sb_scene_validate(&scene, &err), SB_OK);
    TU_ASSERT_CONTAINS(err.message, "pbd.iterations");
    sb_scene_free(&scene);
    /* a negative count is rejected by the library */
    def.pbd_iterations = -1;
    sb_builder* b = sb_builder_create();
    tu_vertex(b, 0, 0, 0, 1, false);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    assert_null(sb_solver_create(m, &def, &err));
    TU_ASSERT_CONTAINS(err.message, "pbd_iterations");
    sb_model_destroy(m);
}

/* An S × S sheet in the xy plane, spacing h along x and `row` along y,
 * mass 0.01 per vertex, bonds (k, spring damping d) along rows, columns
 * and one diagonal, two triangles per cell with angle constant kt and
 * stretch-bend 0.5, the top corners pinned; with `skips`, undamped bonds
 * from each vertex to the next but one of its row too (on no triangle's
 * edge: the bond sweep's). */
static sb_model* sheet_with(int S, double h, double row, double k, double kt, double d, bool skips) {
    sb_builder* b = sb_builder_create();
    for (int r = 0; r < S; ++r)
        for (int c = 0; c < S; ++c) tu_vertex(b, h * c, row * r, 0, 0.01, r == S - 1 && (c == 0 || c == S - 1));
    for (int r = 0; r < S; ++r)
        for (int c = 0; c < S; ++c) {
            uint32_t a = (uint32_t)(r * S + c);
            if (c + 1 < S) tu_bond(b, a, a + 1, -1, k, 0, d);
            if (r + 1 < S) tu_bond(b, a, a + S, -1, k, 0, d);
            if (c + 1 < S && r + 1 < S) tu_bond(b, a, a + S + 1, -1, k, 0, d);
            if (skips && c + 2 < S) tu_bond(b, a, a + 2, -1, k, 0, 0);
        }
    for (int r = 0; r + 1 < S; ++r)
        for (int c = 0; c + 1 < S; ++c) {
            uint32_t a = (uint32_t)(r * S + c);
            tu_triangle(b, a, a + 1, a + S + 1, kt, 0.5);
            tu_triangle(b, a, a + S + 1, a + S, kt, 0.5);
        }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

static sb_model* sheet(int S, double h, double k, double kt, double d) { return sheet_with(S, h, h, k, kt, d, false); }

/* A constant push on every free vertex: the external force under pbd. */
static void push_force(void* user, uint32_t vertex, double time, const double position[3], const double velocity[3],
                       double force[3]) {
    (void)user, (void)vertex, (void)time, (void)position, (void)velocity;
    force[0] += 0.02;
    force[2] += 0.01;
}

/* A sheet falling under gravity and a push, held by its two pinned corners:
 * the pinned vertices stay bitwise at rest while the rest moves. */
static void test_fixed_vertices(void** state) {
    (void)state;
    enum { S = 8 };
    sb_model* m = sheet(S, 0.05, 200, 0.05, 0);
    for (int k = 0; k < 4; ++k) {
        sb_solver_def def = pbd_def(position_based[k % 2], k < 2 ? SB_KERNELS_REFERENCE : SB_KERNELS_FAST);
        def.external_force = push_force;
        sb_solver* s = tu_solver(m, &def);
        tu_advance(s, 2e-3, 300);
        double x[3 * S * S], rest[3], moved = 0;
        sb_solver_get_positions(s, x);
        for (uint32_t i = 0; i < S * S; ++i) {
            sb_model_rest_position(m, i, rest);
            if (sb_model_is_fixed(m, i))
                assert_true(x[3 * i] == (sb_real)rest[0] && x[3 * i + 1] == (sb_real)rest[1] &&
                            x[3 * i + 2] == (sb_real)rest[2]);
            else
                moved = fmax(moved, tu_dist(rest, x + 3 * i));
        }
        print_message("fixed vertices, %-4s (%s kernels): pinned corners unmoved, the sheet moved up to %.3g m\n",
                      sb_integrator_name(def.integrator), k < 2 ? "reference" : "fast", moved);
        assert_true(moved > 0.05);
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

/* A chain of NB rigid bonds (k = 1e9 N/m: k dt² w ≈ 2e5, so the pbd
 * stiffness is 1 − 5e-6 and xpbd's compliance negligible), its first vertex
 * fixed, every bond stretched to 1.5 r0, at rest, no gravity: one step's
 * projection is Gauss-Seidel on the chain, whose error falls by about
 * cos²(π/(2 NB + 1)) ≈ 0.92 a sweep (measured ~0.91), so the worst
 * relative bond error must fall as the iterations grow and be below 1e-3
 * after 256. */
static void test_convergence(void** state) {
    (void)state;
    enum { NB = 5 };
    const double r0 = 0.1;
    sb_builder* b = sb_builder_create();
    for (int i = 0; i <= NB; ++i) tu_vertex(b, 1.5 * r0 * i, 0, 0, 0.01, i == 0);
    for (int i = 0; i < NB; ++i) tu_bond(b, (uint32_t)i, (uint32_t)i + 1, r0, 1e9, 0, 0);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    for (int k = 0; k < 2; ++k) {
        const int counts[5] = {1, 4, 16, 64, 256};
        double errors[5];
        for (int c = 0; c < 5; ++c) {
            sb_solver_def def = pbd_def(position_based[k], SB_KERNELS_REFERENCE);
            def.gravity[2] = 0;
            def.pbd_iterations = counts[c];
            sb_solver* s = tu_solver(m, &def);
            tu_advance(s, 1e-3, 1);
            double x[3 * (NB + 1)];
            sb_solver_get_positions(s, x);
            errors[c] = 0;
            for (int i = 0; i < NB; ++i) errors[c] = fmax(errors[c], fabs(tu_dist(x + 3 * i, x + 3 * i + 3) - r0) / r0);
            sb_solver_destroy(s);
        }
        print_message("convergence, %-4s: worst |r - r0|/r0 after one step with 1, 4, 16, 64, 256 iterations: "
                      "%.3g %.3g %.3g %.3g %.3g (from 0.5)\n",
                      sb_integrator_name(position_based[k]), errors[0], errors[1], errors[2], errors[3], errors[4]);
        /* (one sweep may overshoot: moving a vertex lengthens the next bond) */
        for (int c = 1; c < 5; ++c) TU_ASSERT_LE(errors[c], errors[c - 1]);
        TU_ASSERT_LE(errors[4], 1e-3);
    }
    sb_model_destroy(m);
}

/* Three masses m hanging in a vertical chain from a fixed vertex on bonds
 * of k = 100 N/m, r0 = 0.1 m: at rest bond j (from the top) carries the
 * weight below it, (3 − j) m g, so it is stretched by (3 − j) m g / k
 * (0.0294, 0.0196, 0.0098 m for m = 0.1 kg). xpbd's fixed point is that
 * static equilibrium whatever the iteration count; drag (10/s, zero at
 * rest) settles the swing within 3 s (amplitude × e^-15). Tolerance 1e-3 of
 * the stretch: far above rounding, far below pbd's error. pbd, stiffer at
 * more iterations, is printed beside it. */
static void test_xpbd_static_stretch(void** state) {
    (void)state;
    const double mass = 0.1, k = 100, r0 = 0.1, g = 9.81;
    sb_builder* b = sb_builder_create();
    for (int i = 0; i < 4; ++i) tu_vertex(b, 0, 0, -r0 * i, i ? mass : 1.0, i == 0);
    for (int i = 0; i < 3; ++i) tu_bond(b, (uint32_t)i, (uint32_t)i + 1, r0, k, 0, 0);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    for (int q = 0; q < 4; ++q) {
        sb_solver_def def = pbd_def(position_based[q / 2], SB_KERNELS_REFERENCE);
        def.drag = 10;
        def.pbd_iterations = q % 2 ? 50 : 10;
        sb_solver* s = tu_solver(m, &def);
        tu_advance(s, 1e-3, 3000);
        double x[12], worst = 0;
        sb_solver_get_positions(s, x);
        char line[256];
        int used = 0;
        for (int j = 0; j < 3; ++j) {
            double stretch = tu_dist(x + 3 * j, x + 3 * j + 3) - r0, expect = (3 - j) * mass * g / k;
            worst = fmax(worst, fabs(stretch - expect) / expect);
            used += snprintf(line + used, sizeof line - (size_t)used, " %.6g (k dx/m g = %.4f)", stretch,
                             k * stretch / ((3 - j) * mass * g));
        }
        print_message("hanging chain, %-4s, %2d iterations: stretches%s m; worst relative error %.3g\n",
                      sb_integrator_name(def.integrator), def.pbd_iterations, line, worst);
        if (def.integrator == SB_INTEGRATOR_XPBD) TU_ASSERT_LE(worst, 1e-3);
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

/* A 100 × 100 sheet (29701 bonds, 19602 triangles: thousands of
 * constraints per block color, so that the solver gives every thread work;
 * it keeps small models on one), 20 steps: the state's hash is the same for
 * 1, 2 and 3 threads, with either kernel choice; and with the fast kernels
 * on the sheet with bonds on no triangle too (two groups, so that the SIMD
 * sweeps' units of the triangles wait for those of the bonds and the other
 * way round, kernels/integrators/fast_pbd.c's schedule), damped. */
static void test_threads_deterministic(void** state) {
    (void)state;
    sb_model* models[2] = {sheet(100, 0.01, 500, 0.05, 0), sheet_with(100, 0.01, 0.01, 500, 0.05, 0.02, true)};
    for (int k = 0; k < 6; ++k) {
        uint64_t hashes[3];
        bool fast = k >= 2, both = k >= 4;
        for (int t = 0; t < 3; ++t) {
            sb_solver_def def = pbd_def(position_based[k % 2], fast ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE);
            def.runtime.threads = t + 1;
            sb_solver* s = tu_solver(models[both], &def);
            tu_advance(s, 2e-3, 20);
            hashes[t] = tu_state_hash(s);
            sb_solver_destroy(s);
        }
        print_message("threads, %-4s (%s kernels%s): state hash %016llx (1 thread), %016llx (2), %016llx (3)\n",
                      sb_integrator_name(position_based[k % 2]), fast ? "fast" : "reference",
                      both ? ", bonds on no triangle too" : "", (unsigned long long)hashes[0],
                      (unsigned long long)hashes[1], (unsigned long long)hashes[2]);
        assert_true(hashes[0] == hashes[1]);
        assert_true(hashes[0] == hashes[2]);
    }
    sb_model_destroy(models[0]);
    sb_model_destroy(models[1]);
}

/* The 100 × 100 sheet, bonds on the triangles and bonds on none (a group
 * each, 2 block colors each): a step of 5 sweeps waits at 2 barriers, none
 * in the sweeps, whose units wait only for the units they share vertices
 * with (kernels/integrators/fast_pbd.c's schedule; a barrier after each block color
 * made 2 + 5 × 4, and one after each element color, before the blocked
 * coloring, 2 + 5 × 9 or more). */
static void test_few_barriers(void** state) {
    (void)state;
    sb_model* m = sheet_with(100, 0.01, 0.01, 500, 0.05, 0, true);
    for (int threads = 1; threads <= 3; threads++) {
        sb_solver_def def = pbd_def(SB_INTEGRATOR_XPBD, SB_KERNELS_FAST);
        def.pbd_iterations = 5;
        def.runtime.threads = threads;
        sb_solver* s = tu_solver(m, &def);
        uint32_t across, faults = sb_pbd_wide_schedule_faults(s, &across), barriers = sb_pbd_wide_barriers(s);
        print_message("xpbd, 100 x 100 sheet with bonds on no triangle too, 5 sweeps, %d threads: %u barriers a step, "
                      "%u waits a sweep for another thread's units, %u faults in the schedule\n",
                      threads, barriers, across, faults);
        assert_int_equal(barriers, 2);
        assert_int_equal(faults, 0);
        if (threads == 1)
            assert_int_equal(across, 0);
        else
            assert_true(across > 0); /* the threads' blocks meet */
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

/* Largest |a − b| over 3n values. */
static double max_difference(const double* a, const double* b, size_t n3) {
    double worst = 0;
    for (size_t q = 0; q < n3; ++q) worst = fmax(worst, fabs(a[q] - b[q]));
    return worst;
}

/* The SIMD sweeps (fast kernels, kernels/integrators/fast_pbd.c) against the scalar
 * ones (reference kernels, kernels/integrators/pbd.c) on a damped 24 × 24 sheet with
 * bonds and corners (every bond carried by a triangle), with bonds on no
 * triangle too, and of sliver cells (rows 20 times closer than columns:
 * corners of 2.9° and 87° between edges 20 times apart in length, where
 * the SIMD corner takes 1/|a|² as |b|²/(|a|²|b|²)): the same constraints
 * in the same order, so the
 * positions after the first step and after 40 differ by rounding only
 * (float: sb_real sweeps against double ones; the first step moves the
 * sheet by g dt² = 4e-5 m, where the float positions' rounding is ~4e-4
 * of it), measured against how far the sheet moved; the energies (the fast solver's evaluated when asked
 * for) agree to the float kernels' rounding. */
static void test_fast_matches_scalar(void** state) {
    (void)state;
    enum { S = 24, N = S * S };
    const double tolerance = SB_DOUBLE ? 1e-9 : 5e-3, energy_tolerance = SB_DOUBLE ? 1e-9 : 1e-4;
    const char* kinds[3] = {"", " (bonds on no triangle too)", " (sliver cells)"};
    for (int run = 0; run < 6; ++run) {
        int k = run % 2, kind = run / 2;
        sb_model* m = sheet_with(S, 0.01, kind == 2 ? 0.0005 : 0.01, 500, 0.05, 0.02, kind == 1);
        sb_solver* solvers[2];
        double x[2][3 * N], rest[3 * N], worst[2] = {0, 0};
        for (int q = 0; q < 2; ++q) {
            sb_solver_def def = pbd_def(position_based[k], q ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE);
            def.pbd_iterations = 5;
            solvers[q] = tu_solver(m, &def);
        }
        sb_solver_get_positions(solvers[0], rest);
        for (int phase = 0; phase < 2; ++phase) {
            for (int q = 0; q < 2; ++q) {
                tu_advance(solvers[q], 2e-3, phase ? 39 : 1);
                sb_solver_get_positions(solvers[q], x[q]);
            }
            worst[phase] = max_difference(x[0], x[1], 3 * N) / max_difference(x[0], rest, 3 * N);
        }
        sb_energies e[2] = {sb_solver_energies(solvers[0]), sb_solver_energies(solvers[1])};
        double scale = fabs(e[0].kinetic) + fabs(e[0].gravity), energy_error = fabs(e[0].kinetic - e[1].kinetic);
        for (int t = 0; t < SB_TERM_COUNT; ++t) {
            scale += fabs(e[0].term[t]);
            energy_error += fabs(e[0].term[t] - e[1].term[t]);
        }
        energy_error = (energy_error + fabs(e[0].gravity - e[1].gravity)) / scale;
        print_message("fast against scalar sweeps, %-4s%s: largest position difference / largest move %.3g after 1 "
                      "step, %.3g after 40; energies differ by %.3g of their scale\n",
                      sb_integrator_name(position_based[k]), kinds[kind], worst[0], worst[1], energy_error);
        TU_ASSERT_LE(worst[0], tolerance);
        TU_ASSERT_LE(worst[1], tolerance);
        TU_ASSERT_LE(energy_error, energy_tolerance);
        for (int q = 0; q < 2; ++q) sb_solver_destroy(solvers[q]);
        sb_model_destroy(m);
    }
}

/* The same with triangles whose corners are dead (angle constant 0: their
 * slots stay in the SIMD blocks, beside live ones, with inverse masses
 * times 0): a 24 × 24 sheet whose two halves are thrown apart at 2 m/s,
 * the bonds across its middle column breakable at 5 % stretch (they
 * stretch by tens of % in the first step, so both solvers break them in
 * it, and the triangles on them lose their constants), no tearing. The
 * positions after 1 and 40 steps differ by rounding only, as above, and no
 * value is lost to a dead corner (finite, the same bonds broken). */
static void test_fast_matches_scalar_dead_corners(void** state) {
    (void)state;
    enum { S = 24, N = S * S };
    const double h = 0.01, tolerance = SB_DOUBLE ? 1e-9 : 5e-3;
    sb_builder* b = sb_builder_create();
    for (int r = 0; r < S; ++r)
        for (int c = 0; c < S; ++c) tu_vertex(b, h * c, h * r, 0, 0.01, r == S - 1 && (c == 0 || c == S - 1));
    for (int r = 0; r < S; ++r)
        for (int c = 0; c < S; ++c) {
            uint32_t a = (uint32_t)(r * S + c);
            sb_bond_def d = sb_default_bond_def();
            d.k = 500;
            d.spring_damping = 0.02;
            for (int e = 0; e < 3; ++e) {
                uint32_t to = e == 0 ? a + 1 : e == 1 ? a + S : a + S + 1;
                if ((e != 1 && c + 1 >= S) || (e != 0 && r + 1 >= S)) continue;
                d.i = a;
                d.j = to;
                d.rest_length = e == 2 ? h * sqrt(2.0) : h;
                d.break_max = e != 1 && c == S / 2 - 1 ? 1.05 * d.rest_length : 0.0; /* across the middle */
                assert_true(sb_builder_add_bond(b, &d) >= 0);
            }
        }
    for (int r = 0; r + 1 < S; ++r)
        for (int c = 0; c + 1 < S; ++c) {
            uint32_t a = (uint32_t)(r * S + c);
            tu_triangle(b, a, a + 1, a + S + 1, 0.05, 0.5);
            tu_triangle(b, a, a + S + 1, a + S, 0.05, 0.5);
        }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    double v[3 * N];
    for (uint32_t i = 0; i < N; ++i) {
        v[3 * i] = i % S < S / 2 ? -1.0 : 1.0;
        v[3 * i + 1] = v[3 * i + 2] = 0.0;
    }
    for (int k = 0; k < 2; ++k) {
        sb_solver* solvers[2];
        double x[2][3 * N], rest[3 * N], worst[2] = {0, 0};
        for (int q = 0; q < 2; ++q) {
            sb_solver_def def = pbd_def(position_based[k], q ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE);
            def.pbd_iterations = 5;
            def.max_splits = -1;
            solvers[q] = tu_solver(m, &def);
            assert_int_equal(sb_solver_set_state(solvers[q], NULL, v), SB_OK);
        }
        sb_solver_get_positions(solvers[0], rest);
        for (int phase = 0; phase < 2; ++phase) {
            for (int q = 0; q < 2; ++q) {
                tu_advance(solvers[q], 2e-3, phase ? 39 : 1);
                sb_solver_get_positions(solvers[q], x[q]);
                for (int i = 0; i < 3 * N; ++i) assert_true(isfinite(x[q][i]));
            }
            worst[phase] = max_difference(x[0], x[1], 3 * N) / max_difference(x[0], rest, 3 * N);
        }
        uint32_t broken[2] = {sb_solver_broken_count(solvers[0]), sb_solver_broken_count(solvers[1])};
        print_message("fast against scalar sweeps, %-4s, dead corners (%u bonds broken): largest position difference "
                      "/ largest move %.3g after 1 step, %.3g after 40\n",
                      sb_integrator_name(position_based[k]), broken[1], worst[0], worst[1]);
        assert_int_equal(broken[0], 2 * (S - 1) + 1); /* the rows' and the diagonals' across the middle */
        assert_int_equal(broken[1], broken[0]);
        TU_ASSERT_LE(worst[0], tolerance);
        TU_ASSERT_LE(worst[1], tolerance);
        for (int q = 0; q < 2; ++q) sb_solver_destroy(solvers[q]);
    }
    sb_model_destroy(m);
}

/* The fast xpbd step leaves the new state's forces and energies for when
 * they are asked for: what the getters return then is bitwise what a
 * solver set to the same state evaluates, and so is a checkpoint's. */
static void test_energies_when_asked(void** state) {
    (void)state;
    enum { S = 16, N = S * S };
    sb_model* m = sheet(S, 0.01, 500, 0.05, 0.02);
    sb_solver_def def = pbd_def(SB_INTEGRATOR_XPBD, SB_KERNELS_FAST);
    sb_solver *s = tu_solver(m, &def), *fresh = tu_solver(m, &def);
    tu_advance(s, 2e-3, 25);
    double x[3 * N], v[3 * N], f[2][3 * N];
    sb_solver_get_positions(s, x);
    sb_solver_get_velocities(s, v);
    assert_int_equal(sb_solver_set_state(fresh, x, v), SB_OK);
    sb_energies asked = sb_solver_energies(s), evaluated = sb_solver_energies(fresh);
    sb_solver_get_forces(s, f[0]);
    sb_solver_get_forces(fresh, f[1]);
    assert_memory_equal(&asked, &evaluated, sizeof asked);
    assert_memory_equal(f[0], f[1], sizeof f[0]);
    tu_advance(s, 2e-3, 1);
    size_t size = sb_solver_state_size(s);
    unsigned char* saved = malloc(size);
    assert_non_null(saved);
    assert_int_equal(sb_solver_save_state(s, saved, size, NULL), SB_OK);
    sb_energies after = sb_solver_energies(s);
    assert_int_equal(sb_solver_load_state(fresh, saved, size, NULL), SB_OK);
    evaluated = sb_solver_energies(fresh);
    assert_memory_equal(&after, &evaluated, sizeof after);
    print_message("energies when asked: kinetic %.6g J, bond %.6g J after 25 steps, as a fresh evaluation's\n",
                  asked.kinetic, asked.term[SB_TERM_BOND]);
    free(saved);
    sb_solver_destroy(s);
    sb_solver_destroy(fresh);
    sb_model_destroy(m);
}

/* A free triangle (three bonds, an angle term) collapsed to one point, no
 * gravity: every edge has length 0, the sweeps cannot move it, and the
 * step reports the collapse (SB_ERR_DEGENERATE) with either kernel choice. */
static void test_collapse_reported(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    for (int i = 0; i < 3; ++i) tu_vertex(b, 0.01 * (i == 1), 0.01 * (i == 2), 0, 0.01, false);
    for (int i = 0; i < 3; ++i) tu_bond(b, (uint32_t)i, (uint32_t)(i + 1) % 3, -1, 500, 0, 0);
    tu_triangle(b, 0, 1, 2, 0.05, 0);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    const double x[9] = {0};
    for (int k = 0; k < 2; ++k) {
        sb_solver_def def = pbd_def(SB_INTEGRATOR_XPBD, k ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE);
        def.gravity[2] = 0;
        sb_solver* s = tu_solver(m, &def);
        assert_int_not_equal(sb_solver_set_state(s, x, NULL), SB_OK); /* the evaluation reports it at once */
        sb_status st = sb_solver_advance(s, 1e-3);
        print_message("collapse, %s kernels: %s: %s\n", k ? "fast" : "reference", sb_status_name(st),
                      sb_solver_error(s));
        assert_int_equal(st, SB_ERR_DEGENERATE);
        TU_ASSERT_CONTAINS(sb_solver_error(s), "step 1 ");
        TU_ASSERT_CONTAINS(sb_solver_error(s), "collapsed");
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

/* The blow-up rule under pbd: a bond stretched past SB_STRETCH_LIMIT (set
 * as the state) is reported on the SB_STRETCH_INTERVAL-th advance, naming
 * the step, the time and the bond, with SB_ERR_UNSTABLE; the same chain
 * stretched to 5 × r0 (inside the limit) and pulled back by soft bonds runs. */
static void test_blow_up_rule(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    for (int i = 0; i < 3; ++i) tu_vertex(b, 0.1 * i, 0, 0, 0.01, i == 0);
    for (int i = 0; i < 2; ++i) tu_bond(b, (uint32_t)i, (uint32_t)i + 1, 0.1, 1e-3, 0, 0);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    for (int k = 0; k < 3; ++k) {
        sb_solver_def def = pbd_def(k < 2 ? position_based[k] : SB_INTEGRATOR_VERLET, SB_KERNELS_REFERENCE);
        def.gravity[2] = 0;
        sb_solver* s = tu_solver(m, &def);
        double x[9] = {0, 0, 0, 0.5, 0, 0, 0.5 + 1.2, 0, 0}; /* bond 1 at 12 r0 */
        assert_int_equal(sb_solver_set_state(s, x, NULL), SB_OK);
        sb_status st = SB_OK;
        int i;
        for (i = 1; i <= SB_STRETCH_INTERVAL && st == SB_OK; ++i) st = sb_solver_advance(s, 1e-3);
        print_message("blow-up rule, %-6s: %s after %d advances: %s\n", sb_integrator_name(def.integrator),
                      sb_status_name(st), i - 1, sb_solver_error(s));
        assert_int_equal(st, SB_ERR_UNSTABLE);
        assert_int_equal(i - 1, SB_STRETCH_INTERVAL);
        char where[64];
        snprintf(where, sizeof where, "step %d (t = %g s)", SB_STRETCH_INTERVAL, SB_STRETCH_INTERVAL * 1e-3);
        TU_ASSERT_CONTAINS(sb_solver_error(s), where);
        TU_ASSERT_CONTAINS(sb_solver_error(s), "bond 1 (vertices 1 and 2)");
        x[6] = 0.5 + 0.5; /* 5 r0 */
        assert_int_equal(sb_solver_set_state(s, x, NULL), SB_OK);
        tu_advance(s, 1e-3, 4 * SB_STRETCH_INTERVAL);
        sb_solver_destroy(s);
    }
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names_and_keys),        cmocka_unit_test(test_fixed_vertices),
        cmocka_unit_test(test_convergence),           cmocka_unit_test(test_xpbd_static_stretch),
        cmocka_unit_test(test_threads_deterministic), cmocka_unit_test(test_blow_up_rule),
        cmocka_unit_test(test_fast_matches_scalar),   cmocka_unit_test(test_fast_matches_scalar_dead_corners),
        cmocka_unit_test(test_energies_when_asked),   cmocka_unit_test(test_collapse_reported),
        cmocka_unit_test(test_few_barriers),
    };
    return TU_RUN_TESTS(tests);
}
