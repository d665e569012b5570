/* Private: implicit Euler on the fast kernels (kernels/integrators/implicit_fast.c),
 * and what it shares with the reference Newton (kernels/integrators/implicit_euler.c). */
#ifndef SB_IMPLICIT_FAST_H
#define SB_IMPLICIT_FAST_H

#include "kernels/state/solver_internal.h"

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
 * SB_IMPLICIT_VERTICES_PER_THREAD vertices at most (kernels/integrators/implicit_euler.c),
 * at least one. The result is the same for any count. */
int sb_implicit_width(const sb_solver* solver);

/* Work vectors for a solver of the model's vertices, allocated once; NULL
 * when out of memory. */
struct sb_implicit_fast* sb_implicit_fast_create(const sb_solver* solver);
void sb_implicit_fast_destroy(struct sb_implicit_fast* fast);
/* One backward Euler step on the fast kernels (kernels/integrators/implicit_fast.c). */
sb_status sb_implicit_fast_step(sb_solver* solver, struct sb_implicit_fast* fast, double dt);

#endif
