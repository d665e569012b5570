/* The solver: owns a state of a model and advances it one step at a time
 * with the chosen integrator, checking after every step that the state is
 * still finite and bounded. */
#include "kernels/state/solver_internal.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/contact/self_contact.h"
#include "kernels/interaction/handle_internal.h"
#include "kernels/interaction/breakage.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A vertex further than this many model diameters from its rest position
 * has run away: no stable simulation of a soft body goes there. */
#define SB_RUNAWAY_DIAMETERS 1e6

static const char* const sb_integrator_names[SB_INTEGRATOR_COUNT] = {"verlet",
                                                                     "velocity_verlet",
                                                                     "explicit_euler",
                                                                     "symplectic_euler",
                                                                     "position_verlet",
                                                                     "implicit_euler",
                                                                     "pbd",
                                                                     "xpbd",
                                                                     "vbd"};

const char* sb_integrator_name(sb_integrator integrator) {
    return (unsigned)integrator < SB_INTEGRATOR_COUNT ? sb_integrator_names[integrator] : "unknown";
}

bool sb_integrator_from_name(const char* name, sb_integrator* out) {
    for (int i = 0; i < SB_INTEGRATOR_COUNT; i++)
        if (strcmp(name, sb_integrator_names[i]) == 0) {
            *out = (sb_integrator)i;
            return true;
        }
    return false;
}

bool sb_linear_solver_from_name(const char* name, sb_linear_solver* out) {
    static const char* const names[SB_LINEAR_COUNT] = {"auto", "cg", "cholesky"};
    for (int i = 0; i < SB_LINEAR_COUNT; i++)
        if (strcmp(name, names[i]) == 0) {
            *out = (sb_linear_solver)i;
            return true;
        }
    return false;
}

sb_solver_def sb_default_solver_def(void) {
    return (sb_solver_def){.integrator = SB_INTEGRATOR_VERLET,
                           .kernels = SB_KERNELS_FAST,
                           .gravity = {0.0, 0.0, -9.81},
                           .implicit_tolerance = 1e-8,
                           .implicit_newton_iterations = 20,
                           .implicit_cg_iterations = 200,
                           .pbd_iterations = 10,
                           .vbd_iterations = 10,
                           .runtime = sb_default_runtime_def(),
                           .min_dt = 1e-9};
}

static bool sb_solver_allocate(sb_solver* s, uint32_t n) {
    sb_real** arrays[] = {&s->state.x,  &s->state.y,  &s->state.z,  &s->state.vx, &s->state.vy, &s->state.vz,
                          &s->state.fx, &s->state.fy, &s->state.fz, &s->disp_x,   &s->disp_y,   &s->disp_z};
    bool ok = true;
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++) ok &= (*arrays[a] = calloc(n, sizeof(sb_real))) != NULL;
    double** scratch[] = {&s->scratch_x, &s->scratch_v, &s->scratch_f};
    for (size_t a = 0; a < 3; a++) ok &= (*scratch[a] = calloc(3 * (size_t)n, sizeof(double))) != NULL;
    s->state.vertex_count = n;
    return ok;
}

void sb_solver_destroy(sb_solver* s) {
    if (!s) return;
    sb_contact_destroy(s);
    sb_handles_destroy(s);
    sb_self_contact_destroy(s->self);
    sb_team_destroy(s->team);
    sb_fast_model_destroy(s->fast);
    sb_breakage_destroy(s->breakage);
    free(s->partials);
    free(s->positions4);
    free(s->velocities4);
    free(s->displacements4);
    free(s->forces4);
    free(s->external);
    sb_implicit_destroy(s);
    sb_vbd_destroy(s->vbd);
    free(s->stretch4);
    sb_pbd_destroy(s->pbd);
    sb_backup_destroy(s->backup);
    void* arrays[] = {s->state.x,  s->state.y,  s->state.z,   s->state.vx,  s->state.vy,
                      s->state.vz, s->state.fx, s->state.fy,  s->state.fz,  s->disp_x,
                      s->disp_y,   s->disp_z,   s->scratch_x, s->scratch_v, s->scratch_f};
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++) free(arrays[a]);
    free(s);
}

