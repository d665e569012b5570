/* The contact pass: every free vertex's move of a step against the
 * colliders (softbond/collider.h).
 *
 * Design. Contact is a correction of the step, the same for every
 * integrator that moves by forces (pbd and xpbd: below): the vertex's move
 * (from its position at the start of the step to where the integrator put
 * it) is offered to each collider in order; the earliest contact (smallest
 * fraction; the first collider on a tie) is answered:
 *
 *   position  along the normal: to the contact point from + fraction (to −
 *             from), pushed out by depth, then the rest of the step at the
 *             answered normal velocity; along the surface: from + dt v't,
 *             the whole step at the answered tangential velocity, so that a
 *             vertex that sticks does not creep and one that slides moves
 *             as its velocity says;
 *   velocity  relative to the collider's own velocity u: vr = v − u,
 *             vn = vr·n. A vertex moving into the surface (vn < 0) keeps
 *             −e·vn along n (restitution e) and takes the normal impulse
 *             jn = −(1 + e) vn per unit mass; its tangential velocity vt
 *             stops when |vt| <= μs jn (static friction) and otherwise
 *             loses μ jn of its length (Coulomb); a vertex moving away is
 *             left alone. v = u + vr'.
 *
 * The collider receives −m (v' − v) / dt, summed per fixed chunk of
 * vertices and the chunks in order, so the reaction force and the state are
 * the same for any thread count. Where the pass runs:
 *   - the fused Verlet step (kernels/state/solver_fast.c) calls it per chunk right
 *     after the drift, before the forces: the forces are evaluated at the
 *     corrected positions and the closing kick and energy sums see them;
 *   - every other integrator (and the reference kernels) moves the state
 *     first; the pass then corrects the state's arrays and, when a vertex was
 *     touched, the forces are evaluated again at the corrected positions
 *     (the correct stage, kernels/solver/step.c), so the next step starts
 *     from consistent forces.
 * After the vertices, the surface pass (kernels/contact/surface.c) answers
 * the triangles' points between them, on worker 0 after the fused drift
 * (the surface_packed hook) or in the same correct stage; pbd and xpbd,
 * whose sweeps answered the vertices, take it as their correct stage.
 * A Verlet-form displacement is set to v'·dt so that the next step carries
 * the corrected velocity. A vertex is answered by one collider per step:
 * in a corner of two colliders it can be pushed into the second, which
 * answers it in the next step.
 * Then restitution per body (kernels/contact/body_restitution.c): each
 * answer is reported to it, and after the pass (the fused step's collect
 * stage, the others' correct stage) a body in contact keeps at most e
 * times its centre's approach speed; what it takes off joins the
 * collider's impulse of the step.
 *
 * pbd and xpbd do not take this pass: their step is itself a projection, so
 * a contact is one more constraint inside their sweeps
 * (kernels/contact/contact_pbd.c), found by sb_contact_find and answered by
 * sb_contact_velocity, its impulse in the same partial sums. Implicit Euler
 * takes the pass after its Newton solve, as the Verlet and Euler forms do:
 * an integrator that moves by forces answers contact with this impulse
 * after its move (Bridson et al. 2002 treat implicit cloth so), one that
 * moves by projection projects contact with its other constraints. Inside
 * the Newton solve an inequality contact would need an active-set or
 * complementarity solve, or a stiff penalty force the solve would have to
 * resolve: more than the post-step answer costs, for the same answer at
 * the end of the step. */
#include "kernels/contact/contact.h"
#include "kernels/contact/surface.h"
#include "kernels/contact/body_restitution.h"
#include "kernels/contact/fast_contact.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/contact/colliders/dynamic.h"
#include "kernels/state/solver_fast.h"
#include "kernels/state/vertex_state.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The contact pass's state. */
typedef struct sb_contact_pass {
    double* from;                /* 3n: positions at the start of a step the fused path does not take */
    double* partials;            /* per vertex chunk: 3 impulse sums per collider, the contact count, 3 torque sums */
    double* step;                /* 6 per collider: the last step's impulses on the colliders, then their torques */
    double* impulse;             /* 3 per collider: summed over the accepted steps of this advance */
    bool corrects;               /* the pass corrects the state after the step (not pbd, xpbd: their sweeps project) */
    sb_surface* surface;         /* when a collider meets the surface (kernels/contact/surface.c) */
    uint64_t meets_surface;      /* with a surface: a bit per collider that meets it */
    uint64_t by_vertex;          /* a bit per collider the vertices are answered against (not one with a footprint) */
    uint32_t *kept, stamp;       /* the fused step: from[i] is vertex i's start where kept[i] == stamp */
    sb_body_restitution* bodies; /* restitution per body (kernels/contact/body_restitution.c); NULL where off */
    sb_fast_colliders fast;      /* the step's colliders as the SIMD answer sees them */
} sb_contact_pass;

