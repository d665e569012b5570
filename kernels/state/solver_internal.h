/* Private: the solver's layout, shared by solver.c, solver_forces.c,
 * solver_fast.c, integrators.c, implicit_euler.c and adaptive.c. */
#ifndef SB_SOLVER_INTERNAL_H
#define SB_SOLVER_INTERNAL_H

#include "softbond/solver.h"
#include "mesh/model_internal.h"
#include "kernels/forces/fast_model.h"
#include "kernels/state/state.h"
#include "kernels/runtime/team.h"

#include <math.h>

struct sb_solver {
    const sb_model* model;        /* what the kernels read: the given model, or breakage's working copy */
    const sb_model* given_model;  /* sb_solver_model's */
    struct sb_breakage* breakage; /* kernels/interaction/breakage.c; NULL for a model that cannot break */
    sb_solver_def def;
    sb_state state;
    sb_real *disp_x, *disp_y, *disp_z; /* the last step's displacement, x − x⁻ */
    bool has_displacement;
    double prev_dt;
    double *scratch_x, *scratch_v, *scratch_f; /* 3n interleaved doubles for the reference */
    double center[3], runaway;                 /* a vertex further than runaway from center (any axis) ran away */
    sb_fast_model* fast;                       /* NULL with the reference kernels */
    sb_team* team;                             /* the threads of every parallel pass (kernels/runtime/team.c) */
    double* partials;                          /* per-block energy sums of the fast passes */
    /* The fast path's working state, packed x y z w per vertex; the state's
     * arrays are filled from it on demand (published). */
    sb_real *positions4, *velocities4, *displacements4, *forces4;
    bool published;
    /* The step left the new state's forces and energies to sb_solver_settle
     * (sb_step_needs_forces), or (the fused Verlet step) its kinetic and
     * gravitational energies alone. */
    bool forces_stale;
    bool energies_read; /* sb_solver_energies was called since the last step: the fused step sums the next one's */
    bool near_limits;   /* the fast kernels' last evaluation met a bond near its break limits */
    double* external;   /* 3n: the external forces of the last evaluation (NULL without a callback) */
    struct sb_backup* backup;     /* adaptive stepping: the state before a sub-step */
    double trial_substep;         /* adaptive: the size the next sub-step tries (0: the whole dt) */
    double energy_peak;           /* adaptive: the largest energy scale since the state was set */
    struct sb_implicit* implicit; /* implicit Euler's matrix and work vectors (kernels/integrators/implicit_euler.c) */
    sb_real* stretch4;            /* the blow-up rule's packed copy of the positions (generic integrators) */
    /* contact (kernels/contact/contact.c); NULL without colliders */
    double* contact_from;     /* 3n: positions at the start of a step the fused path does not take */
    double* contact_partials; /* per vertex chunk: 3 impulse sums per collider, the contact count, 3 torque sums */
    double* contact_step;     /* 6 per collider: the last step's impulses on the colliders, then their torques */
    double* contact_impulse;  /* 3 per collider: summed over the accepted steps of this advance */
    double contact_dt;        /* s, the step being taken */
    /* sb_solver_advance_into: where the fused step writes the snapshot (NULL otherwise) */
    sb_real *publish_positions, *publish_velocities;
    bool publish_written;
    double advance_dt;            /* s, the last advance's dt */
    struct sb_pbd* pbd;           /* pbd, xpbd: colored constraints and work arrays */
    struct sb_vbd* vbd;           /* vbd: the vertex colors and work arrays (kernels/integrators/vbd.c) */
    struct sb_self_contact* self; /* self-contact (kernels/contact/self_contact.c); NULL when off */
    /* handles (kernels/interaction/handle.c) */
    bool soft_handles;       /* a soft one among def.handles: its forces join the external ones */
    double* pinned_inv_mass; /* with handles: the model's inverse masses, 0 where a hard handle holds */
    sb_step_stats stats;
    double time;
    uint64_t steps;
    sb_energies energies;
    sb_error error;
};

