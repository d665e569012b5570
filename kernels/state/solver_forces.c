/* The solver's force evaluation: internal terms, gravity, drag, external
 * forces and the post_force hook's (the soft handles'). The external forces
 * of the last evaluation are kept apart (solver->external) so that adaptive
 * stepping can count their work. */
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"
#include "kernels/state/vertex_state.h"
#include "softbond/reference.h"
#include "common/error.h"

/* Adds the callback's force to f and remembers it in ext (when not NULL). */
static void sb_add_external(sb_solver* s, uint32_t i, const double* x, const double* v, double* f, double* ext) {
    double before[3] = {f[0], f[1], f[2]};
    s->def.external_force(s->def.external_user, i, s->time, x, v, f);
    if (ext)
        for (int c = 0; c < 3; c++) ext[c] = f[c] - before[c];
}

void sb_solver_add_body_forces(sb_solver* s, const double* x, const double* v, double* f, double* external) {
    const sb_model* m = s->model;
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        double* fi = f + 3 * i;
        for (int c = 0; c < 3; c++) fi[c] += m->mass[i] * (s->def.gravity[c] - s->def.drag * v[3 * i + c]);
        if (s->def.external_force && !m->fixed[i])
            sb_add_external(s, i, x + 3 * i, v + 3 * i, fi, external ? external + 3 * i : NULL);
    }
    if (s->hooks.post_force) s->hooks.post_force(s, x, v, f, external);
}

/* f = internal + m (g − drag v) + external, all 3n interleaved doubles. */
static sb_status sb_total_forces(sb_solver* s, const double* x, const double* v, double* f, sb_energies* energies,
                                 double* external) {
    sb_status status = sb_reference_forces(s->model, x, v, f, energies, &s->error);
    if (status != SB_OK) return status;
    sb_solver_add_body_forces(s, x, v, f, external);
    return SB_OK;
}

static sb_status sb_reference_step_forces(sb_solver* s) {
    sb_state* st = &s->state;
    uint32_t n = s->model->vertex_count;
    sb_interleave_positions(s, s->scratch_x);
    sb_interleave(s->scratch_v, st->vx, st->vy, st->vz, n);
    sb_status status = sb_total_forces(s, s->scratch_x, s->scratch_v, s->scratch_f, &s->energies, s->external);
    if (status != SB_OK) return status;
    for (uint32_t i = 0; i < n; i++) {
        st->fx[i] = (sb_real)s->scratch_f[3 * i];
        st->fy[i] = (sb_real)s->scratch_f[3 * i + 1];
        st->fz[i] = (sb_real)s->scratch_f[3 * i + 2];
    }
    return SB_OK;
}

sb_status sb_solver_compute_forces(sb_solver* s) {
    return s->fast ? sb_fast_compute_forces(s) : sb_reference_step_forces(s);
}

sb_status sb_solver_settle(sb_solver* s) {
    if (!s->forces_stale) return SB_OK;
    s->forces_stale = false;
    if (sb_fused(s)) { /* the fused Verlet step's forces and term energies are current */
        sb_fast_vertex_energies(s);
        return SB_OK;
    }
    sb_status status = sb_solver_compute_forces(s);
    if (status == SB_OK) sb_update_energies(s);
    return status;
}
