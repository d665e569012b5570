/* Energy-stable adaptive stepping, after the Spring Systems library's
 * solver: sb_solver_advance(Δt) splits Δt into sub-steps h, and a sub-step is
 * kept only if it does not create energy:
 *
 *   gain = [E(t + h) − E(t)] − W,   E = kinetic + internal + gravity,
 *   W    = Σ_free ½ (f_ext(t) + f_ext(t + h)) · (x(t + h) − x(t)),
 *
 * W the work of the external callback's forces, estimated by the trapezoid
 * rule along the sub-step's displacement, plus the work of the dynamic
 * colliders (the energy they would lose if the sub-step were kept:
 * kernels/contact/colliders/dynamic.c) and of the hard handles (what their
 * vertices' imposed motion did, kernels/interaction/handle.c) (gravity is a potential and is in
 * E; drag and spring damping only ever remove energy, so they need no term).
 * When gain > tolerance × S, S the largest kinetic + Σ|term| + |gravity|
 * (+ the dynamic colliders' kinetic + |gravity|) of the accepted states since the state was set and of the new one —
 * the tolerance is the rounding level of those energies, 1e-5 in float and 1e-10 in double unless set; the peak, not
 * the current value, because a system coming to rest would otherwise be
 * judged on the rounding noise of energies that tend to zero — or the
 * sub-step fails (a non-finite, runaway or
 * collapsed state), the state is restored and the sub-step retried at h/2;
 * below min_dt the advance fails with SB_ERR_UNSTABLE (the state then is the
 * last good one). After a success the next sub-step tries 2h, never more
 * than what is left of Δt; the size carries over to the next advance, so a
 * run settles on the largest power-of-two fraction of Δt that keeps the
 * energy from growing — just below the integrator's stability limit when
 * damping takes out the small oscillation of the computed energy that even a
 * stable symplectic step shows.
 *
 * Restoring copies back everything a step changes: the state's arrays, the
 * Verlet displacement, the fast path's packed working state, the external
 * forces, the clock and the energies. */
#include "kernels/solver/adaptive.h"
#include "kernels/solver/step.h"
#include "kernels/state/solver_fast.h"
#include "kernels/contact/contact.h"
#include "kernels/contact/colliders/dynamic.h"
#include "kernels/interaction/handle_internal.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The state before a sub-step, to restore when it is not kept. */
typedef struct sb_backup {
    sb_real* reals;   /* every sb_real array of the step, one after another */
    double* external; /* 3n, NULL without a callback */
    bool has_displacement, published;
    double prev_dt, time;
    sb_energies energies;
} sb_backup;

struct sb_adaptive {
    sb_backup backup;
    double trial_substep; /* the size the next sub-step tries (0: the whole dt) */
    double energy_peak;   /* the largest energy scale since the state was set */
};

int sb_solver_step_arrays(const sb_solver* s, sb_real** arrays, size_t* lengths) {
    size_t n = s->state.vertex_count;
    const sb_state* st = &s->state;
    sb_real* soa[15] = {st->x,  st->y,     st->z,     st->vx,    st->vy,     st->vz,     st->fx,    st->fy,
                        st->fz, s->disp_x, s->disp_y, s->disp_z, s->carry_x, s->carry_y, s->carry_z};
    int count = 0;
    for (int a = 0; a < 15; a++) {
        arrays[count] = soa[a];
        lengths[count++] = n;
    }
    if (s->fast) {
        sb_real* packed[5] = {s->positions4, s->velocities4, s->displacements4, s->forces4, s->carry4};
        for (int a = 0; a < 5; a++) {
            arrays[count] = packed[a];
            lengths[count++] = 4 * n;
        }
    }
    return count;
}

void sb_adaptive_destroy(sb_adaptive* a) {
    if (!a) return;
    free(a->backup.reals);
    free(a->backup.external);
    free(a);
}

sb_adaptive* sb_adaptive_create(sb_solver* s) {
    sb_real* arrays[SB_STEP_ARRAYS];
    size_t lengths[SB_STEP_ARRAYS], total = 1;
    int count = sb_solver_step_arrays(s, arrays, lengths);
    for (int a = 0; a < count; a++) total += lengths[a];
    sb_adaptive* a = calloc(1, sizeof *a);
    if (!a) return NULL;
    sb_backup* snap = &a->backup;
    snap->reals = malloc(total * sizeof(sb_real));
    if (s->external) snap->external = malloc((3 * (size_t)s->state.vertex_count + 1) * sizeof(double));
    if (!snap->reals || (s->external && !snap->external)) {
        sb_adaptive_destroy(a);
        return NULL;
    }
    return a;
}

void sb_adaptive_reset(sb_adaptive* a) {
    if (a) a->trial_substep = a->energy_peak = 0.0;
}

void sb_adaptive_memory(const sb_adaptive* a, double memory[2]) {
    memory[0] = a ? a->trial_substep : 0.0;
    memory[1] = a ? a->energy_peak : 0.0;
}

void sb_adaptive_restore(sb_adaptive* a, const double memory[2]) {
    if (!a) return;
    a->trial_substep = memory[0];
    a->energy_peak = memory[1];
}

