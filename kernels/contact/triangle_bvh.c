/* The triangle hierarchy of self-contact (kernels/contact/triangle_bvh.h).
 *
 * Design. The tree is built once, top-down from
 * the rest shape (each node split at the median of its triangles' centroids
 * along its longest axis, leaves of up to SB_BVH_LEAF triangles, nodes in
 * pre-order so that a subtree is a contiguous range of nodes and of
 * triangles), and only refitted per step: a leaf's box covers its
 * triangles at the start and at the end of the step (a straight move stays
 * inside), inflated by the search margin; a parent's box covers its
 * children's. Boxes are floats rounded outward. The per-triangle part
 * (corners' box, end normal) runs SB_WIDTH triangles at a time over a copy
 * of their corner indices in leaf order (kernels/contact/fast_triangle_bounds.c);
 * each leaf then takes the extremes of its triangles'.
 *
 * Normal cones (Volino and Magnenat-Thalmann 1994, Provot 1997). A
 * connected patch whose normals all lie within 60 degrees of one direction
 * is a height field over the plane across it and cannot touch itself; its
 * node is flat and the search skips every pair inside it. The normals are
 * bounded by a box of unit vectors (both ends of the step), which is
 * cheaper to merge than a cone: the least n·d over the box, d the box's
 * normalized center, must exceed cos 60°. The normals are those at the
 * end of the step (Provot's choice): a patch flat at the end of a step
 * that was folded through itself during it would have to turn a triangle
 * inside out within the step. Whether a node is connected
 * (through shared edges) is found at the build, and again with the
 * corners' copy after tearing changed the triangles' vertices
 * (sb_triangle_bvh_retopologize: the tree itself stays, a torn node only
 * loses its flatness). Like Provot's cones
 * this ignores the contour test (a patch whose outline folds over itself
 * in projection), which a compact patch of a mesh does not do in practice.
 *
 * The cut. Breadth first from the root, the first 64 (or fewer) nodes whose
 * parents were expanded: their subtrees are refitted in parallel, and the
 * nodes above them (the top) on one thread after. */
#include "kernels/contact/triangle_bvh.h"
#include "common/edge_map.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SB_BVH_CUT 64
#define SB_FLAT_COSINE 0.5

typedef struct sb_bvh_builder {
    sb_triangle_bvh* bvh;
    double* centroids; /* 3 per triangle */
    uint32_t next;     /* the next free node */
    int axis;          /* of the current sort */
} sb_bvh_builder;

static sb_bvh_builder* sb_sorting; /* qsort has no context argument: set during a build, on one thread */

static int sb_compare_centroids(const void* a, const void* b) {
    uint32_t i = *(const uint32_t*)a, j = *(const uint32_t*)b;
    double x = sb_sorting->centroids[3 * (size_t)i + sb_sorting->axis];
    double y = sb_sorting->centroids[3 * (size_t)j + sb_sorting->axis];
    return x < y ? -1 : x > y ? 1 : (i > j) - (i < j);
}

/* The longest axis of the centroids of order[first, first + count). */
static int sb_longest_axis(const sb_bvh_builder* b, uint32_t first, uint32_t count) {
    double lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX}, hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    for (uint32_t k = first; k < first + count; k++)
        for (int a = 0; a < 3; a++) {
            double c = b->centroids[3 * (size_t)b->bvh->order[k] + a];
            lo[a] = c < lo[a] ? c : lo[a];
            hi[a] = c > hi[a] ? c : hi[a];
        }
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    return axis;
}

static void sb_build_node(sb_bvh_builder* b, uint32_t first, uint32_t count, uint32_t parent) {
    sb_triangle_bvh* bvh = b->bvh;
    uint32_t index = b->next++;
    sb_bvh_node* node = &bvh->nodes[index];
    node->first = first, node->count = count, node->parent = parent;
    node->leaf = count <= SB_BVH_LEAF;
    if (!node->leaf) {
        b->axis = sb_longest_axis(b, first, count);
        sb_sorting = b;
        qsort(bvh->order + first, count, sizeof *bvh->order, sb_compare_centroids);
        uint32_t half = count / 2;
        sb_build_node(b, first, half, index);
        sb_build_node(b, first + half, count - half, index);
    }
    bvh->nodes[index].end = b->next;
}

/* Up to three triangles that share an edge with each triangle, in free
 * slots (UINT32_MAX: none; a non-manifold edge links its first two). */
