/* The surface a frame shows of a solver that tears (kernels/interaction/topology.c):
 * the solver's vertices now (the model's, then the copies splits made) and
 * its live triangles with their current vertices, so that a torn sheet's
 * frames show the hole and the separate halves; for a volume cut through
 * its tetrahedra, its boundary faces now. */
#ifndef SB_TORN_SURFACE_H
#define SB_TORN_SURFACE_H

#include "softbond/softbond.h"

typedef struct sb_torn_surface {
    sb_mesh mesh;
    bool tears;    /* the solver has spare vertices */
    uint32_t room; /* the triangles mesh.triangles holds (a cut through triangles adds some) */
} sb_torn_surface;

/* Room for the solver's triangles, when it tears. */
sb_status sb_torn_surface_init(sb_torn_surface* surface, const sb_solver* solver, sb_error* err);
void sb_torn_surface_free(sb_torn_surface* surface);

/* The surface to write now, at `positions` (3 per vertex): `whole` for a
 * solver that does not tear, the torn surface otherwise; NULL when out of
 * memory for the triangles a cut added. */
const sb_mesh* sb_torn_surface_update(sb_torn_surface* surface, const sb_solver* solver, const sb_mesh* whole,
                                      double* positions);

#endif
