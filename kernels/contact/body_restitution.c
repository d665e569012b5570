/* Restitution a body obeys: a collider's `restitution` e holds for a soft
 * body's centre of mass, not only for the vertices it touches.
 *
 * Design. The per-vertex law (kernels/contact/contact.c) reverses the
 * normal velocity of the vertices that touch, times e. A flat patch, all
 * of whose vertices touch at once, so rebounds to e² h; a stiff ball does
 * not: a few vertices touch, the rest of the ball runs on into them and
 * compresses its springs, and the springs push it back up, whatever e
 * (an undamped icosphere rebounded to 72–77 % of its drop for e = 0, 0.5
 * and 0.9). The energy the impact puts into the body's springs comes back
 * as rebound, because nothing takes it out.
 *
 * So restitution is also answered per body, as Newton's law states it for
 * a body: while a connected part of the model (a body: its vertices joined
 * by bonds, triangles, hinges, tetrahedra or membranes) is in contact with
 * a collider, its centre of mass leaves the height it touched at with at
 * most e times the speed it came in with:
 *
 *   at first touch  n = the mean of the touching vertices' contact normals,
 *                   u = the mean of the collider's velocities at them,
 *                   e = the mean of their restitutions; the approach speed
 *                   w = −(V⁻ − u)·n, V⁻ the centre-of-mass velocity before
 *                   the step's answers (V minus the answers' impulses over
 *                   the body's mass); no episode when it was not approaching
 *                   (a vibrating body's vertex touching as it leaves);
 *   every step of the episode  s, how far the centre has moved out along
 *                   n since the touch, grows by vr dt, vr = (V − u)·n, u of
 *                   the step's touching vertices; in a step that touches,
 *                   vr may not exceed √((e w)² − 2 g_n s) (g_n: gravity
 *                   into the collider), the speed that reaches the touch
 *                   height (s = 0) at e w: the excess is taken off the
 *                   whole body as Δv = −excess n (every vertex the same, so
 *                   the springs feel nothing), and the collider takes the
 *                   opposite impulse M excess n at the touching vertices'
 *                   mean point.
 *
 * An episode runs from the first touching vertex through the steps in
 * which none touches while the centre is below the touch (s < 0: the
 * lowest vertices bounce off and come back while the rest arrives and
 * while the body springs back), until the centre is back above it
 * untouched, has fallen untouched for longer than SB_CONTACT_GAP (it left,
 * off a ledge say), or another collider touches the body instead (which
 * opens its own). Holding the speed at the touch height rather than at
 * each step (vr <= e w) matters: a ball still compressed when capped keeps
 * touching while gravity slows it on its way back up, and would leave
 * below e w.
 *
 * Only momentum along n is taken, and only what the collider's own pushes
 * gave the body beyond the allowed speed in this step (the step before was
 * capped), so the collider still pushes, never pulls; the tangential
 * motion is left to friction. After the body leaves the collider nothing
 * but gravity changes its centre's velocity, so it rises to e² h. The
 * energy the springs hold stays as the body's vibration (its material's
 * damping takes it, or it rings). For a rebound the body's own springs
 * make smaller (a soft, damped body) nothing is added: e is an upper bound
 * there, as a material's restitution is. A flat patch already leaves with
 * e w, and a lone vertex is its own centre: for them nothing changes. The
 * alternatives weighed: damping the body's internal modes during contact
 * in proportion to 1 − e does not give e² h without tuning per body (how
 * much of the impact goes into which mode depends on the mesh and the
 * stiffness); moving the vibration's energy into the rebound when it falls
 * short of e w would make energy flow against the material's own law.
 *
 * It runs serially after the contact pass (its collect or correct stage),
 * over the touched vertices in index order and the bodies in order, so it
 * is the same for any thread count. Its state is the open episodes (per
 * body: n, e, w, s, u, the collider, the time untouched), kept at accept,
 * so that a rejected adaptive sub-step leaves none, and saved with a
 * checkpoint. pbd and xpbd project contacts inside their sweeps and keep
 * the per-vertex law; a model that tears keeps it too (its bodies change
 * as it runs). A body holding a fixed or handled vertex is held from
 * outside, so its centre is not free: it keeps the per-vertex law. Its
 * cost is a pass over the touched chunks' vertices and one over each
 * touched body's vertices per step, on one thread. */
