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

#endif
