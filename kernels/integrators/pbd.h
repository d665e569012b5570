/* Private: pbd and xpbd (kernels/integrators/pbd.c, with its SIMD sweeps in
 * kernels/integrators/fast_pbd.c). */
#ifndef SB_PBD_H
#define SB_PBD_H

#include "kernels/state/solver_data.h"

sb_status sb_integrate_pbd(sb_solver* solver, double dt);
/* Colors the constraints and allocates the work arrays (at creation). */
sb_status sb_pbd_prepare(sb_solver* solver);
void sb_pbd_destroy(struct sb_pbd* pbd);
int sb_pbd_iterations(const sb_solver_def* def);

#endif