#include "kernels/contact/body_restitution.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/contact/colliders/dynamic.h"
#include "common/error.h"
#include "common/union_find.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* s: a body in contact whose centre approaches the collider untouched
 * longer than this has left it: the gaps in a contact, while the vertices
 * that touched first bounce off and the rest of the body arrives, last a
 * few steps (about 2 ms for the ball of tests/test_restitution.c). */
#define SB_CONTACT_GAP 0.005

/* Vertex i's contact answer in a step. */
typedef struct sb_vertex_hit {
    uint64_t stamp; /* the step it was answered in */
    int32_t collider;
    double restitution, normal[3], velocity[3], impulse[3], point[3];
} sb_vertex_hit;

/* A body's touching vertices summed over a step. */
typedef struct sb_body_hits {
    uint64_t stamp; /* the step the sums are of */
    uint32_t count;
    int32_t collider; /* the first touching vertex's */
    double restitution, normal[3], velocity[3], impulse[3], point[3];
} sb_body_hits;

/* A body's contact episode; doubles only (saved as they are). */
typedef struct sb_episode {
    double open;        /* 1 while in contact */
    double collider;    /* the collider of the first touch */
    double restitution; /* e */
    double approach;    /* m/s, w */
    double rise;        /* m, s: how far the centre moved out along n since the touch */
    double normal[3];
    double velocity[3]; /* m/s, u: the collider's at the last touch */
    double untouched;   /* s: how long the centre has approached since the last touch */
} sb_episode;

struct sb_body_restitution {
    uint32_t vertex_count, body_count;
    uint32_t* body_of;    /* per vertex: its body, or UINT32_MAX (a lone vertex, a held body) */
    uint32_t* first;      /* body b's vertices are vertices[first[b] .. first[b + 1]) */
    uint32_t* vertices;   /* grouped by body, in index order within each */
    double* mass;         /* per body, kg */
    sb_vertex_hit* hits;  /* per vertex */
    uint8_t* chunk_hit;   /* per chunk: a vertex of it was answered this step */
    uint8_t* chunk_body;  /* per chunk: a vertex of it belongs to a body */
    sb_body_hits* sums;   /* per body */
    sb_episode* episodes; /* per body, as of the last accepted step */
    sb_episode* next;     /* per body, as this step leaves them (valid for the bodies in `changed`) */
    uint32_t* changed;    /* the bodies whose episode this step wrote */
    uint32_t changed_count;
    uint32_t open_count; /* episodes open as of the last accepted step */
    uint64_t stamp;      /* the step being taken */
};

/* Joins the vertices of every element of the model. */
static void sb_join_elements(const sb_model* m, uint32_t* parent) {
    for (uint32_t e = 0; e < m->bond_count; e++) sb_join(parent, m->bond_i[e], m->bond_j[e]);
    for (uint32_t e = 0; e < m->triangle_count; e++)
        for (int k = 1; k < 3; k++) sb_join(parent, m->tri_v[0][e], m->tri_v[k][e]);
    for (uint32_t e = 0; e < m->hinge_count; e++) {
        sb_join(parent, m->hinge_e0[e], m->hinge_e1[e]);
        sb_join(parent, m->hinge_e0[e], m->hinge_o0[e]);
        sb_join(parent, m->hinge_e0[e], m->hinge_o1[e]);
    }
    for (uint32_t e = 0; e < m->tet_count; e++)
        for (int k = 1; k < m->tet_nodes[e]; k++) sb_join(parent, m->tet_v[0][e], m->tet_v[k][e]);
    for (uint32_t e = 0; e < m->membrane_count; e++)
        for (int k = 1; k < 3; k++) sb_join(parent, m->membrane_v[0][e], m->membrane_v[k][e]);
}

