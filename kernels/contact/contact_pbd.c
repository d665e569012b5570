/* Contact as constraints inside the pbd and xpbd sweeps (kernels/integrators/pbd.c),
 * in the manner of Müller et al. 2007 and Macklin et al. 2016/2019.
 *
 * Design. After the predict, each free vertex's move from x0 (its position
 * at the start of the step) to its predicted x* is offered to the colliders
 * as the post-step pass offers a move (sb_contact_find, kernels/contact/contact.c:
 * the same sweeps through sb_collide_fn, the same broad phase by the
 * colliders' bounds, the earliest contact). A contact becomes the
 * inequality constraint
 *
 *   C(x) = (x − p)·n >= 0,  p = from + fraction (to − from) + depth n,
 *
 * the half-space above the plane through the answered point p (on the
 * collider's surface inflated by both thicknesses, as the collider stands
 * at the end of the step) with its normal n. It is rigid (compliance 0, in
 * xpbd too) and moves one vertex, so its projection is x += max(−C, 0) n
 * whatever the vertex's mass. It is projected after the bonds and corners
 * in every sweep, so the last sweep leaves every contact satisfied. D, the
 * sum of its pushes over the sweeps, is the normal displacement the contact
 * gave the vertex (its λ / m in xpbd's terms).
 *
 * Found once per step, not re-queried per sweep: a collider answers a sweep
 * of the step's move (continuous, so a fast vertex cannot tunnel), and that
 * move is known once the predict has made it. Asking again in every sweep
 * would ask about moves from x0 to half-projected positions, so a contact
 * could appear and vanish from one sweep to the next (an active set
 * Gauss-Seidel need not settle), and would call the colliders — a
 * program's own are scalar callbacks — pbd_iterations times as often.
 * Müller et al. generate collision constraints once per step too. One
 * second look: before the last sweep's projection, each free vertex still
 * without a contact is asked about its move from x0 to where the sweeps
 * have put it, so that one the other constraints pulled into a collider
 * (a cloth folding onto the floor) is caught in this step, not the next.
 * The price of a plane per contact: a vertex sliding over a curved
 * collider may end a step inside it by up to s²/(2R) (s its travel along
 * the surface, R the radius of curvature); its next move starts inside and
 * the sweep answers it with its depth.
 *
 * After the sweeps, with x their result and v = (x − x0)/dt, each contact
 * the sweeps pushed (D > 0) is answered as the post-step pass answers one
 * (sb_contact_velocity): without the contact the vertex would have moved at
 * v_in = v − (D/dt) n, the velocity it met the surface with (for a lone
 * vertex, the predicted one); v_in's answer v' keeps −e of its normal speed
 * relative to the collider and loses tangential speed by Coulomb friction
 * with the normal impulse (1 + e) |v_in·n| per unit mass (it sticks below
 * the static coefficient). A vertex whose v_in does not approach the
 * collider (the other constraints carried it off) keeps v. Along the
 * surface the vertex takes the whole step at the answered tangential
 * velocity (x += dt (v' − v) less its normal part), so that one that sticks
 * does not creep and one that slides moves as its velocity says; along the
 * normal it stays where the sweeps put it, on or above the plane (a start
 * inside, rounding's or the lag's, is pushed out without gaining speed).
 * The collider receives −m (v' − v_in) / dt. A contact the sweeps never
 * pushed (the other constraints kept the vertex out) carries no normal
 * force: no answer, no friction.
 *
 * Deterministic: the contacts are kept per fixed chunk of vertices in the
 * order found, each constraint moves only its own vertex, and the impulses
 * go into kernels/contact/contact.c's partial sums per chunk, summed in order: the
 * state and the reaction forces are the same for any thread count. */
#include "kernels/contact/contact_pbd.h"
#include "kernels/contact/contact.h"

#include <stdlib.h>
#include <string.h>

/* One vertex's contact of the step. */
typedef struct sb_pbd_contact {
    sb_contact answer; /* the collider's: normal, its velocity, restitution, friction */
    double point[3];   /* p, on the surface at the end of the step */
    double pushed;     /* D: the constraint's pushes over the sweeps, m */
    uint32_t vertex;
    int collider;
} sb_pbd_contact;

struct sb_pbd_contacts {
    uint32_t chunks;
    uint32_t* count;       /* per chunk */
    sb_pbd_contact* slots; /* chunk c's contacts from slot c SB_CHUNK, in the order found */
    uint8_t* touching;     /* per vertex: 1 when it has a contact this step */
};

bool sb_pbd_contacts_create(const sb_solver* s, sb_pbd_contacts** out) {
    *out = NULL;
    if (s->def.collider_count == 0) return true;
    sb_pbd_contacts* c = calloc(1, sizeof *c);
    if (c) {
        c->chunks = sb_chunk_count(s->model->vertex_count);
        c->count = calloc((size_t)c->chunks + 1, sizeof *c->count);
        c->slots = malloc(((size_t)s->model->vertex_count + 1) * sizeof *c->slots);
        c->touching = malloc((size_t)s->model->vertex_count + 1);
    }
    if (!c || !c->count || !c->slots || !c->touching) {
        sb_pbd_contacts_destroy(c);
        return false;
    }
    *out = c;
    return true;
}

void sb_pbd_contacts_destroy(sb_pbd_contacts* c) {
    if (!c) return;
    free(c->count);
    free(c->slots);
    free(c->touching);
    free(c);
}

/* The contact of vertex i's move from → to, into *k; false for none. */
static bool sb_pbd_contact_of(const sb_solver* s, uint32_t i, const double from[3], const double to[3],
                              sb_pbd_contact* k) {
    int hit = sb_contact_find(s, i, from, to, &k->answer);
    if (hit < 0) return false;
    const sb_contact* a = &k->answer;
    for (int q = 0; q < 3; q++) k->point[q] = from[q] + a->fraction * (to[q] - from[q]) + a->depth * a->normal[q];
    k->pushed = 0.0;
    k->vertex = i;
    k->collider = hit;
    return true;
}

