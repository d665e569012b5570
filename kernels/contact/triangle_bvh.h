/* Private: a bounding-volume hierarchy over a model's triangles for
 * self-contact (kernels/contact/triangle_bvh.c): built once from the rest shape,
 * refitted every step around the moving triangles. */
#ifndef SB_TRIANGLE_BVH_H
#define SB_TRIANGLE_BVH_H

#include "softbond/types.h"
#include "kernels/contact/fast_triangle_bounds.h"

#include <stdbool.h>
#include <stddef.h>

/* Triangles per leaf, at most. */
#define SB_BVH_LEAF 8

/* Nodes in pre-order: a node's left child is the next node and its right
 * child starts where the left one's subtree ends. Every node covers a
 * contiguous range of `order`. */
typedef struct sb_bvh_node {
    uint32_t end;          /* index past this node's subtree */
    uint32_t parent;       /* UINT32_MAX for the root */
    uint32_t first, count; /* its triangles: order[first, first + count) */
    bool leaf;
    bool connected; /* its triangles form one patch joined by shared edges */
} sb_bvh_node;

/* Per node, refitted each step: the box around its triangles' swept
 * positions (lo x y z, hi x y z), inflated by the margin, and the box
 * around their unit normals at the end of the step (lo, hi). */
typedef struct sb_bvh_bounds {
    float box[6];
    float normals[6];
} sb_bvh_bounds;

typedef struct sb_triangle_bvh {
    uint32_t triangle_count, node_count;
    const uint32_t* tri_v[3];    /* the model's */
    uint32_t* order;             /* triangle indices in leaf order */
    sb_triangle_corners corners; /* their corners, in the same order (padded) */
    sb_triangle_bounds scratch;  /* per triangle, in the same order: each refit's boxes and normals */
    sb_bvh_node* nodes;
    sb_bvh_bounds* bounds;
    /* Per top and cut node, set by the refit of the top: flat
     * (sb_triangle_bvh_flat) or below a flat node. */
    uint8_t* culled;
    /* The cut: subtrees refitted (and searched) in parallel, and the top
     * nodes above them, in decreasing index (children before parents). */
    uint32_t cut_count, top_count;
    uint32_t *cut, *top;
} sb_triangle_bvh;

/* Builds the hierarchy of the triangles (tri_v, the model's arrays) from
 * the positions (3 per vertex). NULL when out of memory. */
sb_triangle_bvh* sb_triangle_bvh_create(uint32_t triangle_count, const uint32_t* const tri_v[3],
                                        const double* positions);
void sb_triangle_bvh_destroy(sb_triangle_bvh* bvh);
/* After the triangles' vertices changed (tearing's splits), the corners'
 * copy and which nodes are connected, from tri_v again; a node with a dead
 * triangle (dead: per triangle, or NULL) is never connected, so never flat.
 * false when out of memory. */
bool sb_triangle_bvh_retopologize(sb_triangle_bvh* bvh, const uint8_t* dead);

/* Refits the subtree of node `root` from the packed positions (x y z w per
 * vertex) at the start (from4) and end (to4) of the step; boxes inflated by
 * margin (m). */
void sb_triangle_bvh_refit_subtree(sb_triangle_bvh* bvh, uint32_t root, const sb_real* from4, const sb_real* to4,
                                   double margin);
/* Refits the top nodes from their children (after every subtree of the
 * cut), then sets `culled` of the top and cut nodes. */
void sb_triangle_bvh_refit_top(sb_triangle_bvh* bvh);
/* Whether a node is flat: connected and its normals within a cone, so
 * nothing inside it can touch anything else inside it. Worked out when
 * asked (the search asks only about the nodes it reaches). */
bool sb_triangle_bvh_flat(const sb_triangle_bvh* bvh, uint32_t node);
/* The lowest node above both a and b. */
uint32_t sb_triangle_bvh_common(const sb_triangle_bvh* bvh, uint32_t a, uint32_t b);

/* Whether the boxes of nodes a and b overlap. */
static inline bool sb_bvh_overlap(const sb_triangle_bvh* bvh, uint32_t a, uint32_t b) {
    const float *x = bvh->bounds[a].box, *y = bvh->bounds[b].box;
    return x[0] <= y[3] && y[0] <= x[3] && x[1] <= y[4] && y[1] <= x[4] && x[2] <= y[5] && y[2] <= x[5];
}
static inline uint32_t sb_bvh_right(const sb_triangle_bvh* bvh, uint32_t node) { return bvh->nodes[node + 1].end; }

#endif
