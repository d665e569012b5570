/* Private: the rotation R of F = R S, lane-wise over kernels/runtime/wide.h,
 * for the fast pass of the co-rotated tetrahedra (kernels/forces/fast_tets.c).
 *
 * Higham's Newton iteration X ← ½ (ζ X + ζ⁻¹ X⁻ᵀ) from X = F, X⁻ᵀ its
 * cofactor matrix over its determinant: the same operations in every lane,
 * a fixed number of steps, no branch. ζ = (‖X⁻¹‖_F / ‖X‖_F)^½ (Higham's
 * Frobenius scaling) in the first SB_POLAR_SCALED steps, which brings the
 * singular values together fast from any stretch; then plain steps, which
 * converge quadratically. The iteration's answer depends only on F's
 * singular values, not on its rotation. For det F > 0 it converges to the
 * reference's R (kernels/forces/corotated.c, from an SVD by Jacobi sweeps):
 * against it, over 10⁵ random rotations of singular values in [0.5, 2]
 * (strains of −50 % to +100 %), 5 steps reach 1.4e-15 and 4 steps 1.5e-9;
 * in [0.1, 5], 6 steps reach 4e-14 (the reference's own rounding there)
 * and 5 steps 1.4e-10. So SB_POLAR_STEPS is 6 in double and 5 in float.
 *
 * An inverted element (det F <= 0) has no such limit among rotations (the
 * iteration goes to the orthogonal U Vᵀ, whose determinant is −1, where the
 * reference flips the last singular value to keep a rotation), and a
 * nearly flat one may not converge in the fixed count. Both are told, per
 * lane, by sb_w_polar's mask: det F below the smallest normal number, or a
 * last step whose changes of X's entries sum to more than √ε (a converged
 * step's error is about the square of the one before). The caller computes
 * such lanes by the reference's element instead (fast_tets.c does so for
 * the whole block): they are rare in a body that works, and the answer is
 * then the reference's, for any thread count. */
#ifndef SB_WIDE_POLAR_H
#define SB_WIDE_POLAR_H

#include "kernels/runtime/wide.h"

#include <float.h>

enum { SB_POLAR_SCALED = 3, SB_POLAR_STEPS = SB_DOUBLE ? 6 : 5 };

/* C = the cofactors of X (row-major 3 × 3, so X⁻ᵀ = C / det X); returns
 * det X. */
static inline sb_wide sb_w_cofactors(const sb_wide X[9], sb_wide C[9]) {
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
            C[3 * r + c] = sb_w_sub(sb_w_mul(X[3 * r1 + c1], X[3 * r2 + c2]), sb_w_mul(X[3 * r1 + c2], X[3 * r2 + c1]));
        }
    return sb_wv_dot((sb_wvec3){X[0], X[1], X[2]}, (sb_wvec3){C[0], C[1], C[2]});
}

/* ζ of the scaled step: (‖C‖_F / (‖X‖_F |det X|))^½ = (‖X⁻¹‖_F / ‖X‖_F)^½. */
static inline sb_wide sb_w_polar_scale(const sb_wide X[9], const sb_wide C[9], sb_wide det) {
    sb_wide x2 = sb_w_set(0), c2 = sb_w_set(0);
    for (int k = 0; k < 9; k++) {
        x2 = sb_w_add(x2, sb_w_mul(X[k], X[k]));
        c2 = sb_w_add(c2, sb_w_mul(C[k], C[k]));
    }
    return sb_w_sqrt(sb_w_div(sb_w_sqrt(sb_w_div(c2, x2)), sb_w_abs(det)));
}

/* One step on X; returns det X before it, and in *change the sum of its
 * entries' changes (a sum, not a max, so that a NaN is kept). */
static inline sb_wide sb_w_polar_step(sb_wide X[9], bool scaled, sb_wide* change) {
    sb_wide C[9], det = sb_w_cofactors(X, C), half = sb_w_set((sb_real)0.5);
    sb_wide zeta = scaled ? sb_w_polar_scale(X, C, det) : sb_w_set(1);
    sb_wide a = sb_w_mul(half, zeta), b = sb_w_div(half, sb_w_mul(zeta, det));
    *change = sb_w_set(0);
    for (int k = 0; k < 9; k++) {
        sb_wide next = sb_w_add(sb_w_mul(a, X[k]), sb_w_mul(b, C[k]));
        *change = sb_w_add(*change, sb_w_abs(sb_w_sub(next, X[k])));
        X[k] = next;
    }
    return det;
}

/* R of F = R S (row-major); the lanes whose R is not the reference's
 * (inverted, flat, or not finite), as the file's note says. */
static inline sb_wmask sb_w_polar(const sb_wide F[9], sb_wide R[9]) {
    for (int k = 0; k < 9; k++) R[k] = F[k];
    sb_wide change, det = sb_w_polar_step(R, SB_POLAR_SCALED > 0, &change);
    for (int step = 1; step < SB_POLAR_STEPS; step++) sb_w_polar_step(R, step < SB_POLAR_SCALED, &change);
    const sb_real epsilon = SB_DOUBLE ? (sb_real)DBL_EPSILON : (sb_real)FLT_EPSILON;
    sb_wmask flat = sb_w_less(det, sb_w_set(SB_DOUBLE ? (sb_real)DBL_MIN : (sb_real)FLT_MIN));
    return flat | sb_w_less(sb_w_set((sb_real)sqrt(epsilon)), change);
}

#endif