/* The box around the rest shape, grown by SB_RUNAWAY_DIAMETERS diameters. */
static void sb_runaway_box(sb_solver* s) {
    const sb_model* m = s->model;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        double p[3] = {m->rest_x[i], m->rest_y[i], m->rest_z[i]};
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], p[c]);
            hi[c] = fmax(hi[c], p[c]);
        }
    }
    double d2 = 0.0;
    for (int c = 0; c < 3; c++) {
        s->center[c] = 0.5 * (lo[c] + hi[c]);
        d2 += (hi[c] - lo[c]) * (hi[c] - lo[c]);
    }
    s->runaway = SB_RUNAWAY_DIAMETERS * (sqrt(d2) > 0.0 ? sqrt(d2) : 1.0);
}

static sb_status sb_check_def(const sb_solver_def* def, sb_error* err) {
    if ((unsigned)def->integrator >= SB_INTEGRATOR_COUNT)
        return sb_error_set(err, SB_ERR_INVALID, "unknown integrator %d", (int)def->integrator);
    for (int c = 0; c < 3; c++)
        if (!isfinite(def->gravity[c])) return sb_error_set(err, SB_ERR_INVALID, "gravity must be finite");
    if (!isfinite(def->drag) || def->drag < 0.0)
        return sb_error_set(err, SB_ERR_INVALID, "drag must be finite and >= 0 (got %g)", def->drag);
    if (!isfinite(def->implicit_tolerance) || def->implicit_tolerance < 0.0 || def->implicit_newton_iterations < 0 ||
        def->implicit_cg_iterations < 0)
        return sb_error_set(err, SB_ERR_INVALID, "implicit tolerance and iteration caps must be >= 0");
    if ((unsigned)def->implicit_solver >= SB_LINEAR_COUNT)
        return sb_error_set(err, SB_ERR_INVALID, "implicit_solver must be SB_LINEAR_AUTO, _CG or _CHOLESKY, got %d",
                            (int)def->implicit_solver);
    if (def->pbd_iterations < 0)
        return sb_error_set(err, SB_ERR_INVALID, "pbd_iterations must be >= 0 (got %d)", def->pbd_iterations);
    if (def->vbd_iterations < 0)
        return sb_error_set(err, SB_ERR_INVALID, "vbd_iterations must be >= 0 (got %d)", def->vbd_iterations);
    if (!(def->vbd_chebyshev_rho >= 0.0 && def->vbd_chebyshev_rho < 1.0))
        return sb_error_set(err, SB_ERR_INVALID, "vbd_chebyshev_rho must be in [0, 1) (got %g)",
                            def->vbd_chebyshev_rho);
    if (!(def->vbd_relaxation >= 0.0 && def->vbd_relaxation < 2.0))
        return sb_error_set(err, SB_ERR_INVALID, "vbd_relaxation must be in [0, 2) (got %g; 0 = 1)",
                            def->vbd_relaxation);
    if (def->adaptive && !(def->min_dt > 0.0 && isfinite(def->min_dt)))
        return sb_error_set(err, SB_ERR_INVALID, "min_dt must be positive and finite (got %g)", def->min_dt);
    if (!isfinite(def->adaptive_tolerance) || def->adaptive_tolerance < 0.0)
        return sb_error_set(err, SB_ERR_INVALID, "adaptive_tolerance must be finite and >= 0 (got %g)",
                            def->adaptive_tolerance);
    if (!isfinite(def->contact_thickness) || def->contact_thickness < 0.0)
        return sb_error_set(err, SB_ERR_INVALID, "contact_thickness must be finite and >= 0 (got %g)",
                            def->contact_thickness);
    if (def->runtime.threads < 0 || def->runtime.threads > SB_MAX_THREADS)
        return sb_error_set(err, SB_ERR_INVALID, "threads must be from 0 to %d (got %d)", SB_MAX_THREADS,
                            def->runtime.threads);
    if ((unsigned)def->runtime.wait >= SB_WAIT_COUNT)
        return sb_error_set(err, SB_ERR_INVALID, "unknown wait policy %d", (int)def->runtime.wait);
    if (def->kernels != SB_KERNELS_REFERENCE && def->kernels != SB_KERNELS_FAST)
        return sb_error_set(err, SB_ERR_INVALID, "unknown kernels %d", (int)def->kernels);
    if (def->max_splits_per_step < 0)
        return sb_error_set(err, SB_ERR_INVALID, "max_splits_per_step must be >= 0 (got %d)",
                            (int)def->max_splits_per_step);
    return SB_OK;
}

