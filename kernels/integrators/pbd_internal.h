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

#endif