/* Vertices per chunk of the vertex passes, which own their partial sums. */
#define SB_CHUNK 256
static inline uint32_t sb_chunk_count(uint32_t vertex_count) { return (vertex_count + SB_CHUNK - 1) / SB_CHUNK; }

/* Whether a step is the fast path's fused Verlet job (kernels/state/solver_fast.c). */
static inline bool sb_fused(const sb_solver* s) {
    return s->fast && (s->def.integrator == SB_INTEGRATOR_VERLET || s->def.integrator == SB_INTEGRATOR_VELOCITY_VERLET);
}

/* The inverse masses the integrators move the vertices with: the model's,
 * 0 where a hard handle holds (kernels/interaction/handle.c). */
static inline const double* sb_inv_mass(const sb_solver* s) {
    return s->pinned_inv_mass ? s->pinned_inv_mass : s->model->inv_mass;
}

/* What is wrong with vertex i's state, or NULL: sb_check_state's test (every
 * coordinate and velocity finite, the position within runaway of center on
 * every axis), shared with the steps that check their ranges on the team. */
static inline const char* sb_vertex_fault(const sb_solver* s, uint32_t i) {
    const sb_state* st = &s->state;
    double values[6] = {st->x[i], st->y[i], st->z[i], st->vx[i], st->vy[i], st->vz[i]};
    bool finite = true, inside = true;
    for (int c = 0; c < 6; c++) finite &= isfinite(values[c]) != 0;
    for (int c = 0; c < 3; c++) inside &= fabs(values[c] - s->center[c]) <= s->runaway;
    return !finite ? "is not finite" : !inside ? "ran away from the model" : NULL;
}

/* Contact (kernels/contact/contact.c). */
sb_status sb_contact_prepare(sb_solver* solver, sb_error* err);
void sb_contact_destroy(sb_solver* solver);
/* The colliders' begin-step callbacks, in order, on the calling thread. */
void sb_contact_begin_step(sb_solver* solver, double t0, double t1);
/* Keeps the state's positions as the start of the step's moves. */
void sb_contact_save_from(sb_solver* solver);
/* Answers vertex i's move from → x among the colliders of `near` (a bit
 * each, those whose bounds the move reaches; x and v updated in place);
 * returns the collider or -1, the impulse m Δv the vertex took and the
 * point of the collider's surface it met (sb_contact.point). */
int sb_contact_vertex(const sb_solver* solver, uint32_t i, uint64_t near, const double from[3], double x[3],
                      double v[3], double impulse[3], double point[3]);
/* The earliest contact of vertex i's move from → to in the step being
 * taken among the colliders whose bounds the move reaches: the collider and
 * *c, or -1. */
int sb_contact_find(const sb_solver* solver, uint32_t i, const double from[3], const double to[3], sb_contact* c);
/* The velocity answer of contact c for a vertex of velocity v (in place):
 * restitution and Coulomb friction relative to the collider's velocity
 * (kernels/contact/contact.c's design note). */
void sb_contact_velocity(const sb_contact* c, double v[3]);
/* Zeroes a chunk's partial sums; a pass over the chunk then records each
 * answered vertex's impulse m Δv (the collider receives the opposite). */
void sb_contact_chunk_begin(const sb_solver* solver, uint32_t chunk);
void sb_contact_record(const sb_solver* solver, uint32_t chunk, int collider, const double impulse[3]);
/* Adds the torque about a dynamic collider's center of the impulse it
 * receives at the contact point (the opposite of the vertex's) to the
 * chunk's partial sums (nothing for a collider that is not dynamic). */
void sb_contact_record_torque(const sb_solver* solver, uint32_t chunk, int collider, const double point[3],
                              const double impulse[3]);
/* The most colliders a solver takes (a bit each in the broad phase). */
#define SB_MAX_COLLIDERS 64
/* The fused path's pass over one chunk of the packed state, after its drift
 * (from = x − displacement). */