/* The bodies from the parts' roots: a part of two vertices or more with no
 * fixed vertex is a body, numbered in the order of its lowest vertex. */
static void sb_label_bodies(const sb_model* m, sb_body_restitution* b, uint32_t* parent) {
    uint32_t n = m->vertex_count, *size = b->first, *held = b->vertices; /* scratch until filled below */
    memset(size, 0, ((size_t)n + 1) * sizeof *size);
    memset(held, 0, ((size_t)n + 1) * sizeof *held);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t r = sb_find(parent, i);
        size[r]++;
        held[r] |= m->fixed[i] != 0;
    }
    for (uint32_t i = 0; i < n; i++) { /* a root is its part's lowest vertex: labelled before the others */
        uint32_t r = sb_find(parent, i);
        bool body = size[r] >= 2 && !held[r];
        if (body && r == i) b->body_of[i] = b->body_count++;
        b->body_of[i] = body ? b->body_of[r] : UINT32_MAX;
    }
    memset(b->first, 0, ((size_t)n + 1) * sizeof *b->first);
    for (uint32_t i = 0; i < n; i++)
        if (b->body_of[i] != UINT32_MAX) b->first[b->body_of[i] + 1]++;
    for (uint32_t k = 0; k < b->body_count; k++) b->first[k + 1] += b->first[k];
    uint32_t* fill = parent; /* parent's job is done */
    memcpy(fill, b->first, (size_t)b->body_count * sizeof *fill);
    for (uint32_t i = 0; i < n; i++)
        if (b->body_of[i] != UINT32_MAX) {
            uint32_t k = b->body_of[i];
            b->vertices[fill[k]++] = i;
            b->mass[k] += m->mass[i];
        }
}

sb_status sb_body_restitution_create(const sb_solver* s, sb_body_restitution** out, sb_error* err) {
    *out = NULL;
    if (s->breakage) return SB_OK;
    const sb_model* m = s->model;
    size_t n = m->vertex_count;
    sb_body_restitution* b = calloc(1, sizeof *b);
    uint32_t* parent = malloc((n + 1) * sizeof *parent);
    if (b) {
        b->vertex_count = m->vertex_count;
        b->body_of = malloc((n + 1) * sizeof *b->body_of);
        b->first = malloc((n + 1) * sizeof *b->first);
        b->vertices = malloc((n + 1) * sizeof *b->vertices);
        b->mass = calloc(n + 1, sizeof *b->mass);
        b->hits = calloc(n + 1, sizeof *b->hits);
        b->chunk_hit = calloc(sb_chunk_count(m->vertex_count) + 1, 1);
        b->chunk_body = calloc(sb_chunk_count(m->vertex_count) + 1, 1);
    }
    if (!b || !parent || !b->body_of || !b->first || !b->vertices || !b->mass || !b->hits || !b->chunk_hit ||
        !b->chunk_body) {
        free(parent);
        sb_body_restitution_destroy(b);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory for body restitution");
    }
    for (uint32_t i = 0; i < m->vertex_count; i++) parent[i] = i;
    sb_join_elements(m, parent);
    sb_label_bodies(m, b, parent);
    free(parent);
    for (uint32_t i = 0; i < m->vertex_count; i++) b->chunk_body[i / SB_CHUNK] |= b->body_of[i] != UINT32_MAX;
    size_t bodies = (size_t)b->body_count + 1;
    b->sums = calloc(bodies, sizeof *b->sums);
    b->episodes = calloc(bodies, sizeof *b->episodes);
    b->next = calloc(bodies, sizeof *b->next);
    b->changed = calloc(bodies, sizeof *b->changed);
    if (!b->sums || !b->episodes || !b->next || !b->changed) {
        sb_body_restitution_destroy(b);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory for body restitution");
    }
    *out = b;
    return SB_OK;
}

void sb_body_restitution_destroy(sb_body_restitution* b) {
    if (!b) return;
    free(b->body_of);
    free(b->first);
    free(b->vertices);
    free(b->mass);
    free(b->hits);
    free(b->chunk_hit);
    free(b->chunk_body);
    free(b->sums);
    free(b->episodes);
    free(b->next);
    free(b->changed);
    free(b);
}

