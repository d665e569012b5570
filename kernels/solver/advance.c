/* An advance of dt as a list of named stages (DESIGN.md, "A step"):
 *   start      the features' start hooks
 *   steps      one step of dt (kernels/solver/step.c) and its accept stage,
 *              or the adaptive sub-steps (kernels/solver/adaptive.c), each
 *              kept one accepted
 *   end        the features' end hooks, after an advance that succeeded
 * and the snapshot of the state it leaves (sb_solver_advance_into). */
#include "kernels/solver/advance.h"
#include "kernels/solver/adaptive.h"
#include "kernels/solver/step.h"
#include "kernels/state/vertex_state.h"
#include "common/error.h"

#include <math.h>

sb_status sb_solver_advance(sb_solver* s, double dt) {
    if (!(dt > 0.0) || !isfinite(dt))
        return sb_error_set(&s->error, SB_ERR_INVALID, "time step %g s must be positive and finite", dt);
    s->steps++;
    s->stats = (sb_step_stats){.converged = true};
    s->advance_dt = dt;
    for (int k = 0; k < s->feature_count; k++)
        if (s->features[k].start) s->features[k].start(s);
    sb_status status = SB_OK;
    if (s->def.adaptive)
        status = sb_adaptive_advance(s, dt); /* accepts each sub-step it keeps */
    else if ((status = sb_solver_step(s, dt)) == SB_OK)
        status = sb_step_accept(s, dt);
    if (status != SB_OK) return status;
    for (int k = 0; k < s->feature_count; k++)
        if (s->features[k].end) s->features[k].end(s);
    return SB_OK;
}

/* The copy of sb_solver_copy_state, split over the team. */
typedef struct sb_copy_job {
    const sb_solver* solver;
    sb_real *positions, *velocities;
} sb_copy_job;

static void sb_copy_worker(void* context, const sb_worker* w) {
    const sb_copy_job* job = context;
    const sb_solver* s = job->solver;
    const sb_state* st = &s->state;
    int64_t begin, end;
    sb_worker_range(w, s->live_vertices, &begin, &end);
    sb_real *x = job->positions, *v = job->velocities;
    if (s->fast && !s->published) {
        sb_unpack_xyz(s->positions4, x, begin, end);
        sb_unpack_xyz(s->velocities4, v, begin, end);
        return;
    }
    for (int64_t i = begin; i < end; i++) {
        x[3 * i] = st->x[i], x[3 * i + 1] = st->y[i], x[3 * i + 2] = st->z[i];
        v[3 * i] = st->vx[i], v[3 * i + 1] = st->vy[i], v[3 * i + 2] = st->vz[i];
    }
}

void sb_solver_copy_state(const sb_solver* s, sb_real* positions, sb_real* velocities) {
    sb_copy_job job = {s, positions, velocities};
    sb_team_run(s->team, sb_team_size(s->team), sb_copy_worker, &job);
}

sb_status sb_solver_advance_into(sb_solver* s, double dt, sb_real* positions, sb_real* velocities) {
    /* adaptive stepping may undo a sub-step: its snapshot is copied after */
    bool fused = sb_fused(s) && !s->def.adaptive;
    s->step.publish_positions = fused ? positions : NULL;
    s->step.publish_velocities = fused ? velocities : NULL;
    s->step.publish_written = false;
    sb_status status = sb_solver_advance(s, dt);
    if (status == SB_OK && !s->step.publish_written) sb_solver_copy_state(s, positions, velocities);
    s->step.publish_positions = s->step.publish_velocities = NULL;
    return status;
}
