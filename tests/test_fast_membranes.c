/* The lane-wise membranes of the fast kernels (kernels/forces/
 * fast_membranes.c) against the scalar reference (kernels/forces/
 * membrane.c, in double): separate triangles strained, turned and thin,
 * damped and not, and a sheet sagging under gravity in the middle of its
 * motion, within a bound of rounding: per vertex TOLERANCE ε times the
 * stresses' scale of its triangles,
 *     V (2μ + 2λ) ‖D_m⁻¹‖ (‖F‖ + √2 + 2 ‖D_m⁻¹‖ |x|max + β ‖Ḟ‖) ‖F‖ / σ_min,
 * ε of sb_real, |x|max the triangle's largest coordinate (F's rounding from
 * the positions' in sb_real), ‖F‖ / σ_min the rotation's conditioning (a
 * thin triangle's turn out of its line is known to ε ‖F‖ / σ_min). */
#include "test_util.h"
#include "random_deformation.h"

#include "kernels/forces/fast_model.h"

#include <stdio.h>

enum { TOLERANCE = 4 };

/* F = D_s D_m⁻¹ (3 × 2 row-major) of triangle t at the positions (or
 * velocities) x. */
static void plane_deformation(const sb_model* m, uint32_t t, const double* x, double F[6]) {
    for (int i = 0; i < 3; i++) {
        double o = x[3 * m->membrane_v[0][t] + i];
        double e1 = x[3 * m->membrane_v[1][t] + i] - o, e2 = x[3 * m->membrane_v[2][t] + i] - o;
        F[2 * i] = e1 * m->membrane_dm_inv[0][t] + e2 * m->membrane_dm_inv[2][t];
        F[2 * i + 1] = e1 * m->membrane_dm_inv[1][t] + e2 * m->membrane_dm_inv[3][t];
    }
}

static double norm6(const double a[6]) {
    double s = 0.0;
    for (int k = 0; k < 6; k++) s += a[k] * a[k];
    return sqrt(s);
}

/* F's smaller singular value. */
static double smallest_singular_value(const double F[6]) {
    double c00 = F[0] * F[0] + F[2] * F[2] + F[4] * F[4], c11 = F[1] * F[1] + F[3] * F[3] + F[5] * F[5];
    double c01 = F[0] * F[1] + F[2] * F[3] + F[4] * F[5], half = 0.5 * (c00 + c11);
    double gap = sqrt(fmax(half * half - (c00 * c11 - c01 * c01), 0.0));
    return sqrt(fmax(half - gap, 0.0));
}

/* The fast forces and energy at (x, v) against the reference's, within the
 * file's bound, on the free vertices; `what` names the case. */
static void assert_membranes_match_reference(const sb_model* m, const double* x, const double* v, const char* what) {
    uint32_t n = sb_model_vertex_count(m);
    double* scale = calloc(n, sizeof *scale);
    double energy_scale = 0.0;
    for (uint32_t t = 0; t < m->membrane_count; t++) {
        double F[6], Fdot[6] = {0}, dm = 0.0, far = 0.0;
        plane_deformation(m, t, x, F);
        if (v) plane_deformation(m, t, v, Fdot);
        for (int k = 0; k < 4; k++) dm += m->membrane_dm_inv[k][t] * m->membrane_dm_inv[k][t];
        for (int c = 0; c < 3; c++)
            for (int a = 0; a < 3; a++) far = fmax(far, fabs(x[3 * m->membrane_v[c][t] + a]));
        double stiffness = m->membrane_volume[t] * (2.0 * m->membrane_mu[t] + 2.0 * m->membrane_lambda[t]);
        double stress = norm6(F) + sqrt(2.0) + 2.0 * far * sqrt(dm), condition = norm6(F) / smallest_singular_value(F);
        for (int c = 0; c < 3; c++)
            scale[m->membrane_v[c][t]] +=
                stiffness * sqrt(dm) * (stress + m->membrane_beta[t] * norm6(Fdot)) * condition;
        energy_scale += stiffness * stress * stress * condition;
    }
    expect_fast_matches_reference(m, x, v, scale, energy_scale, SB_TERM_MEMBRANE, TOLERANCE, what);
    free(scale);
}

/* How the separate triangles of the next test are deformed, by number. */
enum { MILD, LARGE, THIN, KINDS };

/* 3 × 64 separate triangles of about 1 cm at the origin (they do not
 * touch: only their own vertices), E = 10 kPa, ν = 0.45, 1 mm thick, every
 * other one damped (β = 0.01 s): each mapped by A = R0 diag(s) R1 from its
 * rest shape, kind k of them with s in [0.9, 1.1] (mild), [0.5, 2]
 * (large), or with two of them in [1e-4, 1e-2] (thin: nearly a line),
 * moving at up to 0.1 m/s per corner. */