/* The buffers the chosen integrator and the options need, so that a step
 * never allocates. */
static sb_status sb_prepare_step_buffers(sb_solver* s, sb_error* err) {
    const sb_model* m = s->model;
    bool ok = true;
    if (s->def.external_force || s->soft_handles)
        ok &= (s->external = calloc(3 * (size_t)m->vertex_count + 1, sizeof(double))) != NULL;
    if (!s->fast) ok &= (s->stretch4 = malloc((4 * (size_t)m->vertex_count + 1) * sizeof(sb_real))) != NULL;
    if (s->def.integrator == SB_INTEGRATOR_IMPLICIT_EULER) ok &= sb_implicit_prepare(s);
    if (s->def.integrator == SB_INTEGRATOR_VBD) ok &= sb_vbd_prepare(s);
    if (ok && (s->def.integrator == SB_INTEGRATOR_PBD || s->def.integrator == SB_INTEGRATOR_XPBD) &&
        sb_pbd_prepare(s) != SB_OK) {
        if (err) *err = s->error;
        return SB_ERR_NOMEM;
    }
    if (ok && s->def.adaptive) ok &= (s->backup = sb_backup_create(s)) != NULL;
    if (!ok) return sb_error_set(err, SB_ERR_NOMEM, "out of memory creating a solver for %u vertices", m->vertex_count);
    return SB_OK;
}

