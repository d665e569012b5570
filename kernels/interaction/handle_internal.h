/* Private: the solver's side of the handles (kernels/interaction/handle.c). */
#ifndef SB_HANDLE_INTERNAL_H
#define SB_HANDLE_INTERNAL_H

#include "softbond/handle.h"
#include "softbond/solver.h"
#include "common/sections.h"

/* At solver creation: checks each handle's vertices against the model,
 * attaches it, grabs its vertices at the rest shape and pins the held hard
 * ones (the fused path's packed inverse masses; pbd's pinned_inv_mass). */
sb_status sb_handles_prepare(sb_solver* solver, sb_error* err);
void sb_handles_destroy(sb_solver* solver);
/* The handles take part in a step as the feature "handles" (begin: their
 * poses for the step [t0, t0 + dt]; correct: the held vertices at their
 * targets in the state's arrays; end: those whose release_time has come
 * let go), through the fused step's place_packed hook (the same in the
 * packed working state, over dt) and, with a soft one among them, the
 * post_force hooks (their spring forces join the external ones). */

/* Every vertex a hard handle holds at its target in pbd's predicted
 * positions (3n doubles). One thread. */
void sb_handles_place_predicted(sb_solver* solver, double* x);

/* The handles' state that changes as they run (held, the poses of the
 * step, where the program drove them, the grab positions, the reported
 * force, the release time): written for the saved state
 * (kernels/solver/solver_state.c), and read back from as many bytes as
 * sb_handles_save writes (the caller checked the length), pins included. */
void sb_handles_save(const sb_solver* solver, sb_sections_writer* w);
void sb_handles_load(sb_solver* solver, sb_cursor* r);

/* The hard handles' work (J) over the sub-step just taken (adaptive.c);
 * `before` holds the state's arrays before it, n values each: x, y, z, vx,
 * vy, vz, fx, fy, fz. */
double sb_handles_work(sb_solver* solver, const sb_real* before);

#endif
