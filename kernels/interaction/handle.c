/* Handles (softbond/handle.h): vertices driven to a moving pose.
 *
 * Design. A handle keeps its vertices' positions at grab time in its rest
 * frame, q = pose(t_grab)⁻¹ p, and the poses of the step being taken,
 * pose0 = pose(t0) and pose1 = pose(t1) (from the path, or from where the
 * last step left it to where sb_handle_set_pose put it, as a driven
 * collider): vertex k's target is pose1(q_k), its velocity over the step
 * (pose1(q_k) − pose0(q_k)) / dt.
 *
 * A hard handle places its held vertices, by position:
 *   - the fused Verlet step (kernels/state/solver_fast.c): on worker 0 after the
 *     drift and the contact passes, before the forces; the packed inverse
 *     mass of a held vertex is 0, so the kick leaves its velocity and the
 *     drift its displacement to the handle;
 *   - the other integrators (kernels/solver/solver.c): after the step (and its
 *     contact passes) on the state's arrays (and the Störmer form's
 *     displacement), then the forces again; the explicit ones
 *     (kernels/integrators/integrators.c) move a held vertex with inverse mass 0, so it
 *     drifts at the target's velocity and the forces of the step see it at
 *     its target; implicit Euler's Newton solve treats it as free;
 *   - pbd and xpbd (kernels/integrators/pbd.c): the prediction of a held vertex is its
 *     target and the projection sees it with inverse mass 0 (pinned), and
 *     the generic placement after the step makes it exact whatever the
 *     contacts did.
 * The position is the target rounded to sb_real, at every step: position
 * error 0. A soft handle adds k (target − x) + c (target velocity − v) to
 * each held vertex's force in every force evaluation, after the external
 * callback and into the same kept external forces (solver->external), so
 * pbd's prediction and the adaptive stepper's work count see it as they
 * see the callback's; the sum over its vertices, in vertex order, is the
 * force it reports. Every handle pass runs on one thread, handles and
 * vertices in order: the result does not depend on the thread count. */
#include "kernels/interaction/handle_internal.h"
#include "kernels/state/solver_data.h"
#include "kernels/state/solver_fast.h"
#include "kernels/state/solver_forces.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "common/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct sb_handle {
    char name[64];
    uint32_t* vertices;
    uint32_t count;
    bool has_center;
    double center[3];
    double stiffness, damping;
    sb_keyframe* path;
    uint32_t path_count;
    sb_interpolation interpolation;
    double release_time;
    bool held, driven;
    double driven_to[2][3]; /* sb_handle_set_pose: translate, rotate (made a pose about the center at the step) */
    double pose0[12], pose1[12];
    double dt;    /* s, the step being taken (0 before the first) */
    double* grab; /* 3 per vertex: q, the positions at grab time in the rest frame */
    double force[3];
    sb_solver* solver; /* the solver it is attached to (NULL before) */
};

sb_handle_def sb_default_handle_def(void) {
    return (sb_handle_def){.interpolation = SB_INTERPOLATION_LINEAR, .release_time = INFINITY};
}

static sb_status sb_handle_check(const char* owner, const sb_handle_def* d, sb_error* err) {
    if (d->vertex_count == 0 || !d->vertices)
        return sb_error_set(err, SB_ERR_INVALID, "%s: no vertices (vertex_count is %u)", owner, d->vertex_count);
    if (!(isfinite(d->stiffness) && d->stiffness >= 0.0) || !(isfinite(d->damping) && d->damping >= 0.0))
        return sb_error_set(err, SB_ERR_INVALID, "%s: stiffness and damping must be finite and >= 0 (got %g, %g)",
                            owner, d->stiffness, d->damping);
    if (d->center && !(isfinite(d->center[0]) && isfinite(d->center[1]) && isfinite(d->center[2])))
        return sb_error_set(err, SB_ERR_INVALID, "%s: center must be finite", owner);
    if (isnan(d->release_time)) return sb_error_set(err, SB_ERR_INVALID, "%s: release_time is NaN", owner);
    return sb_path_check(owner, d->path, d->path_count, d->interpolation, err);
}

