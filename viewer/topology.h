/* What the viewer draws of a solver that tears (sb_solver_def.max_splits):
 * its vertices now (the model's, then the copies splits made, each with
 * the model vertex it came from), its live triangles and its unbroken
 * bonds with their current ends. The simulation thread reads them from the
 * solver when the broken bonds or the vertices change and hands a copy to
 * the render thread; a solver that does not tear keeps the model's. */
#ifndef SB_VIEWER_TOPOLOGY_H
#define SB_VIEWER_TOPOLOGY_H

#include "softbond/softbond.h"

typedef struct sb_view_topology {
    uint32_t vertex_count, triangle_count, edge_count;
    uint32_t* origins;   /* per vertex (room for the solver's capacity) */
    uint32_t* triangles; /* 3 per live triangle */
    uint32_t* edges;     /* 2 per unbroken bond */
    uint32_t* bonds;     /* the bond of each edge (its rest length) */
    uint64_t version;    /* counts the changes */
} sb_view_topology;

/* Room for the solver's capacity, the surface's triangles (mesh's, or the
 * model's when the solver tears) and the model's bonds. */
sb_status sb_view_topology_create(sb_view_topology* t, const sb_solver* solver, const sb_mesh* mesh, sb_error* err);
void sb_view_topology_free(sb_view_topology* t);
/* Reads the solver's topology now (its thread); version + 1. */
void sb_view_topology_read(sb_view_topology* t, const sb_solver* solver, const sb_mesh* mesh);
/* Copies from into to (both made for the same solver). */
void sb_view_topology_copy(sb_view_topology* to, const sb_view_topology* from);

#endif