void sb_contact_chunk_packed(const sb_solver* solver, uint32_t chunk, double dt);
/* The pass over the state's arrays (every other step); returns the contacts. */
uint32_t sb_contact_state_pass(sb_solver* solver, double dt);
/* Adds the chunks' partial sums in order into the step's impulses; returns
 * the contacts. */
uint32_t sb_contact_collect(sb_solver* solver);
/* Adds the step's impulses to the advance's. */
void sb_contact_accept(sb_solver* solver);

/* The current positions packed x y z w: the fast path's working state, or
 * the state's arrays gathered into stretch4 (the reference kernels). */
const sb_real* sb_packed_positions(sb_solver* solver);

/* Forces at the state's positions, with the state's velocities for damping:
 * fills state.f (internal + gravity + external) and energies.term[]. */
sb_status sb_solver_compute_forces(sb_solver* solver);

/* Copies the current positions and velocities as 3n interleaved sb_reals,
 * in parallel on the solver's team; reads only (sb_solver_publish). */
void sb_solver_copy_state(const sb_solver* solver, sb_real* positions, sb_real* velocities);
/* out[3i..3i+2] = packed[4i..4i+2] for vertices [begin, end). */
void sb_unpack_xyz(const sb_real* packed, sb_real* out, int64_t begin, int64_t end);
/* sb_solver_advance, and the new positions and velocities into the arrays
 * (3n): written by the fused step's last pass where it runs (no extra pass
 * and no extra wake-up of the team), copied after the advance otherwise. */
sb_status sb_solver_advance_into(sb_solver* solver, double dt, sb_real* positions, sb_real* velocities);

/* out[3i..3i+2] = (a[i], b[i], c[i]): SoA to interleaved doubles. */
void sb_interleave(double* out, const sb_real* a, const sb_real* b, const sb_real* c, uint32_t n);
/* The state's positions and velocities from interleaved doubles, on every
 * vertex that is not fixed (an implicit integrator's result). */
void sb_store_free_vertices(sb_solver* solver, const double* x, const double* v);
/* The same for vertices [begin, end) (vbd: each worker its own range). */
void sb_store_free_range(sb_solver* solver, const double* x, const double* v, uint32_t begin, uint32_t end);

/* The fast kernels' counterparts (kernels/state/solver_fast.c). */
sb_status sb_fast_prepare(sb_solver* solver, sb_error* err);
sb_status sb_fast_compute_forces(sb_solver* solver);
/* The forces at the packed positions4 and velocities4 into forces4:
 * gravity, drag, the element passes and the external forces; nothing
 * published, no energies (implicit Euler's residual, kernels/integrators/implicit_fast.c). */
sb_status sb_fast_forces_packed(sb_solver* solver);
sb_status sb_fast_verlet_step(sb_solver* solver, double dt);
/* The kinetic and gravitational energies of the packed state into the
 * solver's energies, bitwise as the fused step sums them in its passes
 * (sb_solver_settle, after a step that left them for later). */
void sb_fast_vertex_energies(sb_solver* solver);
/* A packed force's starting value, gravity and drag: m (g_a − drag v_a). */
sb_real sb_fast_initial_force(const sb_solver* solver, uint32_t vertex, int axis, double velocity);
/* Fills the state's arrays from the packed working state, when stale. */
void sb_fast_publish(sb_solver* solver);

/* The forces and energies of the current state, evaluated now where the
 * last step left them for later (forces_stale; the fused Verlet step: its
 * kinetic and gravitational energies only); the getters that return them
 * call it first, and so does what changes what they depend on (gravity,
 * the handles' pins) between a step and a read. */
sb_status sb_solver_settle(sb_solver* solver);
/* Whether anything between a step and the next reads the new state's
 * forces or energies, so that the step must evaluate them: the passes after
 * it (collider, self-contact, hard handles: sb_solver_step), the external
 * and soft handles' forces (evaluated with the forces, read by the next
 * step), adaptive stepping's energies. Otherwise a step that can leaves
 * them to sb_solver_settle: pbd's and xpbd's SIMD sweeps (which run only
 * without colliders and handles), the fast vbd sweep (only without
 * breakage), the fast implicit Euler. Breakage does not need them: it reads
 * positions, and the forces only for Verlet's re-kick, whose step never
 * leaves them (tests/test_tearing.c). */
