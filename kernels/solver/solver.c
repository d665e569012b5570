/* The solver: owns a state of a model and advances it one step at a time
 * with the chosen integrator (kernels/solver/step.c), checking after every
 * step that the state is still finite and bounded. This file creates and
 * destroys it — each feature that is on subscribes to the step's stages as
 * it is prepared, in the order the stages call them: contact,
 * self-contact, handles, breakage — and answers the getters. */
#include "kernels/state/solver_data.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"
#include "kernels/solver/adaptive.h"
#include "kernels/contact/contact.h"
#include "kernels/contact/self_contact.h"
#include "kernels/interaction/handle_internal.h"
#include "kernels/interaction/breakage.h"
#include "kernels/interaction/cut_volume.h"
#include "kernels/integrators/implicit_euler.h"
#include "kernels/integrators/pbd.h"
#include "kernels/integrators/vbd.h"
#include "common/error.h"
#include "common/name_table.h"

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
    return sb_name_of(sb_integrator_names, SB_INTEGRATOR_COUNT, (int)integrator);
}

bool sb_integrator_from_name(const char* name, sb_integrator* out) {
    int i = sb_name_index(sb_integrator_names, SB_INTEGRATOR_COUNT, name);
    if (i >= 0) *out = (sb_integrator)i;
    return i >= 0;
}

bool sb_linear_solver_from_name(const char* name, sb_linear_solver* out) {
    static const char* const names[SB_LINEAR_COUNT] = {"auto", "cg", "cholesky"};
    int i = sb_name_index(names, SB_LINEAR_COUNT, name);
    if (i >= 0) *out = (sb_linear_solver)i;
    return i >= 0;
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
    sb_real** arrays[] = {&s->state.x,  &s->state.y,  &s->state.z,  &s->state.vx, &s->state.vy,
                          &s->state.vz, &s->state.fx, &s->state.fy, &s->state.fz, &s->disp_x,
                          &s->disp_y,   &s->disp_z,   &s->carry_x,  &s->carry_y,  &s->carry_z};
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
    free(s->carry4);
    free(s->external);
    sb_implicit_destroy(s);
    sb_vbd_destroy(s->vbd);
    free(s->stretch4);
    sb_pbd_destroy(s->pbd);
    sb_adaptive_destroy(s->adaptive);
    void* arrays[] = {s->state.x,  s->state.y,  s->state.z,  s->state.vx,  s->state.vy,  s->state.vz,
                      s->state.fx, s->state.fy, s->state.fz, s->disp_x,    s->disp_y,    s->disp_z,
                      s->carry_x,  s->carry_y,  s->carry_z,  s->scratch_x, s->scratch_v, s->scratch_f};
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
    if (s->def.external_force || s->hooks.post_force)
        ok &= (s->external = calloc(3 * (size_t)m->vertex_count + 1, sizeof(double))) != NULL;
    if (!s->fast) ok &= (s->stretch4 = malloc((4 * (size_t)m->vertex_count + 1) * sizeof(sb_real))) != NULL;
    if (s->def.integrator == SB_INTEGRATOR_IMPLICIT_EULER) ok &= sb_implicit_prepare(s);
    if (s->def.integrator == SB_INTEGRATOR_VBD) ok &= sb_vbd_prepare(s);
    if (ok && (s->def.integrator == SB_INTEGRATOR_PBD || s->def.integrator == SB_INTEGRATOR_XPBD) &&
        sb_pbd_prepare(s) != SB_OK) {
        if (err) *err = s->error;
        return SB_ERR_NOMEM;
    }
    if (ok && s->def.adaptive) ok &= (s->adaptive = sb_adaptive_create(s)) != NULL;
    if (!ok) return sb_error_set(err, SB_ERR_NOMEM, "out of memory creating a solver for %u vertices", m->vertex_count);
    return SB_OK;
}

/* The co-rotated tetrahedra have forces, energies, a fast pass and the
 * co-rotated stiffness (implicit Euler, vbd), but no constraints for pbd
 * and xpbd yet, and tearing's vertex splits do not know them. Refused here
 * rather than run wrong. */
static sb_status sb_check_tets(const sb_model* m, const sb_solver_def* def, sb_error* err) {
    if (!m->tet_count) return SB_OK;
    sb_integrator it = def->integrator;
    if (it == SB_INTEGRATOR_PBD || it == SB_INTEGRATOR_XPBD)
        return sb_error_set(
            err, SB_ERR_INVALID,
            "the corotated tetrahedra (tissue.model: corotated or corotated_quadratic) have no constraints yet: "
            "integrator %s cannot run them; use verlet, velocity_verlet, position_verlet, "
            "symplectic_euler, explicit_euler, implicit_euler or vbd",
            sb_integrator_name(it));
    return SB_OK;
}

/* A sheet's membranes have forces, energies, a fast pass and the
 * co-rotated stiffness (implicit Euler, vbd), but no constraints for pbd
 * and xpbd yet. Refused here rather than run wrong. */
