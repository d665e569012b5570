/* Private: one co-rotated quadratic tetrahedron (10 nodes: the corners,
 * then the middles of the edges 01 02 03 12 13 23), shared by the scalar
 * reference (reference_tets.c), the fast path's pass (fast_tets.c) and the
 * stiffness (hessian_tets.c), in double.
 *
 * Why quadratic: the linear tetrahedron's strain is constant, so a bent
 * beam's linearly varying strain costs it shear and, near
 * incompressibility, volume change it cannot avoid: it locks (docs/
 * materials.md measures −39 % in bending at 525 vertices, ν 0.45). The
 * quadratic element's strain is linear over it, which bending needs.
 *
 * The element (Müller & Gross 2004's co-rotation over the quadratic
 * element's K0): straight edges, so the rest shape is the corners' (D_m)
 * and each middle node rests at its edge's middle; the shape functions in
 * the barycentric L_i are N_i = L_i (2 L_i − 1) at corner i and
 * N_ij = 4 L_i L_j at the middle of ij, their gradients
 * (4 L_i − 1) g_i and 4 (L_i g_j + L_j g_i) (g_i: the linear element's
 * gradients, from D_m⁻¹). K0 is linear elasticity's
 * ∫ Bᵀ C B dV, by the four-point Gauss rule (degree 2, exact: B is linear),
 * applied matrix-free: at each point the strain ε of the unrotated
 * displacement u'_a = Rᵀ(x_a − x_0) − (X_a − X_0), the stress
 * σ = 2μ ε + λ tr(ε) I, f'_a = −Σ w V σ ∇N_a, and f_a = R f'_a; so
 * f = −R K0 (Rᵀx − X), R held (not differentiated): the forces are not the
 * energy's exact gradient (E = ½ u'ᵀ K0 u', reported) but balance and
 * conserve momentum, and equal it at small strain. R is the rotation of
 * the polar decomposition of the corners' deformation gradient F (the
 * linear element's, corotated.h's sb_corotated_rotation): one rotation per
 * element, from the corners only. */
#ifndef SB_COROTATED_QUADRATIC_H
#define SB_COROTATED_QUADRATIC_H

#include <stdbool.h>

enum { SB_QUAD_NODES = 10, SB_QUAD_DOFS = 30 };

/* Positions of the ten nodes p[a][axis]; writes their forces to f and
 * returns the energy ½ u'ᵀ K0 u'. false when F is not finite. */
bool sb_corotated_quadratic_tet(const double p[SB_QUAD_NODES][3], const double dm_inv[9], double volume, double mu,
                                double lambda, double f[SB_QUAD_NODES][3], double* energy);

/* sb_corotated_quadratic_tet with Rayleigh's stiffness-proportional
 * damping: adds −β R K0 Rᵀ v (v the nodes' velocities, R the rotation at
 * p, the same as the elastic forces'), K0 applied matrix-free to β Rᵀ v
 * as to the displacement. false when F or the forces are not finite. */
bool sb_corotated_quadratic_tet_damped(const double p[SB_QUAD_NODES][3], const double v[SB_QUAD_NODES][3],
                                       const double dm_inv[9], double volume, double mu, double lambda, double beta,
                                       double f[SB_QUAD_NODES][3], double* energy);

/* R K0 Rᵀ at p (30 × 30 row-major, node-major: row 3 a + i is node a's
 * axis i): the exact Jacobian −∂f/∂x of the forces above but for R's
 * derivative. Symmetric, positive semi-definite. false when not finite. */
bool sb_corotated_quadratic_stiffness(const double p[SB_QUAD_NODES][3], const double dm_inv[9], double volume,
                                      double mu, double lambda, double k[SB_QUAD_DOFS * SB_QUAD_DOFS]);

#endif