static void sb_contact_subscribe(sb_solver* s);

/* Doubles per chunk of the partial sums: 3 impulses per collider, the
 * count, then 3 torques per collider. */
static size_t sb_contact_stride(const sb_solver* s) { return 6 * (size_t)s->def.collider_count + 1; }

sb_status sb_contact_prepare(sb_solver* s, sb_error* err) {
    if (s->def.collider_count == 0) return SB_OK;
    if (!s->def.colliders)
        return sb_error_set(err, SB_ERR_INVALID, "colliders: %u given but the list is NULL", s->def.collider_count);
    if (s->def.collider_count > SB_MAX_COLLIDERS)
        return sb_error_set(err, SB_ERR_INVALID, "colliders: %u given, at most %d", s->def.collider_count,
                            SB_MAX_COLLIDERS);
    for (uint32_t c = 0; c < s->def.collider_count; c++)
        if (!s->def.colliders[c]) return sb_error_set(err, SB_ERR_INVALID, "colliders: entry %u is NULL", c);
    size_t n3 = 3 * (size_t)s->model->vertex_count + 1, chunks = sb_chunk_count(s->model->vertex_count) + 1;
    sb_contact_pass* c = s->contact = calloc(1, sizeof *s->contact);
    if (!c) return sb_error_set(err, SB_ERR_NOMEM, "out of memory for contact");
    c->from = malloc(n3 * sizeof *c->from);
    c->partials = calloc(chunks * sb_contact_stride(s), sizeof *c->partials);
    c->impulse = calloc(3 * (size_t)s->def.collider_count, sizeof *c->impulse);
    c->step = calloc(6 * (size_t)s->def.collider_count, sizeof *c->step);
    if (!c->from || !c->partials || !c->impulse || !c->step)
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory for contact");
    c->corrects = s->def.integrator != SB_INTEGRATOR_PBD && s->def.integrator != SB_INTEGRATOR_XPBD;
    if (sb_surface_active(s)) {
        sb_status status = sb_surface_create(s, &c->surface, err);
        if (status != SB_OK) return status;
    }
    if (c->surface && !(c->kept = calloc((size_t)s->model->vertex_count + 1, sizeof *c->kept)))
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory for contact");
    c->by_vertex = ~(uint64_t)0;
    for (uint32_t k = 0; c->surface && k < s->def.collider_count; k++) {
        if (sb_collider_meets_surface(s->def.colliders[k])) c->meets_surface |= (uint64_t)1 << k;
        if (sb_collider_footprint(s->def.colliders[k]) > 0.0) c->by_vertex &= ~((uint64_t)1 << k);
    }
    sb_status status = sb_body_restitution_create(s, &c->bodies, err);
    if (status != SB_OK) return status;
    sb_contact_subscribe(s);
    return SB_OK;
}

void sb_contact_destroy(sb_solver* s) {
    sb_contact_pass* c = s->contact;
    if (!c) return;
    free(c->from);
    free(c->kept);
    free(c->partials);
    free(c->impulse);
    free(c->step);
    sb_surface_destroy(c->surface);
    sb_body_restitution_destroy(c->bodies);
    free(c);
}

/* The colliders' begin-step callbacks, in order, on the calling thread. */
static void sb_contact_begin_step(sb_solver* s, double t0, double t1) {
    for (uint32_t c = 0; c < s->def.collider_count; c++) {
        sb_collider* collider = s->def.colliders[c];
        if (collider->begin_step) collider->begin_step(collider->user, t0, t1);
    }
}