static sb_status sb_check_membranes(const sb_model* m, const sb_solver_def* def, sb_error* err) {
    if (!m->membrane_count) return SB_OK;
    sb_integrator it = def->integrator;
    if (it == SB_INTEGRATOR_PBD || it == SB_INTEGRATOR_XPBD)
        return sb_error_set(err, SB_ERR_INVALID,
                            "the sheet's membranes (factory: membrane) have no constraints yet: "
                            "integrator %s cannot run them; use verlet, velocity_verlet, position_verlet, "
                            "symplectic_euler, explicit_euler, implicit_euler or vbd",
                            sb_integrator_name(it));
    return SB_OK;
}

sb_solver* sb_solver_create(const sb_model* model, const sb_solver_def* def, sb_error* err) {
    if (sb_check_def(def, err) != SB_OK) return NULL;
    if (sb_check_tets(model, def, err) != SB_OK || sb_check_membranes(model, def, err) != SB_OK) return NULL;
    sb_solver* s = calloc(1, sizeof *s);
    if (s && sb_breakage_create(model, def, &s->breakage, err) != SB_OK) {
        free(s);
        return NULL;
    }
    if (s) {
        s->model = s->breakage ? sb_breakage_model(s->breakage) : model; /* with tearing's spare vertices */
        const sb_topology* topology = sb_breakage_topology(s->breakage);
        s->live_vertices = topology ? sb_topology_vertex_count(topology) : model->vertex_count;
    }
    if (!s || !sb_solver_allocate(s, s->model->vertex_count)) {
        sb_solver_destroy(s);
        sb_error_set(err, SB_ERR_NOMEM, "out of memory creating a solver for %u vertices", model->vertex_count);
        return NULL;
    }
    s->given_model = model;
    s->def = *def;
    sb_runaway_box(s);
    sb_status status = (s->team = sb_team_create(&def->runtime, err)) ? SB_OK : SB_ERR_INVALID;
    if (status == SB_OK && def->kernels == SB_KERNELS_FAST) status = sb_fast_prepare(s, err);
    if (status == SB_OK) status = sb_contact_prepare(s, err);
    if (status == SB_OK && def->self_collision) status = sb_self_contact_prepare(s, err);
    if (status == SB_OK) status = sb_handles_prepare(s, err);
    if (status == SB_OK) sb_breakage_subscribe(s);
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
    sb_clear_carries(s);
    sb_adaptive_reset(s->adaptive);
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

uint32_t sb_solver_vertex_count(const sb_solver* s) { return s->live_vertices; }

uint32_t sb_solver_vertex_capacity(const sb_solver* s) { return s->model->vertex_count; }

uint32_t sb_solver_vertex_origin(const sb_solver* s, uint32_t vertex) {
    const sb_topology* t = sb_breakage_topology(s->breakage);
    if (vertex >= s->live_vertices) return UINT32_MAX;
    return t ? sb_topology_origin(t, vertex) : vertex;
}

void sb_solver_get_masses(const sb_solver* s, double* out) {
    memcpy(out, s->model->mass, s->model->vertex_count * sizeof *out);
}

uint32_t sb_solver_triangle_count(const sb_solver* s) { return s->model->triangle_count; }
uint32_t sb_solver_bond_count(const sb_solver* s) { return s->model->bond_count; }

void sb_solver_triangle(const sb_solver* s, uint32_t triangle, uint32_t vertices[3]) {
    for (int c = 0; c < 3; c++) vertices[c] = triangle < s->model->triangle_count ? s->model->tri_v[c][triangle] : 0;
}

bool sb_solver_triangle_alive(const sb_solver* s, uint32_t triangle) {
    return triangle < s->model->triangle_count && !sb_breakage_triangle_dead(s->breakage, triangle);
}

uint32_t sb_solver_face_count(const sb_solver* s) { return s->model->face_count; }

uint32_t sb_solver_face_capacity(const sb_solver* s) {
    const sb_cut_volume* cut = sb_breakage_cut_volume(s->breakage);
    return cut ? sb_cut_volume_face_capacity(cut) : s->model->face_count;
}

void sb_solver_face(const sb_solver* s, uint32_t face, uint32_t vertices[3]) {
    for (int c = 0; c < 3; c++) vertices[c] = face < s->model->face_count ? s->model->face_v[c][face] : 0;
}

void sb_solver_bond(const sb_solver* s, uint32_t bond, uint32_t ends[2]) {
    bool in = bond < s->model->bond_count;
    ends[0] = in ? s->model->bond_i[bond] : 0;
    ends[1] = in ? s->model->bond_j[bond] : 0;
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
    uint32_t n = s->live_vertices;
    if (s->fast && !s->published)
        for (size_t k = 0; k < 3 * (size_t)n; k++) out[k] = packed[4 * (k / 3) + k % 3];
    else
        sb_interleave(out, soa[0], soa[1], soa[2], n);
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
