/* Private: energy-stable adaptive stepping (kernels/solver/adaptive.c). */
#ifndef SB_ADAPTIVE_H
#define SB_ADAPTIVE_H

#include "kernels/state/solver_data.h"

typedef struct sb_adaptive sb_adaptive;

/* The copy of the state a sub-step may restore, made at creation; NULL
 * when out of memory. */
sb_adaptive* sb_adaptive_create(sb_solver* solver);
void sb_adaptive_destroy(sb_adaptive* adaptive);
/* Forgets the sub-step size and the energy peak (the state was set). */
void sb_adaptive_reset(sb_adaptive* adaptive);
/* What it carries from one advance to the next (the size the next sub-step
 * tries, the energy peak), for a saved state; zeros without adaptive
 * stepping, which restore ignores. */
void sb_adaptive_memory(const sb_adaptive* adaptive, double memory[2]);
void sb_adaptive_restore(sb_adaptive* adaptive, const double memory[2]);

/* sb_solver_step over sub-steps with energy control, each kept one
 * accepted (sb_step_accept). */
sb_status sb_adaptive_advance(sb_solver* solver, double dt);

/* The sb_real arrays a step may change and their lengths (the state's,
 * the displacement, the fast path's packed ones): what the backup and the
 * saved state (kernels/solver/solver_state.c) copy. */
#define SB_STEP_ARRAYS 20
int sb_solver_step_arrays(const sb_solver* solver, sb_real** arrays, size_t* lengths);

#endif
