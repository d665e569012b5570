/* A thin sheet's membrane: co-rotated linear constant-strain triangles.
 *
 * The triangle's rest edges, written in its own plane (an orthonormal
 * frame of the rest triangle), give D_m (2 × 2); the current edges give
 * D_s (3 × 2) and F = D_s D_m⁻¹ (3 × 2) maps the rest plane into space.
 * F = R S with R (3 × 2) orthonormal columns and S = √(FᵀF) (2 × 2,
 * symmetric positive definite: √C = (C + √det C I) / √(tr C + 2 √det C)
 * in closed form). The energy is the linear plane-stress element's of the
 * unrotated strain S − I,
 *     V Ψ,  Ψ = μ ‖F − R‖² + ½ λ (tr S − 2)²,
 * V the rest area times the thickness, μ = E / 2(1 + ν) and the
 * plane-stress λ = E ν / (1 − ν²), so that a uniaxial stress σ gives
 * strain σ/E along and −ν σ/E across (E t / (1 − ν²) the stiffness of a
 * sheet stretched with its width held). The forces are its exact negative
 * gradient −V P D_m⁻ᵀ with P = 2μ (F − R) + λ (tr S − 2) R: R's variation
 * (a turn within the plane, or out of it) is orthogonal to F − R and to
 * F under the Frobenius product, as for the tetrahedron
 * (kernels/forces/corotated.h), so the term is conservative. Why
 * co-rotated linear and not StVK: StVK's energy in the Green strain
 * softens under compression (its resisting force peaks at 1/√3 of the
 * length and falls to zero as the element is flattened), which a draped
 * sheet meets everywhere, while this one is linear in the rotated strain
 * at any rotation, the same element as the tetrahedra's, and costs one
 * 2 × 2 square root.
 *
 * The stiffness is the co-rotated approximation (R's derivative left out):
 * with g_a the gradient of corner a's shape function in the rest plane
 * (g_1, g_2 the rows of D_m⁻¹, g_0 = −g_1 − g_2) and r_a = R g_a,
 *     K_ab = V (μ ((g_a·g_b) R Rᵀ + r_b r_aᵀ) + λ r_a r_bᵀ),
 * the plane element's K0 turned into the current plane (R Rᵀ the projector
 * on it: a flat triangle's corners moved out of its plane only turn it,
 * to first order). It is symmetric, positive semi-definite, and the
 * energy's exact Hessian at rest and at any rotation of it.
 *
 * Damping: Rayleigh's stiffness-proportional −β K v, as the tetrahedra's
 * (kernels/forces/corotated.h): K v is the divergence of the plane
 * viscous stress of the rotated strain rate M = Rᵀ Ḟ, so it costs one more
 * 2 × 2 stress, not the 9 × 9 matrix; zero for a translation and for a
 * rotation of the unstrained triangle. A mode of angular frequency ω
 * decays with ζ = β ω / 2. It damps the membrane's (in-plane) modes only:
 * the hinges' bending has no damping of its own. */
#include "kernels/forces/membrane.h"

#include <math.h>
#include <stddef.h>

/* F (3 × 2, row-major) and its rotation R: false when F has rank below 2. */
static bool sb_membrane_rotation(const double p[3][3], const double dm_inv[4], double F[6], double R[6],
                                 double* trace_s) {
    for (int i = 0; i < 3; i++) {
        double e1 = p[1][i] - p[0][i], e2 = p[2][i] - p[0][i];
        F[2 * i] = e1 * dm_inv[0] + e2 * dm_inv[2];
        F[2 * i + 1] = e1 * dm_inv[1] + e2 * dm_inv[3];
    }
    double c00 = 0.0, c01 = 0.0, c11 = 0.0;
    for (int i = 0; i < 3; i++) {
        c00 += F[2 * i] * F[2 * i];
        c01 += F[2 * i] * F[2 * i + 1];
        c11 += F[2 * i + 1] * F[2 * i + 1];
    }
    /* det C = |F₀ × F₁|² (F's columns): c00 c11 − c01² would square a thin
     * triangle's rounding */
    double n[3] = {F[2] * F[5] - F[4] * F[3], F[4] * F[1] - F[0] * F[5], F[0] * F[3] - F[2] * F[1]};
    double det = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (!isfinite(det) || !(det > 1e-24 * (c00 + c11) * (c00 + c11))) return false;
    double root = sqrt(det), scale = 1.0 / sqrt(c00 + c11 + 2.0 * root);
    double s00 = (c00 + root) * scale, s01 = c01 * scale, s11 = (c11 + root) * scale;
    double sdet = s00 * s11 - s01 * s01;
    double i00 = s11 / sdet, i01 = -s01 / sdet, i11 = s00 / sdet; /* S⁻¹ */
    for (int i = 0; i < 3; i++) {
        R[2 * i] = F[2 * i] * i00 + F[2 * i + 1] * i01;
        R[2 * i + 1] = F[2 * i] * i01 + F[2 * i + 1] * i11;
    }
    *trace_s = s00 + s11;
    return true;
}

