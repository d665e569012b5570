/* Private: the forces of the solver's state, with either kernels, and the
 * settling of what a step left for later. */
#ifndef SB_SOLVER_FORCES_H
#define SB_SOLVER_FORCES_H

#include "kernels/state/solver_data.h"

/* Forces at the state's positions, with the state's velocities for damping:
 * fills state.f (internal + gravity + external + the post_force hook's) and
 * energies.term[]. */
sb_status sb_solver_compute_forces(sb_solver* solver);

/* Adds to f (internal forces at x, v) gravity, drag, the external callback's
 * forces (remembered in `external` when not NULL) and the post_force hook's
 * (the soft handles'). */
void sb_solver_add_body_forces(sb_solver* solver, const double* x, const double* v, double* f, double* external);

/* The forces and energies of the current state, evaluated now where the
 * last step left them for later (forces_stale; the fused Verlet step: its
 * kinetic and gravitational energies only); the getters that return them
 * call it first, and so does what changes what they depend on (gravity,
 * the handles' pins) between a step and a read. */
sb_status sb_solver_settle(sb_solver* solver);

#endif