sb_handle* sb_handle_create(const sb_handle_def* def, sb_error* err) {
    if (!def) {
        sb_error_set(err, SB_ERR_INVALID, "handle: no definition (def is NULL)");
        return NULL;
    }
    char owner[96];
    snprintf(owner, sizeof owner, "handle '%s'", def->name ? def->name : "handle");
    if (sb_handle_check(owner, def, err) != SB_OK) return NULL;
    sb_handle* h = calloc(1, sizeof *h);
    if (h) {
        h->vertices = malloc(def->vertex_count * sizeof *h->vertices);
        h->grab = calloc(3 * (size_t)def->vertex_count, sizeof *h->grab);
        h->path = def->path_count ? malloc(def->path_count * sizeof *h->path) : NULL;
    }
    if (!h || !h->vertices || !h->grab || (def->path_count && !h->path)) {
        sb_handle_destroy(h);
        sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", owner);
        return NULL;
    }
    snprintf(h->name, sizeof h->name, "%s", def->name ? def->name : "handle");
    memcpy(h->vertices, def->vertices, def->vertex_count * sizeof *h->vertices);
    if (h->path) memcpy(h->path, def->path, def->path_count * sizeof *h->path);
    h->count = def->vertex_count;
    h->path_count = def->path_count;
    h->has_center = def->center != NULL;
    if (def->center) memcpy(h->center, def->center, sizeof h->center);
    h->stiffness = def->stiffness;
    h->damping = def->damping;
    h->interpolation = def->interpolation;
    h->release_time = def->release_time;
    h->held = true;
    return h;
}

void sb_handle_destroy(sb_handle* h) {
    if (!h) return;
    free(h->vertices);
    free(h->grab);
    free(h->path);
    free(h);
}

static bool sb_handle_soft(const sb_handle* h) { return h->stiffness > 0.0; }

/* x = pose⁻¹(y) = Rᵀ (y − translation) */
static void sb_pose_invert_point(const double pose[12], const double y[3], double x[3]) {
    double r[3] = {y[0] - pose[9], y[1] - pose[10], y[2] - pose[11]};
    for (int i = 0; i < 3; i++) x[i] = pose[i] * r[0] + pose[3 + i] * r[1] + pose[6 + i] * r[2];
}

/* Vertex i's position now, from whichever state is current. */
static void sb_vertex_position(const sb_solver* s, uint32_t i, double p[3]) {
    if (s->fast && !s->published) {
        for (int c = 0; c < 3; c++) p[c] = s->positions4[4 * (size_t)i + c];
        return;
    }
    p[0] = s->state.x[i], p[1] = s->state.y[i], p[2] = s->state.z[i];
}

/* The fused step's gravity energy counts the free vertices it moves (a
 * nonzero packed inverse mass): after the pins change, the energy of the
 * state is summed again over the same set, so that the adaptive stepper's
 * balance across the next step compares like with like. */
static void sb_refresh_gravity(sb_solver* s) {
    if (!sb_fused(s)) return;
    const sb_model* m = s->model;
    const double* g = s->def.gravity;
    double gravity = 0.0;
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        if (s->fast->inv_mass[i] == 0) continue;
        double p[3];
        sb_vertex_position(s, i, p);
        gravity -= m->mass[i] * (g[0] * p[0] + g[1] * p[1] + g[2] * p[2]);
    }
    s->energies.gravity = gravity;
}

/* The inverse masses the fused kick and pbd's projection use: the model's,
 * 0 on every vertex a hard handle holds. */
static void sb_handles_pin(sb_solver* s) {
    if (sb_fused(s)) sb_solver_settle(s); /* the last step's sums first: sb_refresh_gravity's then stands */
    const sb_model* m = s->model;
    for (int pass = 0; pass < 2; pass++) /* restore every handle's vertices, then pin the held hard ones */
        for (uint32_t k = 0; k < s->def.handle_count; k++) {
            const sb_handle* h = s->def.handles[k];
            if (pass == 1 && (sb_handle_soft(h) || !h->held)) continue;
            for (uint32_t j = 0; j < h->count; j++) {
                uint32_t i = h->vertices[j];
                double w = pass == 0 ? m->inv_mass[i] : 0.0;
                if (s->pinned_inv_mass) s->pinned_inv_mass[i] = w;
                if (s->fast) s->fast->inv_mass[i] = (sb_real)w;
            }
        }
    sb_refresh_gravity(s);
}

