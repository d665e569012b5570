/* Private: implicit (backward) Euler (kernels/integrators/implicit_euler.c):
 * Newton's method on J = M + dt D + dt² K, solved by CG or a sparse
 * factorization; on the fast kernels with CG its steps run in
 * kernels/integrators/implicit_fast.c, its SIMD twin. */
#ifndef SB_IMPLICIT_EULER_H
#define SB_IMPLICIT_EULER_H

#include "kernels/state/solver_data.h"

/* CG stops at this relative residual; the line search halves a step at
 * most this many times. */
#define SB_CG_RELATIVE_TOLERANCE 1e-5
#define SB_LINE_SEARCH_HALVINGS 5

/* The Newton limits of sb_solver_def with their defaults. */
typedef struct sb_newton_limits {
    double tolerance;
    int newton_cap, cg_cap;
} sb_newton_limits;

sb_newton_limits sb_newton_limits_of(const sb_solver* solver);

/* The threads an implicit step's jobs run on: the team's, but one per
 * SB_IMPLICIT_VERTICES_PER_THREAD vertices at most, at least one. The
 * result is the same for any count. */
int sb_implicit_width(const sb_solver* solver);

/* One step; leaves forces, velocities and term energies at the new
 * positions. */
sb_status sb_integrate_implicit_euler(sb_solver* solver, double dt);
/* Allocates the step's matrix and work arrays; false when out of memory. */
bool sb_implicit_prepare(sb_solver* solver);
void sb_implicit_destroy(sb_solver* solver);
/* The fast implicit Euler's work, NULL unless implicit Euler runs on the
 * fast kernels with CG. */
struct sb_implicit_fast* sb_implicit_fast_of(const sb_solver* solver);

#endif