void sb_body_restitution_begin(sb_body_restitution* b) {
    b->stamp++;
    b->changed_count = 0;
}

bool sb_body_restitution_follows(const sb_body_restitution* b, uint32_t chunk) { return b->chunk_body[chunk]; }

void sb_body_restitution_touch(sb_body_restitution* b, uint32_t i, int collider, const sb_contact* c,
                               const double impulse[3]) {
    if (b->body_of[i] == UINT32_MAX) return;
    sb_vertex_hit* h = &b->hits[i];
    if (h->stamp == b->stamp) { /* answered again (a corner of the surface pass): its impulses add up */
        for (int k = 0; k < 3; k++) h->impulse[k] += impulse[k];
        return;
    }
    h->stamp = b->stamp;
    h->collider = collider;
    h->restitution = c->restitution;
    memcpy(h->normal, c->normal, sizeof h->normal);
    memcpy(h->velocity, c->velocity, sizeof h->velocity);
    memcpy(h->impulse, impulse, sizeof h->impulse);
    memcpy(h->point, c->point, sizeof h->point);
    b->chunk_hit[i / SB_CHUNK] = 1;
}

/* Adds vertex hit h into its body's sums of this step. */
static void sb_add_hit(sb_body_restitution* b, const sb_vertex_hit* h, sb_body_hits* sum) {
    if (sum->stamp != b->stamp) *sum = (sb_body_hits){.stamp = b->stamp, .collider = h->collider};
    sum->count++;
    sum->restitution += h->restitution;
    for (int k = 0; k < 3; k++) {
        sum->normal[k] += h->normal[k];
        sum->velocity[k] += h->velocity[k];
        sum->impulse[k] += h->impulse[k];
        sum->point[k] += h->point[k];
    }
}

/* Sums the step's hits per body, the chunks and vertices in order; whether
 * there were any. */
static bool sb_sum_hits(sb_body_restitution* b) {
    bool any = false;
    uint32_t chunks = sb_chunk_count(b->vertex_count);
    for (uint32_t c = 0; c < chunks; c++) {
        if (!b->chunk_hit[c]) continue;
        b->chunk_hit[c] = 0;
        uint32_t last = (c + 1) * SB_CHUNK < b->vertex_count ? (c + 1) * SB_CHUNK : b->vertex_count;
        for (uint32_t i = c * SB_CHUNK; i < last; i++)
            if (b->hits[i].stamp == b->stamp) {
                sb_add_hit(b, &b->hits[i], &b->sums[b->body_of[i]]);
                any = true;
            }
    }
    return any;
}

/* Where a vertex's velocity and Verlet displacement are: the packed state
 * of the fused step, or the state's arrays. */
typedef struct sb_velocity_view {
    sb_solver* solver;
    bool packed;
} sb_velocity_view;

static double sb_velocity_of(const sb_velocity_view* view, uint32_t i, int k) {
    const sb_solver* s = view->solver;
    const sb_real* v[3] = {s->state.vx, s->state.vy, s->state.vz};
    return view->packed ? s->velocities4[4 * (size_t)i + k] : v[k][i];
}

/* Adds dv to vertex i's velocity (and dv dt to its displacement, so that
 * the Verlet forms carry it); on the packed state also the drag it feels
 * and the snapshot the fused step wrote. */
static void sb_add_velocity(const sb_velocity_view* view, uint32_t i, const double dv[3], double dt) {
    sb_solver* s = view->solver;
    if (!view->packed) {
        sb_real* v[3] = {s->state.vx, s->state.vy, s->state.vz};
        sb_real* d[3] = {s->disp_x, s->disp_y, s->disp_z};
        for (int k = 0; k < 3; k++) {
            v[k][i] = (sb_real)(v[k][i] + dv[k]);
            d[k][i] = (sb_real)(d[k][i] + dv[k] * dt);
        }
        return;
    }
    size_t at = 4 * (size_t)i;
    double drag = s->model->mass[i] * s->def.drag;
    for (int k = 0; k < 3; k++) {
        s->velocities4[at + k] = (sb_real)(s->velocities4[at + k] + dv[k]);
        s->displacements4[at + k] = (sb_real)(s->displacements4[at + k] + dv[k] * dt);
        s->forces4[at + k] = (sb_real)(s->forces4[at + k] - drag * dv[k]);
        if (s->step.publish_written) s->step.publish_velocities[3 * (size_t)i + k] = s->velocities4[at + k];
    }
}

