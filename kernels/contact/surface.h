/* Private: the colliders against the body's surface, its triangles
 * (kernels/contact/surface.c), after the vertex pass of
 * kernels/contact/contact.c. */
#ifndef SB_SURFACE_H
#define SB_SURFACE_H

#include "kernels/state/solver_data.h"

/* The arrays the pass corrects: positions, velocities, Verlet
 * displacements (and, on the fused step's packed state, the forces the
 * drift set, which a corrected vertex gets again for its new velocity;
 * NULL elsewhere), axis k of vertex i at [k][stride i]; `from`, 3 doubles a
 * vertex, the positions at the start of the step (not x − d: an answer
 * resets d to v dt). With `kept` (the fused step), from[i] holds vertex i's
 * start only where kept[i] == stamp: the vertex pass keeps the starts of
 * the blocks a collider meeting the surface reaches, the pass those of the
 * corners it moves before it moves them; any other vertex was not moved by
 * an answer that could matter here, and starts at x − d. */
typedef struct sb_surface_view {
    sb_real *x[3], *v[3], *d[3], *f[3];
    size_t stride;
    double* from;
    uint32_t *kept, stamp;
} sb_surface_view;

/* Vertices per block of the pass's broad phase, and blocks per group: a
 * group is a chunk of the vertex pass (kernels/contact/contact.c), which
 * computes the boxes of both. */
#define SB_SURFACE_BLOCK 8
#define SB_SURFACE_GROUP (SB_CHUNK / SB_SURFACE_BLOCK)

typedef struct sb_surface sb_surface;

/* Whether a collider meets the surface (a built-in sphere, capsule or box)
 * and the model has triangles: the pass has work. */
bool sb_surface_active(const sb_solver* solver);
/* The pass's broad phase: the triangles each block of vertices owns and
 * the blocks they reach, and where a collider has a footprint, each
 * vertex's neighbours; refuses a footprint shorter than the surface's
 * longest edge at rest, or with tearing. */
sb_status sb_surface_create(const sb_solver* solver, sb_surface** out, sb_error* err);
void sb_surface_destroy(sb_surface* surface);
/* The box of block b's moves this step (lo x y z, hi x y z), from the
 * fused vertex pass, which computes it anyway. */
void sb_surface_set_box(sb_surface* surface, uint32_t block, const double lo[3], const double hi[3]);
/* The box of group g's moves this step; `fine`: its blocks' boxes were set
 * too (otherwise the group's box stands for each of them). */
void sb_surface_set_group_box(sb_surface* surface, uint32_t group, const double lo[3], const double hi[3], bool fine);
/* Triangles whose dead[t] is 1 are out of the pass (tearing's, read in
 * place; the surface must be the model's triangles); NULL: none. */
void sb_surface_set_dead(sb_surface* surface, const uint8_t* dead);
/* The fused step's packed state, and the state's arrays, with `from`. */
sb_surface_view sb_surface_view_packed(sb_solver* solver, double* from, uint32_t* kept, uint32_t stamp);
sb_surface_view sb_surface_view_state(sb_solver* solver, double* from);
/* The pass, on one thread, after the vertex pass of the step: the
 * triangles block by block, in order, each against each collider that
 * meets the surface, in order; the impulses into the partial sums of chunk
 * 0 (which the vertex pass began). `boxes_set`: every group's box was set
 * this step, and the boxes of the blocks of each group set `fine`
 * (sb_surface_set_group_box, sb_surface_set_box); otherwise the pass makes
 * them from the view. Returns the contacts. */
uint32_t sb_surface_pass(const sb_solver* solver, sb_surface* surface, const sb_surface_view* view, bool boxes_set,
                         double dt);

#endif
