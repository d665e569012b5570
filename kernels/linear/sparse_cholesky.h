/* Private: a sparse direct solve of the block matrix (kernels/linear/block_matrix.h)
 * by a supernodal Cholesky factorization on CHOLMOD's analysis (SuiteSparse),
 * for implicit Euler's Newton systems on models small enough to factor. The
 * factor is kept in float: a solve is accurate to float's rounding (a
 * relative residual about 3e-7 on well-conditioned matrices), which a
 * modified Newton with the exact residual absorbs; refining in double
 * (x += solve(b − A x)) gains as much again each sweep.
 *
 * The fill-reducing ordering (AMD) and the factor's pattern come from the
 * block matrix's pattern once (cholmod_analyze), and again only when tearing
 * changed it; the workspace and the first factorization happen there too,
 * so that later ones only compute numbers in memory already allocated: a
 * step never allocates. Rows and columns of vertices that do not move
 * (mask 0) are replaced by the identity's, so the solution is 0 there. The
 * numeric factorization and the solve are kernels/linear/sparse_cholesky.c's own,
 * CHOLMOD's left-looking supernodal algorithm without its OpenMP regions; the
 * supernodes' dense work runs on BLAS and LAPACK (Debian's serial OpenBLAS:
 * three times the simplicial factorization's speed on the 900-vertex
 * default scene, and one thread, so it neither fights the solver's team nor
 * depends on its size: the result is the same for any thread count;
 * CHOLMOD's own OpenMP loops, in the analysis, are kept on the
 * calling thread, see kernels/linear/sparse_cholesky.c). A matrix that is not positive definite (an indefinite
 * stiffness outweighing the mass) fails to factor; the caller then solves by
 * conjugate gradients. */
#ifndef SB_SPARSE_CHOLESKY_H
#define SB_SPARSE_CHOLESKY_H

#include "kernels/linear/block_matrix.h"

typedef struct sb_sparse_cholesky sb_sparse_cholesky;

/* The analysis of a's pattern; NULL when out of memory. */
sb_sparse_cholesky* sb_sparse_cholesky_create(const sb_block_matrix* a);
void sb_sparse_cholesky_destroy(sb_sparse_cholesky* f);
/* The analysis again, after a's pattern changed (tearing); false when out of memory. */
bool sb_sparse_cholesky_analyze(sb_sparse_cholesky* f, const sb_block_matrix* a);
/* Factors a (symmetric: its lower triangle is read) with the rows and
 * columns where mask (3 per vertex) is 0 replaced by the identity's; false
 * when it is not positive definite (or not finite). */
bool sb_sparse_cholesky_factor(sb_sparse_cholesky* f, const sb_block_matrix* a, const double* mask);
/* out = a⁻¹ rhs with the last factorization (3 × rows doubles each). */
void sb_sparse_cholesky_solve(sb_sparse_cholesky* f, const double* rhs, double* out);

#endif
