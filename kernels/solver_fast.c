/* The solver's fast path: one OpenMP parallel region per step.
 *
 * Design. A step is a sequence of passes inside a single parallel region,
 * so a small model pays for one fork and join per step, not one per
 * kernel:
 *   1. drift (per vertex): the Verlet position update, fused with setting
 *      each force to m g, so forces need no separate clearing pass;
 *   2. forces: for each element group (bonds, triangles, hinges), for each
 *      block color, its blocks in parallel, and in each block the SIMD
 *      kernel over each element color (kernels/fast_model.h explains the
 *      blocked coloring). Neither lanes nor threads ever add to the same
 *      vertex at once, so no atomics are needed, and every vertex sums its
 *      contributions in the same order for any thread count: the state is
 *      bitwise the same for 1 or N threads. A barrier separates block
 *      colors (a handful), not element colors;
 *   3. external forces (one thread, only when a callback is set);
 *   4. kick (per vertex): the closing half kick of the velocity, fused with
 *      the kinetic and gravitational energy sums and the finiteness check.
 * Energies are summed per block (and per fixed-size chunk of vertices),
 * never per thread, and those sums are added in order after the region.
 *
 * Alternatives measured against this scheme are in bench/results (see
 * README there); the colored scatter is what the fast path keeps. */
#include "kernels/solver_internal.h"
#include "softbond/runtime.h"
#include "kernels/fast_kernels.h"
#include "kernels/error.h"
#include "kernels/wide.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* Vertices per chunk of the vertex passes, which own their energy sums. */
#define SB_CHUNK 256

typedef bool (*sb_fast_kernel)(const sb_fast_model*, const sb_fast_frame*, uint32_t, uint32_t, bool, double*);

/* Where each pass keeps its per-block (per-chunk) sums in solver->partials. */
typedef struct sb_partial_layout {
    double* bonds;     /* 2 per block: bond, spring */
    double* triangles; /* 4 per block: angle, stretch-bend, fused bond, fused spring */
    double* hinges;    /* 1 per block */
    double* vertices;  /* 2 per vertex chunk: kinetic, gravity */
    uint32_t vertex_chunks;
} sb_partial_layout;

static uint32_t sb_vertex_chunks(uint32_t n) { return (n + SB_CHUNK - 1) / SB_CHUNK; }

static sb_partial_layout sb_partials_of(const sb_solver* s) {
    const sb_fast_model* f = s->fast;
    sb_partial_layout p;
    p.bonds = s->partials;
    p.triangles = p.bonds + 2 * (size_t)f->bonds.block_count;
    p.hinges = p.triangles + 4 * (size_t)f->triangles.block_count;
    p.vertices = p.hinges + f->hinges.block_count;
    p.vertex_chunks = sb_vertex_chunks(f->vertex_count);
    return p;
}

sb_status sb_fast_prepare(sb_solver* s, sb_error* err) {
    s->threads = sb_runtime_threads(s->def.threads, err);
    if (s->threads < 0) return SB_ERR_INVALID;
    s->fast = sb_fast_model_create(s->model, err);
    if (!s->fast) return SB_ERR_NOMEM;
    const sb_fast_model* f = s->fast;
    size_t count = 2 * (size_t)f->bonds.block_count + 4 * (size_t)f->triangles.block_count + f->hinges.block_count +
                   2 * (size_t)sb_vertex_chunks(f->vertex_count);
    s->partials = calloc(count ? count : 1, sizeof *s->partials);
    size_t packed = ((4 * (size_t)f->vertex_count * sizeof(sb_real)) / 64 + 1) * 64;
    s->positions4 = aligned_alloc(64, packed);
    s->forces4 = aligned_alloc(64, packed);
    if (!s->partials || !s->positions4 || !s->forces4)
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory for the fast solver");
    memset(s->positions4, 0, packed);
    memset(s->forces4, 0, packed);
    sb_runtime_bind(s->threads);
    return SB_OK;
}

static void sb_run_block(const sb_fast_model* f, const sb_element_group* g, uint32_t b, sb_fast_kernel kernel,
                         int terms, const sb_fast_frame* frame, double* partials, int* collapsed) {
    const sb_block block = g->blocks[b];
    double* energy = partials + (size_t)terms * b;
    memset(energy, 0, (size_t)terms * sizeof *energy);
    bool bad = false;
    for (uint32_t r = block.first_range; r < block.first_range + block.range_count; r++)
        bad |= kernel(f, frame, g->ranges[r].begin, g->ranges[r].end, g->ranges[r].serial, energy);
    if (bad) {
#pragma omp atomic write
        *collapsed = 1;
    }
}

