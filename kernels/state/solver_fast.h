/* Private: the fast path (kernels/state/solver_fast.c): the solver's
 * packed working state, the fast force passes over it, and the fused
 * Verlet step built from them. */
#ifndef SB_SOLVER_FAST_H
#define SB_SOLVER_FAST_H

#include "kernels/state/solver_data.h"
#include "kernels/forces/fast_kernels.h"

/* The fast model, the packed arrays and the passes' partial sums. */
sb_status sb_fast_prepare(sb_solver* solver, sb_error* err);
/* The fast model built again from the solver's model, whose elements
 * changed (a cut through them, kernels/interaction/cut_mesh.c), with the
 * partial sums' room for its blocks; the packed state stays (the vertex
 * slots are the same), the inverse masses are those the integrators move
 * the vertices with (0 where a hard handle holds). On failure the old
 * fast model stays. */
sb_status sb_fast_rebuild(sb_solver* solver, sb_error* err);
/* sb_solver_compute_forces on the fast kernels: packs the state, runs the
 * force passes and the hooks, publishes. */
sb_status sb_fast_compute_forces(sb_solver* solver);
/* The forces at the packed positions4 and velocities4 into forces4:
 * gravity, drag, the element passes and the external forces; nothing
 * published, no energies (implicit Euler's residual, kernels/integrators/implicit_fast.c). */
sb_status sb_fast_forces_packed(sb_solver* solver);
/* One Verlet (or velocity Verlet) step as one job of the team, its passes
 * calling the in-step hooks (sb_step_hooks). */
sb_status sb_fast_verlet_step(sb_solver* solver, double dt);
/* The kinetic and gravitational energies of the packed state into the
 * solver's energies, bitwise as the fused step sums them in its passes
 * (sb_solver_settle, after a step that left them for later). */
void sb_fast_vertex_energies(sb_solver* solver);
/* A packed force's starting value, gravity and drag: m (g_a − drag v_a). */
sb_real sb_fast_initial_force(const sb_solver* solver, uint32_t vertex, int axis, double velocity);
/* Fills the state's arrays from the packed working state, when stale. */
void sb_fast_publish(sb_solver* solver);
/* Inside a job of the team: kernels[0], [1], [2], [3], [4] over the bonds,
 * triangles, hinges, tetrahedra and membranes that the force passes run, in their blocked coloring, for
 * kernels that keep no energies and raise no flags
 * (kernels/forces/fast_hessian.h). Returns with every worker past the last
 * barrier. */
void sb_fast_element_passes(const sb_worker* w, const sb_solver* s, const sb_fast_kernel kernels[5],
                            const sb_fast_frame* frame);

#endif
