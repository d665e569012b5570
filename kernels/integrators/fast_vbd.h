/* Private: vbd's fast sweep (kernels/integrators/fast_vbd.c), the sweeps of
 * kernels/integrators/vbd.c in sb_real and SIMD over the vertices of a color. */
#ifndef SB_FAST_VBD_H
#define SB_FAST_VBD_H

#include "kernels/runtime/team.h"
#include "kernels/forces/vertex_elements.h"

typedef struct sb_fast_vbd sb_fast_vbd;

/* The parts of vbd.c's partition of the vertices: in a team of this many
 * workers, worker p runs the colors of part p (in any other team each color
 * is split over the workers). */
enum { SB_VBD_PARTS = 2 };

/* The layout for vbd's colors: color_start (color_count + 1 entries) cuts
 * order, the moving vertices by color (in the sweep's order), color_part
 * gives each color's part (0 or 1); the sweeps' waits planned for a team
 * of `width` (other widths run too, waiting on every need). Built once;
 * NULL when out of memory. The model must not change afterwards (no
 * breakage, no tearing). */
sb_fast_vbd* sb_fast_vbd_create(const sb_model* m, const sb_vertex_elements* at, const uint32_t* color_start,
                                uint32_t color_count, const uint8_t* color_part, const uint32_t* order, bool chebyshev,
                                int width);
void sb_fast_vbd_destroy(sb_fast_vbd* f);

/* Chebyshev acceleration across a step's sweeps (as the VBD paper uses
 * it): after sweep n ≥ SB_VBD_CHEBYSHEV_FIRST, x ← ω_n (x − x⁽ⁿ⁻²⁾) +
 * x⁽ⁿ⁻²⁾, x⁽ⁿ⁻²⁾ the iterate two sweeps back (x⁽⁰⁾ the first guess), with
 * ω = 2/(2 − ρ²) at the first accelerated sweep and ω_n = 4/(4 − ρ² ω_{n−1})
 * after it: the weight of sweep n given the previous one. The first two
 * sweeps stay plain: accelerating the second (ω = 1.68 at ρ = 0.9) ran a
 * 30 × 30 sheet away at dt = 1 ms within 0.07 s where plain sweeps held. */
enum { SB_VBD_CHEBYSHEV_FIRST = 3 };
static inline double sb_vbd_chebyshev_weight(double rho, int sweep, double previous) {
    if (sweep < SB_VBD_CHEBYSHEV_FIRST) return 1.0;
    return sweep == SB_VBD_CHEBYSHEV_FIRST ? 2.0 / (2.0 - rho * rho) : 4.0 / (4.0 - rho * rho * previous);
}

/* One step (3n interleaved doubles): x holds the first guess and receives
 * the result on the vertices that move (inv_mass > 0); every vertex's new
 * position also goes to positions4 (the fast path's packed x y z w).
 * *collapsed is raised when an element with a constant other than 0
 * collapsed during the sweeps. Each worker packs at the start and unpacks
 * at the end its own range of vertices (sb_worker_range over the vertex
 * count), without a barrier after the unpacking: the caller predicts and
 * finishes the same ranges, and needs no barrier of its own between. */
typedef struct sb_fast_vbd_step {
    double* x;
    const double *x0, *y, *inv_mass;
    double dt, drag;
    int sweeps;
    double chebyshev_rho; /* 0: no acceleration; otherwise the layout was created with chebyshev */
    double relaxation;    /* ω: each vertex moves ω times its Newton step (1: plain) */
    sb_real* positions4;
    atomic_int* collapsed;
} sb_fast_vbd_step;

/* Checks the sweeps' schedule against the model's elements (for the
 * tests): for every element with a constant other than 0 and every two of
 * its vertices in blocks x and y, x ≠ y and y is among x's needs. Returns
 * the pairs that fail (UINT32_MAX when out of memory) and, in *needs, the
 * needs listed in all. */
uint32_t sb_fast_vbd_schedule_faults(const sb_fast_vbd* f, const sb_model* m, uint32_t* needs);

/* The step's team job, on every worker of the team. */
void sb_fast_vbd_run(sb_fast_vbd* f, const sb_fast_vbd_step* step, const sb_worker* w);

#endif