static uint32_t* sb_edge_neighbours(const sb_triangle_bvh* bvh) {
    uint32_t n = bvh->triangle_count, *across = malloc(3 * (size_t)n * sizeof *across);
    sb_edge_map map;
    if (!across || !sb_edge_map_init(&map, 3 * (size_t)n)) {
        free(across);
        return NULL;
    }
    for (size_t k = 0; k < 3 * (size_t)n; k++) across[k] = UINT32_MAX;
    for (uint32_t t = 0; t < n; t++)
        for (int e = 0; e < 3; e++) {
            bool inserted;
            uint32_t* first = sb_edge_map_upsert(&map, bvh->tri_v[e][t], bvh->tri_v[(e + 1) % 3][t], t, &inserted);
            if (inserted || *first == t) continue;
            uint32_t *a = across + 3 * (size_t)*first, *b = across + 3 * (size_t)t;
            int fa = 0, fb = 0;
            while (fa < 3 && a[fa] != UINT32_MAX) fa++;
            while (fb < 3 && b[fb] != UINT32_MAX) fb++;
            if (fa < 3 && fb < 3) a[fa] = t, b[fb] = *first;
        }
    sb_edge_map_free(&map);
    return across;
}

/* The corners of the triangles in leaf order, padded with the last one's. */
static void sb_copy_corners(sb_triangle_bvh* bvh) {
    uint32_t n = bvh->triangle_count;
    for (int c = 0; c < 3; c++)
        for (size_t k = 0; k < (size_t)n + 16; k++)
            bvh->corners.corner[c][k] = bvh->tri_v[c][bvh->order[k < n ? k : n - 1]];
}

/* Whether each node's triangles are edge-connected: a search from its first
 * triangle through neighbours inside the node's range reaches them all. */
static bool sb_mark_connected(sb_triangle_bvh* bvh) {
    uint32_t n = bvh->triangle_count, *across = sb_edge_neighbours(bvh);
    uint32_t *position = malloc((size_t)n * sizeof *position), *stack = malloc((size_t)n * sizeof *stack);
    uint32_t* seen = calloc(n, sizeof *seen); /* the node (+1) that last reached it */
    bool ok = across && position && stack && seen;
    for (uint32_t k = 0; ok && k < n; k++) position[bvh->order[k]] = k;
    for (uint32_t i = 0; ok && i < bvh->node_count; i++) {
        sb_bvh_node* node = &bvh->nodes[i];
        uint32_t top = 0, reached = 1, start = bvh->order[node->first];
        stack[top++] = start;
        seen[start] = i + 1;
        while (top) {
            uint32_t t = stack[--top];
            for (int e = 0; e < 3; e++) {
                uint32_t u = across[3 * (size_t)t + e];
                if (u == UINT32_MAX || seen[u] == i + 1) continue;
                if (position[u] < node->first || position[u] >= node->first + node->count) continue;
                seen[u] = i + 1;
                stack[top++] = u;
                reached++;
            }
        }
        node->connected = reached == node->count;
    }
    free(across), free(position), free(stack), free(seen);
    return ok;
}

/* The cut (breadth first, at most SB_BVH_CUT nodes) and the top above it. */
static bool sb_choose_cut(sb_triangle_bvh* bvh) {
    bvh->cut = malloc(SB_BVH_CUT * sizeof *bvh->cut);
    bvh->top = malloc(SB_BVH_CUT * sizeof *bvh->top);
    if (!bvh->cut || !bvh->top) return false;
    bvh->cut[0] = 0;
    bvh->cut_count = 1;
    bvh->top_count = 0;
    /* expand the largest non-leaf cut node while the cut has room for its two children */
    while (bvh->cut_count < SB_BVH_CUT) {
        uint32_t best = UINT32_MAX;
        for (uint32_t k = 0; k < bvh->cut_count; k++) {
            const sb_bvh_node* node = &bvh->nodes[bvh->cut[k]];
            if (!node->leaf && (best == UINT32_MAX || node->count > bvh->nodes[bvh->cut[best]].count)) best = k;
        }
        if (best == UINT32_MAX) break;
        uint32_t node = bvh->cut[best];
        bvh->top[bvh->top_count++] = node;
        bvh->cut[best] = node + 1;
        bvh->cut[bvh->cut_count++] = sb_bvh_right(bvh, node);
    }
    /* cut nodes in tree order; top nodes children first (decreasing index) */
    for (uint32_t i = 1; i < bvh->cut_count; i++)
        for (uint32_t j = i; j > 0 && bvh->cut[j - 1] > bvh->cut[j]; j--) {
            uint32_t t = bvh->cut[j];
            bvh->cut[j] = bvh->cut[j - 1], bvh->cut[j - 1] = t;
        }
    for (uint32_t i = 1; i < bvh->top_count; i++)
        for (uint32_t j = i; j > 0 && bvh->top[j - 1] < bvh->top[j]; j--) {
            uint32_t t = bvh->top[j];
            bvh->top[j] = bvh->top[j - 1], bvh->top[j - 1] = t;
        }
    return true;
}

