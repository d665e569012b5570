/* Private: a step as a list of named stages (kernels/solver/step.c;
 * DESIGN.md, "A step"). */
#ifndef SB_STEP_H
#define SB_STEP_H

#include "kernels/state/solver_data.h"

/* One step of dt through the stages begin, integrate, correct or collect,
 * and check: the chosen integrator with the chosen kernels, the features'
 * hooks, the state checked and the energies updated. */
sb_status sb_solver_step(sb_solver* solver, double dt);
/* The accept stage, after a step (or an adaptive sub-step) of dt is kept:
 * the features' accept hooks in order, then the step's stats. */
sb_status sb_step_accept(sb_solver* solver, double dt);

#endif
