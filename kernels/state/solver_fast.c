/* The solver's fast path: one job of the solver's thread team per step.
 *
 * Design. A step is a sequence of passes inside a single job of the team,
 * so a small model pays for one fork and join per step, not one per
 * kernel (the team and its wait policy: kernels/runtime/team.c):
 *   1. drift (per vertex): the Verlet position update, fused with setting
 *      each force to m g, so forces need no separate clearing pass, and
 *      with the position check in the same loop, followed per chunk by the
 *      contact pass (kernels/contact/contact.c) and, on a step whose energies are
 *      summed (or after a contact pass), while the chunk is in cache, the
 *      gravitational energy sum and the position check (in the kick
 *      instead when self-contact or hard handles move vertices after the
 *      drift);
 *   2. forces: for each element group (bonds, triangles, hinges,
 *      tetrahedra, membranes), for each block color, its blocks in parallel,
 *      and in each block the kernel (SIMD but the tetrahedra's and the
 *      membranes') over each element
 *      color (kernels/forces/fast_model.h explains the
 *      blocked coloring). The triangle kernel also computes the bonds and
 *      hinges on its edges (kernels/forces/fast_corners.c), so on a mesh the bond
 *      and hinge passes have nothing to do. Neither lanes nor threads ever
 *      add to the same vertex at once, so no atomics are needed, and every
 *      vertex sums its contributions in the same order for any thread
 *      count: the state is bitwise the same for 1 or N threads. A barrier
 *      separates block colors (a handful), not element colors;
 *   3. external forces (one thread, only when a callback is set);
 *   4. kick (per vertex): the closing half kick of the velocity, fused with
 *      the velocities' finiteness check and, on a step whose energies are
 *      summed, the kinetic energy sum. When
 *      nothing reads the half-step velocities (sb_half_step_velocity_read)
 *      the Störmer drift does not store them and the kick recomputes them
 *      from the displacements it reads instead.
 * Energies are summed per block (and per fixed-size chunk of vertices),
 * never per thread, and those sums are added in order after the job. The
 * term energies come with the forces; the kinetic and gravitational sums
 * only on steps whose energies are read (sb_step_sums), the others leave
 * them to sb_solver_settle (sb_fast_vertex_energies, the same arithmetic
 * on the packed state). The state check runs on every step.
 *
 * Per-thread force buffers (no block coloring, a reduction instead) were
 * measured slower at 10k, 100k and 1M vertices, and their sums depend on
 * how blocks fall to threads, so results would differ between thread
 * counts; the blocked coloring with packed x y z w loads and a packed
 * working state is faster at every size and deterministic. At 100k a step
 * is bound by the triangle kernel's gathers and scatters (27 packed
 * loads/adds per triangle), at 1M by memory bandwidth (the byte model of
 * bench/bench_model.c), which is why the passes stream one real of mass a
 * vertex and the kick reads no positions nothing changed. The table of
 * those schemes and the byte model's history are in
 * bench/results/notes/fast_step.md. */
#include "kernels/state/solver_fast.h"
#include "kernels/forces/fast_bonds.h"
#include "kernels/forces/fast_corners.h"
#include "kernels/forces/fast_hinges.h"
#include "kernels/forces/fast_tets.h"
#include "kernels/forces/fast_membranes.h"
#include "kernels/state/vertex_state.h"
#include "softbond/reference.h"
#include "softbond/runtime.h"
#include "common/error.h"
#include "kernels/runtime/wide.h"
#include "kernels/runtime/team.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* What the force passes report: an edge collapsed; a bond near its break
 * limits (SB_KERNEL_NEAR_LIMIT). */
typedef struct sb_pass_flags {
    atomic_int collapsed, near_limit;
} sb_pass_flags;

/* Where each pass keeps its per-block (per-chunk) sums in solver->partials. */
typedef struct sb_partial_layout {
    double* bonds;     /* 2 per block: bond, spring */
    double* triangles; /* 5 per block: angle, stretch-bend, fused bond, fused spring, fused bend */
    double* hinges;    /* 1 per block */
    double* tets;      /* 1 per block: corotated */
    double* membranes; /* 2 per block: membrane, a flat sheet's plate bending */
    double* vertices;  /* 2 per vertex chunk: kinetic, gravity */
    uint32_t vertex_chunks;
} sb_partial_layout;

static uint32_t sb_vertex_chunks(uint32_t n) { return sb_chunk_count(n); }

static sb_partial_layout sb_partials_of(const sb_solver* s) {
    const sb_fast_model* f = s->fast;
    sb_partial_layout p;
    p.bonds = s->partials;
    p.triangles = p.bonds + 2 * (size_t)f->bonds.block_count;
    p.hinges = p.triangles + 5 * (size_t)f->triangles.block_count;
    p.tets = p.hinges + f->hinges.block_count;
    p.membranes = p.tets + f->tets.block_count;
    p.vertices = p.membranes + 2 * (size_t)f->membranes.block_count;
    p.vertex_chunks = sb_vertex_chunks(f->vertex_count);
    return p;
}

/* The partial sums' count: per block of each group, per chunk of vertices. */
static size_t sb_partial_count(const sb_fast_model* f) {
    return 2 * (size_t)f->bonds.block_count + 5 * (size_t)f->triangles.block_count + f->hinges.block_count +
           f->tets.block_count + 2 * (size_t)f->membranes.block_count + 2 * (size_t)sb_vertex_chunks(f->vertex_count);
}

