/* Private: vertex block descent (kernels/integrators/vbd.c, with its SIMD
 * sweep in kernels/integrators/fast_vbd.c). */
#ifndef SB_VBD_H
#define SB_VBD_H

#include "kernels/state/solver_data.h"
#include "common/sections.h"

sb_status sb_integrate_vbd(sb_solver* solver, double dt);
/* Allocates everything a step needs; false when out of memory. */
bool sb_vbd_prepare(sb_solver* solver);
void sb_vbd_destroy(struct sb_vbd* vbd);
int sb_vbd_iterations(const sb_solver_def* def);
/* The fast sweeps' schedule checked against the model
 * (sb_fast_vbd_schedule_faults); UINT32_MAX when the solver has no fast
 * sweeps. */
uint32_t sb_vbd_schedule_faults(const sb_solver* solver, uint32_t* needs);
/* Its part of a saved state. */
void sb_vbd_save(const sb_solver* solver, sb_sections_writer* w);
void sb_vbd_load(sb_solver* solver, sb_cursor* r);

#endif