static void sb_handle_take(sb_handle* h) {
    for (uint32_t j = 0; j < h->count; j++) {
        double p[3];
        sb_vertex_position(h->solver, h->vertices[j], p);
        sb_pose_invert_point(h->pose1, p, h->grab + 3 * (size_t)j);
    }
    h->held = true;
}

sb_status sb_handle_grab(sb_handle* h) {
    if (!h->solver) return sb_error_set(NULL, SB_ERR_INVALID, "handle '%s' is not attached to a solver", h->name);
    sb_handle_take(h);
    sb_handles_pin(h->solver);
    return SB_OK;
}

sb_status sb_handle_grab_vertex(sb_handle* h, uint32_t vertex) {
    if (h->count != 1 || !h->solver || vertex >= h->solver->model->vertex_count)
        return sb_error_set(NULL, SB_ERR_INVALID, "handle '%s': cannot hold vertex %u", h->name, vertex);
    h->vertices[0] = vertex;
    return sb_handle_grab(h);
}

void sb_handle_release(sb_handle* h) {
    h->held = false;
    memset(h->force, 0, sizeof h->force);
    if (h->solver) sb_handles_pin(h->solver);
}

bool sb_handle_held(const sb_handle* h) { return h->held; }
void sb_handle_force(const sb_handle* h, double force[3]) { memcpy(force, h->force, sizeof h->force); }
const char* sb_handle_name(const sb_handle* h) { return h->name; }
uint32_t sb_handle_vertex_count(const sb_handle* h) { return h->count; }

void sb_handle_target(const sb_handle* h, uint32_t k, double target[3]) {
    sb_pose_apply(h->pose1, h->grab + 3 * (size_t)(k < h->count ? k : 0), target);
}

void sb_handle_set_pose(sb_handle* h, const double translate[3], const double rotate[3]) {
    memcpy(h->driven_to[0], translate, sizeof h->driven_to[0]);
    memcpy(h->driven_to[1], rotate, sizeof h->driven_to[1]);
    h->driven = true;
}

/* Vertex k's target at t1 and its velocity over the step. */
static void sb_handle_motion(const sb_handle* h, uint32_t k, double target[3], double velocity[3]) {
    double before[3];
    sb_pose_apply(h->pose1, h->grab + 3 * (size_t)k, target);
    sb_pose_apply(h->pose0, h->grab + 3 * (size_t)k, before);
    for (int c = 0; c < 3; c++) velocity[c] = h->dt > 0.0 ? (target[c] - before[c]) / h->dt : 0.0;
}

/* ---- the solver's side -------------------------------------------------- */

static sb_status sb_handle_attach(sb_solver* s, sb_handle* h, sb_error* err) {
    const sb_model* m = s->model;
    for (uint32_t j = 0; j < h->count; j++)
        if (h->vertices[j] >= m->vertex_count)
            return sb_error_set(err, SB_ERR_INVALID,
                                "handle '%s': vertex %u (entry %u) is not in the model (%u vertices)", h->name,
                                h->vertices[j], j, m->vertex_count);
    if (!h->has_center) {
        double sum[3] = {0, 0, 0};
        for (uint32_t j = 0; j < h->count; j++) {
            uint32_t i = h->vertices[j];
            sum[0] += m->rest_x[i], sum[1] += m->rest_y[i], sum[2] += m->rest_z[i];
        }
        for (int c = 0; c < 3; c++) h->center[c] = sum[c] / h->count;
    }
    h->solver = s;
    h->dt = 0.0;
    memset(h->force, 0, sizeof h->force);
    sb_path_pose(h->path, h->path_count, h->interpolation, h->center, 0.0, h->pose1);
    memcpy(h->pose0, h->pose1, sizeof h->pose0);
    /* the solver starts at the rest shape: grab it there */
    for (uint32_t j = 0; j < h->count; j++) {
        uint32_t i = h->vertices[j];
        double p[3] = {m->rest_x[i], m->rest_y[i], m->rest_z[i]};
        sb_pose_invert_point(h->pose1, p, h->grab + 3 * (size_t)j);
    }
    h->held = true;
    return SB_OK;
}