bool sb_contact_reaches(const sb_solver* s, uint32_t c, const double lo[3], const double hi[3]) {
    const double* b = s->def.colliders[c]->bounds;
    double t = s->def.contact_thickness;
    return lo[0] - t <= b[3] && hi[0] + t >= b[0] && lo[1] - t <= b[4] && hi[1] + t >= b[1] && lo[2] - t <= b[5] &&
           hi[2] + t >= b[2];
}

/* The colliders (a bit each) whose bounds the box [lo, hi] reaches. */
static uint64_t sb_colliders_near(const sb_solver* s, const double lo[3], const double hi[3]) {
    uint64_t near = 0;
    for (uint32_t c = 0; c < s->def.collider_count; c++)
        if (sb_contact_reaches(s, c, lo, hi)) near |= (uint64_t)1 << c;
    return near;
}

/* The colliders of `near` whose bounds the move from → to reaches. */
static uint64_t sb_move_near(const sb_solver* s, uint64_t near, const double from[3], const double to[3]) {
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        bool down = to[k] < from[k];
        lo[k] = down ? to[k] : from[k];
        hi[k] = down ? from[k] : to[k];
    }
    for (uint32_t c = 0; c < s->def.collider_count; c++)
        if ((near >> c & 1) && !sb_contact_reaches(s, c, lo, hi)) near &= ~((uint64_t)1 << c);
    return near;
}

/* The earliest contact of a move among the colliders of `near`; -1 for none. */
static int sb_first_contact(const sb_solver* s, const sb_contact_query* q, uint64_t near, sb_contact* best) {
    int hit = -1;
    for (uint32_t c = 0; c < s->def.collider_count; c++) {
        if (!(near >> c & 1)) continue;
        const sb_collider* collider = s->def.colliders[c];
        sb_contact contact;
        if (collider->collide(collider->user, q, &contact) && (hit < 0 || contact.fraction < best->fraction)) {
            *best = contact;
            hit = (int)c;
        }
    }
    return hit;
}

/* The velocity answer of one contact (see the design note). */
void sb_contact_velocity(const sb_contact* c, double v[3]) {
    double vr[3], vn = 0.0;
    for (int k = 0; k < 3; k++) vr[k] = v[k] - c->velocity[k];
    for (int k = 0; k < 3; k++) vn += vr[k] * c->normal[k];
    if (vn >= 0.0) return;
    double jn = -(1.0 + c->restitution) * vn, vt[3], vt_length = 0.0;
    for (int k = 0; k < 3; k++) {
        vt[k] = vr[k] - vn * c->normal[k];
        vt_length += vt[k] * vt[k];
    }
    vt_length = sqrt(vt_length);
    double keep = vt_length <= c->static_friction * jn ? 0.0 : 1.0 - c->friction * jn / vt_length;
    if (keep < 0.0) keep = 0.0;
    for (int k = 0; k < 3; k++) v[k] = c->velocity[k] - c->restitution * vn * c->normal[k] + keep * vt[k];
}

void sb_contact_position(const sb_contact* c, double dt, const double from[3], const double to[3], const double v[3],
                         double x[3]) {
    double normal_move = 0.0, vn = 0.0;
    for (int k = 0; k < 3; k++) {
        normal_move += c->fraction * (to[k] - from[k]) * c->normal[k];
        vn += v[k] * c->normal[k];
    }
    normal_move += c->depth + (1.0 - c->fraction) * dt * vn;
    for (int k = 0; k < 3; k++) x[k] = from[k] + dt * (v[k] - vn * c->normal[k]) + normal_move * c->normal[k];
}

/* Vertex i's move from → to in the step being taken. */
static sb_contact_query sb_contact_query_of(const sb_solver* s, uint32_t i, const double from[3], const double to[3]) {
    sb_contact_query q = {
        .vertex = i, .t0 = s->time - s->step.dt, .t1 = s->time, .thickness = s->def.contact_thickness};
    memcpy(q.from, from, sizeof q.from);
    memcpy(q.to, to, sizeof q.to);
    return q;
}

int sb_contact_find(const sb_solver* s, uint32_t i, const double from[3], const double to[3], sb_contact* c) {
    uint64_t near = sb_move_near(s, s->contact->by_vertex, from, to);
    if (!near) return -1;
    sb_contact_query q = sb_contact_query_of(s, i, from, to);
    return sb_first_contact(s, &q, near, c);
}

