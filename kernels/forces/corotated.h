/* Private: one co-rotated linear tetrahedron (Müller & Gross 2004), shared
 * by the scalar reference (reference_tets.c) and the fast path's pass
 * (fast_tets.c), both in double.
 *
 * F = D_s D_m⁻¹, F = R S its polar decomposition (R a rotation even when
 * the element is inverted: from F's singular value decomposition with the
 * last singular value's sign carried, Irving, Teran & Fedkiw 2004). The
 * energy is Müller & Gross's ½ (Rᵀx − x0)ᵀ K0 (Rᵀx − x0) = V Ψ,
 * Ψ = μ ‖F − R‖² + ½ λ (tr(RᵀF) − 3)² (the linear element's energy of the
 * unrotated displacement, whose strain is S − I); the forces are its exact
 * negative gradient, −V P D_m⁻ᵀ with P = 2μ (F − R) + λ (tr(RᵀF) − 3) R
 * (McAdams et al. 2011), so the term is conservative (Müller & Gross's
 * f = −R K0 (Rᵀx − x0) holds R constant, which is not). */
#ifndef SB_COROTATED_H
#define SB_COROTATED_H

#include <stdbool.h>

/* Positions of the four corners p[c][axis]; dm_inv row-major; adds nothing,
 * writes the four forces to f and returns the energy. false when F is not
 * finite. */
bool sb_corotated_tet(const double p[4][3], const double dm_inv[9], double volume, double mu, double lambda,
                      double f[4][3], double* energy);

/* The co-rotated stiffness R K0 Rᵀ at the corners p (12 × 12 row-major,
 * corner-major: row 3 a + i is corner a's axis i), R of F at p
 * (kernels/forces/hessian_tets.c says what it is and leaves out). false
 * when it is not finite. */
bool sb_corotated_stiffness(const double p[4][3], const double dm_inv[9], double volume, double mu, double lambda,
                            double k[144]);

/* sb_corotated_tet with Rayleigh's stiffness-proportional damping: adds
 * −β R K0 Rᵀ v to the forces (v the corners' velocities, R the rotation at
 * p, the same as the elastic forces'), the divergence of the viscous stress
 * β (μ (L + Lᵀ) + λ tr(L) I), L = Ḟ Rᵀ: zero for a translation and for a
 * rotation of the unstrained element. false when F or Ḟ is not finite. */
bool sb_corotated_tet_damped(const double p[4][3], const double v[4][3], const double dm_inv[9], double volume,
                             double mu, double lambda, double beta, double f[4][3], double* energy);

/* R of F = R S (row-major 3 × 3), as above. */
void sb_corotated_rotation(const double F[9], double R[9]);

#endif
