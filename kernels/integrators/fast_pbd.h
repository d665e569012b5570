/* Private: pbd's and xpbd's SIMD sweeps (kernels/integrators/fast_pbd.c), on pbd's colors (pbd_internal.h). */
#ifndef SB_FAST_PBD_H
#define SB_FAST_PBD_H

#include "kernels/integrators/pbd_internal.h"

/* Whether the solver's pbd steps take the SIMD sweeps: the fast kernels,
 * no colliders and no handles (their passes work on the scalar sweeps'
 * double positions). */
bool sb_pbd_wide_applies(const sb_solver* solver);
/* The SIMD layout of p's colors (the same colors and order); NULL when out
 * of memory. */
sb_pbd_wide* sb_pbd_wide_create(const sb_pbd* p, const sb_model* model);
void sb_pbd_wide_destroy(sb_pbd_wide* wide);
/* One step: prediction, the sweeps and v = (x − x_prev)/dt, on the state's
 * arrays and the packed positions and velocities, the state checked; the
 * forces and energies of the new state are left to sb_solver_settle
 * (kernels/solver/solver.c) unless the next step needs them. */
sb_status sb_pbd_wide_step(sb_solver* solver, double dt);
/* The barriers of a step of the SIMD sweeps on more than one thread: one
 * before the sweeps and one after them; none in them (kernels/integrators/fast_pbd.c's
 * schedule). */
uint32_t sb_pbd_wide_barriers(const sb_solver* solver);
/* For the tests: the faults of the SIMD sweeps' schedule, checked by brute
 * force (a pair of units in different phases that share a vertex without
 * waiting for each other, or that wait without sharing one; a unit not
 * planned on exactly one worker; a worker's plan out of phase order, or
 * the overflow color's units out of order), 0
 * when sound; *across: the waits for a unit of another worker. */
uint32_t sb_pbd_wide_schedule_faults(const sb_solver* solver, uint32_t* across);

#endif