static void sb_handles_subscribe(sb_solver* s, bool soft);

sb_status sb_handles_prepare(sb_solver* s, sb_error* err) {
    if (s->def.handle_count == 0) return SB_OK;
    bool soft = false; /* a soft one among them: its forces join the external ones */
    if (!s->def.handles)
        return sb_error_set(err, SB_ERR_INVALID, "handle_count is %u but handles is NULL", s->def.handle_count);
    for (uint32_t k = 0; k < s->def.handle_count; k++) {
        sb_status st = sb_handle_attach(s, s->def.handles[k], err);
        if (st != SB_OK) return st;
        soft |= sb_handle_soft(s->def.handles[k]);
    }
    s->pinned_inv_mass = malloc(((size_t)s->model->vertex_count + 1) * sizeof *s->pinned_inv_mass);
    if (!s->pinned_inv_mass) return sb_error_set(err, SB_ERR_NOMEM, "out of memory for the handles");
    memcpy(s->pinned_inv_mass, s->model->inv_mass, s->model->vertex_count * sizeof *s->pinned_inv_mass);
    sb_handles_pin(s);
    sb_handles_subscribe(s, soft);
    return SB_OK;
}

void sb_handles_destroy(sb_solver* s) {
    for (uint32_t k = 0; k < s->def.handle_count && s->def.handles; k++)
        if (s->def.handles[k] && s->def.handles[k]->solver == s) s->def.handles[k]->solver = NULL;
    free(s->pinned_inv_mass);
}

static void sb_handles_begin_step(sb_solver* s, double t0, double dt) {
    for (uint32_t k = 0; k < s->def.handle_count; k++) {
        sb_handle* h = s->def.handles[k];
        if (h->driven) { /* from where the last step left it to where the program put it */
            memcpy(h->pose0, h->pose1, sizeof h->pose0);
            sb_pose_from(h->driven_to[0], h->driven_to[1], h->center, h->pose1);
        } else {
            sb_path_pose(h->path, h->path_count, h->interpolation, h->center, t0, h->pose0);
            sb_path_pose(h->path, h->path_count, h->interpolation, h->center, t0 + dt, h->pose1);
        }
        h->dt = dt;
    }
}

static void sb_handles_end_advance(sb_solver* s) {
    for (uint32_t k = 0; k < s->def.handle_count; k++) {
        sb_handle* h = s->def.handles[k];
        if (!(s->time >= h->release_time)) continue;
        h->release_time = INFINITY; /* once */
        if (h->held) sb_handle_release(h);
    }
}

/* Calls place(s, vertex, target, velocity) for every vertex a hard handle
 * holds, handles and vertices in order. */
typedef void (*sb_place_fn)(sb_solver* s, uint32_t i, const double target[3], const double velocity[3], void* extra);

static bool sb_handles_each_held_hard(sb_solver* s, sb_place_fn place, void* extra) {
    bool any = false;
    for (uint32_t k = 0; k < s->def.handle_count; k++) {
        const sb_handle* h = s->def.handles[k];
        if (sb_handle_soft(h) || !h->held) continue;
        for (uint32_t j = 0; j < h->count; j++) {
            if (s->model->fixed[h->vertices[j]]) continue;
            double target[3], velocity[3];
            sb_handle_motion(h, j, target, velocity);
            place(s, h->vertices[j], target, velocity, extra);
            any = true;
        }
    }
    return any;
}

static void sb_place_packed(sb_solver* s, uint32_t i, const double target[3], const double velocity[3], void* extra) {
    double dt = *(const double*)extra;
    for (int c = 0; c < 3; c++) {
        size_t q = 4 * (size_t)i + c;
        s->positions4[q] = (sb_real)target[c];
        s->velocities4[q] = (sb_real)velocity[c];
        s->displacements4[q] = (sb_real)(velocity[c] * dt);
    }
}

static void sb_handles_place_packed(sb_solver* s, double dt) { sb_handles_each_held_hard(s, sb_place_packed, &dt); }