sb_solver* sb_solver_create(const sb_model* model, const sb_solver_def* def, sb_error* err) {
    if (sb_check_def(def, err) != SB_OK) return NULL;
    sb_solver* s = calloc(1, sizeof *s);
    if (s && sb_breakage_create(model, def, &s->breakage, err) != SB_OK) {
        free(s);
        return NULL;
    }
    if (s) s->model = s->breakage ? sb_breakage_model(s->breakage) : model; /* with tearing's spare vertices */
    if (!s || !sb_solver_allocate(s, s->model->vertex_count)) {
        sb_solver_destroy(s);
        sb_error_set(err, SB_ERR_NOMEM, "out of memory creating a solver for %u vertices", model->vertex_count);
        return NULL;
    }
    s->given_model = model;
    s->def = *def;
    sb_runaway_box(s);
    sb_status status = (s->team = sb_team_create(&def->runtime, err)) ? SB_OK : SB_ERR_INVALID;
    if (status == SB_OK && def->self_collision && sb_breakage_topology(s->breakage))
        status = sb_error_set(err, SB_ERR_INVALID,
                              "self_collision with a model that tears is not supported yet (set max_splits < 0 to "
                              "keep its surface whole)");
    if (status == SB_OK && def->kernels == SB_KERNELS_FAST) status = sb_fast_prepare(s, err);
    if (status == SB_OK) status = sb_contact_prepare(s, err);
    if (status == SB_OK && def->self_collision) status = sb_self_contact_prepare(s, err);
    if (status == SB_OK) status = sb_handles_prepare(s, err);
    if (status == SB_OK) status = sb_prepare_step_buffers(s, err);
    if (status != SB_OK) {
        sb_solver_destroy(s);
        return NULL;
    }
    status = sb_solver_set_state(s, NULL, NULL);
    if (status != SB_OK) {
        if (err) *err = s->error;
        sb_solver_destroy(s);
        return NULL;
    }
    return s;
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

/* Puts "step N (t = T s): " in front of the solver's message. */
static void sb_prefix_step(sb_solver* s) {
    sb_error original = s->error;
    sb_error_set(&s->error, SB_OK, "step %llu (t = %.9g s): %s", (unsigned long long)s->steps, s->time,
                 original.message);
}

static sb_status sb_integrate(sb_solver* s, double dt) {
    switch (s->def.integrator) {
    case SB_INTEGRATOR_VERLET:
    case SB_INTEGRATOR_VELOCITY_VERLET:
        if (s->fast) return sb_fast_verlet_step(s, dt); /* the fused step */
        return s->def.integrator == SB_INTEGRATOR_VERLET ? sb_integrate_verlet(s, dt)
                                                         : sb_integrate_velocity_verlet(s, dt);
    case SB_INTEGRATOR_EXPLICIT_EULER: return sb_integrate_explicit_euler(s, dt);
    case SB_INTEGRATOR_SYMPLECTIC_EULER: return sb_integrate_symplectic_euler(s, dt);
    case SB_INTEGRATOR_POSITION_VERLET: return sb_integrate_position_verlet(s, dt);
    case SB_INTEGRATOR_IMPLICIT_EULER: return sb_integrate_implicit_euler(s, dt);
    case SB_INTEGRATOR_PBD:
    case SB_INTEGRATOR_XPBD: return sb_integrate_pbd(s, dt);
    case SB_INTEGRATOR_VBD: return sb_integrate_vbd(s, dt);
    default: return sb_error_set(&s->error, SB_ERR_INVALID, "unknown integrator %d", (int)s->def.integrator);
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

/* Whether any of `count` edges (a[e], b[e]) with rest length r0[e] is longer
 * than SB_STRETCH_LIMIT r0: a branch-free pass (in sb_real) that vectorizes. */
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
static sb_status sb_check_stretch(sb_solver* s) {
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

static void sb_count_self_contacts(sb_solver* s) {
    s->stats.self_contacts += sb_self_contact_count(s->self);
    s->stats.self_dropped += sb_self_contact_dropped(s->self);
}

/* The contact pass of a step the fused path did not take: the state's
 * arrays corrected, and the forces evaluated again where a vertex moved. */
static sb_status sb_contact_after_step(sb_solver* s, double dt) {
    uint32_t contacts = sb_contact_state_pass(s, dt);
    s->stats.contacts += contacts;
    return contacts > 0 ? sb_solver_compute_forces(s) : SB_OK;
}

/* The hard handles' placement after a step the fused path did not take,
 * after the contact passes; forces again where a vertex was placed. */
static sb_status sb_handles_after_step(sb_solver* s, double dt) {
    sb_fast_publish(s); /* pbd, xpbd: the state's arrays current */
    return sb_handles_place_state(s, dt) ? sb_solver_compute_forces(s) : SB_OK;
}

/* The self-contact pass of a step the fused path did not take, after the
 * collider pass; forces again where a vertex moved. */
static sb_status sb_self_contact_after_step(sb_solver* s, double dt) {
    uint32_t contacts = sb_self_contact_state_pass(s, dt);
    sb_count_self_contacts(s);
    return contacts > 0 ? sb_solver_compute_forces(s) : SB_OK;
}

/* Whether a step is followed by the collider pass: pbd and xpbd project
 * the colliders inside their sweeps (kernels/contact/contact_pbd.c). */
static bool sb_contact_after(const sb_solver* s) { return s->def.collider_count > 0 && !s->pbd; }

bool sb_step_needs_forces(const sb_solver* s) {
    return s->def.adaptive || s->def.external_force || s->soft_handles || s->self || s->def.handle_count > 0 ||
           sb_contact_after(s);
}

sb_status sb_solver_step(sb_solver* s, double dt) {
    bool contact = s->def.collider_count > 0;
    bool after = sb_contact_after(s);
    if (contact) sb_contact_begin_step(s, s->time, s->time + dt);
    sb_handles_begin_step(s, s->time, dt);
    if (after && !sb_fused(s)) sb_contact_save_from(s);
    if (s->self && !sb_fused(s)) sb_self_contact_save_state(s);
    s->contact_dt = dt;
    s->time += dt; /* forces of this step are evaluated at the new time */
    sb_status status = sb_integrate(s, dt);
    /* A non-finite state also makes the force terms fail: name the cause. */
    if (sb_fused(s)) { /* the fused step checked the state and summed the energies itself */
        if (contact) s->stats.contacts += sb_contact_collect(s);
        sb_count_self_contacts(s);
        if (status == SB_ERR_DEGENERATE) sb_prefix_step(s);
        return status == SB_OK ? sb_check_stretch(s) : status;
    }
    if (s->forces_stale) /* the step checked the state; nothing below runs (sb_step_needs_forces); the energies wait */
        return status == SB_OK ? sb_check_stretch(s) : status;
    if (status == SB_OK && after) status = sb_contact_after_step(s, dt);
    if (status == SB_OK && s->self) status = sb_self_contact_after_step(s, dt);
    if (status == SB_OK && s->def.handle_count) status = sb_handles_after_step(s, dt);
    /* The generic integrators leave the state's arrays current (the fast
     * force evaluation packs them at its start and publishes at its end). */
    sb_status state_status = sb_check_state(s);
    if (state_status != SB_OK) return state_status;
    if (status != SB_OK) {
        sb_prefix_step(s);
        return status;
    }
    sb_update_energies(s);
    return sb_check_stretch(s);
}

sb_status sb_solver_advance(sb_solver* s, double dt) {
    if (!(dt > 0.0) || !isfinite(dt))
        return sb_error_set(&s->error, SB_ERR_INVALID, "time step %g s must be positive and finite", dt);
    s->steps++;
    s->stats = (sb_step_stats){.converged = true};
    s->advance_dt = dt;
    if (s->contact_impulse) memset(s->contact_impulse, 0, 3 * (size_t)s->def.collider_count * sizeof(double));
    sb_status status = s->def.adaptive ? sb_adaptive_advance(s, dt) : sb_solver_step(s, dt);
    if (status == SB_OK && !s->def.adaptive) status = sb_breakage_after_step(s);
    if (status == SB_OK && !s->def.adaptive) {
        if (s->contact_impulse) {
            sb_contact_accept(s);
            sb_colliders_after_step(s->def.colliders, s->def.collider_count, s->contact_step, s->def.gravity, dt);
        }
        s->stats.substeps = 1;
        s->stats.last_substep = s->stats.min_substep = dt;
    }
    if (status == SB_OK) sb_handles_end_advance(s);
    return status;
}

sb_step_stats sb_solver_last_step(const sb_solver* s) { return s->stats; }

void sb_solver_last_iterations(const sb_solver* s, int* newton, int* cg) {
    if (newton) *newton = s->stats.newton_iterations;
    if (cg) *cg = s->stats.cg_iterations;
}

sb_status sb_solver_set_state(sb_solver* s, const double* positions, const double* velocities) {
    const sb_model* m = s->model;
    sb_state* st = &s->state;
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        bool keep_rest = !positions || m->fixed[i];
        st->x[i] = (sb_real)(keep_rest ? m->rest_x[i] : positions[3 * i]);
        st->y[i] = (sb_real)(keep_rest ? m->rest_y[i] : positions[3 * i + 1]);
        st->z[i] = (sb_real)(keep_rest ? m->rest_z[i] : positions[3 * i + 2]);
        bool initial = !positions && !velocities;
        const double* v = velocities && !m->fixed[i] ? velocities + 3 * i : NULL; /* a spare slot is fixed */
        st->vx[i] = m->fixed[i] ? 0 : (sb_real)(initial ? m->vel_x[i] : v ? v[0] : 0.0);
        st->vy[i] = m->fixed[i] ? 0 : (sb_real)(initial ? m->vel_y[i] : v ? v[1] : 0.0);
        st->vz[i] = m->fixed[i] ? 0 : (sb_real)(initial ? m->vel_z[i] : v ? v[2] : 0.0);
    }
    s->has_displacement = s->forces_stale = false;
    s->trial_substep = s->energy_peak = 0.0;
    sb_status status = sb_check_state(s);
    if (status == SB_OK) status = sb_solver_compute_forces(s);
    if (status == SB_OK) sb_update_energies(s);
    return status;
}

/* Forces are linear in gravity: m (g' − g) is added to each vertex's total
 * force wherever it is kept (the fast path's packed forces, the
 * state's arrays), as if evaluated with g' at the current state. */
sb_status sb_solver_set_gravity(sb_solver* s, const double gravity[3]) {
    for (int c = 0; c < 3; c++)
        if (!isfinite(gravity[c])) return sb_error_set(&s->error, SB_ERR_INVALID, "gravity must be finite");
    if (sb_fused(s)) sb_solver_settle(s); /* the last step's gravitational energy, in its gravity */
    const sb_model* m = s->model;
    double change[3];
    for (int c = 0; c < 3; c++) change[c] = gravity[c] - s->def.gravity[c];
    sb_real* soa[3] = {s->state.fx, s->state.fy, s->state.fz};
    for (uint32_t i = 0; i < m->vertex_count; i++)
        for (int c = 0; c < 3; c++) {
            soa[c][i] = (sb_real)(soa[c][i] + m->mass[i] * change[c]);
            if (!s->fast) continue;
            size_t k = 4 * (size_t)i + c;
            s->forces4[k] = (sb_real)(s->forces4[k] + m->mass[i] * change[c]);
        }
    memcpy(s->def.gravity, gravity, sizeof s->def.gravity);
    return SB_OK;
}

const char* sb_solver_error(const sb_solver* s) { return s->error.message; }
double sb_solver_time(const sb_solver* s) { return s->time; }
uint64_t sb_solver_step_count(const sb_solver* s) { return s->steps; }
const sb_model* sb_solver_model(const sb_solver* s) { return s->given_model; }
uint32_t sb_solver_broken_count(const sb_solver* s) { return sb_breakage_count(s->breakage); }
bool sb_solver_bond_broken(const sb_solver* s, uint32_t bond) { return sb_breakage_broken(s->breakage, bond); }

uint32_t sb_solver_vertex_count(const sb_solver* s) {
    const sb_topology* t = sb_breakage_topology(s->breakage);
    return t ? sb_topology_vertex_count(t) : s->model->vertex_count;
}

uint32_t sb_solver_vertex_capacity(const sb_solver* s) { return s->model->vertex_count; }

uint32_t sb_solver_vertex_origin(const sb_solver* s, uint32_t vertex) {
    const sb_topology* t = sb_breakage_topology(s->breakage);
    if (vertex >= sb_solver_vertex_count(s)) return UINT32_MAX;
    return t ? sb_topology_origin(t, vertex) : vertex;
}

void sb_solver_triangle(const sb_solver* s, uint32_t triangle, uint32_t vertices[3]) {
    for (int c = 0; c < 3; c++) vertices[c] = triangle < s->model->triangle_count ? s->model->tri_v[c][triangle] : 0;
}

bool sb_solver_triangle_alive(const sb_solver* s, uint32_t triangle) {
    return triangle < s->model->triangle_count && !sb_breakage_triangle_dead(s->breakage, triangle);
}

void sb_solver_bond(const sb_solver* s, uint32_t bond, uint32_t ends[2]) {
    bool in = bond < s->model->bond_count;
    ends[0] = in ? s->model->bond_i[bond] : 0;
    ends[1] = in ? s->model->bond_j[bond] : 0;
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

/* The getters of forces and energies settle them first: a cache of the
 * current state filled on demand, so the solver is written through a
 * const pointer (never a const object: sb_solver_create allocates it). */
sb_energies sb_solver_energies(const sb_solver* s) {
    ((sb_solver*)s)->energies_read = true; /* read after this step: likely after the next (sb_fast_verlet_step) */
    sb_solver_settle((sb_solver*)s);
    return s->energies;
}
/* Copies one quantity out as 3n interleaved doubles: from the fast path's
 * packed working state when the state's arrays are stale, from the arrays
 * otherwise. Reads only. */
static void sb_copy_out(const sb_solver* s, const sb_real* packed, const sb_real* soa[3], double* out) {
    uint32_t n = sb_solver_vertex_count(s);
    if (s->fast && !s->published)
        for (size_t k = 0; k < 3 * (size_t)n; k++) out[k] = packed[4 * (k / 3) + k % 3];
    else
        sb_interleave(out, soa[0], soa[1], soa[2], n);
}

void sb_interleave(double* out, const sb_real* a, const sb_real* b, const sb_real* c, uint32_t n) {
    for (uint32_t i = 0; i < n; i++) {
        out[3 * i] = a[i];
        out[3 * i + 1] = b[i];
        out[3 * i + 2] = c[i];
    }
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

void sb_solver_get_positions(const sb_solver* s, double* out) {
    const sb_real* soa[3] = {s->state.x, s->state.y, s->state.z};
    sb_copy_out(s, s->positions4, soa, out);
}

void sb_solver_get_velocities(const sb_solver* s, double* out) {
    const sb_real* soa[3] = {s->state.vx, s->state.vy, s->state.vz};
    sb_copy_out(s, s->velocities4, soa, out);
}

void sb_solver_get_forces(const sb_solver* s, double* out) {
    sb_solver_settle((sb_solver*)s);
    const sb_real* soa[3] = {s->state.fx, s->state.fy, s->state.fz};
    sb_copy_out(s, s->forces4, soa, out);
}

/* The copy of sb_solver_copy_state, split over the team. */
typedef struct sb_copy_job {
    const sb_solver* solver;
    sb_real *positions, *velocities;
} sb_copy_job;

static void sb_copy_worker(void* context, const sb_worker* w) {
    const sb_copy_job* job = context;
    const sb_solver* s = job->solver;
    const sb_state* st = &s->state;
    int64_t begin, end;
    sb_worker_range(w, sb_solver_vertex_count(s), &begin, &end);
    sb_real *x = job->positions, *v = job->velocities;
    if (s->fast && !s->published) {
        sb_unpack_xyz(s->positions4, x, begin, end);
        sb_unpack_xyz(s->velocities4, v, begin, end);
        return;
    }
    for (int64_t i = begin; i < end; i++) {
        x[3 * i] = st->x[i], x[3 * i + 1] = st->y[i], x[3 * i + 2] = st->z[i];
        v[3 * i] = st->vx[i], v[3 * i + 1] = st->vy[i], v[3 * i + 2] = st->vz[i];
    }
}

void sb_solver_copy_state(const sb_solver* s, sb_real* positions, sb_real* velocities) {
    sb_copy_job job = {s, positions, velocities};
    sb_team_run(s->team, sb_team_size(s->team), sb_copy_worker, &job);
}

void sb_unpack_xyz(const sb_real* packed, sb_real* out, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; i++)
        for (int c = 0; c < 3; c++) out[3 * i + c] = packed[4 * i + c];
}

sb_status sb_solver_advance_into(sb_solver* s, double dt, sb_real* positions, sb_real* velocities) {
    /* adaptive stepping may undo a sub-step: its snapshot is copied after */
    bool fused = sb_fused(s) && !s->def.adaptive;
    s->publish_positions = fused ? positions : NULL;
    s->publish_velocities = fused ? velocities : NULL;
    s->publish_written = false;
    sb_status status = sb_solver_advance(s, dt);
    if (status == SB_OK && !s->publish_written) sb_solver_copy_state(s, positions, velocities);
    s->publish_positions = s->publish_velocities = NULL;
    return status;
}