void sb_pbd_contacts_find(const sb_solver* s, sb_pbd_contacts* c, const sb_worker* w, const double* x0, const double* x,
                          bool again) {
    uint32_t n = s->model->vertex_count;
    int64_t begin, end;
    sb_worker_range(w, c->chunks, &begin, &end);
    for (int64_t chunk = begin; chunk < end; chunk++) {
        uint32_t first = (uint32_t)chunk * SB_CHUNK, last = first + SB_CHUNK < n ? first + SB_CHUNK : n;
        uint32_t count = again ? c->count[chunk] : 0;
        for (uint32_t i = first; i < last; i++) {
            /* a fixed vertex (inverse mass 0) never moves; the second look is for the others */
            if (s->model->fixed[i] || (again && c->touching[i])) continue;
            c->touching[i] = sb_pbd_contact_of(s, i, x0 + 3 * (size_t)i, x + 3 * (size_t)i, c->slots + first + count);
            count += c->touching[i];
        }
        c->count[chunk] = count;
    }
    if (!again) sb_worker_barrier(w); /* the sweeps move every vertex next */
}

void sb_pbd_contacts_project(sb_pbd_contacts* c, const sb_worker* w, double* x) {
    int64_t begin, end;
    sb_worker_range(w, c->chunks, &begin, &end);
    for (int64_t chunk = begin; chunk < end; chunk++) {
        sb_pbd_contact* k = c->slots + (size_t)chunk * SB_CHUNK;
        for (uint32_t j = 0; j < c->count[chunk]; j++, k++) {
            double* p = x + 3 * (size_t)k->vertex;
            const double* normal = k->answer.normal;
            double C = 0.0;
            for (int q = 0; q < 3; q++) C += (p[q] - k->point[q]) * normal[q];
            if (C >= 0.0) continue;
            for (int q = 0; q < 3; q++) p[q] -= C * normal[q];
            k->pushed -= C;
        }
    }
    sb_worker_barrier(w);
}

static double sb_dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* One contact's answer (see the design note): the end position x (from the
 * sweeps) and velocity v' of its vertex, and the impulse m (v' − v_in). */
static void sb_pbd_answer(const sb_pbd_contact* k, double mass, double dt, const double x0[3], double x[3], double v[3],
                          double impulse[3]) {
    const double* n = k->answer.normal;
    double after[3], in[3];
    for (int q = 0; q < 3; q++) {
        after[q] = (x[q] - x0[q]) / dt;
        in[q] = after[q] - k->pushed / dt * n[q];
        v[q] = in[q];
    }
    if (sb_dot3(in, n) < sb_dot3(k->answer.velocity, n))
        sb_contact_velocity(&k->answer, v);
    else /* it would not have approached the collider: the other constraints carried it off */
        memcpy(v, after, sizeof after);
    double slip[3]; /* dt (v' − v): the position follows its part along the surface */
    for (int q = 0; q < 3; q++) slip[q] = dt * (v[q] - after[q]);
    double slip_n = sb_dot3(slip, n);
    for (int q = 0; q < 3; q++) {
        x[q] += slip[q] - slip_n * n[q];
        impulse[q] = mass * (v[q] - in[q]);
    }
}

/* The answers of one chunk's contacts into the state and its partial sums. */
static void sb_pbd_answer_chunk(sb_solver* s, const sb_pbd_contacts* c, uint32_t chunk, const double* x0,
                                const double* xs, double dt) {
    sb_state* st = &s->state;
    sb_contact_chunk_begin(s, chunk);
    const sb_pbd_contact* k = c->slots + (size_t)chunk * SB_CHUNK;
    for (uint32_t j = 0; j < c->count[chunk]; j++, k++) {
        if (!(k->pushed > 0.0)) continue;
        uint32_t i = k->vertex;
        double x[3] = {xs[3 * (size_t)i], xs[3 * (size_t)i + 1], xs[3 * (size_t)i + 2]}, v[3], impulse[3];
        sb_pbd_answer(k, s->model->mass[i], dt, x0 + 3 * (size_t)i, x, v, impulse);
        st->x[i] = (sb_real)x[0], st->y[i] = (sb_real)x[1], st->z[i] = (sb_real)x[2];
        st->vx[i] = (sb_real)v[0], st->vy[i] = (sb_real)v[1], st->vz[i] = (sb_real)v[2];
        sb_contact_touch(s, i, k->collider, &k->answer, impulse);
        sb_contact_record(s, chunk, k->collider, impulse);
        sb_contact_record_torque(s, chunk, k->collider, k->answer.point, impulse);
    }
}

typedef struct sb_pbd_answer_job {
    sb_solver* solver;
    const sb_pbd_contacts* contacts;
    const double *x0, *x;
    double dt;
} sb_pbd_answer_job;

static void sb_pbd_answer_worker(void* context, const sb_worker* w) {
    const sb_pbd_answer_job* job = context;
    int64_t begin, end;
    sb_worker_range(w, job->contacts->chunks, &begin, &end);
    for (int64_t c = begin; c < end; c++)
        sb_pbd_answer_chunk(job->solver, job->contacts, (uint32_t)c, job->x0, job->x, job->dt);
}

uint32_t sb_pbd_contacts_answer(sb_solver* s, sb_pbd_contacts* c, const double* x0, const double* x, double dt) {
    sb_pbd_answer_job job = {s, c, x0, x, dt};
    sb_team_run(s->team, sb_team_size(s->team), sb_pbd_answer_worker, &job);
    return sb_contact_collect(s);
}