int sb_contact_vertex(const sb_solver* s, uint32_t i, uint64_t near, const double from[3], double x[3], double v[3],
                      double impulse[3], double point[3]) {
    sb_contact_query q = sb_contact_query_of(s, i, from, x);
    sb_contact c = {0};
    int hit = sb_first_contact(s, &q, near, &c);
    if (hit < 0) return -1;
    double before[3] = {v[0], v[1], v[2]};
    sb_contact_velocity(&c, v);
    sb_contact_position(&c, s->step.dt, from, q.to, v, x);
    double m = s->model->mass[i];
    for (int k = 0; k < 3; k++) impulse[k] = m * (v[k] - before[k]);
    memcpy(point, c.point, sizeof c.point);
    sb_contact_touch(s, i, hit, &c, impulse);
    return hit;
}

void sb_contact_touch(const sb_solver* s, uint32_t i, int collider, const sb_contact* c, const double impulse[3]) {
    if (s->contact->bodies) sb_body_restitution_touch(s->contact->bodies, i, collider, c, impulse);
}

void sb_contact_chunk_begin(const sb_solver* s, uint32_t chunk) {
    memset(s->contact->partials + chunk * sb_contact_stride(s), 0, sb_contact_stride(s) * sizeof(double));
}

void sb_contact_record(const sb_solver* s, uint32_t chunk, int collider, const double impulse[3]) {
    double* partial = s->contact->partials + chunk * sb_contact_stride(s);
    for (int k = 0; k < 3; k++) partial[3 * collider + k] -= impulse[k];
    partial[3 * s->def.collider_count] += 1.0;
}

void sb_contact_record_torque(const sb_solver* s, uint32_t chunk, int collider, const double point[3],
                              const double impulse[3]) {
    if (!s->def.colliders[collider]->dynamic) return; /* its torque sum stays zero */
    double* partial = s->contact->partials + chunk * sb_contact_stride(s) + 3 * (size_t)s->def.collider_count + 1;
    double received[3] = {-impulse[0], -impulse[1], -impulse[2]}, torque[3];
    sb_collider_torque(s->def.colliders[collider], point, received, torque);
    for (int k = 0; k < 3; k++) partial[3 * collider + k] += torque[k];
}

/* The box around the moves of vertices [first, last) in the packed state
 * (x and x − d), in 16 independent lanes (4 vertices of x y z w) that
 * vectorize, folded to x y z at the end; plain comparisons, because fmin
 * would be a call per value. */