bool sb_step_needs_forces(const sb_solver* solver);

/* Fills the solver's error naming the first vertex that is not finite or ran
 * away; SB_OK if there is none. */
sb_status sb_check_state(sb_solver* solver);
void sb_update_energies(sb_solver* solver);

/* One step of each integrator; each leaves forces, velocities and term
 * energies at the new positions (through sb_solver_compute_forces). */
sb_status sb_integrate_verlet(sb_solver* solver, double dt);
sb_status sb_integrate_velocity_verlet(sb_solver* solver, double dt);
sb_status sb_integrate_explicit_euler(sb_solver* solver, double dt);
sb_status sb_integrate_symplectic_euler(sb_solver* solver, double dt);
sb_status sb_integrate_position_verlet(sb_solver* solver, double dt);
sb_status sb_integrate_implicit_euler(sb_solver* solver, double dt);
/* Allocates implicit Euler's work arrays; false when out of memory. */
bool sb_implicit_prepare(sb_solver* solver);
void sb_implicit_destroy(sb_solver* solver);
/* vbd (kernels/integrators/vbd.c): prepare allocates everything a step needs. */
sb_status sb_integrate_vbd(sb_solver* solver, double dt);
bool sb_vbd_prepare(sb_solver* solver);
void sb_vbd_destroy(struct sb_vbd* vbd);
int sb_vbd_iterations(const sb_solver_def* def);
/* Its part of a saved state (kernels/solver/solver_state.c). */
struct sb_sections_writer;
struct sb_cursor;
void sb_vbd_save(const sb_solver* solver, struct sb_sections_writer* w);
void sb_vbd_load(sb_solver* solver, struct sb_cursor* r);
/* The fast implicit Euler's work (kernels/integrators/implicit_fast.c), NULL unless
 * implicit Euler runs on the fast kernels with CG; its part of a
 * checkpoint: the first guess the next step starts from. */
struct sb_implicit_fast* sb_implicit_fast_of(const sb_solver* solver);
void sb_implicit_fast_save(const sb_solver* solver, struct sb_sections_writer* w);
void sb_implicit_fast_load(sb_solver* solver, struct sb_cursor* r);

/* pbd and xpbd (kernels/integrators/pbd.c). */
sb_status sb_integrate_pbd(sb_solver* solver, double dt);
/* Colors the constraints and allocates the work arrays (at creation). */
sb_status sb_pbd_prepare(sb_solver* solver);
void sb_pbd_destroy(struct sb_pbd* pbd);
int sb_pbd_iterations(const sb_solver_def* def);

/* One step of the chosen integrator with the chosen kernels, the state
 * checked and the energies updated (kernels/solver/solver.c). */
sb_status sb_solver_step(sb_solver* solver, double dt);
/* sb_solver_step over sub-steps with energy control (kernels/solver/adaptive.c). */
sb_status sb_adaptive_advance(sb_solver* solver, double dt);
/* The sb_real arrays a step may change and their lengths (the state's,
 * the displacement, the fast path's packed ones): what the adaptive
 * stepper's backup and the saved state (kernels/solver/solver_state.c) copy. */
#define SB_STEP_ARRAYS 16
int sb_solver_step_arrays(const sb_solver* solver, sb_real** arrays, size_t* lengths);
/* The adaptive stepper's copy of the state, made at creation. */
struct sb_backup* sb_backup_create(sb_solver* solver);
void sb_backup_destroy(struct sb_backup* backup);

/* Adds to f (internal forces at x, v) gravity, drag, the external callback's
 * forces (remembered in `external` when not NULL) and the soft handles'. */
void sb_solver_add_body_forces(sb_solver* solver, const double* x, const double* v, double* f, double* external);

#endif