/* Adds to P (3 × 2) the viscous stress β R (μ (M + Mᵀ) + λ tr(M) I),
 * M = Rᵀ Ḟ (2 × 2), Ḟ the corners' velocities v through D_m⁻¹: then
 * −V P D_m⁻ᵀ carries −β K v, K the co-rotated stiffness below (its blocks
 * summed against v). */
static void sb_membrane_viscous(const double v[3][3], const double dm_inv[4], const double R[6], double mu,
                                double lambda, double beta, double P[6]) {
    double Fdot[6], M[2][2];
    for (int i = 0; i < 3; i++) {
        double e1 = v[1][i] - v[0][i], e2 = v[2][i] - v[0][i];
        Fdot[2 * i] = e1 * dm_inv[0] + e2 * dm_inv[2];
        Fdot[2 * i + 1] = e1 * dm_inv[1] + e2 * dm_inv[3];
    }
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) M[a][b] = R[a] * Fdot[b] + R[2 + a] * Fdot[2 + b] + R[4 + a] * Fdot[4 + b];
    double trace = M[0][0] + M[1][1], S[2][2];
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) S[a][b] = beta * (mu * (M[a][b] + M[b][a]) + (a == b ? lambda * trace : 0.0));
    for (int i = 0; i < 3; i++)
        for (int b = 0; b < 2; b++) P[2 * i + b] += R[2 * i] * S[0][b] + R[2 * i + 1] * S[1][b];
}

/* The forces −V P D_m⁻ᵀ, with the damping's stress when v is given. */
static bool sb_membrane_forces(const double p[3][3], const double v[3][3], const double dm_inv[4], double volume,
                               double mu, double lambda, double beta, double f[3][3], double* energy) {
    double F[6], R[6], trace_s;
    if (!sb_membrane_rotation(p, dm_inv, F, R, &trace_s)) return false;
    double dilation = trace_s - 2.0, norm2 = 0.0, P[6];
    for (int q = 0; q < 6; q++) {
        double d = F[q] - R[q];
        norm2 += d * d;
        P[q] = 2.0 * mu * d + lambda * dilation * R[q];
    }
    if (v) sb_membrane_viscous(v, dm_inv, R, mu, lambda, beta, P);
    bool finite = true;
    for (int i = 0; i < 3; i++) {
        f[1][i] = -volume * (P[2 * i] * dm_inv[0] + P[2 * i + 1] * dm_inv[1]);
        f[2][i] = -volume * (P[2 * i] * dm_inv[2] + P[2 * i + 1] * dm_inv[3]);
        f[0][i] = -f[1][i] - f[2][i];
        finite &= isfinite(f[0][i]) != 0;
    }
    *energy = volume * (mu * norm2 + 0.5 * lambda * dilation * dilation);
    return finite;
}

bool sb_membrane_triangle(const double p[3][3], const double dm_inv[4], double volume, double mu, double lambda,
                          double f[3][3], double* energy) {
    return sb_membrane_forces(p, NULL, dm_inv, volume, mu, lambda, 0.0, f, energy);
}

bool sb_membrane_triangle_damped(const double p[3][3], const double v[3][3], const double dm_inv[4], double volume,
                                 double mu, double lambda, double beta, double f[3][3], double* energy) {
    return sb_membrane_forces(p, v, dm_inv, volume, mu, lambda, beta, f, energy);
}

bool sb_membrane_stiffness(const double p[3][3], const double dm_inv[4], double volume, double mu, double lambda,
                           double k[81]) {
    double F[6], R[6], trace_s;
    if (!sb_membrane_rotation(p, dm_inv, F, R, &trace_s)) return false;
    const double g[3][2] = {
        {-dm_inv[0] - dm_inv[2], -dm_inv[1] - dm_inv[3]}, {dm_inv[0], dm_inv[1]}, {dm_inv[2], dm_inv[3]}};
    double r[3][3], plane[3][3];
    for (int a = 0; a < 3; a++)
        for (int i = 0; i < 3; i++) r[a][i] = R[2 * i] * g[a][0] + R[2 * i + 1] * g[a][1];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) plane[i][j] = R[2 * i] * R[2 * j] + R[2 * i + 1] * R[2 * j + 1];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double gg = g[a][0] * g[b][0] + g[a][1] * g[b][1];
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    k[(3 * a + i) * 9 + 3 * b + j] =
                        volume * (mu * (gg * plane[i][j] + r[b][i] * r[a][j]) + lambda * r[a][i] * r[b][j]);
        }
    return true;
}