/* Body k's centre-of-mass velocity; false when a vertex of it is held (a
 * hard handle), so that its centre is not free. */
static bool sb_body_velocity(const sb_body_restitution* b, const sb_velocity_view* view, uint32_t k, double V[3]) {
    const double* inv_mass = sb_inv_mass(view->solver);
    const double* mass = view->solver->model->mass;
    V[0] = V[1] = V[2] = 0.0;
    for (uint32_t j = b->first[k]; j < b->first[k + 1]; j++) {
        uint32_t i = b->vertices[j];
        if (inv_mass[i] == 0.0) return false;
        for (int a = 0; a < 3; a++) V[a] += mass[i] * sb_velocity_of(view, i, a);
    }
    for (int a = 0; a < 3; a++) V[a] /= b->mass[k];
    return true;
}

/* The episode a body in contact opens (see the design note), closed where
 * its centre was not approaching; V its centre's velocity after the step's
 * answers. */
static sb_episode sb_episode_open(const sb_body_restitution* b, uint32_t k, const double V[3]) {
    const sb_body_hits* h = &b->sums[k];
    double length = sqrt(h->normal[0] * h->normal[0] + h->normal[1] * h->normal[1] + h->normal[2] * h->normal[2]);
    if (!(length > 0.0)) return (sb_episode){0};
    sb_episode e = {.open = 1.0, .collider = h->collider, .restitution = h->restitution / h->count};
    double approach = 0.0;
    for (int a = 0; a < 3; a++) {
        e.normal[a] = h->normal[a] / length;
        double before = V[a] - h->impulse[a] / b->mass[k];
        approach -= (before - h->velocity[a] / h->count) * e.normal[a];
    }
    if (!(approach > 0.0)) return (sb_episode){0}; /* touched while leaving (a vibration's vertex): no impact */
    e.approach = approach;
    return e;
}

/* The collider of episode e takes the impulse `received` at the body's
 * touching vertices' mean point: into the step's sums. */
static void sb_record_reaction(const sb_solver* s, const sb_body_hits* h, const sb_episode* e, const double received[3],
                               double* step) {
    uint32_t c = (uint32_t)e->collider, colliders = s->def.collider_count;
    double point[3] = {h->point[0] / h->count, h->point[1] / h->count, h->point[2] / h->count}, torque[3];
    sb_collider_torque(s->def.colliders[c], point, received, torque);
    for (int a = 0; a < 3; a++) {
        step[3 * c + a] += received[a];
        step[3 * (size_t)colliders + 3 * c + a] += torque[a];
    }
}

/* The centre's normal velocity relative to the collider, vr. */
static double sb_outward(const sb_episode* e, const double V[3]) {
    double outward = 0.0;
    for (int a = 0; a < 3; a++) outward += (V[a] - e->velocity[a]) * e->normal[a];
    return outward;
}

/* The most vr may be at the episode's rise s: what leaves the touch height
 * at e w, (e w)² − 2 g_n s, g_n gravity's pull into the collider. */
static double sb_allowed(const sb_solver* s, const sb_episode* e) {
    double pull = 0.0, kept = e->restitution * e->approach;
    for (int a = 0; a < 3; a++) pull -= s->def.gravity[a] * e->normal[a];
    double squared = kept * kept - 2.0 * pull * e->rise;
    return squared > 0.0 ? sqrt(squared) : 0.0;
}

/* Body k touched this step under episode e: the outward velocity of its
 * centre beyond what is allowed taken off; whether it was. */
