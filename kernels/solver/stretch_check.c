/* The blow-up rule (softbond/solver.h): a tangled, exploding mesh stays
 * inside the runaway box long after its energy has grown a billionfold; its
 * bonds do not stay short. */
#include "kernels/solver/stretch_check.h"
#include "kernels/state/vertex_state.h"
#include "common/error.h"

#include <math.h>

/* The edges of one overstretch test, shared by the team's workers. */
typedef struct sb_stretch_job {
    const sb_real* p;
    const uint32_t *a, *b;
    const double* r0;
    uint32_t count;
    atomic_int any;
} sb_stretch_job;

static void sb_stretch_worker(void* context, const sb_worker* w) {
    sb_stretch_job* job = context;
    const sb_real limit2 = (sb_real)(SB_STRETCH_LIMIT * SB_STRETCH_LIMIT);
    const sb_real* p = job->p;
    int64_t begin, end;
    sb_worker_range(w, job->count, &begin, &end);
    int any = 0;
    for (int64_t e = begin; e < end; e++) {
        const sb_real *pa = p + 4 * (size_t)job->a[e], *pb = p + 4 * (size_t)job->b[e];
        sb_real dx = pa[0] - pb[0], dy = pa[1] - pb[1], dz = pa[2] - pb[2], r = (sb_real)job->r0[e];
        any |= (dx * dx + dy * dy + dz * dz > limit2 * r * r) & (r > 0); /* r0 = 0: no ratio */
    }
    if (any) sb_worker_raise(&job->any);
}

/* Whether any of `count` edges (a[e], b[e]) with rest length r0[e] is longer
 * than SB_STRETCH_LIMIT r0: a branch-free pass (in sb_real) that vectorizes. */
static bool sb_any_overstretched(sb_team* team, const sb_real* p, const uint32_t* a, const uint32_t* b,
                                 const double* r0, uint32_t count) {
    sb_stretch_job job = {p, a, b, r0, count, 0};
    sb_team_run(team, sb_team_size(team), sb_stretch_worker, &job);
    return atomic_load(&job.any) != 0;
}

/* The first such edge (in double), or UINT32_MAX; runs only after a hit. */
static uint32_t sb_first_overstretched(const sb_real* p, const uint32_t* a, const uint32_t* b, const double* r0,
                                       uint32_t count) {
    for (uint32_t e = 0; e < count; e++) {
        const sb_real *pa = p + 4 * (size_t)a[e], *pb = p + 4 * (size_t)b[e];
        double dx = (double)pa[0] - pb[0], dy = (double)pa[1] - pb[1], dz = (double)pa[2] - pb[2];
        if (r0[e] > 0 && sqrt(dx * dx + dy * dy + dz * dz) > SB_STRETCH_LIMIT * r0[e]) return e;
    }
    return UINT32_MAX;
}

/* The blow-up rule (softbond/solver.h): no bond, or in a model without
 * bonds no triangle edge, past SB_STRETCH_LIMIT times its rest length. A
 * tangled, exploding mesh stays inside the runaway box long after its
 * energy has grown a billionfold; its bonds do not stay short. One pass
 * over the bonds every SB_STRETCH_INTERVAL-th advance keeps the cost out
 * of the fused fast step. */
sb_status sb_check_stretch(sb_solver* s) {
    if (s->steps % SB_STRETCH_INTERVAL != 0) return SB_OK;
    const sb_model* m = s->model;
    const sb_real* p = sb_packed_positions(s);
    if (m->bond_count > 0) {
        if (!sb_any_overstretched(s->team, p, m->bond_i, m->bond_j, m->bond_r0, m->bond_count)) return SB_OK;
        uint32_t b = sb_first_overstretched(p, m->bond_i, m->bond_j, m->bond_r0, m->bond_count);
        if (b == UINT32_MAX) return SB_OK; /* a float rounding at the limit */
        const sb_real *pi = p + 4 * (size_t)m->bond_i[b], *pj = p + 4 * (size_t)m->bond_j[b];
        double dx = (double)pi[0] - pj[0], dy = (double)pi[1] - pj[1], dz = (double)pi[2] - pj[2];
        return sb_error_set(&s->error, SB_ERR_UNSTABLE,
                            "step %llu (t = %.9g s): bond %u (vertices %u and %u) is %.3g times its rest length "
                            "(limit %g); the time step is too large for the stiffness",
                            (unsigned long long)s->steps, s->time, b, m->bond_i[b], m->bond_j[b],
                            sqrt(dx * dx + dy * dy + dz * dz) / m->bond_r0[b], SB_STRETCH_LIMIT);
    }
    for (int c = 0; c < 3; c++) {
        const uint32_t *a = m->tri_v[c], *b = m->tri_v[(c + 1) % 3];
        if (!sb_any_overstretched(s->team, p, a, b, m->tri_len0[c], m->triangle_count)) continue;
        uint32_t t = sb_first_overstretched(p, a, b, m->tri_len0[c], m->triangle_count);
        if (t != UINT32_MAX)
            return sb_error_set(&s->error, SB_ERR_UNSTABLE,
                                "step %llu (t = %.9g s): triangle %u, edge from vertex %u to %u, is over %g times its "
                                "rest length; the time step is too large for the stiffness",
                                (unsigned long long)s->steps, s->time, t, a[t], b[t], SB_STRETCH_LIMIT);
    }
    return SB_OK;
}
