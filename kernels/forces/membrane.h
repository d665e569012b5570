/* Private: one co-rotated linear constant-strain triangle, a thin sheet's
 * membrane (kernels/forces/membrane.c says the model), shared by the scalar
 * reference (reference_membranes.c) and the Hessian (hessian_membranes.c),
 * in double. */
#ifndef SB_MEMBRANE_H
#define SB_MEMBRANE_H

#include <stdbool.h>

/* Positions of the three corners p[c][axis]; dm_inv the rest edges' 2 × 2
 * inverse (row-major) in the rest triangle's own plane; volume its rest
 * area times the thickness; mu and lambda the plane-stress Lamé constants
 * (μ = E / 2(1 + ν), λ = E ν / (1 − ν²)). Writes the three forces to f and returns the energy
 * in *energy; false when the triangle collapsed (nothing written). */
bool sb_membrane_triangle(const double p[3][3], const double dm_inv[4], double volume, double mu, double lambda,
                          double f[3][3], double* energy);

/* sb_membrane_triangle with Rayleigh's stiffness-proportional damping:
 * adds −β K v (v the corners' velocities, K the stiffness below at p) to
 * the forces. false when the triangle collapsed or a force is not
 * finite. */
bool sb_membrane_triangle_damped(const double p[3][3], const double v[3][3], const double dm_inv[4], double volume,
                                 double mu, double lambda, double beta, double f[3][3], double* energy);

/* The co-rotated stiffness at the corners p (9 × 9 row-major,
 * corner-major: row 3 a + i is corner a's axis i); false when the triangle
 * collapsed. */
bool sb_membrane_stiffness(const double p[3][3], const double dm_inv[4], double volume, double mu, double lambda,
                           double k[81]);

#endif
