/* Private: the solver's layout, which every room of kernels/ above state/
 * reads. It holds what lasts between steps; one step's temporaries are in
 * its step context (sb_step_context), and each feature keeps its own state
 * in its own struct (contact, self-contact, handles' targets, breakage,
 * adaptive stepping), reached through the pointer named after it.
 *
 * A step is a list of named stages (kernels/solver/step.c, DESIGN.md "A
 * step"). The features take part through hooks: the stage hooks of
 * sb_feature (begin, correct, collect, accept, end), which the stages call
 * in the order the features were registered, and the in-step hooks of
 * sb_step_hooks, which the integrators' own passes call (LAMMPS's fixes
 * subscribe to the hook points of its Verlet::run the same way). Neither
 * kind is a call from here up into a feature's file: the layers of
 * kernels/ depend one way (tests/layers.sh). This header declares no
 * function: each file's functions are in its own header. */
#ifndef SB_SOLVER_DATA_H
#define SB_SOLVER_DATA_H

#include "softbond/solver.h"
#include "mesh/model_internal.h"
#include "kernels/forces/fast_model.h"
#include "kernels/state/state.h"
#include "kernels/runtime/team.h"

#include <math.h>

/* A feature's hooks into the stages of a step; NULL where it has none. */
typedef struct sb_feature {
    const char* name;
    /* start: at the start of an advance (before its steps) */
    void (*start)(sb_solver* s);
    /* begin: before the integrator, on the calling thread (the step's
     * times t0 and t0 + dt) */
    void (*begin)(sb_solver* s, double t0, double dt);
    /* correct: after a step the fused path did not take, on the state's
     * arrays; returns whether a vertex moved (the forces are evaluated
     * again) */
    bool (*correct)(sb_solver* s, double dt);
    /* collect: after the fused step, what its passes left per chunk */
    void (*collect)(sb_solver* s);
    /* accept: a step (or an adaptive sub-step) of dt is kept */
    sb_status (*accept)(sb_solver* s, double dt);
    /* end: at the end of an advance */
    void (*end)(sb_solver* s);
} sb_feature;

/* The most features a solver runs: contact, self-contact, handles, breakage. */
#define SB_MAX_FEATURES 4

/* The in-step hooks the integrators' passes call; NULL where no feature
 * subscribes. */
typedef struct sb_step_hooks {
    /* post_force: adds forces at x, v (3n doubles) to f, and to external
     * when not NULL (the soft handles: the forces join the external ones) */
    void (*post_force)(sb_solver* s, const double* x, const double* v, double* f, double* external);
    /* post_force_packed: the same on the packed state (the fast path) */
    void (*post_force_packed)(sb_solver* s);
    /* before_drift: the packed reals [begin, end) before the fused drift
     * moves them (self-contact keeps them) */
    void (*before_drift)(sb_solver* s, size_t begin, size_t end);
    /* drift_chunk: after the fused drift of one vertex chunk, while it is
     * in cache (the colliders' contact) */
    void (*drift_chunk)(const sb_solver* s, uint32_t chunk, double dt);
    /* surface_packed: worker 0, after every chunk's drift, before
     * after_drift (the colliders against the triangles) */
    void (*surface_packed)(sb_solver* s, double dt);
    /* after_drift: all workers, after every chunk's drift (self-contact) */
    void (*after_drift)(const sb_worker* w, sb_solver* s, double dt);
    /* place_packed: worker 0 puts the vertices a feature holds at their
     * targets (the hard handles) */
    void (*place_packed)(sb_solver* s, double dt);
} sb_step_hooks;

/* One step's temporaries. */
typedef struct sb_step_context {
    double dt; /* s, the step (sub-step) being taken */
    /* sb_solver_advance_into: where the fused step writes the snapshot
     * (NULL otherwise), and whether it did */
    sb_real *publish_positions, *publish_velocities;
    bool publish_written;
} sb_step_context;

struct sb_solver {
    const sb_model* model;        /* what the kernels read: the given model, or breakage's working copy */
    const sb_model* given_model;  /* sb_solver_model's */
    struct sb_breakage* breakage; /* kernels/interaction/breakage.c; NULL for a model that cannot break */
    sb_solver_def def;
    sb_state state;
    sb_real *disp_x, *disp_y, *disp_z; /* the last step's displacement, x − x⁻ */
    /* The Verlet drifts' compensation (sb_compensated_add): what rounding x + Δ
     * to sb_real left out, added to the next drift; zero in double builds. */
    sb_real *carry_x, *carry_y, *carry_z;
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
    sb_real* carry4; /* the fused drift's compensation, packed like the positions */
    bool published;
    /* The step left the new state's forces and energies to sb_solver_settle
     * (sb_step_needs_forces), or (the fused Verlet step) its kinetic and
     * gravitational energies alone. */
    bool forces_stale;
    bool energies_read; /* sb_solver_energies was called since the last step: the fused step sums the next one's */
    bool near_limits;   /* the fast kernels' last evaluation met a bond near its break limits */
    double* external;   /* 3n: the external forces of the last evaluation (NULL without a callback) */
    struct sb_adaptive* adaptive; /* adaptive stepping (kernels/solver/adaptive.c); NULL when off */
    struct sb_implicit* implicit; /* implicit Euler's matrix and work vectors (kernels/integrators/implicit_euler.c) */
    sb_real* stretch4;            /* the blow-up rule's packed copy of the positions (generic integrators) */
    struct sb_contact_pass* contact; /* the colliders' contact (kernels/contact/contact.c); NULL without colliders */
    double advance_dt;               /* s, the last advance's dt */
    struct sb_pbd* pbd;              /* pbd, xpbd: colored constraints and work arrays */
    struct sb_vbd* vbd;              /* vbd: the vertex colors and work arrays (kernels/integrators/vbd.c) */
    struct sb_self_contact* self;    /* self-contact (kernels/contact/self_contact.c); NULL when off */
    /* with handles: the model's inverse masses, 0 where a hard handle holds
     * (kept by kernels/interaction/handle.c) */
    double* pinned_inv_mass;
    /* the vertices in use: the model's, and the ones tearing has split off
     * so far (kept by kernels/interaction/breakage.c) */
    uint32_t live_vertices;
    sb_feature features[SB_MAX_FEATURES]; /* in the order the stages call them */
    int feature_count;
    sb_step_hooks hooks;
    sb_step_context step;
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

/* Subscribes a feature to the stages, after those already subscribed. */
static inline void sb_add_feature(sb_solver* s, sb_feature feature) {
    if (s->feature_count < SB_MAX_FEATURES) s->features[s->feature_count++] = feature;
}

/* The most colliders a solver takes (a bit each in the broad phase). */
#define SB_MAX_COLLIDERS 64

#endif