static void sb_place_state(sb_solver* s, uint32_t i, const double target[3], const double velocity[3], void* extra) {
    double dt = *(const double*)extra;
    sb_state* st = &s->state;
    sb_real* x[3] = {st->x, st->y, st->z};
    sb_real* v[3] = {st->vx, st->vy, st->vz};
    sb_real* d[3] = {s->disp_x, s->disp_y, s->disp_z}; /* the Störmer form's displacement */
    for (int c = 0; c < 3; c++) {
        x[c][i] = (sb_real)target[c];
        v[c][i] = (sb_real)velocity[c];
        d[c][i] = (sb_real)(velocity[c] * dt);
    }
}

static bool sb_handles_place_state(sb_solver* s, double dt) {
    return sb_handles_each_held_hard(s, sb_place_state, &dt);
}

static void sb_place_predicted(sb_solver* s, uint32_t i, const double target[3], const double velocity[3],
                               void* extra) {
    (void)s, (void)velocity;
    memcpy((double*)extra + 3 * (size_t)i, target, 3 * sizeof(double));
}

void sb_handles_place_predicted(sb_solver* s, double* x) { sb_handles_each_held_hard(s, sb_place_predicted, x); }

/* The work of the hard handles over the sub-step just taken, for the
 * adaptive stepper's energy balance: what each held vertex's motion did to
 * the body, −½ (f⁰ + f¹)·(x¹ − x⁰) with f the internal force on it (the
 * total less gravity and drag), plus the change of its own kinetic energy
 * and, where the step's energies count it (not the fused step: a pinned
 * vertex is fixed there), of its energy in gravity. */
double sb_handles_work(sb_solver* s, const sb_real* before) {
    if (!s->def.handle_count) return 0.0;
    sb_fast_publish(s);
    size_t n = s->model->vertex_count;
    const sb_state* st = &s->state;
    const sb_real* after[9] = {st->x, st->y, st->z, st->vx, st->vy, st->vz, st->fx, st->fy, st->fz};
    const double *g = s->def.gravity, drag = s->def.drag;
    bool gravity_counted = !sb_fused(s);
    double work = 0.0;
    for (uint32_t k = 0; k < s->def.handle_count; k++) {
        const sb_handle* h = s->def.handles[k];
        if (sb_handle_soft(h) || !h->held) continue;
        for (uint32_t j = 0; j < h->count; j++) {
            size_t i = h->vertices[j];
            double m = s->model->mass[i];
            if (s->model->fixed[i]) continue;
            for (int c = 0; c < 3; c++) {
                double x0 = before[c * n + i], v0 = before[(3 + c) * n + i], f0 = before[(6 + c) * n + i];
                double x1 = after[c][i], v1 = after[3 + c][i], f1 = after[6 + c][i];
                double internal0 = f0 - m * g[c] + drag * m * v0, internal1 = f1 - m * g[c] + drag * m * v1;
                double d = x1 - x0;
                work += -0.5 * (internal0 + internal1) * d + 0.5 * m * (v1 * v1 - v0 * v0);
                if (gravity_counted) work -= m * g[c] * d;
            }
        }
    }
    return work;
}

/* ---- the saved state (kernels/solver/solver_state.c) ----------------------------- */

/* A handle's fields that change as it runs, as doubles. */
static int sb_handle_moving(sb_handle* h, double* fields[], size_t counts[]) {
    double* list[] = {&h->release_time, (double*)h->driven_to, h->pose0, h->pose1, &h->dt, h->force, h->grab};
    size_t sizes[] = {1, 6, 12, 12, 1, 3, 3 * (size_t)h->count};
    int n = (int)(sizeof sizes / sizeof *sizes);
    for (int k = 0; k < n; k++) fields[k] = list[k], counts[k] = sizes[k];
    return n;
}

void sb_handles_save(const sb_solver* s, sb_sections_writer* w) {
    for (uint32_t k = 0; k < s->def.handle_count; k++) {
        sb_handle* h = s->def.handles[k];
        uint8_t flags[2] = {h->held, h->driven};
        sb_sections_put(w, flags, sizeof flags);
        double* fields[8];
        size_t counts[8];
        for (int f = 0, n = sb_handle_moving(h, fields, counts); f < n; f++)
            sb_sections_put(w, fields[f], counts[f] * sizeof(double));
    }
}

