/* The solver's force evaluation: internal terms, gravity, external forces. */
#include "kernels/solver_internal.h"
#include "kernels/error.h"

static void sb_add_external(sb_solver* s, uint32_t i, double* force) {
    const double* x = s->scratch_x + 3 * i;
    const double* v = s->scratch_v + 3 * i;
    s->def.external_force(s->def.external_user, i, s->time, x, v, force);
}

static sb_status sb_reference_step_forces(sb_solver* s) {
    const sb_model* m = s->model;
    sb_state* st = &s->state;
    uint32_t n = m->vertex_count;
    sb_interleave(s->scratch_x, st->x, st->y, st->z, n);
    sb_interleave(s->scratch_v, st->vx, st->vy, st->vz, n);
    sb_status status = sb_reference_forces(m, s->scratch_x, s->scratch_v, s->scratch_f, &s->energies, &s->error);
    if (status != SB_OK) return status;
    for (uint32_t i = 0; i < n; i++) {
        double* f = s->scratch_f + 3 * i;
        const double* v = s->scratch_v + 3 * i;
        for (int c = 0; c < 3; c++) f[c] += m->mass[i] * (s->def.gravity[c] - s->def.drag * v[c]);
        if (s->def.external_force && !m->fixed[i]) sb_add_external(s, i, f);
        st->fx[i] = (sb_real)f[0];
        st->fy[i] = (sb_real)f[1];
        st->fz[i] = (sb_real)f[2];
    }
    return SB_OK;
}

sb_status sb_solver_compute_forces(sb_solver* s) {
    return s->fast ? sb_fast_compute_forces(s) : sb_reference_step_forces(s);
}