sb_status sb_fast_prepare(sb_solver* s, sb_error* err) {
    s->fast = sb_fast_model_create(s->model, err);
    if (!s->fast) return SB_ERR_NOMEM;
    size_t count = sb_partial_count(s->fast);
    s->partials = calloc(count ? count : 1, sizeof *s->partials);
    size_t packed = ((4 * (size_t)s->fast->vertex_count * sizeof(sb_real)) / 64 + 1) * 64;
    sb_real** arrays[5] = {&s->positions4, &s->velocities4, &s->displacements4, &s->forces4, &s->carry4};
    bool ok = s->partials != NULL;
    for (int a = 0; a < 5; a++) {
        *arrays[a] = aligned_alloc(64, packed);
        ok = ok && *arrays[a];
        if (*arrays[a]) memset(*arrays[a], 0, packed);
    }
    if (!ok) return sb_error_set(err, SB_ERR_NOMEM, "out of memory for the fast solver");
    return SB_OK;
}

sb_status sb_fast_rebuild(sb_solver* s, sb_error* err) {
    sb_fast_model* fast = sb_fast_model_create(s->model, err);
    if (!fast) return SB_ERR_NOMEM;
    size_t count = sb_partial_count(fast);
    double* partials = calloc(count ? count : 1, sizeof *partials);
    if (!partials) {
        sb_fast_model_destroy(fast);
        free(partials);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory rebuilding the fast model");
    }
    const double* moving = sb_inv_mass(s); /* 0 where a hard handle holds */
    for (uint32_t i = 0; i < fast->vertex_count; i++) fast->inv_mass[i] = (sb_real)moving[i];
    sb_fast_model_destroy(s->fast);
    free(s->partials);
    s->fast = fast;
    s->partials = partials;
    return SB_OK;
}

sb_real sb_fast_initial_force(const sb_solver* s, uint32_t i, int a, double velocity) {
    return (sb_real)(s->model->mass[i] * (s->def.gravity[a] - s->def.drag * velocity));
}

/* Gravity per packed lane: (g_x, g_y, g_z, 0). */
static void sb_gravity4(const sb_solver* s, sb_real g4[4]) {
    for (int a = 0; a < 4; a++) g4[a] = a < 3 ? (sb_real)s->def.gravity[a] : 0;
}

static void sb_run_block(const sb_fast_model* f, const sb_element_group* g, uint32_t b, sb_fast_kernel kernel,
                         int terms, const sb_fast_frame* frame, double* partials, sb_pass_flags* flags) {
    const sb_block block = g->blocks[b];
    double* energy = partials + (size_t)terms * b;
    memset(energy, 0, (size_t)terms * sizeof *energy);
    int raised = 0;
    for (uint32_t r = block.first_range; r < block.first_range + block.range_count; r++)
        raised |= kernel(f, frame, g->ranges[r].begin, g->ranges[r].end, g->ranges[r].serial, energy);
    if (raised & SB_KERNEL_COLLAPSED) sb_worker_raise(&flags->collapsed);
    if (raised & SB_KERNEL_NEAR_LIMIT) sb_worker_raise(&flags->near_limit);
}

/* Runs one kernel over a whole group. Called by all workers of the job;
 * returns with all of them past the last block color's barrier. A color's
 * blocks share no vertex and each sums into its own partials, so they are
 * claimed (sb_worker_claim): whichever worker runs a block, the result is
 * the same. The overflow block color, whose blocks may share vertices,
 * runs on worker 0. */
static void sb_group_pass(const sb_worker* w, const sb_fast_model* f, const sb_element_group* g, sb_fast_kernel kernel,
                          int terms, const sb_fast_frame* frame, double* partials, sb_pass_flags* flags) {
    for (uint32_t k = 0; k < g->block_colors; k++) {
        int64_t first = g->color_first_block[k], last = g->color_first_block[k + 1], begin, end;
        if (k == SB_OVERFLOW_COLOR) { /* worker 0 alone */
            for (int64_t b = w->index == 0 ? first : last; b < last; b++)
                sb_run_block(f, g, (uint32_t)b, kernel, terms, frame, partials, flags);
        } else {
            sb_claims claims = sb_worker_claims(last - first);
            while (sb_worker_claim(w, &claims, &begin, &end))
                for (int64_t b = first + begin; b < first + end; b++)
                    sb_run_block(f, g, (uint32_t)b, kernel, terms, frame, partials, flags);
        }
        sb_worker_barrier(w);
    }
}

void sb_fast_element_passes(const sb_worker* w, const sb_solver* s, const sb_fast_kernel kernels[5],
                            const sb_fast_frame* frame) {
    const sb_fast_model* f = s->fast;
    sb_pass_flags flags = {0, 0}; /* such kernels raise none */
    if (f->has_bond || f->has_spring) sb_group_pass(w, f, &f->bonds, kernels[0], 0, frame, s->partials, &flags);
    if (f->has_corners || f->fused_bonds) sb_group_pass(w, f, &f->triangles, kernels[1], 0, frame, s->partials, &flags);
    if (f->has_hinges) sb_group_pass(w, f, &f->hinges, kernels[2], 0, frame, s->partials, &flags);
    if (f->has_tets) sb_group_pass(w, f, &f->tets, kernels[3], 0, frame, s->partials, &flags);
    if (f->has_membranes) sb_group_pass(w, f, &f->membranes, kernels[4], 0, frame, s->partials, &flags);
}

