/* The solver's per-vertex state: its checks, its energies and its copies
 * between layouts (the state's arrays, packed x y z w, interleaved). */
#include "kernels/state/vertex_state.h"
#include "common/error.h"

#include <math.h>
#include <string.h>

sb_status sb_check_state(sb_solver* s) {
    for (uint32_t i = 0; i < s->state.vertex_count; i++) {
        const char* fault = sb_vertex_fault(s, i);
        if (fault)
            return sb_error_set(&s->error, SB_ERR_UNSTABLE,
                                "step %llu (t = %.9g s): vertex %u %s; the time step is too large for the stiffness",
                                (unsigned long long)s->steps, s->time, i, fault);
    }
    return SB_OK;
}

void sb_update_energies(sb_solver* s) {
    const sb_model* m = s->model;
    const sb_state* st = &s->state;
    double kinetic = 0.0, gravity = 0.0;
    const double* g = s->def.gravity;
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        if (m->fixed[i]) continue;
        double v2 = (double)st->vx[i] * st->vx[i] + (double)st->vy[i] * st->vy[i] + (double)st->vz[i] * st->vz[i];
        kinetic += 0.5 * m->mass[i] * v2;
        gravity -= m->mass[i] * (g[0] * st->x[i] + g[1] * st->y[i] + g[2] * st->z[i]);
    }
    s->energies.kinetic = kinetic;
    s->energies.gravity = gravity;
    if (sb_fused(s)) s->forces_stale = false; /* after the forces (breakage): no vertex sums wait */
}

void sb_interleave(double* out, const sb_real* a, const sb_real* b, const sb_real* c, uint32_t n) {
    for (uint32_t i = 0; i < n; i++) {
        out[3 * i] = a[i];
        out[3 * i + 1] = b[i];
        out[3 * i + 2] = c[i];
    }
}

void sb_unpack_xyz(const sb_real* packed, sb_real* out, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; i++)
        for (int c = 0; c < 3; c++) out[3 * i + c] = packed[4 * i + c];
}

void sb_store_free_vertices(sb_solver* s, const double* x, const double* v) {
    sb_store_free_range(s, x, v, 0, s->state.vertex_count);
}

void sb_store_free_range(sb_solver* s, const double* x, const double* v, uint32_t begin, uint32_t end) {
    sb_state* st = &s->state;
    sb_real* pos[3] = {st->x, st->y, st->z};
    sb_real* vel[3] = {st->vx, st->vy, st->vz};
    for (uint32_t i = begin; i < end; i++) {
        if (s->model->fixed[i]) continue;
        for (int c = 0; c < 3; c++) {
            pos[c][i] = (sb_real)x[3 * (size_t)i + c];
            vel[c][i] = (sb_real)v[3 * (size_t)i + c];
        }
    }
}

const sb_real* sb_packed_positions(sb_solver* s) {
    if (s->fast) return s->positions4; /* current after any step */
    for (uint32_t i = 0; i < s->model->vertex_count; i++) {
        s->stretch4[4 * (size_t)i] = s->state.x[i];
        s->stretch4[4 * (size_t)i + 1] = s->state.y[i];
        s->stretch4[4 * (size_t)i + 2] = s->state.z[i];
    }
    return s->stretch4;
}

bool sb_step_needs_forces(const sb_solver* s) {
    bool corrected = false; /* a feature corrects the state after the step */
    for (int k = 0; k < s->feature_count; k++) corrected |= s->features[k].correct != NULL;
    return s->def.adaptive || s->def.external_force || s->hooks.post_force || corrected;
}

void sb_clear_carries(sb_solver* s) {
    size_t n = s->state.vertex_count;
    memset(s->carry_x, 0, n * sizeof(sb_real));
    memset(s->carry_y, 0, n * sizeof(sb_real));
    memset(s->carry_z, 0, n * sizeof(sb_real));
    if (s->carry4) memset(s->carry4, 0, 4 * n * sizeof(sb_real));
}

void sb_interleave_positions(const sb_solver* s, double* out) {
    const sb_state* st = &s->state;
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        out[3 * i] = (double)st->x[i] + (double)s->carry_x[i];
        out[3 * i + 1] = (double)st->y[i] + (double)s->carry_y[i];
        out[3 * i + 2] = (double)st->z[i] + (double)s->carry_z[i];
    }
}
