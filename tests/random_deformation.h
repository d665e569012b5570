/* Random deformations with a known rotation, for the tests of the fast
 * elements (test_fast_tets.c, test_fast_membranes.c): F = R0 diag(s) R1,
 * whose rotation is R0 R1 (also with the last singular value negative,
 * the rotation an inverted element keeps). */
#ifndef RANDOM_DEFORMATION_H
#define RANDOM_DEFORMATION_H

#include "test_util.h"

/* A rotation from the unit quaternion along q. */
static inline void rotation(const double q[4], double R[9]) {
    double n = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    double w = q[0], x = q[1], y = q[2], z = q[3];
    double m[9] = {w * w + x * x - y * y - z * z, 2 * (x * y - w * z),           2 * (x * z + w * y),
                   2 * (x * y + w * z),           w * w - x * x + y * y - z * z, 2 * (y * z - w * x),
                   2 * (x * z - w * y),           2 * (y * z + w * x),           w * w - x * x - y * y + z * z};
    for (int k = 0; k < 9; k++) R[k] = m[k] / n;
}

static inline void random_rotation(tu_rng* rng, double R[9]) {
    double q[4];
    do {
        for (int k = 0; k < 4; k++) q[k] = tu_uniform(rng, -1, 1);
    } while (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] < 0.01);
    rotation(q, R);
}

static inline void multiply(const double a[9], const double b[9], double c[9]) {
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) c[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
}

/* F = R0 diag(s) R1 and its rotation R0 R1 (s descending, s[2] may be
 * negative). */
static inline void random_deformation(tu_rng* rng, const double s[3], double F[9], double R[9]) {
    double R0[9], R1[9], D[9] = {s[0], 0, 0, 0, s[1], 0, 0, 0, s[2]}, T[9];
    random_rotation(rng, R0);
    random_rotation(rng, R1);
    multiply(R0, D, T);
    multiply(T, R1, F);
    multiply(R0, R1, R);
}

/* Three singular values from [lo, hi] (log-uniform), descending; the last
 * one's sign flipped when `inverted`. */
static inline void singular_values(tu_rng* rng, double lo, double hi, bool inverted, double s[3]) {
    for (int k = 0; k < 3; k++) s[k] = exp(tu_uniform(rng, log(lo), log(hi)));
    for (int a = 0; a < 3; a++)
        for (int b = a + 1; b < 3; b++)
            if (s[b] > s[a]) {
                double t = s[a];
                s[a] = s[b];
                s[b] = t;
            }
    if (inverted) s[2] = -s[2];
}

/* The fast kernels' forces and energy term at (x, v) (v may be NULL)
 * against the reference's on the free vertices of m: each vertex's error
 * within `tolerance` ε times scale[i], the energy's within tolerance ε
 * times energy_scale; `what` names the case. */
static inline void expect_fast_matches_reference(const sb_model* m, const double* x, const double* v,
                                                 const double* scale, double energy_scale, sb_term term,
                                                 double tolerance, const char* what) {
    uint32_t n = sb_model_vertex_count(m);
    double *f = malloc(3 * n * sizeof *f), *fast = malloc(3 * n * sizeof *fast);
    sb_energies reference;
    sb_error err;
    assert_int_equal(sb_reference_forces(m, x, v, f, &reference, &err), SB_OK);
    sb_solver_def def = sb_default_solver_def();
    def.kernels = SB_KERNELS_FAST;
    def.runtime.threads = 2;
    def.gravity[2] = 0.0;
    sb_solver* solver = sb_solver_create(m, &def, &err);
    if (!solver) fail_msg("%s", err.message);
    assert_int_equal(sb_solver_set_state(solver, x, v), SB_OK);
    sb_solver_get_forces(solver, fast);
    double worst = 0.0, largest = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        if (sb_model_is_fixed(m, i)) continue; /* a solver's forces there are not the reference's */
        double d[3] = {fast[3 * i] - f[3 * i], fast[3 * i + 1] - f[3 * i + 1], fast[3 * i + 2] - f[3 * i + 2]};
        worst = fmax(worst, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / (TU_REAL_EPS * scale[i]));
        largest = fmax(largest, fabs(f[3 * i]) + fabs(f[3 * i + 1]) + fabs(f[3 * i + 2]));
    }
    double e = sb_solver_energies(solver).term[term], e_ref = reference.term[term];
    print_message("%s: largest force error %.3g eps of its scale, energy %.6g J against %.6g J (%.3g eps)\n", what,
                  worst, e, e_ref, fabs(e - e_ref) / (TU_REAL_EPS * energy_scale));
    assert_true(largest > 0.0 && e_ref > 0.0);
    TU_ASSERT_LE(worst, tolerance);
    TU_ASSERT_NEAR(e, e_ref, tolerance * TU_REAL_EPS * energy_scale);
    sb_solver_destroy(solver);
    free(f);
    free(fast);
}

#endif