static void sb_force_passes(const sb_worker* w, const sb_solver* s, const sb_partial_layout* p, sb_pass_flags* flags) {
    const sb_fast_model* f = s->fast;
    sb_fast_frame frame = {s->positions4, s->carry4, s->velocities4, s->forces4};
    if (f->has_bond || f->has_spring) sb_group_pass(w, f, &f->bonds, sb_fast_bonds, 2, &frame, p->bonds, flags);
    if (f->has_corners || f->fused_bonds || f->fused_hinges)
        sb_group_pass(w, f, &f->triangles, sb_fast_corners, 5, &frame, p->triangles, flags);
    if (f->has_hinges && !f->fused_hinges) sb_group_pass(w, f, &f->hinges, sb_fast_hinges, 1, &frame, p->hinges, flags);
    if (f->has_tets) sb_group_pass(w, f, &f->tets, sb_fast_tets, 1, &frame, p->tets, flags);
    if (f->has_membranes) sb_group_pass(w, f, &f->membranes, sb_fast_membranes, 2, &frame, p->membranes, flags);
}

/* Serial, on one thread: the callback need not be thread-safe; then the
 * post_force hook (the soft handles' forces). */
static void sb_external_pass(sb_solver* s) {
    for (uint32_t i = 0; i < s->state.vertex_count && s->def.external_force; i++) {
        if (s->model->fixed[i]) continue;
        const sb_real *x4 = s->positions4 + 4 * (size_t)i, *v4 = s->velocities4 + 4 * (size_t)i;
        sb_real* f4 = s->forces4 + 4 * (size_t)i;
        double x[3] = {x4[0], x4[1], x4[2]}, v[3] = {v4[0], v4[1], v4[2]}, f[3] = {f4[0], f4[1], f4[2]};
        s->def.external_force(s->def.external_user, i, s->time, x, v, f);
        for (int c = 0; c < 3; c++) {
            if (s->external) s->external[3 * i + c] = f[c] - f4[c]; /* kept for adaptive stepping */
            f4[c] = (sb_real)f[c];
        }
    }
    if (s->hooks.post_force_packed) s->hooks.post_force_packed(s);
}

/* Worker 0 calls the external-force callback (it need not be thread-safe);
 * the others wait for it. */
static void sb_external_step(const sb_worker* w, sb_solver* s) {
    if (!s->def.external_force && !s->hooks.post_force_packed) return;
    if (w->index == 0) sb_external_pass(s);
    sb_worker_barrier(w);
}

/* The vertex chunks of the first n vertices this worker claims
 * (sb_worker_claim: each chunk sums into its own partials, so whichever
 * worker runs it the result is the same), one at a time, each with its
 * packed range [begin, end) (4 reals a vertex):
 *     for (sb_chunks it = sb_my_chunks(w, p, n); sb_next_chunk(&it);) ...
 * A chunk past n is not visited: its chunk sums keep the zeros they were
 * allocated with. */
typedef struct sb_chunks {
    const sb_worker* worker;
    sb_claims claims;
    int64_t chunk, last; /* the claim's chunks [chunk + 1, last) are left */
    uint32_t vertex_count;
    size_t begin, end;
} sb_chunks;

static inline sb_chunks sb_my_chunks(const sb_worker* w, const sb_partial_layout* p, uint32_t vertex_count) {
    return (sb_chunks){.worker = w, .claims = sb_worker_claims(p->vertex_chunks), .vertex_count = vertex_count};
}

static inline bool sb_next_chunk(sb_chunks* it) {
    if (++it->chunk >= it->last && !sb_worker_claim(it->worker, &it->claims, &it->chunk, &it->last)) return false;
    size_t first = (size_t)it->chunk * SB_CHUNK, n = it->vertex_count;
    if (first >= n) return false; /* so are the chunks after it */
    it->begin = 4 * first;
    it->end = 4 * (first + SB_CHUNK < n ? first + SB_CHUNK : n);
    return true;
}

/* The vertices a step moves: a tearing solver's spare vertices past
 * live_vertices are dormant (fixed, massless, in no element) until a split
 * fills them and evaluates everything again, so the drift and the kick
 * skip them (a tenth of the 100k sheet's vertices: bench/results/tearing.md). */
static inline uint32_t sb_moving_vertices(const sb_solver* s) { return s->live_vertices; }

/* Sets the packed forces [begin, end) to gravity and drag at the packed
 * velocities. */
static void sb_initial_forces_range(const sb_solver* s, size_t begin, size_t end) {
    const sb_real* m = s->fast->mass;
    const sb_real drag = (sb_real)s->def.drag;
    sb_real g4[4];
    sb_gravity4(s, g4);
    for (size_t k = begin; k < end; k++) s->forces4[k] = sb_packed_lane(m, k) * (g4[k & 3] - drag * s->velocities4[k]);
}

/* Packs the state's positions and velocities (after sb_solver_set_state)
 * and sets the packed forces to gravity and drag. */