static void test_separate_membranes_match_reference(void** state) {
    (void)state;
    enum { COUNT = 64 * KINDS };
    const double h = 0.01;
    static const double corners[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    tu_rng rng = {7};
    sb_builder* b = sb_builder_create();
    double *x = malloc(3 * 3 * COUNT * sizeof *x), *v = malloc(3 * 3 * COUNT * sizeof *v);
    for (uint32_t t = 0; t < COUNT; t++) {
        double rest[3][3], s[3], A[9], R[9];
        int kind = (int)(t / (COUNT / KINDS)); /* in runs, so that most SIMD blocks hold one kind */
        singular_values(&rng, kind == MILD ? 0.9 : 0.5, kind == MILD ? 1.1 : 2.0, false, s);
        if (kind == THIN) s[1] = s[2] = exp(tu_uniform(&rng, log(1e-4), log(1e-2)));
        random_deformation(&rng, s, A, R);
        sb_membrane_def d = {
            .young_modulus = 1e4, .poisson_ratio = 0.45, .thickness = 1e-3, .stiffness_damping = t % 2 ? 0.01 : 0.0};
        for (int c = 0; c < 3; c++) {
            for (int a = 0; a < 3; a++) rest[c][a] = h * (corners[c][a] + tu_uniform(&rng, -0.2, 0.2));
            d.v[c] = (uint32_t)tu_vertex(b, rest[c][0], rest[c][1], rest[c][2], 1e-3, false);
            for (int a = 0; a < 3; a++) {
                double* p = x + 3 * (3 * t + c);
                p[a] = rest[0][a] + 0.5 * h;
                for (int k = 0; k < 3; k++) p[a] += A[3 * a + k] * (rest[c][k] - rest[0][k]);
                v[3 * (3 * t + c) + a] = tu_uniform(&rng, -0.1, 0.1);
            }
        }
        if (sb_builder_add_membrane(b, &d) < 0) fail_msg("sb_builder_add_membrane failed");
    }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    assert_membranes_match_reference(m, x, NULL, "separate triangles, still");
    assert_membranes_match_reference(m, x, v, "separate triangles, moving");
    free(x);
    free(v);
    sb_model_destroy(m);
}

/* A 10 × 10 cm sheet of 2 × 20 × 20 triangles (E = 10 kPa, ν = 0.45,
 * 1 mm thick, β = 0.001 s) held along one edge, sagging under gravity:
 * after 0.03 s of the reference's Verlet steps, its forces at its positions
 * and velocities. */
static void test_sheet_mid_motion_matches_reference(void** state) {
    (void)state;
    enum { N = 20 };
    const double h = 0.1 / N;
    sb_builder* b = sb_builder_create();
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) tu_vertex(b, i * h, j * h, 0.0, 1060.0 * h * h * 1e-3, i == 0);
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            uint32_t a = (uint32_t)(j * (N + 1) + i), c[4] = {a, a + 1, a + N + 1, a + N + 2};
            const uint32_t halves[2][3] = {{c[0], c[1], c[3]}, {c[0], c[3], c[2]}};
            for (int k = 0; k < 2; k++) {
                sb_membrane_def d = {.young_modulus = 1e4,
                                     .poisson_ratio = 0.45,
                                     .thickness = 1e-3,
                                     .stiffness_damping = 1e-3,
                                     .v = {halves[k][0], halves[k][1], halves[k][2]}};
                if (sb_builder_add_membrane(b, &d) < 0) fail_msg("sb_builder_add_membrane failed");
            }
        }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    sb_solver_def def = sb_default_solver_def();
    def.kernels = SB_KERNELS_REFERENCE;
    def.integrator = SB_INTEGRATOR_VERLET;
    sb_error err;
    sb_solver* solver = sb_solver_create(m, &def, &err);
    if (!solver) fail_msg("%s", err.message);
    for (int step = 0; step < 300; step++) assert_int_equal(sb_solver_advance(solver, 1e-4), SB_OK);
    uint32_t n = sb_model_vertex_count(m);
    double *x = malloc(3 * n * sizeof *x), *v = malloc(3 * n * sizeof *v);
    sb_solver_get_positions(solver, x);
    sb_solver_get_velocities(solver, v);
    sb_solver_destroy(solver);
    double sag = 0.0;
    for (uint32_t i = 0; i < n; i++) sag = fmax(sag, -x[3 * i + 2]);
    print_message("sheet: sagged %.3g m\n", sag);
    assert_true(sag > 1e-3);
    assert_membranes_match_reference(m, x, v, "sheet mid-motion");
    free(x);
    free(v);
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_separate_membranes_match_reference),
        cmocka_unit_test(test_sheet_mid_motion_matches_reference),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