void sb_handles_load(sb_solver* s, sb_cursor* r) {
    for (uint32_t k = 0; k < s->def.handle_count; k++) {
        sb_handle* h = s->def.handles[k];
        uint8_t flags[2] = {0, 0};
        sb_cursor_take(r, flags, sizeof flags);
        h->held = flags[0] != 0;
        h->driven = flags[1] != 0;
        double* fields[8];
        size_t counts[8];
        for (int f = 0, n = sb_handle_moving(h, fields, counts); f < n; f++)
            sb_cursor_take(r, fields[f], counts[f] * sizeof(double));
    }
    if (s->def.handle_count) sb_handles_pin(s);
}

/* Where the soft handles' forces read positions and velocities and add
 * forces: 3n interleaved doubles, or (x NULL) the packed working state. */
typedef struct sb_force_view {
    const double *x, *v;
    double* f;
} sb_force_view;

static void sb_view_read(const sb_solver* s, const sb_force_view* view, uint32_t i, double x[3], double v[3]) {
    for (int c = 0; c < 3; c++) {
        x[c] = view->x ? view->x[3 * (size_t)i + c] : s->positions4[4 * (size_t)i + c];
        v[c] = view->x ? view->v[3 * (size_t)i + c] : s->velocities4[4 * (size_t)i + c];
    }
}

static void sb_view_add(sb_solver* s, const sb_force_view* view, uint32_t i, const double force[3]) {
    for (int c = 0; c < 3; c++)
        if (view->x)
            view->f[3 * (size_t)i + c] += force[c];
        else
            s->forces4[4 * (size_t)i + c] = (sb_real)(s->forces4[4 * (size_t)i + c] + force[c]);
}

/* Without a callback the kept external forces of the handles' vertices are
 * theirs alone: they start at 0. */
static void sb_clear_external(sb_solver* s, double* external) {
    if (!external || s->def.external_force) return;
    for (uint32_t k = 0; k < s->def.handle_count; k++)
        for (uint32_t j = 0; j < s->def.handles[k]->count; j++)
            memset(external + 3 * (size_t)s->def.handles[k]->vertices[j], 0, 3 * sizeof *external);
}

static void sb_soft_forces(sb_solver* s, const sb_force_view* view, double* external, bool record) {
    sb_clear_external(s, external);
    for (uint32_t k = 0; k < s->def.handle_count; k++) {
        sb_handle* h = s->def.handles[k];
        if (!sb_handle_soft(h) || !h->held) continue;
        double total[3] = {0, 0, 0};
        for (uint32_t j = 0; j < h->count; j++) {
            uint32_t i = h->vertices[j];
            if (s->model->fixed[i]) continue;
            double target[3], velocity[3], x[3], v[3], spring[3];
            sb_handle_motion(h, j, target, velocity);
            sb_view_read(s, view, i, x, v);
            for (int c = 0; c < 3; c++) {
                spring[c] = h->stiffness * (target[c] - x[c]) + h->damping * (velocity[c] - v[c]);
                if (external) external[3 * (size_t)i + c] += spring[c];
                total[c] += spring[c];
            }
            sb_view_add(s, view, i, spring);
        }
        if (record) memcpy(h->force, total, sizeof total);
    }
}

static void sb_handles_forces(sb_solver* s, const double* x, const double* v, double* f, double* external) {
    sb_force_view view = {x, v, f};
    sb_soft_forces(s, &view, external, external != NULL);
}

static void sb_handles_forces_packed(sb_solver* s) {
    sb_force_view view = {NULL, NULL, NULL};
    sb_soft_forces(s, &view, s->external, true);
}

/* The correct stage: the vertices the hard handles hold at their targets
 * in the state's arrays (pbd, xpbd: current first); whether one moved. */
static bool sb_handles_correct(sb_solver* s, double dt) {
    sb_fast_publish(s);
    return sb_handles_place_state(s, dt);
}

static void sb_handles_subscribe(sb_solver* s, bool soft) {
    sb_add_feature(s, (sb_feature){.name = "handles",
                                   .begin = sb_handles_begin_step,
                                   .correct = sb_handles_correct,
                                   .end = sb_handles_end_advance});
    s->hooks.place_packed = sb_handles_place_packed;
    if (!soft) return;
    s->hooks.post_force = sb_handles_forces;
    s->hooks.post_force_packed = sb_handles_forces_packed;
}