sb_triangle_bvh* sb_triangle_bvh_create(uint32_t triangle_count, const uint32_t* const tri_v[3],
                                        const double* positions) {
    sb_triangle_bvh* bvh = calloc(1, sizeof *bvh);
    if (!bvh || triangle_count == 0) {
        free(bvh);
        return NULL;
    }
    bvh->triangle_count = triangle_count;
    for (int c = 0; c < 3; c++) bvh->tri_v[c] = tri_v[c];
    size_t nodes = 2 * (size_t)triangle_count; /* a binary tree over at most that many leaves */
    bvh->order = malloc(triangle_count * sizeof *bvh->order);
    bvh->nodes = calloc(nodes, sizeof *bvh->nodes);
    bvh->bounds = calloc(nodes, sizeof *bvh->bounds);
    bvh->culled = calloc(nodes, 1);
    sb_bvh_builder b = {.bvh = bvh, .centroids = malloc(3 * (size_t)triangle_count * sizeof(double))};
    if (!bvh->order || !bvh->nodes || !bvh->bounds || !bvh->culled || !b.centroids) {
        free(b.centroids);
        sb_triangle_bvh_destroy(bvh);
        return NULL;
    }
    for (uint32_t t = 0; t < triangle_count; t++) {
        bvh->order[t] = t;
        for (int a = 0; a < 3; a++) {
            double sum = 0.0;
            for (int c = 0; c < 3; c++) sum += positions[3 * (size_t)tri_v[c][t] + a];
            b.centroids[3 * (size_t)t + a] = sum / 3.0;
        }
    }
    sb_build_node(&b, 0, triangle_count, UINT32_MAX);
    sb_sorting = NULL;
    free(b.centroids);
    bvh->node_count = b.next;
    bool ok = true;
    size_t padded = (size_t)triangle_count + 16;
    for (int c = 0; c < 3; c++) ok = ok && (bvh->corners.corner[c] = malloc(padded * sizeof(uint32_t))) != NULL;
    if (ok) sb_copy_corners(bvh);
    for (int j = 0; j < 9; j++) ok = ok && (bvh->scratch.value[j] = malloc(padded * sizeof(sb_real))) != NULL;
    if (!ok || !sb_mark_connected(bvh) || !sb_choose_cut(bvh)) {
        sb_triangle_bvh_destroy(bvh);
        return NULL;
    }
    return bvh;
}

bool sb_triangle_bvh_retopologize(sb_triangle_bvh* bvh, const uint8_t* dead) {
    sb_copy_corners(bvh);
    if (!sb_mark_connected(bvh)) return false;
    for (uint32_t i = 0; dead && i < bvh->node_count; i++) {
        sb_bvh_node* node = &bvh->nodes[i];
        for (uint32_t k = node->first; node->connected && k < node->first + node->count; k++)
            node->connected = !dead[bvh->order[k]];
    }
    return true;
}

void sb_triangle_bvh_destroy(sb_triangle_bvh* bvh) {
    if (!bvh) return;
    for (int c = 0; c < 3; c++) free(bvh->corners.corner[c]);
    for (int j = 0; j < 9; j++) free(bvh->scratch.value[j]);
    free(bvh->order), free(bvh->nodes), free(bvh->bounds), free(bvh->culled);
    free(bvh->cut), free(bvh->top);
    free(bvh);
}

/* Whether the normal box [lo, hi] lies within the cone of SB_FLAT_COSINE
 * about its center d: the least n·d over the box, Σ min(lo d, hi d), is
 * above SB_FLAT_COSINE |d| (squared, so no root is taken). */
static bool sb_normals_flat(const float normals[6]) {
    float d[3], length2 = 0.0f, least = 0.0f;
    for (int k = 0; k < 3; k++) {
        d[k] = 0.5f * (normals[k] + normals[3 + k]);
        length2 += d[k] * d[k];
    }
    for (int k = 0; k < 3; k++) {
        float a = normals[k] * d[k], b = normals[3 + k] * d[k];
        least += a < b ? a : b;
    }
    return least > 0.0f && least * least > (float)(SB_FLAT_COSINE * SB_FLAT_COSINE) * length2;
}

/* A float box corner moved outward past any rounding of the margin's sum. */
static float sb_outward(float x, float margin, float sign) { return x + sign * (margin + fabsf(x) * 4e-7f); }

