/* Private: an advance and the snapshot it leaves (kernels/solver/advance.c). */
#ifndef SB_ADVANCE_H
#define SB_ADVANCE_H

#include "kernels/state/solver_data.h"

/* sb_solver_advance, and the new positions and velocities into the arrays
 * (3n): written by the fused step's last pass where it runs (no extra pass
 * and no extra wake-up of the team), copied after the advance otherwise. */
sb_status sb_solver_advance_into(sb_solver* solver, double dt, sb_real* positions, sb_real* velocities);
/* Copies the current positions and velocities as 3n interleaved sb_reals,
 * in parallel on the solver's team; reads only (sb_solver_publish). */
void sb_solver_copy_state(const sb_solver* solver, sb_real* positions, sb_real* velocities);

#endif
