/* Energy over a long run: an undamped body stepped by Verlet at half its
 * stable step keeps its energy. Verlet is symplectic, so its energy only
 * oscillates, by O((ω dt)²), about the true value (the oracle is that
 * law: the total at the end within 1 % of the start; double: +0.03 %);
 * what can make it drift is the state's rounding. In float, before the
 * drifts were compensated (kernels/state/vertex_state.h), rounding x + Δ to
 * 24 bits each step heated this body by +154 % (fast kernels) and +196 %
 * (reference) over 4 × 10⁵ steps. Compensated, with forces evaluated at
 * x + carry, it keeps to +0.03 % (reference, in double) and +0.01 % (fast
 * kernels, each element placed about its first vertex with the carries,
 * kernels/forces/fast_block.h), as double does; the fast kernels reading
 * the 24-bit positions alone heated it by +46 %.
 *
 * The body: a 12 × 12 sheet of bonds (10 cm, 50 N/m, 1 g a vertex, no
 * bending), set 1 m from the origin so that its coordinates carry the
 * rounding of a scene's, ringing in its two lowest stretch modes (so that
 * Verlet's own energy error, O((ω dt)²) for the modes that ring, is
 * small), no
 * gravity, no drag, no pins. Its stable step is 2/ω_max; ω_max² is at most
 * the largest Gershgorin row sum of M⁻¹K, 2 Σ_j k_ij / m_i, so
 * dt = 1 / √(that) is at most half the stable step. The same sheet with
 * the cells' triangles and their angle term (ANGLE_K, adding about
 * k_θ / l² ≈ 1.2 N/m, 2 % of a bond's stiffness, so that dt stays about
 * half the stable step) runs the fast path's triangle kernel too, which
 * takes the bonds on its edges (kernels/forces/fast_corners.c): +0.27 %
 * there (the reference and double +0.26 %, the method's own error; +46 %
 * when the fast kernels read the rounded positions). */
#include "tests/test_util.h"

enum { SIDE = 12, STEPS = 400000 };
#define SPACING (0.1 / (SIDE - 1)) /* m */
#define OFFSET 1.0                 /* m */
#define BOND_K 50.0                /* N/m */
#define MASS 1e-3                  /* kg */
#define SPEED 0.01                 /* m/s */
#define ANGLE_K 1e-4               /* J/rad² */

/* The two triangles of the cell whose lowest vertex is a, split along the
 * bond a → a + SIDE + 1. */
static void add_cell_triangles(sb_builder* b, uint32_t a) {
    tu_triangle(b, a, a + 1, a + SIDE + 1, ANGLE_K, 0);
    tu_triangle(b, a, a + SIDE + 1, a + SIDE, ANGLE_K, 0);
}

/* The sheet; with its triangles when `triangles`. */
static sb_model* ringing_sheet(bool triangles) {
    sb_builder* b = sb_builder_create();
    for (int r = 0; r < SIDE; r++)
        for (int c = 0; c < SIDE; c++) {
            int64_t v = tu_vertex(b, OFFSET + c * SPACING, OFFSET + r * SPACING, OFFSET, MASS, false);
            double* velocity = sb_builder_vertex(b, (uint32_t)v)->velocity; /* the lowest stretch modes */
            velocity[0] = SPEED * cos(M_PI * c / (SIDE - 1));
            velocity[1] = SPEED * cos(M_PI * r / (SIDE - 1));
        }
    for (int r = 0; r < SIDE; r++)
        for (int c = 0; c < SIDE; c++) {
            uint32_t a = (uint32_t)(r * SIDE + c);
            if (c + 1 < SIDE) tu_bond(b, a, a + 1, -1, BOND_K, 0, 0);
            if (r + 1 < SIDE) tu_bond(b, a, a + SIDE, -1, BOND_K, 0, 0);
            if (c + 1 < SIDE && r + 1 < SIDE) tu_bond(b, a, a + SIDE + 1, -1, BOND_K, 0, 0);
            if (c > 0 && r + 1 < SIDE) tu_bond(b, a, a + SIDE - 1, -1, BOND_K, 0, 0);
            if (triangles && c + 1 < SIDE && r + 1 < SIDE) add_cell_triangles(b, a);
        }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

/* The relative change of the total energy over STEPS steps. */
static double energy_drift(sb_integrator integrator, sb_kernels kernels, bool triangles) {
    sb_model* m = ringing_sheet(triangles);
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.kernels = kernels;
    def.gravity[2] = 0.0;
    sb_solver* s = tu_solver(m, &def);
    double dt = 1.0 / sqrt(2.0 * 8.0 * BOND_K / MASS); /* a vertex has at most 8 bonds */
    sb_energies e = sb_solver_energies(s);
    double start = sb_energies_total(&e);
    tu_advance(s, dt, STEPS);
    e = sb_solver_energies(s);
    double drift = sb_energies_total(&e) / start - 1.0;
    print_message("%s, %s kernels, %s%s: energy %+.3f %% over %d steps of %.3g s\n", SB_DOUBLE ? "double" : "float",
                  kernels == SB_KERNELS_FAST ? "fast" : "reference", sb_integrator_name(integrator),
                  triangles ? ", triangles" : "", 100.0 * drift, STEPS, dt);
    sb_solver_destroy(s);
    sb_model_destroy(m);
    return drift;
}

static void test_verlet_fast(void** state) {
    (void)state;
    assert_true(fabs(energy_drift(SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, false)) < 0.01);
}

static void test_verlet_reference(void** state) {
    (void)state;
    assert_true(fabs(energy_drift(SB_INTEGRATOR_VERLET, SB_KERNELS_REFERENCE, false)) < 0.01);
}

static void test_velocity_verlet_reference(void** state) {
    (void)state;
    assert_true(fabs(energy_drift(SB_INTEGRATOR_VELOCITY_VERLET, SB_KERNELS_REFERENCE, false)) < 0.01);
}

static void test_velocity_verlet_fast(void** state) {
    (void)state;
    assert_true(fabs(energy_drift(SB_INTEGRATOR_VELOCITY_VERLET, SB_KERNELS_FAST, false)) < 0.01);
}

static void test_verlet_fast_triangles(void** state) {
    (void)state;
    assert_true(fabs(energy_drift(SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, true)) < 0.01);
}

static void test_verlet_reference_triangles(void** state) {
    (void)state;
    assert_true(fabs(energy_drift(SB_INTEGRATOR_VERLET, SB_KERNELS_REFERENCE, true)) < 0.01);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_verlet_fast),
        cmocka_unit_test(test_verlet_reference),
        cmocka_unit_test(test_velocity_verlet_reference),
        cmocka_unit_test(test_velocity_verlet_fast),
        cmocka_unit_test(test_verlet_fast_triangles),
        cmocka_unit_test(test_verlet_reference_triangles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