/* A leaf from its triangles' bounds (the scratch the subtree's pass filled). */
static void sb_refit_leaf(sb_triangle_bvh* bvh, uint32_t i, double margin) {
    const sb_bvh_node* node = &bvh->nodes[i];
    sb_real extreme[9];
    for (int j = 0; j < 9; j++) extreme[j] = bvh->scratch.value[j][node->first];
    sb_real normal_lo[3] = {extreme[6], extreme[7], extreme[8]};
    for (uint32_t k = node->first + 1; k < node->first + node->count; k++)
        for (int a = 0; a < 3; a++) {
            sb_real lo = bvh->scratch.value[a][k], hi = bvh->scratch.value[3 + a][k], n = bvh->scratch.value[6 + a][k];
            extreme[a] = lo < extreme[a] ? lo : extreme[a];
            extreme[3 + a] = hi > extreme[3 + a] ? hi : extreme[3 + a];
            normal_lo[a] = n < normal_lo[a] ? n : normal_lo[a];
            extreme[6 + a] = n > extreme[6 + a] ? n : extreme[6 + a];
        }
    sb_bvh_bounds* b = &bvh->bounds[i];
    for (int a = 0; a < 3; a++) {
        /* float of a double position rounds by at most half an ulp, which
         * the outward step covers */
        b->box[a] = sb_outward((float)extreme[a], (float)margin, -1.0f);
        b->box[3 + a] = sb_outward((float)extreme[3 + a], (float)margin, 1.0f);
        b->normals[a] = (float)normal_lo[a] - 1e-5f;
        b->normals[3 + a] = (float)extreme[6 + a] + 1e-5f;
    }
}

static void sb_refit_inner(sb_triangle_bvh* bvh, uint32_t i) {
    const sb_bvh_bounds *l = &bvh->bounds[i + 1], *r = &bvh->bounds[sb_bvh_right(bvh, i)];
    sb_bvh_bounds* b = &bvh->bounds[i];
    for (int a = 0; a < 3; a++) {
        b->box[a] = l->box[a] < r->box[a] ? l->box[a] : r->box[a];
        b->box[3 + a] = l->box[3 + a] > r->box[3 + a] ? l->box[3 + a] : r->box[3 + a];
        b->normals[a] = l->normals[a] < r->normals[a] ? l->normals[a] : r->normals[a];
        b->normals[3 + a] = l->normals[3 + a] > r->normals[3 + a] ? l->normals[3 + a] : r->normals[3 + a];
    }
}

bool sb_triangle_bvh_flat(const sb_triangle_bvh* bvh, uint32_t node) {
    return bvh->nodes[node].connected && sb_normals_flat(bvh->bounds[node].normals);
}

void sb_triangle_bvh_refit_subtree(sb_triangle_bvh* bvh, uint32_t root, const sb_real* from4, const sb_real* to4,
                                   double margin) {
    const sb_bvh_node* r = &bvh->nodes[root];
    sb_fast_triangle_bounds(&bvh->corners, from4, to4, r->first, r->first + r->count, &bvh->scratch);
    for (uint32_t i = bvh->nodes[root].end; i-- > root;) {
        if (bvh->nodes[i].leaf)
            sb_refit_leaf(bvh, i, margin);
        else
            sb_refit_inner(bvh, i);
    }
}

void sb_triangle_bvh_refit_top(sb_triangle_bvh* bvh) {
    for (uint32_t k = 0; k < bvh->top_count; k++) sb_refit_inner(bvh, bvh->top[k]);
    /* culled, parents first: the top in increasing index, then the cut */
    for (uint32_t k = bvh->top_count; k-- > 0;) {
        uint32_t i = bvh->top[k], parent = bvh->nodes[i].parent;
        bvh->culled[i] = sb_triangle_bvh_flat(bvh, i) || (parent != UINT32_MAX && bvh->culled[parent]);
    }
    for (uint32_t k = 0; k < bvh->cut_count; k++) {
        uint32_t i = bvh->cut[k], parent = bvh->nodes[i].parent;
        bvh->culled[i] = sb_triangle_bvh_flat(bvh, i) || (parent != UINT32_MAX && bvh->culled[parent]);
    }
}

uint32_t sb_triangle_bvh_common(const sb_triangle_bvh* bvh, uint32_t a, uint32_t b) {
    /* in pre-order, a node's ancestors have smaller indices and their subtree covers it */
    while (!(a <= b && b < bvh->nodes[a].end)) a = bvh->nodes[a].parent;
    return a;
}
