/* Private: exact second derivatives of the internal forces, for the
 * implicit integrators.
 *
 * An element is what one term couples: a bond (2 vertices: bond stretch and
 * the damped spring's elastic part), a triangle (3: its three corners' angle
 * bend and stretch-bend) or a hinge (4). Each term's force formula is run on
 * dual numbers (common/dual.h): seeded with positions x + ε p it returns the
 * element's forces and their exact directional derivative ∂f/∂x · p. From
 * that one function per term come the element stiffness matrix K_e = −∂f/∂x
 * (3n seeds, kernels/forces/hessian.c) and its product with a vector (one seed);
 * bonds' and triangles' matrices, and every element's vertex share, are
 * also written in closed form.
 *
 * The stiffness is the Hessian of the elastic energy, symmetric. The damped
 * spring's force also depends on x through its direction; that part of
 * ∂f/∂x is not symmetric and is left out (as Baraff and Witkin do): the
 * solvers that use K keep the exact residual, so it costs iterations, never
 * accuracy. Its velocity Jacobian, D = −∂f/∂v = d u uᵀ per spring, is exact.
 *
 * A co-rotated tetrahedron (4 vertices, or 10 when quadratic) is the exception: its stiffness is
 * the co-rotated approximation R K0 Rᵀ (kernels/forces/hessian_tets.c),
 * which leaves out the derivative of the element's rotation R. It is
 * symmetric and positive semi-definite, exact at rest and at any rotation
 * of it, and off by terms that grow with the stress under strain; its
 * "dual" forces (sb_element_forces_dual) are the exact forces with the
 * derivative part −R K0 Rᵀ p, so that every function below serves it by
 * that matrix. As with the spring's left-out part, the solvers keep the
 * exact residual: it costs iterations, not accuracy.
 *
 * This header: the elements and their functions (kernels/forces/hessian.c),
 * which call each term family's, declared in its own header:
 * kernels/forces/hessian_edges.h (the bond's), hessian_corners.h (the
 * triangle's), hessian_hinges.h (the hinge's) and hessian_tets.h (the
 * tetrahedron's). */
#ifndef SB_HESSIAN_H
#define SB_HESSIAN_H

#include "common/dual.h"
#include "mesh/model_internal.h"

typedef enum sb_element_kind {
    SB_ELEMENT_BOND,
    SB_ELEMENT_TRIANGLE,
    SB_ELEMENT_HINGE,
    SB_ELEMENT_TET,
    SB_ELEMENT_MEMBRANE,
    SB_ELEMENT_PLATE
} sb_element_kind;

enum { SB_ELEMENT_MAX = SB_TET_NODES };                           /* a quadratic tetrahedron's 10 */
enum { SB_ELEMENT_MATRIX = 9 * SB_ELEMENT_MAX * SB_ELEMENT_MAX }; /* the largest element matrix, doubles */

typedef struct sb_element {
    sb_element_kind kind;
    uint32_t index; /* bond, triangle, hinge, tetrahedron, membrane or plate index in the model */
    int count;      /* vertices */
    uint32_t vertex[SB_ELEMENT_MAX];
} sb_element;

/* Elements are numbered bonds, then triangles, then hinges, then
 * tetrahedra, then membranes (a sheet's triangles, 3 vertices: like a
 * tetrahedron, one co-rotated matrix, kernels/forces/hessian_membranes.c),
 * then plates (a flat sheet's bending, one per membrane, up to
 * SB_PLATE_NODES vertices, none where the membrane has no plate: one
 * constant matrix, kernels/forces/plate.c). */
uint64_t sb_element_count(const sb_model* m);
sb_element sb_element_at(const sb_model* m, uint64_t e);

/* The element's elastic forces at the dual positions x[0..count): value and
 * derivative parts in f. False when an edge or a wing collapsed (f is then
 * not written). Terms the model disables contribute nothing. */
bool sb_element_forces_dual(const sb_model* m, const sb_element* e, const sb_dvec3* x, sb_dvec3* f);

/* K_e = −∂f_e/∂x at x (3n interleaved), row-major 3 count × 3 count in k
 * (at most 30 × 30). False when the element collapsed. Bonds and triangles
 * in closed form (sb_bond_stiffness_matrix, sb_triangle_stiffness: several
 * times faster than the 12-seed dual run), hinges by the dual run. */
bool sb_element_stiffness(const sb_model* m, const sb_element* e, const double* x, double* k);

/* Vertex `place` of the element (at x, 3n interleaved): adds its exact
 * force to f and its diagonal block of sb_element_stiffness_definite's
 * stand-in (below) to block (3 × 3); false when the element collapsed
 * (nothing added). What vbd needs, in closed form: the block is positive
 * semi-definite, so that a vertex's Newton step is a descent direction on
 * the incremental potential (a compressed bond without its negative
 * sideways stiffness, each triangle corner's λ w wᵀ, a hinge's k u_p u_pᵀ
 * with u_p = −∇_p φ; kernels/integrators/vbd.c says why). */
bool sb_element_vertex_share(const sb_model* m, const sb_element* e, const double* x, int place, double* f,
                             double* block);

/* A positive semi-definite stand-in for K_e (the definiteness fix of
 * implicit Euler), equal to K_e at the rest shape wherever K_e is positive
 * semi-definite there (a tetrahedron's is its R K0 Rᵀ):
 *   bond: k (u uᵀ + max(0, 1 − r0/r)(I − u uᵀ)) per block, K_e's own
 *     projection (a compressed bond loses its negative sideways stiffness);
 *   triangle: per corner, the quadratic form of its energy in (c − c0, S),
 *     [[kθ, ksb], [ksb, 0]] — indefinite whenever ksb ≠ 0 — keeps its
 *     positive eigenvalue λ with eigenvector (p, q): λ w wᵀ with
 *     w = p ∇c + q ∇S (Gauss-Newton on the projected form);
 *   hinge: k ∇φ ∇φᵀ, the geometric term k (φ − φ0) ∇²φ left out.
 * Each costs about what its forces cost, where an eigendecomposition of a
 * 12 × 12 matrix per hinge would cost a hundred times more. */
bool sb_element_stiffness_definite(const sb_model* m, const sb_element* e, const double* x, double* k);
/* k += scale w wᵀ (w of `size` entries, k row-major size × size). */
static inline void sb_add_outer(double* k, int size, const double* w, double scale) {
    for (int r = 0; r < size; r++)
        for (int c = 0; c < size; c++) k[r * size + c] += scale * w[r] * w[c];
}

/* The element's share of implicit Euler's J = M + dt D + dt² K as its
 * count × count 3 × 3 blocks, block-major (block (r, c) of the local
 * vertices at blocks + 9 (count r + c), row-major): dt² K_e
 * (sb_element_stiffness; the stand-in of sb_element_stiffness_definite
 * when `definite`, and a hinge's always: its geometric term
 * k (φ − φ0) ∇²φ is small beside k ∇φ ∇φᵀ wherever the fold is small,
 * its dual run is dear, and Newton and CG took the same iterations without
 * it: bench/results/notes/implicit_euler.md), and on a bond also dt times its spring's damping block. The
 * triangle's in closed form in the plane of each corner's edges (each
 * block of a corner is a multiple of I plus a 2 × 2 form in â, b̂), the
 * hinge's without its angle (no atan2). False when the element collapsed. */
bool sb_element_jacobian_blocks(const sb_model* m, const sb_element* e, const double* x, bool definite, double dt,
                                double* blocks);

/* out = K p over every element (3n interleaved); false when one collapsed. */
bool sb_stiffness_product(const sb_model* m, const double* x, const double* p, double* out);

#endif
