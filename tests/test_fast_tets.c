/* The lane-wise co-rotated tetrahedra of the fast kernels
 * (kernels/forces/fast_tets.c) against closed forms and the scalar
 * reference (kernels/forces/corotated.c, in double):
 *
 * - the polar iteration (kernels/forces/wide_polar.h) on F = R0 diag(s) R1,
 *   whose rotation is R0 R1 by construction (also with the last singular
 *   value negative: an inverted element, the rotation the reference keeps),
 *   to rounding for the strains a tissue sees, and the inverted lanes told;
 * - the forces and energy of separate tetrahedra strained, turned, nearly
 *   flat and inverted, damped and not, and of a body of tissue in the middle
 *   of its motion, against the reference's, within a bound of rounding:
 *   per vertex TOLERANCE ε times the stresses' scale of its elements,
 *   V (2μ + 3λ) ‖D_m⁻¹‖ (‖F‖ + √3 + 2 ‖D_m⁻¹‖ |x|max + β ‖Ḟ‖), ε of
 *   sb_real (the third term: F's rounding from the positions' in sb_real,
 *   |x|max the element's largest coordinate). */
#include "test_util.h"
#include "random_deformation.h"

#include "kernels/forces/fast_model.h"
#include "kernels/forces/wide_polar.h"

#include <stdio.h>

enum { TOLERANCE = 4 };

/* SB_WIDTH deformations at a time through sb_w_polar: the largest error of
 * R's entries over `samples` of them, and how many lanes were told. */
static double polar_error(double lo, double hi, bool inverted, int samples, int* told) {
    tu_rng rng = {lo < 0.3 ? 21u : 22u};
    double worst = 0.0;
    *told = 0;
    for (int done = 0; done < samples; done += SB_WIDTH) {
        sb_real lanes[9][SB_WIDTH];
        double expected[SB_WIDTH][9];
        for (int l = 0; l < SB_WIDTH; l++) {
            double s[3], F[9];
            singular_values(&rng, lo, hi, inverted, s);
            random_deformation(&rng, s, F, expected[l]);
            for (int k = 0; k < 9; k++) lanes[k][l] = (sb_real)F[k];
        }
        sb_wide F[9], R[9];
        for (int k = 0; k < 9; k++) F[k] = sb_w_load(lanes[k]);
        sb_wmask mask = sb_w_polar(F, R);
        for (int l = 0; l < SB_WIDTH; l++) *told += (int)((unsigned)mask >> l & 1u); /* a bit a lane */
        for (int k = 0; k < 9; k++) {
            sb_w_store(lanes[k], R[k]);
            for (int l = 0; l < SB_WIDTH; l++) worst = fmax(worst, fabs((double)lanes[k][l] - expected[l][k]));
        }
    }
    return worst;
}

/* Strains of −50 % to +100 % converge to rounding (the rounding of F itself
 * is ε ‖F‖, and R's is that over the sum of two singular values), and so do
 * the nearly flat ones of [0.1, 5]; no lane is told. Inverted elements are
 * all told, for the reference to compute. */
static void test_polar_converges(void** state) {
    (void)state;
    int told;
    double tissue = polar_error(0.5, 2.0, false, 20000, &told);
    print_message("polar, singular values in [0.5, 2]: largest error %.3g (%.3g eps), %d told\n", tissue,
                  tissue / TU_REAL_EPS, told);
    TU_ASSERT_LE(tissue, 16 * TU_REAL_EPS);
    assert_int_equal(told, 0);
    double wide = polar_error(0.1, 5.0, false, 20000, &told);
    print_message("polar, singular values in [0.1, 5]: largest error %.3g (%.3g eps), %d told\n", wide,
                  wide / TU_REAL_EPS, told);
    TU_ASSERT_LE(wide, 256 * TU_REAL_EPS);
    assert_int_equal(told, 0);
    polar_error(0.5, 2.0, true, 2000, &told);
    assert_int_equal(told, 2000 + (SB_WIDTH - 2000 % SB_WIDTH) % SB_WIDTH);
}

/* ---- forces against the reference ------------------------------------- */

static double norm9(const double a[9]) {
    double s = 0.0;
    for (int k = 0; k < 9; k++) s += a[k] * a[k];
    return sqrt(s);
}

/* D_s D_m⁻¹ of tetrahedron t at the positions (or velocities) x. */
static void deformation(const sb_model* m, uint32_t t, const double* x, double F[9]) {
    const uint32_t* v[4] = {m->tet_v[0], m->tet_v[1], m->tet_v[2], m->tet_v[3]};
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) {
            F[3 * r + k] = 0.0;
            for (int c = 0; c < 3; c++)
                F[3 * r + k] += (x[3 * v[c + 1][t] + r] - x[3 * v[0][t] + r]) * m->tet_dm_inv[3 * c + k][t];
        }
}

/* The fast forces and energy at (x, v) against the reference's, within the
 * file's bound; `what` names the case. */
