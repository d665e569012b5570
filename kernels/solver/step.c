/* A step as a list of named stages (DESIGN.md, "A step"). An advance
 * (kernels/solver/advance.c) takes one step of dt, or adaptive sub-steps
 * (kernels/solver/adaptive.c), each of them:
 *     begin      the features' begin hooks at the step's start time, then
 *                the clock moves to its end (forces are evaluated at the
 *                new time)
 *     integrate  the integrator's own passes (sb_methods), which call the
 *                in-step hooks (post_force; in the fused Verlet step also
 *                before_drift, drift_chunk, after_drift, place_packed)
 *     correct    after a step the fused path did not take: the features'
 *                correct hooks in order, the forces evaluated again after
 *                each that moved a vertex
 *     collect    after the fused step: the features' collect hooks
 *     check      the state finite and bounded, its energies, the blow-up
 *                rule
 *     accept     the kept step's features' accept hooks, and the stats
 * A step that left its forces and energies for later (forces_stale: nothing
 * after it reads them, sb_step_needs_forces) has checked its state itself
 * and skips correct; so does the fused step, whose passes check the state
 * and sum the energies. */
#include "kernels/solver/step.h"
#include "kernels/solver/stretch_check.h"
#include "kernels/state/solver_fast.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/vertex_state.h"
#include "kernels/integrators/integrators.h"
#include "kernels/integrators/implicit_euler.h"
#include "kernels/integrators/pbd.h"
#include "kernels/integrators/vbd.h"
#include "common/error.h"

#include <math.h>

/* Verlet and velocity Verlet on the fast kernels are the fused step. */
static sb_status sb_verlet_method(sb_solver* s, double dt) {
    return s->fast ? sb_fast_verlet_step(s, dt) : sb_integrate_verlet(s, dt);
}
static sb_status sb_velocity_verlet_method(sb_solver* s, double dt) {
    return s->fast ? sb_fast_verlet_step(s, dt) : sb_integrate_velocity_verlet(s, dt);
}

/* The integrate stage of each integrator. */
static sb_status (*const sb_methods[SB_INTEGRATOR_COUNT])(sb_solver* s, double dt) = {
    [SB_INTEGRATOR_VERLET] = sb_verlet_method,
    [SB_INTEGRATOR_VELOCITY_VERLET] = sb_velocity_verlet_method,
    [SB_INTEGRATOR_EXPLICIT_EULER] = sb_integrate_explicit_euler,
    [SB_INTEGRATOR_SYMPLECTIC_EULER] = sb_integrate_symplectic_euler,
    [SB_INTEGRATOR_POSITION_VERLET] = sb_integrate_position_verlet,
    [SB_INTEGRATOR_IMPLICIT_EULER] = sb_integrate_implicit_euler,
    [SB_INTEGRATOR_PBD] = sb_integrate_pbd,
    [SB_INTEGRATOR_XPBD] = sb_integrate_pbd,
    [SB_INTEGRATOR_VBD] = sb_integrate_vbd,
};

/* Puts "step N (t = T s): " in front of the solver's message. */
static void sb_prefix_step(sb_solver* s) {
    sb_error original = s->error;
    sb_error_set(&s->error, SB_OK, "step %llu (t = %.9g s): %s", (unsigned long long)s->steps, s->time,
                 original.message);
}

static void sb_stage_begin(sb_solver* s, double dt) {
    for (int k = 0; k < s->feature_count; k++)
        if (s->features[k].begin) s->features[k].begin(s, s->time, dt);
    s->step.dt = dt;
    s->time += dt; /* forces of this step are evaluated at the new time */
}

static sb_status sb_stage_correct(sb_solver* s, double dt) {
    for (int k = 0; k < s->feature_count; k++) {
        const sb_feature* f = &s->features[k];
        if (!f->correct || !f->correct(s, dt)) continue;
        sb_status status = sb_solver_compute_forces(s); /* at the corrected state */
        if (status != SB_OK) return status;
    }
    return SB_OK;
}

static void sb_stage_collect(sb_solver* s) {
    for (int k = 0; k < s->feature_count; k++)
        if (s->features[k].collect) s->features[k].collect(s);
}

/* The check after a step the fused path did not take; `status` is the
 * integrate and correct stages'. A non-finite state also makes the force
 * terms fail: the state's fault names the cause. The generic integrators
 * leave the state's arrays current (the fast force evaluation packs them
 * at its start and publishes at its end). */
static sb_status sb_stage_check(sb_solver* s, sb_status status) {
    sb_status state_status = sb_check_state(s);
    if (state_status != SB_OK) return state_status;
    if (status != SB_OK) {
        sb_prefix_step(s);
        return status;
    }
    sb_update_energies(s);
    return sb_check_stretch(s);
}

sb_status sb_solver_step(sb_solver* s, double dt) {
    sb_stage_begin(s, dt);
    sb_status status = sb_methods[s->def.integrator](s, dt);
    if (sb_fused(s)) { /* the fused step checked the state and summed the energies itself */
        sb_stage_collect(s);
        if (status == SB_ERR_DEGENERATE) sb_prefix_step(s);
        return status == SB_OK ? sb_check_stretch(s) : status;
    }
    if (s->forces_stale) /* the step checked the state; nothing below runs (sb_step_needs_forces); the energies wait */
        return status == SB_OK ? sb_check_stretch(s) : status;
    if (status == SB_OK) status = sb_stage_correct(s, dt);
    return sb_stage_check(s, status);
}

sb_status sb_step_accept(sb_solver* s, double dt) {
    for (int k = 0; k < s->feature_count; k++) {
        if (!s->features[k].accept) continue;
        sb_status status = s->features[k].accept(s, dt);
        if (status != SB_OK) return status;
    }
    sb_step_stats* st = &s->stats;
    st->substeps++;
    st->last_substep = dt;
    st->min_substep = st->substeps == 1 ? dt : fmin(st->min_substep, dt);
    return SB_OK;
}