/* Runs one kernel over a whole group. Called by all threads of the region;
 * returns with all of them past the last block color's barrier. The
 * overflow block color, whose blocks may share vertices, runs on one thread. */
static void sb_group_pass(const sb_fast_model* f, const sb_element_group* g, sb_fast_kernel kernel, int terms,
                          const sb_fast_frame* frame, double* partials, int* collapsed) {
    for (uint32_t k = 0; k < g->block_colors; k++) {
        int first = (int)g->color_first_block[k], last = (int)g->color_first_block[k + 1];
        if (k == SB_OVERFLOW_COLOR) {
#pragma omp single
            for (int b = first; b < last; b++) sb_run_block(f, g, (uint32_t)b, kernel, terms, frame, partials, collapsed);
        } else {
#pragma omp for schedule(static)
            for (int b = first; b < last; b++) sb_run_block(f, g, (uint32_t)b, kernel, terms, frame, partials, collapsed);
        }
    }
}

static void sb_force_passes(const sb_solver* s, const sb_partial_layout* p, int* collapsed) {
    const sb_fast_model* f = s->fast;
    const sb_state* st = &s->state;
    sb_fast_frame frame = {s->positions4, st->vx, st->vy, st->vz, s->forces4};
    if (f->has_bond || f->has_spring) sb_group_pass(f, &f->bonds, sb_fast_bonds, 2, &frame, p->bonds, collapsed);
    if (f->has_corners || f->fused_bonds)
        sb_group_pass(f, &f->triangles, sb_fast_corners, 4, &frame, p->triangles, collapsed);
    if (f->has_hinges) sb_group_pass(f, &f->hinges, sb_fast_hinges, 1, &frame, p->hinges, collapsed);
}

/* Serial, on one thread: the callback need not be thread-safe. */
static void sb_external_pass(sb_solver* s) {
    sb_state* st = &s->state;
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        if (s->model->fixed[i]) continue;
        sb_real* packed = s->forces4 + 4 * (size_t)i;
        double x[3] = {st->x[i], st->y[i], st->z[i]}, v[3] = {st->vx[i], st->vy[i], st->vz[i]};
        double f[3] = {packed[0], packed[1], packed[2]};
        s->def.external_force(s->def.external_user, i, s->time, x, v, f);
        for (int c = 0; c < 3; c++) packed[c] = (sb_real)f[c];
    }
}

/* The vertex range of chunk c. */
static void sb_vertex_range(uint32_t n, int c, uint32_t* begin, uint32_t* end) {
    *begin = (uint32_t)c * SB_CHUNK;
    *end = *begin + SB_CHUNK < n ? *begin + SB_CHUNK : n;
}

/* Packs the positions and sets the packed forces to gravity and drag. */
static void sb_gravity_pass(sb_solver* s, const sb_partial_layout* p) {
    sb_state* st = &s->state;
    const sb_real* mass = s->fast->mass;
    const sb_real gx = (sb_real)s->def.gravity[0], gy = (sb_real)s->def.gravity[1], gz = (sb_real)s->def.gravity[2];
    const sb_real drag = (sb_real)s->def.drag;
#pragma omp for schedule(static)
    for (int c = 0; c < (int)p->vertex_chunks; c++) {
        uint32_t begin, end;
        sb_vertex_range(st->vertex_count, c, &begin, &end);
        sb_real *p4 = s->positions4, *f4 = s->forces4;
#pragma omp simd
        for (uint32_t i = begin; i < end; i++) {
            p4[4 * i] = st->x[i];
            p4[4 * i + 1] = st->y[i];
            p4[4 * i + 2] = st->z[i];
            f4[4 * i] = mass[i] * (gx - drag * st->vx[i]);
            f4[4 * i + 1] = mass[i] * (gy - drag * st->vy[i]);
            f4[4 * i + 2] = mass[i] * (gz - drag * st->vz[i]);
        }
    }
}

/* Drift for both Verlet forms (see kernels/integrators.c for the
 * formulas), fused with initialising the forces to gravity and drag. */
