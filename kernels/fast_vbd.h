/* Private: vbd's fast sweep (kernels/fast_vbd.c), the sweeps of
 * kernels/vbd.c in sb_real and SIMD over the vertices of a color. */
#ifndef SB_FAST_VBD_H
#define SB_FAST_VBD_H

#include "kernels/team.h"
#include "kernels/vertex_elements.h"

typedef struct sb_fast_vbd sb_fast_vbd;

/* The layout for vbd's colors: color_start (color_count + 1 entries) cuts
 * order, the moving vertices by color. Built once; NULL when out of memory.
 * The model must not change afterwards (no breakage, no tearing). */
sb_fast_vbd* sb_fast_vbd_create(const sb_model* m, const sb_vertex_elements* at, const uint32_t* color_start,
                                uint32_t color_count, const uint32_t* order);
void sb_fast_vbd_destroy(sb_fast_vbd* f);

/* One step (3n interleaved doubles): x holds the first guess and receives
 * the result on the vertices that move (inv_mass > 0); every vertex's new
 * position also goes to positions4 (the fast path's packed x y z w).
 * *collapsed is raised when an element with a constant other than 0
 * collapsed during the sweeps. */
typedef struct sb_fast_vbd_step {
    double* x;
    const double *x0, *y, *inv_mass;
    double dt, drag;
    int sweeps;
    sb_real* positions4;
    atomic_int* collapsed;
} sb_fast_vbd_step;

/* The step's team job, on every worker of the team. */
void sb_fast_vbd_run(sb_fast_vbd* f, const sb_fast_vbd_step* step, const sb_worker* w);

#endif