static void sb_pack_pass(const sb_worker* w, sb_solver* s, const sb_partial_layout* p) {
    const sb_state* st = &s->state;
    const sb_real* soa[2][3] = {{st->x, st->y, st->z}, {st->vx, st->vy, st->vz}};
    for (sb_chunks it = sb_my_chunks(w, p, st->vertex_count); sb_next_chunk(&it);) {
        size_t begin = it.begin, end = it.end;
        for (size_t k = begin; k < end; k++) {
            size_t i = k / 4;
            int a = (int)(k & 3);
            s->positions4[k] = a < 3 ? soa[0][a][i] : 0;
            s->velocities4[k] = a < 3 ? soa[1][a][i] : 0;
        }
        sb_initial_forces_range(s, begin, end);
    }
    sb_worker_barrier(w);
}

/* Sets the packed forces to gravity and drag at the packed velocities. */
static void sb_initial_forces_pass(const sb_worker* w, sb_solver* s, const sb_partial_layout* p) {
    for (sb_chunks it = sb_my_chunks(w, p, s->state.vertex_count); sb_next_chunk(&it);) {
        size_t begin = it.begin, end = it.end;
        sb_initial_forces_range(s, begin, end);
    }
    sb_worker_barrier(w);
}

/* The runaway box measured from the origin: looser than the exact test of
 * sb_check_state by the model's offset, a millionth of it. */
static sb_real sb_runaway_limit(const sb_solver* s) {
    return (sb_real)(s->runaway + fmax(fabs(s->center[0]), fmax(fabs(s->center[1]), fabs(s->center[2]))));
}

/* Whether anything between the drift and the kick reads the half-step
 * velocities: damping in the force kernels (the springs', the elements'
 * Rayleigh β), the colliders' contact, the
 * self-contact, the handles, the external-force callback. */
static bool sb_half_step_velocity_read(const sb_solver* s) {
    const sb_fast_model* f = s->fast;
    return f->has_damping || f->fused_damping || f->tet_damped || f->membrane_damped || s->def.collider_count ||
           s->self || s->def.handle_count || s->hooks.post_force_packed || s->def.external_force;
}

/* The Verlet constants of one step. */
typedef struct sb_step_constants {
    sb_real scale, accel, step, inv_dt, drag, half;
    sb_real gravity[4]; /* per packed lane: no stream of m g per vertex */
    sb_real limit;      /* the runaway box (sb_runaway_limit) */
    bool stormer;
    /* Something reads the half-step velocities before the kick (damping,
     * contact, handles, the callback): the drift stores them. Otherwise
     * (Störmer form only) the kick recomputes them from the displacements
     * it reads instead, and a step writes no velocity stream twice. */
    bool store_velocity;
    /* Nothing moves a vertex after its chunk's drift and contact (no
     * self-contact, no hard handles): the drift pass sums the gravitational
     * energy and checks the positions while the chunk is in cache, and the
     * kick need not read the positions again. */
    bool positions_final_in_drift;
    /* This step's kinetic and gravitational energies are summed in its
     * passes (something reads them: sb_step_sums); otherwise they wait for
     * sb_solver_settle (sb_fast_vertex_energies) and the step keeps only
     * the state check, fused where the values are in registers. */
    bool sums;
    /* The drift loop checks the positions it writes: no sums, and nothing
     * moves a vertex after it (positions_final_in_drift, no contact). */
    bool check_in_drift;
} sb_step_constants;

/* One chunk's masses and inverse masses spread over its packed lanes (w
 * lanes 0) in L1: the model keeps one real a vertex of each, so the vertex
 * passes stream a quarter of what packed copies would cost, and their
 * loops read them packed like the state. */
typedef struct sb_chunk_masses {
    sb_real m4[4 * SB_CHUNK], im4[4 * SB_CHUNK];
} sb_chunk_masses;

/* The masses of the packed reals [begin, end), one chunk; the inverse
 * masses alone without with_mass (a kick that sums no kinetic energy). */
static void sb_spread_masses(const sb_fast_model* f, size_t begin, size_t end, bool with_mass, sb_chunk_masses* out) {
    const sb_real *m = f->mass + begin / 4, *im = f->inv_mass + begin / 4;
    size_t n = end - begin, q = 0;
    for (; q + SB_WIDTH <= n; q += SB_WIDTH) {
        if (with_mass) sb_w_store(out->m4 + q, sb_w_spread4(m, q));
        sb_w_store(out->im4 + q, sb_w_spread4(im, q));
    }
    for (; q < n; q++) {
        if (with_mass) out->m4[q] = sb_packed_lane(m, q);
        out->im4[q] = sb_packed_lane(im, q);
    }
}

/* Drift of the packed reals [0, n) of one chunk (arrays start at the chunk)
 * for both Verlet forms (see kernels/integrators/integrators.c for the formulas), fused
 * with initialising the forces to gravity and drag. The w lanes have zero
 * mass and inverse mass and stay zero. v is the chunk's velocities or, when
 * nothing reads them (!store_velocity, Störmer form), a scratch buffer in L1.
 * With check_in_drift it returns whether a new position is not finite or
 * outside the runaway box, tested while it is in a register (an OR of
 * comparisons the compiler vectorizes with the loop); 0 otherwise.
 * The arrays are restrict parameters, not locals, because only then does
 * GCC 12 vectorize the loops (its report says so). */