static void sb_drift_pass(sb_solver* s, const sb_partial_layout* p, double dt, bool stormer) {
    sb_state* st = &s->state;
    const sb_real *mass = s->fast->mass, *inv_mass = s->fast->inv_mass;
    const sb_real gx = (sb_real)s->def.gravity[0], gy = (sb_real)s->def.gravity[1], gz = (sb_real)s->def.gravity[2];
    const sb_real scale = stormer ? (sb_real)(dt / s->prev_dt) : 0;
    const sb_real accel = stormer ? (sb_real)(0.5 * dt * (dt + s->prev_dt)) : (sb_real)(0.5 * dt);
    const sb_real step = (sb_real)dt, inv_dt = (sb_real)(1.0 / dt), drag = (sb_real)s->def.drag;
    sb_real* pos[3] = {st->x, st->y, st->z};
    sb_real* disp[3] = {s->disp_x, s->disp_y, s->disp_z};
    sb_real* vel[3] = {st->vx, st->vy, st->vz};
    sb_real* force[3] = {st->fx, st->fy, st->fz}; /* the last step's, published by the kick */
    sb_real *p4 = s->positions4, *f4 = s->forces4;
    const sb_real g[3] = {gx, gy, gz};
#pragma omp for schedule(static)
    for (int c = 0; c < (int)p->vertex_chunks; c++) {
        uint32_t begin, end;
        sb_vertex_range(st->vertex_count, c, &begin, &end);
        for (int a = 0; a < 3; a++) {
            sb_real *x = pos[a], *d = disp[a], *v = vel[a], *f = force[a];
#pragma omp simd
            for (uint32_t i = begin; i < end; i++) {
                if (stormer) {
                    d[i] = scale * d[i] + accel * inv_mass[i] * f[i];
                    v[i] = d[i] * inv_dt;
                } else {
                    v[i] = v[i] + accel * inv_mass[i] * f[i];
                    d[i] = step * v[i];
                }
                x[i] = x[i] + d[i];
                p4[4 * i + a] = x[i];
                f4[4 * i + a] = mass[i] * (g[a] - drag * v[i]);
            }
        }
    }
}

/* Closing half kick, fused with publishing the packed forces to the state,
 * the energy sums and the state check. */
static void sb_kick_pass(sb_solver* s, const sb_partial_layout* p, double dt, int* bad) {
    sb_state* st = &s->state;
    const sb_real *mass = s->fast->mass, *inv_mass = s->fast->inv_mass;
    const sb_real half = (sb_real)(0.5 * dt);
    const double* g = s->def.gravity;
    const sb_real cx = (sb_real)s->center[0], cy = (sb_real)s->center[1], cz = (sb_real)s->center[2];
    const sb_real limit = (sb_real)s->runaway;
#pragma omp for schedule(static)
    for (int c = 0; c < (int)p->vertex_chunks; c++) {
        uint32_t begin, end;
        sb_vertex_range(st->vertex_count, c, &begin, &end);
        double kinetic = 0.0, gravity = 0.0;
        int outside = 0;
        const sb_real* f4 = s->forces4;
#pragma omp simd reduction(+ : kinetic, gravity, outside)
        for (uint32_t i = begin; i < end; i++) {
            st->fx[i] = f4[4 * i];
            st->fy[i] = f4[4 * i + 1];
            st->fz[i] = f4[4 * i + 2];
            sb_real w = half * inv_mass[i];
            sb_real vx = st->vx[i] + w * st->fx[i], vy = st->vy[i] + w * st->fy[i], vz = st->vz[i] + w * st->fz[i];
            st->vx[i] = vx;
            st->vy[i] = vy;
            st->vz[i] = vz;
            sb_real free = inv_mass[i] != 0 ? 1 : 0;
            kinetic += (double)(free * (sb_real)0.5 * mass[i] * (vx * vx + vy * vy + vz * vz));
            gravity -= (double)(free * mass[i] * ((sb_real)g[0] * st->x[i] + (sb_real)g[1] * st->y[i] + (sb_real)g[2] * st->z[i]));
            /* written so that NaN fails the comparison and counts as outside */
            outside += !(fabs(st->x[i] - cx) <= limit && fabs(st->y[i] - cy) <= limit &&
                         fabs(st->z[i] - cz) <= limit && fabs(vx) <= (sb_real)INFINITY &&
                         fabs(vy) <= (sb_real)INFINITY && fabs(vz) <= (sb_real)INFINITY);
        }
        p->vertices[2 * c] = kinetic;
        p->vertices[2 * c + 1] = gravity;
        if (outside) {
#pragma omp atomic write
            *bad = 1;
        }
    }
}

