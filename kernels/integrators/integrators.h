/* Private: the explicit integrators on the state's arrays
 * (kernels/integrators/integrators.c). Each step leaves forces, velocities
 * and term energies at the new positions. The fast path's Verlet and
 * velocity Verlet are the fused step of kernels/state/solver_fast.c. */
#ifndef SB_INTEGRATORS_H
#define SB_INTEGRATORS_H

#include "kernels/state/solver_data.h"

sb_status sb_integrate_verlet(sb_solver* solver, double dt);
sb_status sb_integrate_velocity_verlet(sb_solver* solver, double dt);
sb_status sb_integrate_explicit_euler(sb_solver* solver, double dt);
sb_status sb_integrate_symplectic_euler(sb_solver* solver, double dt);
sb_status sb_integrate_position_verlet(sb_solver* solver, double dt);

#endif