static inline __attribute__((always_inline)) int sb_drift_loop(const sb_real* restrict m4, const sb_real* restrict im4,
                                                               sb_real* restrict x, sb_real* restrict carry,
                                                               sb_real* restrict d, sb_real* restrict v,
                                                               sb_real* restrict f, const sb_step_constants* k,
                                                               size_t n, bool stormer, bool check) {
    const sb_real scale = k->scale, accel = k->accel, step = k->step, inv_dt = k->inv_dt, drag = k->drag;
    const sb_real limit = k->limit;
    const sb_real* g = k->gravity;
    int outside = 0; /* NaN fails both comparisons and counts as outside */
    for (size_t q = 0; q < n; q++) {
        if (stormer) {
            d[q] = scale * d[q] + accel * im4[q] * f[q];
            v[q] = d[q] * inv_dt;
        } else {
            v[q] = v[q] + accel * im4[q] * f[q];
            d[q] = step * v[q];
        }
        if (SB_DOUBLE) /* 53 bits: no carry (kernels/state/vertex_state.h) */
            x[q] = x[q] + d[q];
        else {
            sb_compensated next = sb_compensated_add(x[q], d[q], carry[q]);
            x[q] = next.sum, carry[q] = next.carry;
        }
        f[q] = m4[q] * (g[q & 3] - drag * v[q]);
        if (check) outside |= !((x[q] <= limit) & (x[q] >= -limit));
    }
    return outside;
}

/* sb_drift_loop inlined once for each form, with and without the check. */
static int sb_drift_range(const sb_real* restrict m4, const sb_real* restrict im4, sb_real* restrict x,
                          sb_real* restrict carry, sb_real* restrict d, sb_real* restrict v, sb_real* restrict f,
                          const sb_step_constants* k, size_t n) {
    if (k->stormer)
        return k->check_in_drift ? sb_drift_loop(m4, im4, x, carry, d, v, f, k, n, true, true)
                                 : sb_drift_loop(m4, im4, x, carry, d, v, f, k, n, true, false);
    return k->check_in_drift ? sb_drift_loop(m4, im4, x, carry, d, v, f, k, n, false, true)
                             : sb_drift_loop(m4, im4, x, carry, d, v, f, k, n, false, false);
}

/* Returns whether a position of packed reals [begin, end) is not finite
 * or outside the runaway box; with sum_gravity, their gravitational energy
 * into *gravity (a step that sums no energy only checks). m4 and im4 start
 * at begin.
 * Lane-wise sums in SIMD registers, reduced once (see sb_kick_range).
 * Inlined into two copies, with and without the sum. */
static inline __attribute__((always_inline)) int
sb_positions_range_of(const sb_real* restrict m4, const sb_real* restrict im4, const sb_real* restrict x,
                      const sb_step_constants* k, size_t begin, size_t end, bool sum_gravity, double* gravity) {
    sb_real g[4 + SB_WIDTH]; /* g[i] = gravity[i % 4]: lanes from q on load g + q % 4 */
    if (sum_gravity)
        for (int i = 0; i < 4 + SB_WIDTH; i++) g[i] = k->gravity[i & 3];
    const sb_wide zero = sb_w_set(0), one = sb_w_set(1), bound = sb_w_set(k->limit);
    sb_wide sum = zero;
    sb_wmask outside = 0;
    size_t q = begin;
    for (; q + SB_WIDTH <= end; q += SB_WIDTH) {
        sb_wide xq = sb_w_load(x + q);
        if (sum_gravity) {
            sb_wide free = sb_w_pick_greater(sb_w_load(im4 + (q - begin)), zero, one, zero);
            sum = sb_w_sub(sum,
                           sb_w_mul(sb_w_mul(free, sb_w_load(m4 + (q - begin))), sb_w_mul(sb_w_load(g + (q & 3)), xq)));
        }
        outside |= sb_w_less(bound, sb_w_abs(xq)); /* NaN fails the comparison and counts as outside */
    }
    if (sum_gravity) *gravity = sb_w_sum(sum, SB_WIDTH);
    int bad = sb_w_any(outside, SB_WIDTH);
    for (; q < end; q++) {
        if (sum_gravity) *gravity -= (im4[q - begin] > 0 ? m4[q - begin] : 0) * g[q & 3] * x[q];
        bad |= !((x[q] <= k->limit) & (x[q] >= -k->limit));
    }
    return bad;
}

/* sb_positions_range_of in a step: summing the energy when the step sums
 * (k->sums). */
static int sb_positions_range(const sb_real* restrict m4, const sb_real* restrict im4, const sb_real* restrict x,
                              const sb_step_constants* k, size_t begin, size_t end, double* gravity) {
    return k->sums ? sb_positions_range_of(m4, im4, x, k, begin, end, true, gravity)
                   : sb_positions_range_of(m4, im4, x, k, begin, end, false, gravity);
}

/* The drift of this worker's chunks, each followed by its contact pass
 * (kernels/contact/contact.c) and, when they are final, its positions' energy and
 * check, while the chunk is in cache (the check alone inside the drift's
 * loop when no energy is summed and no contact moves them). */
