/* Private: pbd's and xpbd's colored constraints (kernels/integrators/pbd.c), shared with
 * their SIMD sweeps (kernels/integrators/fast_pbd.c). */
#ifndef SB_PBD_INTERNAL_H
#define SB_PBD_INTERNAL_H

#include "kernels/state/solver_data.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"
#include "kernels/forces/coloring.h"
#include "kernels/contact/contact_pbd.h"

/* One kind of constraint item (bonds or triangles) in a blocked coloring:
 * runs.order holds the items' model indices (model order within a run). */
typedef struct sb_pbd_group {
    sb_blocked runs;
    double* lambda; /* xpbd, in run order: 1 per bond, 6 per triangle (its corners, then its edges' bonds) */
} sb_pbd_group;

/* A triangle edge that carries no bond of its own (sb_pbd.edge_bond). */
#define SB_PBD_NO_BOND UINT32_MAX

typedef struct sb_pbd_wide sb_pbd_wide;

typedef struct sb_pbd {
    int threads;
    sb_pbd_group bonds, triangles; /* bonds: those no triangle carries */
    /* edge_bond[c][t]: the bond that edge c (vertices c, c + 1) of model
     * triangle t carries in its projection, or SB_PBD_NO_BOND; each bond
     * on a triangle's edge is carried by one triangle. */
    uint32_t* edge_bond[3];
    double *x, *x0;            /* 3n: positions being projected, positions at the start */
    sb_pbd_contacts* contacts; /* NULL without colliders (kernels/contact/contact_pbd.c) */
    sb_pbd_wide* wide;         /* the SIMD sweeps (kernels/integrators/fast_pbd.c); NULL where the scalar ones run */
} sb_pbd;

/* Component c of vertex i's predicted velocity: v + dt (g + f_ext/m − drag v)
 * on a free vertex, v on a fixed one (the step's prediction, both sweeps). */
static inline double sb_pbd_predicted_velocity(const sb_solver* s, uint32_t i, int c, double v, double dt) {
    const sb_model* m = s->model;
    if (m->fixed[i]) return v;
    double external = s->external ? s->external[3 * (size_t)i + c] * m->inv_mass[i] : 0.0;
    return v + dt * (s->def.gravity[c] + external - s->def.drag * v);
}

/* This worker's blocks [begin, end) of block color k of g (all of the
 * overflow color's on worker 0). */
void sb_pbd_block_share(const sb_worker* worker, const sb_blocked* g, int k, uint32_t* begin, uint32_t* end);

/* Whether the solver's pbd steps take the SIMD sweeps: the fast kernels,
 * no colliders and no handles (their passes work on the scalar sweeps'
 * double positions). */
bool sb_pbd_wide_applies(const sb_solver* solver);
/* The SIMD layout of p's colors (the same colors and order); NULL when out
 * of memory. */
sb_pbd_wide* sb_pbd_wide_create(const sb_pbd* p, const sb_model* model);
void sb_pbd_wide_destroy(sb_pbd_wide* wide);
/* One step: prediction, the sweeps and v = (x − x_prev)/dt, on the state's
 * arrays and the packed positions and velocities, the state checked; the
 * forces and energies of the new state are left to sb_solver_settle
 * (kernels/solver/solver.c) unless the next step needs them. */
sb_status sb_pbd_wide_step(sb_solver* solver, double dt);
/* The barriers of a step of the SIMD sweeps on more than one thread: one
 * before the sweeps and one after them; none in them (kernels/integrators/fast_pbd.c's
 * schedule). */
uint32_t sb_pbd_wide_barriers(const sb_solver* solver);
/* For the tests: the faults of the SIMD sweeps' schedule, checked by brute
 * force (a pair of units in different phases that share a vertex without
 * waiting for each other, or that wait without sharing one; a unit not
 * planned on exactly one worker; a worker's plan out of phase order, or
 * the overflow color's units out of order), 0
 * when sound; *across: the waits for a unit of another worker. */
uint32_t sb_pbd_wide_schedule_faults(const sb_solver* solver, uint32_t* across);

#endif