static void sb_backup_copy(sb_solver* s, bool save) {
    sb_backup* snap = &s->adaptive->backup;
    sb_real* arrays[SB_STEP_ARRAYS];
    size_t lengths[SB_STEP_ARRAYS], offset = 0;
    int count = sb_solver_step_arrays(s, arrays, lengths);
    for (int a = 0; a < count; a++) {
        sb_real* saved = snap->reals + offset;
        if (save)
            memcpy(saved, arrays[a], lengths[a] * sizeof(sb_real));
        else
            memcpy(arrays[a], saved, lengths[a] * sizeof(sb_real));
        offset += lengths[a];
    }
    size_t external = 3 * (size_t)s->state.vertex_count * sizeof(double);
    if (s->external) memcpy(save ? snap->external : s->external, save ? s->external : snap->external, external);
    if (save) {
        snap->has_displacement = s->has_displacement;
        snap->published = s->published;
        snap->prev_dt = s->prev_dt;
        snap->time = s->time;
        snap->energies = s->energies;
    } else {
        s->has_displacement = snap->has_displacement;
        s->published = snap->published;
        s->prev_dt = snap->prev_dt;
        s->time = snap->time;
        s->energies = snap->energies;
    }
}

/* The magnitudes the energy test is relative to. */
static double sb_energy_scale(const sb_energies* e) {
    double scale = fabs(e->kinetic) + fabs(e->gravity);
    for (int t = 0; t < SB_TERM_COUNT; t++) scale += fabs(e->term[t]);
    return scale;
}

/* Trapezoid work of the external forces over the sub-step just taken. */
static double sb_external_work(sb_solver* s) {
    if (!s->external) return 0.0;
    sb_fast_publish(s);
    const sb_backup* snap = &s->adaptive->backup;
    size_t n = s->state.vertex_count;
    const sb_real* before[3] = {snap->reals, snap->reals + n, snap->reals + 2 * n}; /* x, y, z come first */
    const sb_real* after[3] = {s->state.x, s->state.y, s->state.z};
    double work = 0.0;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            work += 0.5 * (snap->external[3 * i + c] + s->external[3 * i + c]) * ((double)after[c][i] - before[c][i]);
    return work;
}

static double sb_adaptive_tolerance(const sb_solver* s) {
    if (s->def.adaptive_tolerance > 0.0) return s->def.adaptive_tolerance;
    return sizeof(sb_real) == sizeof(float) ? 1e-5 : 1e-10;
}

/* The sub-step cannot be halved any more: restore and report. */
static sb_status sb_give_up(sb_solver* s, sb_status status, double h, double gain) {
    sb_error cause = s->error;
    sb_backup_copy(s, false);
    if (status != SB_OK)
        return sb_error_set(&s->error, status, "%s (adaptive: still failing at a sub-step of %g s, min_dt %g s)",
                            cause.message, h, s->def.min_dt);
    return sb_error_set(&s->error, SB_ERR_UNSTABLE,
                        "step %llu (t = %.9g s): a sub-step of %g s still gains %.3g J of energy and the next would "
                        "be below min_dt (%g s); the system is too stiff for it",
                        (unsigned long long)s->steps, s->time, h, gain, s->def.min_dt);
}

sb_status sb_adaptive_advance(sb_solver* s, double dt) {
    sb_adaptive* a = s->adaptive;
    const double tolerance = sb_adaptive_tolerance(s);
    double remaining = dt, trial = a->trial_substep > 0.0 ? a->trial_substep : dt;
    while (remaining > 0.0) {
        double h = fmin(trial, remaining);
        if (remaining - h <= 1e-9 * dt) h = remaining; /* no sliver of a last sub-step */
        if (s->external) sb_fast_publish(s);           /* the work needs the positions before the sub-step */
        sb_backup_copy(s, true);
        /* the dynamic colliders' energies belong to the system's scale (they do not change in a sub-step
         * until it is kept) */
        double bodies = sb_colliders_energy_scale(s->def.colliders, s->def.collider_count, s->def.gravity);
        a->energy_peak = fmax(a->energy_peak, sb_energy_scale(&s->energies) + bodies);
        double e0 = sb_energies_total(&s->energies);
        sb_status status = sb_solver_step(s, h);
        if (status != SB_OK && status != SB_ERR_UNSTABLE && status != SB_ERR_DEGENERATE) return status;
        double gain = status == SB_OK ? sb_energies_total(&s->energies) - e0 - sb_external_work(s) -
                                            sb_contact_step_work(s, h) - sb_handles_work(s, a->backup.reals)
                                      : INFINITY;
        double scale = fmax(a->energy_peak, sb_energy_scale(&s->energies) + bodies); /* a blow-up's gain: ~ all */
        if (status == SB_OK && gain <= tolerance * scale) {
            a->energy_peak = scale;
            remaining -= h;
            sb_status accepted = sb_step_accept(s, h); /* a dynamic collider moves only with the sub-steps kept */
            if (accepted != SB_OK) return accepted;
            if (h >= trial) trial = 2.0 * h; /* a sub-step cut short by what was left does not grow */
            continue;
        }
        if (0.5 * h < s->def.min_dt) return sb_give_up(s, status, h, gain);
        sb_backup_copy(s, false);
        s->stats.rejected++;
        trial = 0.5 * h;
    }
    a->trial_substep = trial;
    return SB_OK;
}