static void sb_drift_pass(const sb_worker* w, sb_solver* s, const sb_partial_layout* p, const sb_step_constants* k,
                          double dt, atomic_int* bad) {
    sb_real scratch[4 * SB_CHUNK]; /* the half-step velocities nothing reads */
    sb_chunk_masses masses;
    for (sb_chunks it = sb_my_chunks(w, p, sb_moving_vertices(s)); sb_next_chunk(&it);) {
        int c = it.chunk;
        size_t begin = it.begin, end = it.end;
        if (s->hooks.before_drift) s->hooks.before_drift(s, begin, end);
        sb_spread_masses(s->fast, begin, end, true, &masses);
        if (sb_drift_range(masses.m4, masses.im4, s->positions4 + begin, s->carry4 + begin, s->displacements4 + begin,
                           k->store_velocity ? s->velocities4 + begin : scratch, s->forces4 + begin, k, end - begin))
            sb_worker_raise(bad);
        if (s->hooks.drift_chunk) s->hooks.drift_chunk(s, (uint32_t)c, dt);
        if (k->positions_final_in_drift && !k->check_in_drift &&
            sb_positions_range(masses.m4, masses.im4, s->positions4, k, begin, end, p->vertices + 2 * c + 1))
            sb_worker_raise(bad);
    }
    sb_worker_barrier(w);
}

/* One SIMD vector's kinetic energy ½ m v² added to the lane-wise sums, and
 * one packed real's: the kick and sb_fast_vertex_energies share them, so
 * that the sums are bitwise the same whichever pass makes them. */
static inline sb_wide sb_kinetic_add(sb_wide sum, sb_wide m, sb_wide v) {
    return sb_w_add(sum, sb_w_mul(sb_w_mul(sb_w_set((sb_real)0.5), m), sb_w_mul(v, v)));
}
static inline double sb_kinetic_of(sb_real m, sb_real v) { return (sb_real)0.5 * m * v * v; }

/* Closing half kick of packed reals [begin, end), with sum_kinetic fused
 * with the kinetic energy sum into *kinetic; returns whether a
 * velocity is not finite. m4 (read only for the sum) and im4 start at
 * begin. The
 * half-step velocity is u times a factor: u the velocities the drift stored
 * (factor 1) or its displacements (factor 1 / dt, as the drift computed
 * it); u and v may then be one array, so neither is restrict. The sums are
 * kept lane-wise in SIMD registers and reduced once: one float sum of a
 * loop the compiler vectorizes is added in order, lane after lane, a chain
 * of scalar additions that took most of the pass (100k sheet, all terms,
 * 1 thread, bench/results/notes/fast_step.md).
 * Inlined into two copies, with and without the sum. */
static inline __attribute__((always_inline)) int sb_kick_range(const sb_real* restrict m4, const sb_real* restrict im4,
                                                               const sb_real* u, sb_real* v, const sb_real* restrict f,
                                                               const sb_step_constants* k, size_t begin, size_t end,
                                                               bool sum_kinetic, double* kinetic) {
    const sb_real factor = k->store_velocity ? 1 : k->inv_dt;
    const sb_wide half = sb_w_set(k->half), scale = sb_w_set(factor), zero = sb_w_set(0);
    sb_wide sum = zero;
    sb_wmask outside = 0;
    size_t q = begin;
    for (; q + SB_WIDTH <= end; q += SB_WIDTH) {
        sb_wide vq = sb_w_add(sb_w_mul(sb_w_load(u + q), scale),
                              sb_w_mul(sb_w_mul(half, sb_w_load(im4 + (q - begin))), sb_w_load(f + q)));
        sb_w_store(v + q, vq);
        if (sum_kinetic) sum = sb_kinetic_add(sum, sb_w_load(m4 + (q - begin)), vq);
        outside |= sb_w_less(sb_w_set((sb_real)INFINITY), sb_w_abs(vq)); /* NaN counts as outside */
    }
    if (sum_kinetic) *kinetic = sb_w_sum(sum, SB_WIDTH);
    int bad = sb_w_any(outside, SB_WIDTH);
    for (; q < end; q++) {
        v[q] = u[q] * factor + k->half * im4[q - begin] * f[q];
        if (sum_kinetic) *kinetic += sb_kinetic_of(m4[q - begin], v[q]);
        bad |= !((v[q] <= (sb_real)INFINITY) & (v[q] >= -(sb_real)INFINITY));
    }
    return bad;
}

/* The kinetic energy of packed reals [begin, end) into *kinetic, as the
 * kick sums it (sb_kinetic_add, sb_kinetic_of), from the velocities v. m4
 * starts at begin. */
static void sb_kinetic_range(const sb_real* restrict m4, const sb_real* restrict v, size_t begin, size_t end,
                             double* kinetic) {
    sb_wide sum = sb_w_set(0);
    size_t q = begin;
    for (; q + SB_WIDTH <= end; q += SB_WIDTH) sum = sb_kinetic_add(sum, sb_w_load(m4 + (q - begin)), sb_w_load(v + q));
    *kinetic = sb_w_sum(sum, SB_WIDTH);
    for (; q < end; q++) *kinetic += sb_kinetic_of(m4[q - begin], v[q]);
}