static void sb_block_box_packed(const sb_solver* s, uint32_t first, uint32_t last, double dlo[3], double dhi[3]) {
    sb_real lo[16], hi[16];
    for (int k = 0; k < 16; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    const sb_real *x = s->positions4 + 4 * (size_t)first, *d = s->displacements4 + 4 * (size_t)first;
    size_t count = 4 * (size_t)(last - first), whole = count / 16 * 16;
    for (size_t q = 0; q < whole; q += 16)
        for (int k = 0; k < 16; k++) {
            sb_real a = x[q + k], b = a - d[q + k], small = a < b ? a : b, large = a < b ? b : a;
            lo[k] = small < lo[k] ? small : lo[k];
            hi[k] = large > hi[k] ? large : hi[k];
        }
    for (size_t q = whole; q < count; q++) { /* the last vertices of a short block */
        sb_real a = x[q], b = a - d[q], small = a < b ? a : b, large = a < b ? b : a;
        lo[q & 3] = small < lo[q & 3] ? small : lo[q & 3];
        hi[q & 3] = large > hi[q & 3] ? large : hi[q & 3];
    }
    for (int c = 0; c < 3; c++) { /* folded in locals: stores through dlo and dhi were a third of the function */
        sb_real small = lo[c], large = hi[c];
        for (int v = 1; v < 4; v++) {
            small = lo[4 * v + c] < small ? lo[4 * v + c] : small;
            large = hi[4 * v + c] > large ? hi[4 * v + c] : large;
        }
        dlo[c] = small, dhi[c] = large;
    }
}

/* Vertices per block of the broad phase inside a chunk: a chunk of a mesh
 * row spans most of its width; a block of 32 is a small patch. The surface
 * pass's blocks are finer (a block of 32 is a strip of a sheet's row, most
 * of whose triangles lie away from a small sphere under it): their boxes,
 * per vertex the same work, are made here, and joined for the block's. */
#define SB_CONTACT_BLOCK 32
_Static_assert(SB_CONTACT_BLOCK % SB_SURFACE_BLOCK == 0 && SB_CHUNK % SB_CONTACT_BLOCK == 0,
               "a contact block is whole surface blocks, a chunk whole contact blocks");

/* The colliders the moves of block [first, last) reach; with a surface
 * pass, the boxes of its surface blocks kept for it (the block's box their
 * join), else one box. */
static uint64_t sb_block_near_packed(const sb_solver* s, uint32_t first, uint32_t last) {
    const uint32_t part = s->contact->surface ? SB_SURFACE_BLOCK : last - first;
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (uint32_t block = first; block < last; block += part) {
        double blo[3], bhi[3];
        sb_block_box_packed(s, block, block + part < last ? block + part : last, blo, bhi);
        if (s->contact->surface) sb_surface_set_box(s->contact->surface, block / SB_SURFACE_BLOCK, blo, bhi);
        for (int k = 0; k < 3; k++) {
            lo[k] = blo[k] < lo[k] ? blo[k] : lo[k];
            hi[k] = bhi[k] > hi[k] ? bhi[k] : hi[k];
        }
    }
    return sb_colliders_near(s, lo, hi);
}

/* Vertex i of the packed state (from = x − displacement) against the
 * colliders of `near`: the scalar reference. */
static void sb_contact_vertex_packed(const sb_solver* s, uint32_t chunk, uint64_t near, uint32_t i, double dt) {
    if (s->model->fixed[i]) return;
    sb_real *x4 = s->positions4 + 4 * (size_t)i, *v4 = s->velocities4 + 4 * (size_t)i;
    sb_real* d4 = s->displacements4 + 4 * (size_t)i;
    double x[3] = {x4[0], x4[1], x4[2]}, v[3] = {v4[0], v4[1], v4[2]}, impulse[3], point[3];
    double from[3] = {x[0] - d4[0], x[1] - d4[1], x[2] - d4[2]};
    uint64_t reached = sb_move_near(s, near, from, x);
    int hit = reached ? sb_contact_vertex(s, i, reached, from, x, v, impulse, point) : -1;
    if (hit < 0) return;
    sb_real* f4 = s->forces4 + 4 * (size_t)i; /* the drift set it to m g − drag m v */
    for (int k = 0; k < 3; k++) {
        x4[k] = (sb_real)x[k];
        v4[k] = (sb_real)v[k];
        d4[k] = (sb_real)(v[k] * dt);
        f4[k] = sb_fast_initial_force(s, i, k, v[k]);
    }
    sb_contact_record(s, chunk, hit, impulse);
    sb_contact_record_torque(s, chunk, hit, point, impulse);
}

/* A vertex the SIMD answer answered, to body restitution. */
static void sb_body_touch(void* user, uint32_t i, int collider, const sb_contact* c, const double impulse[3]) {
    sb_body_restitution_touch(user, i, collider, c, impulse);
}

/* The vertices [first, last) of a block whose colliders in reach are all
 * static planes, spheres and boxes, answered in SIMD
 * (kernels/contact/fast_contact.c) into the chunk's sums; returns how many from the first (whole registers:
 * the rest go to the scalar reference). */
static uint32_t sb_contact_block_fast(const sb_solver* s, uint32_t chunk, uint64_t near, uint32_t first, uint32_t last,
                                      double dt) {
    size_t at = 4 * (size_t)first;
    sb_packed_run run = {.x = s->positions4 + at,
                         .v = s->velocities4 + at,
                         .d = s->displacements4 + at,
                         .f = s->forces4 + at,
                         .mass = s->fast->mass + first,
                         .inv_mass = s->fast->inv_mass + first,
                         .count = last - first};
    sb_fast_contact_step step = {.dt = dt, .drag = s->def.drag, .first = first};
    if (s->contact->bodies && sb_body_restitution_follows(s->contact->bodies, chunk))
        step.touch = sb_body_touch, step.user = s->contact->bodies;
    memcpy(step.gravity, s->def.gravity, sizeof step.gravity);
    double* partial = s->contact->partials + chunk * sb_contact_stride(s);
    return sb_fast_contact_answer(&s->contact->fast, near, &run, &step, partial, partial + 3 * s->def.collider_count);
}

/* The vertices [first, last) against the colliders of `near`: in SIMD
 * when they are all static planes, spheres and boxes, the rest (and any
 * other collider) by the scalar reference. */
static void sb_contact_run_packed(const sb_solver* s, uint32_t chunk, uint64_t near, uint32_t first, uint32_t last,
                                  double dt) {
    uint32_t i = first;
    near &= s->contact->by_vertex;
    if (!near) return;
    if (!(near & ~s->contact->fast.simd)) i += sb_contact_block_fast(s, chunk, near, first, last, dt);
    for (; i < last; i++) sb_contact_vertex_packed(s, chunk, near, i, dt);
}

/* Keeps the starts x − d of the moves of vertices [first, last) of the
 * packed state before any answer, for the surface pass: an answer sets a
 * vertex's d to v dt, after which x − d is no start of its move (a corner
 * the pass re-answers from there could start inside, or past, a thin
 * capsule and be pushed out on its far side). Only the blocks a collider
 * meeting the surface reaches: the others' answers (a floor's) do not
 * move a vertex the pass answers against such a collider. */
static void sb_contact_keep_from_packed(const sb_solver* s, uint32_t first, uint32_t last) {
    const sb_real *x4 = s->positions4, *d4 = s->displacements4;
    for (size_t i = first; i < last; i++) {
        for (int k = 0; k < 3; k++) s->contact->from[3 * i + k] = (double)x4[4 * i + k] - (double)d4[4 * i + k];
        s->contact->kept[i] = s->contact->stamp;
    }
}

/* The fused path's pass over one chunk of the packed state, after its drift
 * (from = x − displacement): the drift_chunk hook. First the chunk's box:
 * when no collider meeting the surface is in its reach, the chunk is one
 * run against the colliders it reaches (none: skipped) and its blocks keep
 * its box for the surface pass (a box of a block's moves need only hold
 * them; a body lying on a floor costs a box a chunk, not one a block).
 * Otherwise block by block, the colliders in reach (none: the block is
 * skipped); consecutive blocks with the same colliders are answered as one
 * run (the SIMD answer's per-run constants and sums are made once). */
static void sb_contact_chunk_packed(const sb_solver* s, uint32_t chunk, double dt) {
    uint32_t n = s->model->vertex_count, first = chunk * SB_CHUNK, last = first + SB_CHUNK < n ? first + SB_CHUNK : n;
    uint32_t run = first;
    uint64_t run_near = 0;
    sb_contact_chunk_begin(s, chunk);
    double lo[3], hi[3];
    sb_block_box_packed(s, first, last, lo, hi);
    uint64_t chunk_near = sb_colliders_near(s, lo, hi);
    bool fine = chunk_near & s->contact->meets_surface;
    if (s->contact->surface) sb_surface_set_group_box(s->contact->surface, chunk, lo, hi, fine);
    if (!fine) {
        sb_contact_run_packed(s, chunk, chunk_near, first, last, dt);
        return;
    }
    for (uint32_t block = first; block < last; block += SB_CONTACT_BLOCK) {
        uint32_t end = block + SB_CONTACT_BLOCK < last ? block + SB_CONTACT_BLOCK : last;
        uint64_t near = sb_block_near_packed(s, block, end);
        if (near & s->contact->meets_surface) sb_contact_keep_from_packed(s, block, end);
        if (near == run_near) continue;
        sb_contact_run_packed(s, chunk, run_near, run, block, dt);
        run = block, run_near = near;
    }
    sb_contact_run_packed(s, chunk, run_near, run, last, dt);
}

/* The state's arrays, from the positions saved before the step. */
static void sb_contact_chunk_state(sb_solver* s, uint32_t chunk, double dt) {
    uint32_t n = s->model->vertex_count, first = chunk * SB_CHUNK, last = first + SB_CHUNK < n ? first + SB_CHUNK : n;
    sb_state* st = &s->state;
    sb_contact_chunk_begin(s, chunk);
    for (uint32_t i = first; i < last; i++) {
        if (s->model->fixed[i]) continue;
        sb_real* xs[3] = {&st->x[i], &st->y[i], &st->z[i]};
        sb_real* vs[3] = {&st->vx[i], &st->vy[i], &st->vz[i]};
        sb_real* ds[3] = {&s->disp_x[i], &s->disp_y[i], &s->disp_z[i]};
        double x[3] = {*xs[0], *xs[1], *xs[2]}, v[3] = {*vs[0], *vs[1], *vs[2]}, impulse[3], point[3];
        const double* from = s->contact->from + 3 * (size_t)i;
        uint64_t reached = sb_move_near(s, s->contact->by_vertex, from, x);
        int hit = reached ? sb_contact_vertex(s, i, reached, from, x, v, impulse, point) : -1;
        if (hit < 0) continue;
        for (int k = 0; k < 3; k++) {
            *xs[k] = (sb_real)x[k];
            *vs[k] = (sb_real)v[k];
            *ds[k] = (sb_real)(v[k] * dt);
        }
        sb_contact_record(s, chunk, hit, impulse);
        sb_contact_record_torque(s, chunk, hit, point, impulse);
    }
}

typedef struct sb_contact_job {
    sb_solver* solver;
    double dt;
} sb_contact_job;

static void sb_contact_state_worker(void* context, const sb_worker* w) {
    const sb_contact_job* job = context;
    int64_t begin, end;
    sb_worker_range(w, sb_chunk_count(job->solver->model->vertex_count), &begin, &end);
    for (int64_t c = begin; c < end; c++) sb_contact_chunk_state(job->solver, (uint32_t)c, job->dt);
}

/* Keeps the state's positions as the start of the step's moves. */
static void sb_contact_save_from(sb_solver* s) {
    sb_interleave(s->contact->from, s->state.x, s->state.y, s->state.z, s->state.vertex_count);
}

uint32_t sb_contact_collect(sb_solver* s) {
    uint32_t colliders = s->def.collider_count, chunks = sb_chunk_count(s->model->vertex_count), contacts = 0;
    double* step = s->contact->step;
    memset(step, 0, 6 * (size_t)colliders * sizeof *step);
    for (uint32_t c = 0; c < chunks; c++) {
        const double* partial = s->contact->partials + c * sb_contact_stride(s);
        for (uint32_t k = 0; k < 3 * colliders; k++) {
            step[k] += partial[k];
            step[3 * colliders + k] += partial[3 * colliders + 1 + k];
        }
        contacts += (uint32_t)partial[3 * colliders];
    }
    return contacts;
}

/* The correct stage: the pass over the state's arrays of a step the fused
 * path did not take; whether a vertex moved. */
static bool sb_contact_correct(sb_solver* s, double dt) {
    sb_contact_job job = {s, dt};
    sb_team_run(s->team, sb_team_size(s->team), sb_contact_state_worker, &job);
    if (s->contact->surface) {
        sb_surface_view view = sb_surface_view_state(s, s->contact->from);
        sb_surface_pass(s, s->contact->surface, &view, false, dt);
    }
    uint32_t contacts = sb_contact_collect(s);
    s->stats.contacts += contacts;
    bool held = s->contact->bodies && sb_body_restitution_apply(s, s->contact->bodies, false, dt, s->contact->step);
    return contacts > 0 || held;
}

/* The correct stage of pbd and xpbd, whose sweeps answered the vertices:
 * the surface pass after the step, into the step's sums (the sweeps'
 * contacts already counted), then restitution per body on what both
 * answered. */
static bool sb_contact_correct_swept(sb_solver* s, double dt) {
    bool moved = false;
    if (s->contact->surface) {
        sb_surface_view view = sb_surface_view_state(s, s->contact->from);
        uint32_t contacts = sb_surface_pass(s, s->contact->surface, &view, false, dt);
        if (contacts > 0) {
            sb_contact_collect(s);
            s->stats.contacts += contacts;
            moved = true;
        }
    }
    if (s->contact->bodies) moved |= sb_body_restitution_apply(s, s->contact->bodies, false, dt, s->contact->step);
    return moved;
}

/* The fused step's surface pass (the surface_packed hook). */
static void sb_contact_surface_packed(sb_solver* s, double dt) {
    sb_surface_view view = sb_surface_view_packed(s, s->contact->from, s->contact->kept, s->contact->stamp);
    sb_surface_pass(s, s->contact->surface, &view, true, dt);
}

/* The begin stage: the colliders' callbacks, and the positions the moves
 * start from where the correct stage will run (the fused step keeps them in
 * its drift hook, for its surface pass). */
static void sb_contact_begin(sb_solver* s, double t0, double dt) {
    sb_contact_begin_step(s, t0, t0 + dt);
    if (s->contact->bodies) sb_body_restitution_begin(s->contact->bodies);
    sb_fast_colliders_set(&s->contact->fast, s->def.colliders, s->def.collider_count, s->def.contact_thickness);
    if ((s->contact->corrects || s->contact->surface) && !sb_fused(s)) sb_contact_save_from(s);
    if (s->contact->kept && ++s->contact->stamp == 0) { /* a new step's stamp; on wrapping, none kept */
        memset(s->contact->kept, 0, (size_t)s->model->vertex_count * sizeof *s->contact->kept);
        s->contact->stamp = 1;
    }
}

/* The collect stage: the fused step's chunk sums, then restitution per
 * body on the packed state. */
static void sb_contact_collect_fused(sb_solver* s) {
    s->stats.contacts += sb_contact_collect(s);
    if (s->contact->bodies) sb_body_restitution_apply(s, s->contact->bodies, true, s->step.dt, s->contact->step);
}

/* The start of an advance: its impulses start from zero. */
static void sb_contact_start(sb_solver* s) {
    memset(s->contact->impulse, 0, 3 * (size_t)s->def.collider_count * sizeof(double));
}

/* The accept stage: the step's impulses join the advance's, and a dynamic
 * collider moves only with the steps kept. */
static sb_status sb_contact_accept(sb_solver* s, double dt) {
    sb_contact_pass* c = s->contact;
    for (uint32_t k = 0; k < 3 * s->def.collider_count; k++) c->impulse[k] += c->step[k];
    sb_colliders_after_step(s->def.colliders, s->def.collider_count, c->step, s->def.gravity, dt);
    if (c->bodies) sb_body_restitution_accept(c->bodies);
    return SB_OK;
}

void sb_contact_set_dead_triangles(sb_solver* s, const uint8_t* dead) {
    if (s->contact && s->contact->surface) sb_surface_set_dead(s->contact->surface, dead);
}

static void sb_contact_subscribe(sb_solver* s) {
    sb_feature f = {.name = "contact",
                    .start = sb_contact_start,
                    .begin = sb_contact_begin,
                    .collect = sb_contact_collect_fused,
                    .accept = sb_contact_accept};
    if (s->contact->corrects)
        f.correct = sb_contact_correct;
    else if (s->contact->surface || s->contact->bodies)
        f.correct = sb_contact_correct_swept;
    sb_add_feature(s, f);
    s->hooks.drift_chunk = sb_contact_chunk_packed;
    if (s->contact->surface) s->hooks.surface_packed = sb_contact_surface_packed;
}

double sb_contact_step_work(const sb_solver* s, double dt) {
    if (!s->contact) return 0.0;
    return sb_colliders_step_work(s->def.colliders, s->def.collider_count, s->contact->step, s->def.gravity, dt);
}

void sb_contact_save(const sb_solver* s, sb_sections_writer* w) {
    size_t colliders = s->def.collider_count;
    sb_sections_put(w, s->contact->step, 6 * colliders * sizeof(double));
    sb_sections_put(w, s->contact->impulse, 3 * colliders * sizeof(double));
}

void sb_contact_load(sb_solver* s, sb_cursor* r) {
    size_t colliders = s->def.collider_count;
    sb_cursor_take(r, s->contact->step, 6 * colliders * sizeof(double));
    sb_cursor_take(r, s->contact->impulse, 3 * colliders * sizeof(double));
}

bool sb_contact_has_bodies(const sb_solver* s) { return s->contact && s->contact->bodies; }

void sb_contact_bodies_save(const sb_solver* s, sb_sections_writer* w) {
    sb_body_restitution_save(s->contact->bodies, w);
}

void sb_contact_bodies_load(sb_solver* s, sb_cursor* r) { sb_body_restitution_load(s->contact->bodies, r); }

void sb_solver_contact_force(const sb_solver* s, uint32_t index, double force[3]) {
    for (int k = 0; k < 3; k++)
        force[k] = index < s->def.collider_count && s->advance_dt > 0.0
                       ? s->contact->impulse[3 * (size_t)index + k] / s->advance_dt
                       : 0.0;
}