static bool sb_cap_body(const sb_velocity_view* view, sb_body_restitution* b, uint32_t k, sb_episode* e,
                        const double V[3], double dt, double* step) {
    double outward = sb_outward(e, V), excess = outward - sb_allowed(view->solver, e);
    e->rise += (excess > 0.0 ? outward - excess : outward) * dt;
    if (!(excess > 0.0)) return false;
    double dv[3], received[3], M = b->mass[k];
    for (int a = 0; a < 3; a++) {
        dv[a] = -excess * e->normal[a];
        received[a] = -M * dv[a];
    }
    for (uint32_t j = b->first[k]; j < b->first[k + 1]; j++) sb_add_velocity(view, b->vertices[j], dv, dt);
    if (view->packed) /* the fused step summed its kinetic energy before: P·Δv + M |Δv|² / 2 */
        view->solver->energies.kinetic +=
            M * (0.5 * excess * excess - excess * (V[0] * e->normal[0] + V[1] * e->normal[1] + V[2] * e->normal[2]));
    sb_record_reaction(view->solver, &b->sums[k], e, received, step);
    return true;
}

/* Body k's episode after this step (in b->next); whether its velocity
 * changed. An episode goes on while the body touches its collider, and
 * through the steps it touches nothing while its centre is below the
 * touch (s < 0): a ball's lowest vertices bounce off and come back while
 * the rest of it arrives and while it springs back. It ends once the
 * centre is back above the touch untouched, once it has fallen untouched
 * for longer than SB_CONTACT_GAP (it left: off a ledge, say), or when
 * another collider touches the body instead (a new episode). */
static bool sb_body_step(const sb_velocity_view* view, sb_body_restitution* b, uint32_t k, double dt, double* step) {
    const sb_body_hits* h = &b->sums[k];
    bool touched = h->stamp == b->stamp;
    sb_episode* e = &b->next[k];
    *e = b->episodes[k];
    double V[3];
    if (!sb_body_velocity(b, view, k, V)) { /* held */
        *e = (sb_episode){0};
        return false;
    }
    if (touched && !(e->open && e->collider == h->collider)) *e = sb_episode_open(b, k, V);
    if (!e->open) return false;
    if (!touched) {
        double outward = sb_outward(e, V);
        e->rise += outward * dt;
        e->untouched = outward < 0.0 ? e->untouched + dt : 0.0;
        if (e->rise >= 0.0 || e->untouched > SB_CONTACT_GAP) *e = (sb_episode){0};
        return false;
    }
    e->untouched = 0.0;
    for (int a = 0; a < 3; a++) e->velocity[a] = h->velocity[a] / h->count;
    return sb_cap_body(view, b, k, e, V, dt, step);
}

bool sb_body_restitution_apply(sb_solver* s, sb_body_restitution* b, bool packed, double dt, double* step) {
    if (!sb_sum_hits(b) && b->open_count == 0) return false;
    sb_velocity_view view = {s, packed};
    bool moved = false;
    for (uint32_t k = 0; k < b->body_count; k++) {
        if (b->sums[k].stamp != b->stamp && !b->episodes[k].open) continue;
        b->changed[b->changed_count++] = k;
        moved |= sb_body_step(&view, b, k, dt, step);
    }
    return moved;
}

void sb_body_restitution_accept(sb_body_restitution* b) {
    for (uint32_t j = 0; j < b->changed_count; j++) {
        uint32_t k = b->changed[j];
        b->open_count += (b->next[k].open != 0.0) - (b->episodes[k].open != 0.0);
        b->episodes[k] = b->next[k];
    }
    b->changed_count = 0;
}

void sb_body_restitution_save(const sb_body_restitution* b, sb_sections_writer* w) {
    sb_sections_put(w, b->episodes, (size_t)b->body_count * sizeof *b->episodes);
}

void sb_body_restitution_load(sb_body_restitution* b, sb_cursor* r) {
    sb_cursor_take(r, b->episodes, (size_t)b->body_count * sizeof *b->episodes);
    b->open_count = 0;
    for (uint32_t k = 0; k < b->body_count; k++) b->open_count += b->episodes[k].open != 0.0;
}