static void assert_tets_match_reference(const sb_model* m, const double* x, const double* v, const char* what) {
    uint32_t n = sb_model_vertex_count(m);
    double* scale = calloc(n, sizeof *scale);
    double energy_scale = 0.0;
    for (uint32_t t = 0; t < m->tet_count; t++) {
        double F[9], Fdot[9] = {0}, dm = 0.0, far = 0.0;
        deformation(m, t, x, F);
        if (v) deformation(m, t, v, Fdot);
        for (int k = 0; k < 9; k++) dm += m->tet_dm_inv[k][t] * m->tet_dm_inv[k][t];
        for (int c = 0; c < 4; c++)
            for (int a = 0; a < 3; a++) far = fmax(far, fabs(x[3 * m->tet_v[c][t] + a]));
        double stiffness = m->tet_volume[t] * (2.0 * m->tet_mu[t] + 3.0 * m->tet_lambda[t]);
        double stress = norm9(F) + sqrt(3.0) + 2.0 * far * sqrt(dm);
        for (int c = 0; c < 4; c++)
            scale[m->tet_v[c][t]] += stiffness * sqrt(dm) * (stress + m->tet_beta[t] * norm9(Fdot));
        energy_scale += stiffness * stress * stress;
    }
    expect_fast_matches_reference(m, x, v, scale, energy_scale, SB_TERM_COROTATED, TOLERANCE, what);
    free(scale);
}

/* How the separate tetrahedra of the next test are deformed, by number. */
enum { MILD, LARGE, FLAT, INVERTED, KINDS };

/* 4 × 64 separate tetrahedra of about 1 cm at the origin (they do not
 * touch: only their own vertices), E = 3.5 kPa, ν = 0.45, every
 * other one damped (β = 0.01 s): each placed at F = R0 diag(s) R1 of its
 * rest shape, kind k of them with s in [0.9, 1.1] (mild), [0.5, 2]
 * (large), with the last in [0.02, 0.1] (nearly flat) or in
 * [−0.5, −0.05] (inverted), moving at up to 0.1 m/s per corner. The
 * kinds come in runs of 64, so that the SIMD blocks of the first three run
 * lane-wise and the inverted ones' by the reference's element. */
static void test_separate_tets_match_reference(void** state) {
    (void)state;
    enum { COUNT = 64 * KINDS };
    const double h = 0.01;
    static const double corners[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tu_rng rng = {5};
    sb_builder* b = sb_builder_create();
    double *x = malloc(3 * 4 * COUNT * sizeof *x), *v = malloc(3 * 4 * COUNT * sizeof *v);
    for (uint32_t t = 0; t < COUNT; t++) {
        double rest[4][3], s[3], F[9], R[9];
        int kind = (int)(t / (COUNT / KINDS)); /* in runs, so that most SIMD blocks hold one kind */
        singular_values(&rng, kind == MILD ? 0.9 : 0.5, kind == MILD ? 1.1 : 2.0, kind == INVERTED, s);
        if (kind == FLAT) s[2] = tu_uniform(&rng, 0.02, 0.1);
        if (kind == INVERTED) s[2] = -tu_uniform(&rng, 0.05, 0.5);
        random_deformation(&rng, s, F, R);
        sb_tet_def d = {.young_modulus = 3500.0, .poisson_ratio = 0.45, .stiffness_damping = t % 2 ? 0.01 : 0.0};
        for (int c = 0; c < 4; c++) {
            for (int a = 0; a < 3; a++) rest[c][a] = h * (corners[c][a] + tu_uniform(&rng, -0.2, 0.2));
            d.v[c] = (uint32_t)tu_vertex(b, rest[c][0], rest[c][1], rest[c][2], 1e-3, false);
            for (int a = 0; a < 3; a++) {
                double* p = x + 3 * (4 * t + c);
                p[a] = rest[0][a] + 0.5 * h;
                for (int k = 0; k < 3; k++) p[a] += F[3 * a + k] * (rest[c][k] - rest[0][k]);
                v[3 * (4 * t + c) + a] = tu_uniform(&rng, -0.1, 0.1);
            }
        }
        if (sb_builder_add_tet(b, &d) < 0) fail_msg("sb_builder_add_tet failed");
    }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    assert_tets_match_reference(m, x, NULL, "separate tetrahedra, still");
    assert_tets_match_reference(m, x, v, "separate tetrahedra, moving");
    free(x);
    free(v);
    sb_model_destroy(m);
}

/* A 10 × 4 × 4 cm block of tissue (E = 3.5 kPa, ν = 0.45, 960
 * tetrahedra) clamped at one end, sagging under gravity: after 0.04 s of
 * the reference's Verlet steps, its forces at its positions and
 * velocities. */
static void test_body_mid_motion_matches_reference(void** state) {
    (void)state;
    sb_model* m = tu_tet_block(10, 4, 4, 0.01, 3500.0, 0.45, 0.15, 3, true);
    sb_solver_def def = sb_default_solver_def();
    def.kernels = SB_KERNELS_REFERENCE;
    def.integrator = SB_INTEGRATOR_VERLET;
    sb_error err;
    sb_solver* solver = sb_solver_create(m, &def, &err);
    if (!solver) fail_msg("%s", err.message);
    for (int step = 0; step < 200; step++) assert_int_equal(sb_solver_advance(solver, 2e-4), SB_OK);
    uint32_t n = sb_model_vertex_count(m);
    double *x = malloc(3 * n * sizeof *x), *v = malloc(3 * n * sizeof *v), *rest = tu_rest_positions(m);
    sb_solver_get_positions(solver, x);
    sb_solver_get_velocities(solver, v);
    sb_solver_destroy(solver);
    double sag = 0.0;
    for (uint32_t i = 0; i < n; i++) sag = fmax(sag, rest[3 * i + 2] - x[3 * i + 2]);
    print_message("body: sagged %.3g m\n", sag);
    assert_true(sag > 1e-3);
    assert_tets_match_reference(m, x, v, "body mid-motion");
    free(x);
    free(v);
    free(rest);
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_polar_converges),
        cmocka_unit_test(test_separate_tets_match_reference),
        cmocka_unit_test(test_body_mid_motion_matches_reference),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