/* The last pass of a step: no barrier after it but the join. */
static void sb_kick_pass(const sb_worker* w, sb_solver* s, const sb_partial_layout* p, const sb_step_constants* k,
                         atomic_int* bad) {
    const sb_real* u = k->store_velocity ? s->velocities4 : s->displacements4;
    sb_chunk_masses masses;
    for (sb_chunks it = sb_my_chunks(w, p, sb_moving_vertices(s)); sb_next_chunk(&it);) {
        int c = it.chunk;
        size_t begin = it.begin, end = it.end;
        sb_spread_masses(s->fast, begin, end, k->sums || !k->positions_final_in_drift, &masses);
        double* kinetic = p->vertices + 2 * c;
        int raised =
            k->sums
                ? sb_kick_range(masses.m4, masses.im4, u, s->velocities4, s->forces4, k, begin, end, true, kinetic)
                : sb_kick_range(masses.m4, masses.im4, u, s->velocities4, s->forces4, k, begin, end, false, kinetic);
        if (raised) sb_worker_raise(bad);
        if (!k->positions_final_in_drift &&
            sb_positions_range(masses.m4, masses.im4, s->positions4, k, begin, end, p->vertices + 2 * c + 1))
            sb_worker_raise(bad);
        if (s->step.publish_positions) { /* sb_solver_advance_into: the snapshot from the chunk still in cache */
            sb_unpack_xyz(s->positions4, s->step.publish_positions, begin / 4, end / 4);
            sb_unpack_xyz(s->velocities4, s->step.publish_velocities, begin / 4, end / 4);
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
    e->term[SB_TERM_BOND] =
        sb_sum_strided(p->bonds, bond_chunks, 2, 0) + sb_sum_strided(p->triangles, triangle_chunks, 5, 2);
    e->term[SB_TERM_SPRING] =
        sb_sum_strided(p->bonds, bond_chunks, 2, 1) + sb_sum_strided(p->triangles, triangle_chunks, 5, 3);
    e->term[SB_TERM_ANGLE] = sb_sum_strided(p->triangles, triangle_chunks, 5, 0);
    e->term[SB_TERM_STRETCH_BEND] = sb_sum_strided(p->triangles, triangle_chunks, 5, 1);
    e->term[SB_TERM_BEND] = sb_sum_strided(p->hinges, f->hinges.block_count, 1, 0) +
                            sb_sum_strided(p->triangles, triangle_chunks, 5, 4) +
                            sb_sum_strided(p->membranes, f->membranes.block_count, 2, 1);
    e->term[SB_TERM_COROTATED] = sb_sum_strided(p->tets, f->tets.block_count, 1, 0);
    e->term[SB_TERM_MEMBRANE] = sb_sum_strided(p->membranes, f->membranes.block_count, 2, 0);
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
    if (status == SB_OK)
        sb_error_set(&s->error, SB_ERR_DEGENERATE, "an edge collapsed (below %g of its rest length)", 1e-9);
    return SB_ERR_DEGENERATE;
}

/* Copies this worker's share of the packed working state to the state's
 * arrays. The last pass of its job. */
static void sb_publish_pass(const sb_worker* w, sb_solver* s) {
    sb_state* st = &s->state;
    sb_real* soa[3][3] = {{st->x, st->y, st->z}, {st->vx, st->vy, st->vz}, {st->fx, st->fy, st->fz}};
    const sb_real* packed[3] = {s->positions4, s->velocities4, s->forces4};
    int64_t begin, end;
    sb_worker_range(w, st->vertex_count, &begin, &end);
    for (int64_t i = begin; i < end; i++)
        for (int q = 0; q < 3; q++)
            for (int a = 0; a < 3; a++) soa[q][a][i] = packed[q][4 * (size_t)i + a];
}

/* What a job of the team needs: the solver, the pass layout, the step's
 * constants and the flags any worker may raise. */
typedef struct sb_fast_job {
    sb_solver* solver;
    sb_partial_layout layout;
    sb_step_constants constants;
    double dt;
    sb_pass_flags flags;
    atomic_int bad;
} sb_fast_job;

/* The kinetic and gravitational energies of this worker's chunks of the
 * packed state, into their chunk sums, as the step's passes sum them. */
static void sb_vertex_energies_job(void* context, const sb_worker* w) {
    sb_fast_job* job = context;
    const sb_solver* s = job->solver;
    const sb_partial_layout* p = &job->layout;
    sb_chunk_masses masses;
    for (sb_chunks it = sb_my_chunks(w, p, s->state.vertex_count); sb_next_chunk(&it);) {
        int c = it.chunk;
        size_t begin = it.begin, end = it.end;
        sb_spread_masses(s->fast, begin, end, true, &masses);
        sb_kinetic_range(masses.m4, s->velocities4, begin, end, p->vertices + 2 * c);
        sb_positions_range_of(masses.m4, masses.im4, s->positions4, &job->constants, begin, end, true,
                              p->vertices + 2 * c + 1);
    }
}

void sb_fast_vertex_energies(sb_solver* s) {
    sb_fast_job job = {.solver = s, .layout = sb_partials_of(s)};
    sb_gravity4(s, job.constants.gravity);
    job.constants.limit = sb_runaway_limit(s);
    sb_team_run(s->team, sb_team_size(s->team), sb_vertex_energies_job, &job);
    s->energies.kinetic = sb_sum_strided(job.layout.vertices, job.layout.vertex_chunks, 2, 0);
    s->energies.gravity = sb_sum_strided(job.layout.vertices, job.layout.vertex_chunks, 2, 1);
}

static void sb_publish_job(void* context, const sb_worker* w) {
    sb_fast_job* job = context;
    sb_publish_pass(w, job->solver);
}

void sb_fast_publish(sb_solver* s) {
    if (!s->fast || s->published) return;
    sb_fast_job job = {.solver = s};
    sb_team_run(s->team, sb_team_size(s->team), sb_publish_job, &job);
    s->published = true;
}

static void sb_forces_job(void* context, const sb_worker* w) {
    sb_fast_job* job = context;
    sb_pack_pass(w, job->solver, &job->layout);
    sb_force_passes(w, job->solver, &job->layout, &job->flags);
    sb_external_step(w, job->solver);
    sb_publish_pass(w, job->solver);
}

static void sb_packed_forces_job(void* context, const sb_worker* w) {
    sb_fast_job* job = context;
    sb_initial_forces_pass(w, job->solver, &job->layout);
    sb_force_passes(w, job->solver, &job->layout, &job->flags);
    sb_external_step(w, job->solver);
}

sb_status sb_fast_forces_packed(sb_solver* s) {
    sb_fast_job job = {.solver = s, .layout = sb_partials_of(s)};
    sb_team_run(s->team, sb_team_size(s->team), sb_packed_forces_job, &job);
    return atomic_load(&job.flags.collapsed) ? sb_report_collapse(s) : SB_OK;
}

sb_status sb_fast_compute_forces(sb_solver* s) {
    sb_fast_job job = {.solver = s, .layout = sb_partials_of(s)};
    sb_team_run(s->team, sb_team_size(s->team), sb_forces_job, &job);
    s->published = true;
    s->near_limits = atomic_load(&job.flags.near_limit) != 0;
    sb_collect_energies(s, &job.layout, false);
    return atomic_load(&job.flags.collapsed) ? sb_report_collapse(s) : SB_OK;
}

/* Worker 0 puts the vertices a feature holds at their targets (the
 * place_packed hook: the hard handles); the others wait for it. */
static void sb_place_step(const sb_worker* w, sb_solver* s, double dt) {
    if (!s->hooks.place_packed) return;
    if (w->index == 0) s->hooks.place_packed(s, dt);
    sb_worker_barrier(w);
}

/* The surface_packed hook on worker 0 (the others wait for it), then the
 * after_drift hook on every worker (self-contact). */
static void sb_after_drift_step(const sb_worker* w, sb_solver* s, double dt) {
    if (s->hooks.surface_packed) {
        if (w->index == 0) s->hooks.surface_packed(s, dt);
        sb_worker_barrier(w);
    }
    if (s->hooks.after_drift) s->hooks.after_drift(w, s, dt);
}

static void sb_verlet_job(void* context, const sb_worker* w) {
    sb_fast_job* job = context;
    sb_drift_pass(w, job->solver, &job->layout, &job->constants, job->dt, &job->bad);
    sb_after_drift_step(w, job->solver, job->dt);
    sb_place_step(w, job->solver, job->dt);
    sb_force_passes(w, job->solver, &job->layout, &job->flags);
    sb_external_step(w, job->solver);
    sb_kick_pass(w, job->solver, &job->layout, &job->constants, &job->bad);
}

/* Whether this step sums its kinetic and gravitational energies in its
 * passes: the adaptive stepper reads them after every sub-step, and a
 * caller that read them after the last step (sb_solver_energies: a run's
 * armed kinetic-energy stop, a published snapshot) likely reads them after
 * this one too. Otherwise they wait for sb_solver_settle. (The forces,
 * sb_step_needs_forces's concern, this step always evaluates; of what
 * follows a step only the adaptive stepper reads its energies.) */
static bool sb_step_sums(sb_solver* s) {
    bool sums = s->def.adaptive || s->energies_read;
    s->energies_read = false;
    return sums;
}

sb_status sb_fast_verlet_step(sb_solver* s, double dt) {
    bool stormer = s->def.integrator == SB_INTEGRATOR_VERLET && s->has_displacement;
    bool sums = sb_step_sums(s);
    bool positions_final_in_drift = !s->self && !s->def.handle_count;
    sb_fast_job job = {.solver = s, .layout = sb_partials_of(s), .dt = dt};
    job.constants = (sb_step_constants){
        .scale = stormer ? (sb_real)(dt / s->prev_dt) : 0,
        .accel = stormer ? (sb_real)(0.5 * dt * (dt + s->prev_dt)) : (sb_real)(0.5 * dt),
        .step = (sb_real)dt,
        .inv_dt = (sb_real)(1.0 / dt),
        .drag = (sb_real)s->def.drag,
        .half = (sb_real)(0.5 * dt),
        .limit = sb_runaway_limit(s),
        .stormer = stormer,
        .store_velocity = !stormer || sb_half_step_velocity_read(s),
        .positions_final_in_drift = positions_final_in_drift,
        .sums = sums,
        .check_in_drift = !sums && positions_final_in_drift && !s->def.collider_count,
    };
    sb_gravity4(s, job.constants.gravity);
    sb_team_run_adaptive(s->team, sb_team_size(s->team), sb_verlet_job, &job);
    s->has_displacement = true;
    s->prev_dt = dt;
    s->published = false;
    s->step.publish_written = s->step.publish_positions != NULL;
    sb_collect_energies(s, &job.layout, sums);
    s->forces_stale = !sums; /* the forces and term energies are current; the vertex sums wait */
    s->near_limits = atomic_load(&job.flags.near_limit) != 0;
    bool bad = atomic_load(&job.bad), collapsed = atomic_load(&job.flags.collapsed);
    if (bad || collapsed) sb_fast_publish(s);
    if (bad) return sb_check_state(s);
    return collapsed ? sb_report_collapse(s) : SB_OK;
}
