/* Private: implicit Euler on the fast kernels (kernels/integrators/implicit_fast.c),
 * the SIMD twin of kernels/integrators/implicit_euler.c. */
#ifndef SB_IMPLICIT_FAST_H
#define SB_IMPLICIT_FAST_H

#include "kernels/state/solver_data.h"
#include "common/sections.h"

/* Work vectors for a solver of the model's vertices, allocated once; NULL
 * when out of memory. */
struct sb_implicit_fast* sb_implicit_fast_create(const sb_solver* solver);
void sb_implicit_fast_destroy(struct sb_implicit_fast* fast);
/* One backward Euler step on the fast kernels. */
sb_status sb_implicit_fast_step(sb_solver* solver, struct sb_implicit_fast* fast, double dt);
/* Its part of a checkpoint: the first guess the next step starts from. */
void sb_implicit_fast_save(const sb_solver* solver, sb_sections_writer* w);
void sb_implicit_fast_load(sb_solver* solver, sb_cursor* r);

#endif