static double sb_sum_strided(const double* values, uint32_t count, int stride, int offset) {
    double sum = 0.0;
    for (uint32_t c = 0; c < count; c++) sum += values[(size_t)c * stride + offset];
    return sum;
}

/* Adds the chunk sums in chunk order into the solver's energies. A pass
 * that never runs leaves its chunk sums at the zeros they were allocated with. */
static void sb_collect_energies(sb_solver* s, const sb_partial_layout* p, bool with_vertices) {
    const sb_fast_model* f = s->fast;
    sb_energies* e = &s->energies;
    uint32_t bond_chunks = f->bonds.block_count, triangle_chunks = f->triangles.block_count;
    e->term[SB_TERM_BOND] = sb_sum_strided(p->bonds, bond_chunks, 2, 0) + sb_sum_strided(p->triangles, triangle_chunks, 4, 2);
    e->term[SB_TERM_SPRING] = sb_sum_strided(p->bonds, bond_chunks, 2, 1) + sb_sum_strided(p->triangles, triangle_chunks, 4, 3);
    e->term[SB_TERM_ANGLE] = sb_sum_strided(p->triangles, triangle_chunks, 4, 0);
    e->term[SB_TERM_STRETCH_BEND] = sb_sum_strided(p->triangles, triangle_chunks, 4, 1);
    e->term[SB_TERM_BEND] = sb_sum_strided(p->hinges, f->hinges.block_count, 1, 0);
    if (with_vertices) {
        e->kinetic = sb_sum_strided(p->vertices, p->vertex_chunks, 2, 0);
        e->gravity = sb_sum_strided(p->vertices, p->vertex_chunks, 2, 1);
    }
}

/* A collapse was flagged: the reference names the element. */
static sb_status sb_report_collapse(sb_solver* s) {
    sb_interleave(s->scratch_x, s->state.x, s->state.y, s->state.z, s->state.vertex_count);
    sb_energies ignored;
    sb_status status = sb_reference_forces(s->model, s->scratch_x, NULL, s->scratch_f, &ignored, &s->error);
    if (status == SB_OK) sb_error_set(&s->error, SB_ERR_DEGENERATE, "an edge collapsed (below %g of its rest length)", 1e-9);
    return SB_ERR_DEGENERATE;
}

/* Copies the packed forces to the state's arrays. */
static void sb_publish_pass(sb_solver* s) {
    sb_state* st = &s->state;
    const sb_real* f4 = s->forces4;
#pragma omp for schedule(static)
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        st->fx[i] = f4[4 * i];
        st->fy[i] = f4[4 * i + 1];
        st->fz[i] = f4[4 * i + 2];
    }
}

sb_status sb_fast_compute_forces(sb_solver* s) {
    sb_partial_layout p = sb_partials_of(s);
    int collapsed = 0;
#pragma omp parallel num_threads(s->threads)
    {
        sb_gravity_pass(s, &p);
        sb_force_passes(s, &p, &collapsed);
#pragma omp single
        if (s->def.external_force) sb_external_pass(s);
        sb_publish_pass(s);
    }
    sb_collect_energies(s, &p, false);
    return collapsed ? sb_report_collapse(s) : SB_OK;
}

sb_status sb_fast_verlet_step(sb_solver* s, double dt) {
    bool stormer = s->def.integrator == SB_INTEGRATOR_VERLET && s->has_displacement;
    sb_partial_layout p = sb_partials_of(s);
    int collapsed = 0, bad = 0;
#pragma omp parallel num_threads(s->threads)
    {
        sb_drift_pass(s, &p, dt, stormer);
        sb_force_passes(s, &p, &collapsed);
#pragma omp single
        if (s->def.external_force) sb_external_pass(s);
        sb_kick_pass(s, &p, dt, &bad);
    }
    s->has_displacement = true;
    s->prev_dt = dt;
    sb_collect_energies(s, &p, true);
    if (bad) return sb_check_state(s);
    return collapsed ? sb_report_collapse(s) : SB_OK;
}
