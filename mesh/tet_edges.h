/* Private: the unique edges of a tetrahedral mesh, numbered in order of
 * first appearance (tetrahedron by tetrahedron, each one's edges in
 * sb_tet_def's order 01 02 03 12 13 23). The spring factory puts a spring
 * on each; the quadratic tissue a vertex at each one's middle, numbered
 * after the mesh's vertices in this order, which its surface
 * (sb_tet_mesh_quadratic_surface) shares. */
#ifndef SB_TET_EDGES_H
#define SB_TET_EDGES_H

#include "common/edge_map.h"
#include "softbond/volume.h"

typedef struct sb_tet_edge_set {
    uint32_t count;
    uint32_t* ends;   /* 2 per edge */
    uint32_t* of_tet; /* 6 per tetrahedron: its edges' numbers */
    sb_edge_map map;  /* (a, b) → number */
} sb_tet_edge_set;

/* The edge corners in sb_tet_def's order. */
extern const int sb_tet_edge_corners[6][2];

sb_status sb_tet_edge_set_find(const sb_tet_mesh* mesh, sb_tet_edge_set* out, sb_error* err);
void sb_tet_edge_set_free(sb_tet_edge_set* set);

#endif
