/* The triangle mesh's sweep (collider_internal.h): a static or kinematic
 * collider made of a triangle mesh (softbond/collider.h, SB_COLLIDER_MESH).
 *
 * What is solid. A closed mesh (every edge on exactly two triangles,
 * consistently oriented) bounds a volume; the solid is that volume
 * inflated by the thickness t: the points inside it or within t of its
 * surface. An open mesh (a boundary edge, or an edge on three or more
 * triangles) bounds nothing; its solid is the shell of the points within
 * t of its surface, so t must be > 0 (the collider's own thickness; the
 * solver's is added to it). Signed distance sd (> 0 outside the volume;
 * an open mesh has no inside, sd = the distance): a point is in the solid
 * when sd <= t, depth t − sd, and its normal of least penetration points
 * from the nearest surface point to it (outside) or from it to the nearest
 * point (inside the volume).
 *
 * Why a bounding-volume hierarchy and not a signed-distance grid. The
 * sweep contract asks for the first point of a move in the solid and the
 * exact depth and normal at its ends; a grid answers with trilinear
 * interpolation, rounds edges and corners off by a cell, needs a fine
 * grid (memory cubic in the resolution) to keep a thin wall from being
 * lost between samples, and a fast vertex still needs a ray march through
 * it. A BVH of axis-aligned boxes over the triangles answers exactly (as
 * exactly as the analytic shapes: the tests compare a cube mesh with the
 * box), costs 2 nodes per triangle, and a query visits O(log n) nodes.
 * Built once when the collider is made (top down, split at the median of
 * the triangles' centroids along the widest axis, at most 4 triangles a
 * leaf); the triangles are stored in leaf order.
 *
 * The queries, each a walk of the tree with a stack:
 *   nearest   the nearest triangle to a point (children nearest first;
 *             a node, or a leaf's triangle by its own box, farther than
 *             the best so far is skipped). Inside or outside a closed
 *             mesh is the sign of (x − q)·N, q the nearest point and N
 *             the angle-weighted pseudo-normal of the feature q lies on
 *             (face, edge or corner; Bærentzen and Aanæs 2005), exact for
 *             a closed, consistently oriented mesh. An open mesh's ends
 *             need only the triangles within t;
 *   entry     the earliest point of the move in the solid, for a move from
 *             outside: the nodes whose box grown by t the move's segment
 *             crosses before the best entry so far; per triangle (unless
 *             its own box grown by t misses the segment, or both ends lie
 *             beyond t on one side of its plane), for t > 0 the line's
 *             interval in the rounded triangle (the triangle grown by t:
 *             its prism |height| <= t and the capsules of its edges, a
 *             convex union), normal from the triangle's nearest point; for
 *             t = 0 (closed only) the move crossing a face against its
 *             outward normal.
 * A move from outside never reaches the volume without first coming
 * within t of the surface, so the entry is the solid's. */
#include "kernels/contact/colliders/mesh_shape.h"
#include "kernels/contact/colliders/capsule.h"
#include "kernels/contact/colliders/triangle_point.h"
#include "kernels/contact/colliders/sweep.h"
#include "common/edge_map.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SB_MESH_LEAF 4
/* Deeper than any median-split tree of 2^32 triangles. */
#define SB_MESH_STACK 64
/* The edge map's mark of an edge already on two triangles. */
#define SB_EDGE_PAIRED UINT32_MAX

typedef struct sb_mesh_node {
    double box[6];         /* lo x y z, hi x y z */
    uint32_t first, count; /* a leaf's triangles; count 0: an inner node */
    uint32_t right;        /* an inner node's right child (its left is the next node) */
} sb_mesh_node;

struct sb_mesh_shape {
    sb_mesh mesh;
    bool closed;
    double* face_normals;   /* 3 per triangle, unit, outward when closed */
    double* triangle_boxes; /* 6 per triangle: lo x y z, hi x y z (a leaf's triangles tested by their own box first) */
    double* edge_normals;   /* 9 per triangle: edge k (corner k to k + 1), unit sum of its faces' normals */
    double* vertex_normals; /* 3 per vertex: the angle-weighted sum of its faces' normals, unit */
    uint8_t* sharp;         /* 3 per triangle: edge k is a ridge (convex, not flat) or a shell's rim */
    sb_mesh_node* nodes;
    uint32_t node_count;
    double tiny; /* m: nearer the surface than this, the direction to it is noise: the pseudo-normal serves */
};

/* ---- small vector helpers --------------------------------------------------- */

static double sb_dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void sb_sub(const double a[3], const double b[3], double out[3]) {
    for (int k = 0; k < 3; k++) out[k] = a[k] - b[k];
}

static void sb_cross(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* v / |v|; false (v left) when v is zero. */
static bool sb_normalize(double v[3]) {
    double length = sqrt(sb_dot(v, v));
    if (!(length > 0.0)) return false;
    for (int k = 0; k < 3; k++) v[k] /= length;
    return true;
}

static const double* sb_corner(const sb_mesh_shape* m, uint32_t triangle, int k) {
    return m->mesh.positions + 3 * (size_t)m->mesh.triangles[3 * (size_t)triangle + (uint32_t)k];
}

/* ---- checking and copying ----------------------------------------------------- */

static sb_status sb_mesh_check(const char* label, const sb_mesh* mesh, sb_error* err) {
    if (mesh->triangle_count == 0)
        return sb_error_set(err, SB_ERR_INVALID, "collider '%s': the mesh has no triangles", label);
    if (!mesh->positions || !mesh->triangles)
        return sb_error_set(err, SB_ERR_INVALID, "collider '%s': the mesh's positions or triangles are NULL", label);
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        const double* p = mesh->positions + 3 * (size_t)v;
        if (!(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2])))
            return sb_error_set(err, SB_ERR_INVALID, "collider '%s': mesh vertex %u is not finite (%g, %g, %g)", label,
                                v, p[0], p[1], p[2]);
    }
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t* c = mesh->triangles + 3 * (size_t)t;
        for (int k = 0; k < 3; k++)
            if (c[k] >= mesh->vertex_count)
                return sb_error_set(err, SB_ERR_INVALID,
                                    "collider '%s': mesh triangle %u has vertex %u but the mesh has %u vertices", label,
                                    t, c[k], mesh->vertex_count);
        const double *a = mesh->positions + 3 * (size_t)c[0], *b = mesh->positions + 3 * (size_t)c[1],
                     *d = mesh->positions + 3 * (size_t)c[2];
        double ab[3], ad[3], n[3];
        sb_sub(b, a, ab);
        sb_sub(d, a, ad);
        sb_cross(ab, ad, n);
        if (!(sb_dot(n, n) > 0.0))
            return sb_error_set(err, SB_ERR_INVALID,
                                "collider '%s': mesh triangle %u (vertices %u, %u, %u) has no area", label, t, c[0],
                                c[1], c[2]);
    }
    return SB_OK;
}

/* ---- the hierarchy ------------------------------------------------------------ */

static void sb_triangle_box(const sb_mesh_shape* m, uint32_t t, double box[6]) {
    for (int k = 0; k < 3; k++) box[k] = INFINITY, box[3 + k] = -INFINITY;
    for (int c = 0; c < 3; c++) {
        const double* p = sb_corner(m, t, c);
        for (int k = 0; k < 3; k++) box[k] = fmin(box[k], p[k]), box[3 + k] = fmax(box[3 + k], p[k]);
    }
}

static void sb_swap(uint32_t* a, uint32_t* b) {
    uint32_t t = *a;
    *a = *b;
    *b = t;
}

/* Puts the order's k-th smallest key (of order[0, count)) at k, none
 * larger before it and none smaller after it (quickselect). */
static void sb_select(uint32_t* order, int64_t count, int64_t k, const double* key) {
    int64_t lo = 0, hi = count - 1;
    while (lo < hi) {
        sb_swap(&order[lo + (hi - lo) / 2], &order[hi]);
        double pivot = key[order[hi]];
        int64_t store = lo;
        for (int64_t i = lo; i < hi; i++)
            if (key[order[i]] < pivot) sb_swap(&order[i], &order[store++]);
        sb_swap(&order[store], &order[hi]);
        if (k == store) return;
        if (k < store)
            hi = store - 1;
        else
            lo = store + 1;
    }
}

typedef struct sb_mesh_build {
    sb_mesh_shape* m;
    uint32_t* order;      /* triangle indices, partitioned in place */
    double* boxes;        /* 6 per triangle */
    double* centroid_key; /* one axis of the centroids at a time, per triangle */
} sb_mesh_build;

/* The node over order[first, first + count); returns its index. */
static uint32_t sb_build_node(sb_mesh_build* b, uint32_t first, uint32_t count) {
    sb_mesh_shape* m = b->m;
    uint32_t index = m->node_count++;
    sb_mesh_node* node = &m->nodes[index];
    double centroid_lo[3] = {INFINITY, INFINITY, INFINITY}, centroid_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int k = 0; k < 3; k++) node->box[k] = INFINITY, node->box[3 + k] = -INFINITY;
    for (uint32_t i = first; i < first + count; i++) {
        const double* box = b->boxes + 6 * (size_t)b->order[i];
        for (int k = 0; k < 3; k++) {
            node->box[k] = fmin(node->box[k], box[k]);
            node->box[3 + k] = fmax(node->box[3 + k], box[3 + k]);
            double c = 0.5 * (box[k] + box[3 + k]);
            centroid_lo[k] = fmin(centroid_lo[k], c);
            centroid_hi[k] = fmax(centroid_hi[k], c);
        }
    }
    node->first = first;
    node->count = count;
    if (count <= SB_MESH_LEAF) return index;
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if (centroid_hi[k] - centroid_lo[k] > centroid_hi[axis] - centroid_lo[axis]) axis = k;
    for (uint32_t i = first; i < first + count; i++) {
        const double* box = b->boxes + 6 * (size_t)b->order[i];
        b->centroid_key[b->order[i]] = box[axis] + box[3 + axis];
    }
    uint32_t half = count / 2;
    if (centroid_hi[axis] > centroid_lo[axis]) /* (all at one point: any split will do) */
        sb_select(b->order + first, count, half, b->centroid_key);
    node->count = 0;
    sb_build_node(b, first, half);
    node->right = sb_build_node(b, first + half, count - half);
    return index;
}

/* Builds the tree and puts the triangles in its leaf order. */
static bool sb_build_tree(sb_mesh_shape* m) {
    uint32_t n = m->mesh.triangle_count;
    sb_mesh_build b = {m, malloc(n * sizeof *b.order), malloc(6 * (size_t)n * sizeof *b.boxes),
                       malloc(n * sizeof *b.centroid_key)};
    uint32_t* sorted = malloc(3 * (size_t)n * sizeof *sorted);
    m->nodes = malloc(2 * (size_t)n * sizeof *m->nodes);
    bool ok = b.order && b.boxes && b.centroid_key && sorted && m->nodes;
    if (ok) {
        for (uint32_t t = 0; t < n; t++) {
            b.order[t] = t;
            sb_triangle_box(m, t, b.boxes + 6 * (size_t)t);
        }
        m->node_count = 0;
        sb_build_node(&b, 0, n);
        for (uint32_t i = 0; i < n; i++) memcpy(sorted + 3 * (size_t)i, m->mesh.triangles + 3 * (size_t)b.order[i], 12);
        memcpy(m->mesh.triangles, sorted, 3 * (size_t)n * sizeof *sorted);
    }
    free(b.order);
    free(b.boxes);
    free(b.centroid_key);
    free(sorted);
    return ok;
}

/* ---- edges: closed or open, orientation --------------------------------------- */

typedef struct sb_edge_report {
    uint32_t boundary, non_manifold;
    bool inconsistent;
    uint32_t a, b, t0, t1; /* the first edge used the same way twice, and its triangles */
} sb_edge_report;

/* Pairs each half-edge 3 t + k (corner k to k + 1) with the other use of
 * its edge (twin, UINT32_MAX for none) and reports what is not closed. */
static bool sb_pair_edges(const sb_mesh_shape* m, uint32_t* twin, sb_edge_report* report) {
    size_t half_edges = 3 * (size_t)m->mesh.triangle_count;
    const uint32_t* tri = m->mesh.triangles;
    sb_edge_map map;
    if (!sb_edge_map_init(&map, half_edges)) return false;
    memset(report, 0, sizeof *report);
    for (size_t h = 0; h < half_edges; h++) twin[h] = UINT32_MAX;
    for (size_t h = 0; h < half_edges; h++) {
        uint32_t a = tri[h], b = tri[h - h % 3 + (h + 1) % 3];
        bool inserted;
        uint32_t* first = sb_edge_map_upsert(&map, a, b, (uint32_t)h, &inserted);
        if (inserted) continue;
        if (*first == SB_EDGE_PAIRED) {
            report->non_manifold++;
            continue;
        }
        uint32_t g = *first;
        if (tri[g] == a && !report->inconsistent) { /* the other use runs the same way */
            report->inconsistent = true;
            report->a = a, report->b = b, report->t0 = g / 3, report->t1 = (uint32_t)(h / 3);
        }
        twin[h] = g;
        twin[g] = (uint32_t)h;
        *first = SB_EDGE_PAIRED;
    }
    for (size_t h = 0; h < half_edges; h++) report->boundary += twin[h] == UINT32_MAX;
    sb_edge_map_free(&map);
    return true;
}

/* Six times the signed volume the triangles bound (> 0 when they face out). */
static double sb_signed_volume(const sb_mesh_shape* m) {
    double volume = 0.0;
    for (uint32_t t = 0; t < m->mesh.triangle_count; t++) {
        double n[3];
        sb_cross(sb_corner(m, t, 1), sb_corner(m, t, 2), n);
        volume += sb_dot(sb_corner(m, t, 0), n);
    }
    return volume;
}

static void sb_flip_triangles(sb_mesh_shape* m) {
    for (uint32_t t = 0; t < m->mesh.triangle_count; t++) {
        uint32_t* c = m->mesh.triangles + 3 * (size_t)t;
        uint32_t swap = c[1];
        c[1] = c[2];
        c[2] = swap;
    }
}

/* ---- normals -------------------------------------------------------------------- */

static void sb_compute_normals(sb_mesh_shape* m, const uint32_t* twin) {
    uint32_t nt = m->mesh.triangle_count;
    for (uint32_t t = 0; t < nt; t++) {
        double ab[3], ac[3], *n = m->face_normals + 3 * (size_t)t;
        sb_sub(sb_corner(m, t, 1), sb_corner(m, t, 0), ab);
        sb_sub(sb_corner(m, t, 2), sb_corner(m, t, 0), ac);
        sb_cross(ab, ac, n);
        sb_normalize(n);
    }
    memset(m->vertex_normals, 0, 3 * (size_t)m->mesh.vertex_count * sizeof *m->vertex_normals);
    for (uint32_t t = 0; t < nt; t++) {
        const double* n = m->face_normals + 3 * (size_t)t;
        for (int k = 0; k < 3; k++) {
            size_t h = 3 * (size_t)t + (size_t)k;
            double *e = m->edge_normals + 3 * h, u[3], w[3];
            const double* other = twin[h] == UINT32_MAX ? n : m->face_normals + 3 * (size_t)(twin[h] / 3);
            for (int j = 0; j < 3; j++) e[j] = n[j] + other[j];
            if (!sb_normalize(e)) memcpy(e, n, 3 * sizeof *e); /* a fold flat onto itself */
            sb_sub(sb_corner(m, t, (k + 1) % 3), sb_corner(m, t, k), u);
            sb_sub(sb_corner(m, t, (k + 2) % 3), sb_corner(m, t, k), w);
            sb_normalize(u);
            sb_normalize(w);
            double angle = acos(fmax(-1.0, fmin(1.0, sb_dot(u, w))));
            double* v = m->vertex_normals + 3 * (size_t)m->mesh.triangles[h];
            for (int j = 0; j < 3; j++) v[j] += angle * n[j];
        }
    }
    for (uint32_t v = 0; v < m->mesh.vertex_count; v++) sb_normalize(m->vertex_normals + 3 * (size_t)v);
}

/* A ridge bends the surface away from its faces' planes by more than
 * SB_RIDGE_COS: a feature a surface between vertices can rest on, where a
 * flat or concave edge lies in or under the surface the vertices meet. */
#define SB_RIDGE_COS 0.9998 /* 1.1° */

static void sb_find_ridges(sb_mesh_shape* m, const uint32_t* twin) {
    for (size_t h = 0; h < 3 * (size_t)m->mesh.triangle_count; h++) {
        if (twin[h] == UINT32_MAX) {
            m->sharp[h] = 1;
            continue;
        }
        uint32_t t = (uint32_t)(h / 3), u = twin[h] / 3;
        const double *n = m->face_normals + 3 * (size_t)t, *other = m->face_normals + 3 * (size_t)u;
        double away[3]; /* from the edge to the neighbour's third corner */
        sb_sub(sb_corner(m, u, (int)((twin[h] % 3 + 2) % 3)), sb_corner(m, t, (int)(h % 3)), away);
        m->sharp[h] = sb_dot(n, other) < SB_RIDGE_COS && sb_dot(n, away) < 0.0;
    }
}

/* ---- making and destroying ---------------------------------------------------- */

void sb_mesh_shape_destroy(sb_mesh_shape* m) {
    if (!m) return;
    sb_mesh_free(&m->mesh);
    free(m->face_normals);
    free(m->triangle_boxes);
    free(m->edge_normals);
    free(m->vertex_normals);
    free(m->sharp);
    free(m->nodes);
    free(m);
}

static bool sb_mesh_shape_allocate(sb_mesh_shape* m, const sb_mesh* mesh) {
    size_t nv = mesh->vertex_count, nt = mesh->triangle_count;
    m->mesh.vertex_count = mesh->vertex_count;
    m->mesh.triangle_count = mesh->triangle_count;
    m->mesh.positions = malloc(3 * nv * sizeof *m->mesh.positions);
    m->mesh.triangles = malloc(3 * nt * sizeof *m->mesh.triangles);
    m->face_normals = malloc(3 * nt * sizeof *m->face_normals);
    m->triangle_boxes = malloc(6 * nt * sizeof *m->triangle_boxes);
    m->edge_normals = malloc(9 * nt * sizeof *m->edge_normals);
    m->vertex_normals = malloc(3 * nv * sizeof *m->vertex_normals);
    m->sharp = malloc(3 * nt * sizeof *m->sharp);
    if (!m->mesh.positions || !m->mesh.triangles || !m->face_normals || !m->triangle_boxes || !m->edge_normals ||
        !m->vertex_normals || !m->sharp)
        return false;
    memcpy(m->mesh.positions, mesh->positions, 3 * nv * sizeof *m->mesh.positions);
    memcpy(m->mesh.triangles, mesh->triangles, 3 * nt * sizeof *m->mesh.triangles);
    return true;
}

/* Closed or open (a closed one consistently oriented and turned outward);
 * an open one needs a thickness. */
static sb_status sb_mesh_topology(const char* label, sb_mesh_shape* m, uint32_t* twin, double thickness,
                                  sb_error* err) {
    sb_edge_report r;
    if (!sb_pair_edges(m, twin, &r)) return sb_error_set(err, SB_ERR_NOMEM, "collider '%s': out of memory", label);
    m->closed = r.boundary == 0 && r.non_manifold == 0;
    if (m->closed && r.inconsistent)
        return sb_error_set(err, SB_ERR_INVALID,
                            "collider '%s': the mesh is closed but not consistently oriented: edge %u-%u runs the "
                            "same way in triangles %u and %u (in the collider's order)",
                            label, r.a, r.b, r.t0, r.t1);
    if (!m->closed && !(thickness > 0.0))
        return sb_error_set(err, SB_ERR_INVALID,
                            "collider '%s': the mesh is open (%u boundary and %u non-manifold edge uses), so it is a "
                            "shell of the collider's thickness around its surface: thickness must be > 0 (got %g)",
                            label, r.boundary, r.non_manifold, thickness);
    if (m->closed && sb_signed_volume(m) < 0.0) { /* it faces in */
        sb_flip_triangles(m);
        if (!sb_pair_edges(m, twin, &r)) return sb_error_set(err, SB_ERR_NOMEM, "collider '%s': out of memory", label);
    }
    return SB_OK;
}

sb_mesh_shape* sb_mesh_shape_create(const char* label, const sb_mesh* mesh, double thickness, sb_error* err) {
    if (!mesh) {
        sb_error_set(err, SB_ERR_INVALID, "collider '%s': a mesh collider needs a mesh (mesh is NULL)", label);
        return NULL;
    }
    if (sb_mesh_check(label, mesh, err)) return NULL;
    sb_mesh_shape* m = calloc(1, sizeof *m);
    uint32_t* twin = malloc(3 * (size_t)mesh->triangle_count * sizeof *twin);
    if (!m || !twin || !sb_mesh_shape_allocate(m, mesh) || !sb_build_tree(m)) {
        sb_error_set(err, SB_ERR_NOMEM, "collider '%s': out of memory", label);
        sb_mesh_shape_destroy(m);
        free(twin);
        return NULL;
    }
    if (sb_mesh_topology(label, m, twin, thickness, err)) {
        sb_mesh_shape_destroy(m);
        free(twin);
        return NULL;
    }
    sb_compute_normals(m, twin);
    sb_find_ridges(m, twin);
    free(twin);
    for (uint32_t t = 0; t < mesh->triangle_count; t++) sb_triangle_box(m, t, m->triangle_boxes + 6 * (size_t)t);
    const double* box = m->nodes[0].box;
    double diagonal[3] = {box[3] - box[0], box[4] - box[1], box[5] - box[2]};
    m->tiny = 1e-9 * sqrt(sb_dot(diagonal, diagonal));
    return m;
}

const sb_mesh* sb_mesh_shape_mesh(const sb_mesh_shape* m) { return &m->mesh; }

void sb_mesh_shape_box(const sb_mesh_shape* m, double box[6]) { memcpy(box, m->nodes[0].box, 6 * sizeof *box); }

/* ---- the nearest point ---------------------------------------------------------- */

/* Where on a triangle its nearest point lies. */
enum { SB_ON_FACE = 0, SB_ON_CORNER = 1, SB_ON_EDGE = 4 }; /* + k for corner k, edge k (corner k to k + 1) */

/* The nearest point q of triangle (a, b, c) to p and its feature (Ericson,
 * Real-Time Collision Detection, 5.1.5). */
static int sb_nearest_on_triangle(const double p[3], const double a[3], const double b[3], const double c[3],
                                  double q[3]) {
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    sb_sub(b, a, ab);
    sb_sub(c, a, ac);
    sb_sub(p, a, ap);
    double d1 = sb_dot(ab, ap), d2 = sb_dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) {
        memcpy(q, a, 3 * sizeof *q);
        return SB_ON_CORNER;
    }
    sb_sub(p, b, bp);
    double d3 = sb_dot(ab, bp), d4 = sb_dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) {
        memcpy(q, b, 3 * sizeof *q);
        return SB_ON_CORNER + 1;
    }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        double v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++) q[k] = a[k] + v * ab[k];
        return SB_ON_EDGE;
    }
    sb_sub(p, c, cp);
    double d5 = sb_dot(ab, cp), d6 = sb_dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) {
        memcpy(q, c, 3 * sizeof *q);
        return SB_ON_CORNER + 2;
    }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        double w = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++) q[k] = a[k] + w * ac[k];
        return SB_ON_EDGE + 2;
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++) q[k] = b[k] + w * (c[k] - b[k]);
        return SB_ON_EDGE + 1;
    }
    double denominator = 1.0 / (va + vb + vc), v = vb * denominator, w = vc * denominator;
    for (int k = 0; k < 3; k++) q[k] = a[k] + v * ab[k] + w * ac[k];
    return SB_ON_FACE;
}

typedef struct sb_mesh_nearest_hit {
    double d2, q[3];
    uint32_t triangle;
    int feature;
} sb_mesh_nearest_hit;

static double sb_box_distance2(const double box[6], const double x[3]) {
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double gap = x[k] < box[k] ? box[k] - x[k] : x[k] > box[3 + k] ? x[k] - box[3 + k] : 0.0;
        d2 += gap * gap;
    }
    return d2;
}

static void sb_nearest_in_leaf(const sb_mesh_shape* m, const sb_mesh_node* node, const double x[3],
                               sb_mesh_nearest_hit* hit, bool* found) {
    for (uint32_t t = node->first; t < node->first + node->count; t++) {
        if (sb_box_distance2(m->triangle_boxes + 6 * (size_t)t, x) > hit->d2) continue;
        double q[3], v[3];
        int feature = sb_nearest_on_triangle(x, sb_corner(m, t, 0), sb_corner(m, t, 1), sb_corner(m, t, 2), q);
        sb_sub(x, q, v);
        double d2 = sb_dot(v, v);
        if (d2 < hit->d2 || (!*found && d2 <= hit->d2)) {
            hit->d2 = d2;
            memcpy(hit->q, q, sizeof hit->q);
            hit->triangle = t;
            hit->feature = feature;
            *found = true;
        }
    }
}

/* The nearest triangle to x no farther than sqrt(reach2); false for none. */
static bool sb_mesh_nearest(const sb_mesh_shape* m, const double x[3], double reach2, sb_mesh_nearest_hit* hit) {
    bool found = false;
    uint32_t stack[SB_MESH_STACK], top = 0;
    hit->d2 = reach2;
    stack[top++] = 0;
    while (top) {
        const sb_mesh_node* node = &m->nodes[stack[--top]];
        if (sb_box_distance2(node->box, x) > hit->d2) continue;
        if (node->count) {
            sb_nearest_in_leaf(m, node, x, hit, &found);
            continue;
        }
        uint32_t left = (uint32_t)(node - m->nodes) + 1, right = node->right;
        bool left_first = sb_box_distance2(m->nodes[left].box, x) <= sb_box_distance2(m->nodes[right].box, x);
        stack[top++] = left_first ? right : left; /* the nearer child is taken first */
        stack[top++] = left_first ? left : right;
    }
    return found;
}

/* The unit pseudo-normal of the feature the nearest point lies on. */
static const double* sb_pseudo_normal(const sb_mesh_shape* m, const sb_mesh_nearest_hit* hit) {
    size_t t = hit->triangle;
    if (hit->feature >= SB_ON_EDGE) return m->edge_normals + 9 * t + 3 * (size_t)(hit->feature - SB_ON_EDGE);
    if (hit->feature >= SB_ON_CORNER)
        return m->vertex_normals + 3 * (size_t)m->mesh.triangles[3 * t + (size_t)(hit->feature - SB_ON_CORNER)];
    return m->face_normals + 3 * t;
}

/* One end of a move (collider_internal.h's sb_sweep_end). */
static void sb_mesh_end(const sb_mesh_shape* m, const double x[3], double t, sb_sweep_end* end) {
    memset(end, 0, sizeof *end);
    sb_mesh_nearest_hit hit;
    /* a closed mesh needs the nearest triangle however far (inside or out); an open one only those within t */
    double reach = m->closed ? INFINITY : t;
    if (sb_box_distance2(m->nodes[0].box, x) > t * t || !sb_mesh_nearest(m, x, reach * reach, &hit)) return;
    double v[3], d = sqrt(hit.d2);
    const double* pseudo = sb_pseudo_normal(m, &hit);
    sb_sub(x, hit.q, v);
    bool in_volume = m->closed && sb_dot(v, pseudo) < 0.0;
    if (!in_volume && d > t) return;
    end->inside = true;
    end->depth = in_volume ? t + d : t - d;
    /* over a face the direction is its normal (x − q rounded is not quite); on an edge or a corner, the way from
     * the nearest point to x (out of the volume); right on the surface, the pseudo-normal */
    double side = in_volume || sb_dot(v, pseudo) >= 0.0 ? 1.0 : -1.0; /* an open mesh's side of x */
    for (int k = 0; k < 3; k++)
        end->normal[k] = d <= m->tiny                ? pseudo[k]
                         : hit.feature == SB_ON_FACE ? side * pseudo[k]
                                                     : (in_volume ? -v[k] : v[k]) / d;
}

/* ---- the entry of a move ------------------------------------------------------- */

/* Whether the segment from + s d, s in [0, limit], meets the box grown by g
 * (plain comparisons: fmin and fmax are a library call each, and this is
 * the walk's inner test). */
static bool sb_segment_meets_box(const double box[6], double g, const double from[3], const double d[3], double limit) {
    double s0 = 0.0, s1 = limit;
    for (int k = 0; k < 3; k++) {
        double lo = box[k] - g, hi = box[3 + k] + g;
        if (d[k] == 0.0) {
            if (from[k] < lo || from[k] > hi) return false;
            continue;
        }
        double a = (lo - from[k]) / d[k], b = (hi - from[k]) / d[k];
        if (a > b) {
            double swap = a;
            a = b;
            b = swap;
        }
        s0 = a > s0 ? a : s0;
        s1 = b < s1 ? b : s1;
        if (s0 > s1) return false;
    }
    return true;
}

/* Clips [lo, hi] of the line from + s d to the half-space m·x <= c. */
static bool sb_clip(const double m[3], double c, const double from[3], const double d[3], double* lo, double* hi) {
    double f = sb_dot(m, from) - c, g = sb_dot(m, d);
    if (g == 0.0) return f <= 0.0;
    double s = -f / g;
    if (g > 0.0)
        *hi = fmin(*hi, s);
    else
        *lo = fmax(*lo, s);
    return *lo <= *hi;
}

/* The line's interval in triangle t's prism (its points at height <= r
 * above or below it, over the triangle). */
static bool sb_prism_line(const sb_mesh_shape* m, uint32_t t, double r, const double from[3], const double d[3],
                          double* lo, double* hi) {
    const double* n = m->face_normals + 3 * (size_t)t;
    const double* a = sb_corner(m, t, 0);
    double below[3] = {-n[0], -n[1], -n[2]}, height = sb_dot(n, a);
    *lo = -INFINITY, *hi = INFINITY;
    if (!sb_clip(n, height + r, from, d, lo, hi) || !sb_clip(below, r - height, from, d, lo, hi)) return false;
    for (int k = 0; k < 3; k++) { /* the side through edge k: (edge × n)·x <= its value at corner k */
        double edge[3], side[3];
        const double* p = sb_corner(m, t, k);
        sb_sub(sb_corner(m, t, (k + 1) % 3), p, edge);
        sb_cross(edge, n, side);
        if (!sb_clip(side, sb_dot(side, p), from, d, lo, hi)) return false;
    }
    return true;
}

/* The line's interval in triangle t grown by r > 0: its prism and the
 * capsules of its edges (a convex union, so one interval). */
static bool sb_rounded_triangle_line(const sb_mesh_shape* m, uint32_t t, double r, const double from[3],
                                     const double to[3], double* lo, double* hi) {
    double d[3], l, h, unused[3];
    sb_sub(to, from, d);
    bool entered = sb_prism_line(m, t, r, from, d, lo, hi);
    for (int k = 0; k < 3; k++) {
        if (!sb_capsule_line(sb_corner(m, t, k), sb_corner(m, t, (k + 1) % 3), r, from, to, &l, &h, unused)) continue;
        *lo = entered ? fmin(*lo, l) : l;
        *hi = entered ? fmax(*hi, h) : h;
        entered = true;
    }
    return entered;
}

/* Where the segment from + s d (s in [0, 1]) crosses triangle t against
 * its outward normal (Möller and Trumbore; a hair of slack on the edges, so
 * that a move through an edge crosses one of its triangles). */
static bool sb_triangle_crossing(const sb_mesh_shape* m, uint32_t t, const double from[3], const double d[3],
                                 double* s) {
    const double* n = m->face_normals + 3 * (size_t)t;
    if (!(sb_dot(d, n) < 0.0)) return false;
    const double *a = sb_corner(m, t, 0), slack = 1e-12;
    double e1[3], e2[3], p[3], q[3], w[3];
    sb_sub(sb_corner(m, t, 1), a, e1);
    sb_sub(sb_corner(m, t, 2), a, e2);
    sb_cross(d, e2, p);
    double det = sb_dot(e1, p);
    if (det == 0.0) return false;
    sb_sub(from, a, w);
    double u = sb_dot(w, p) / det;
    if (u < -slack || u > 1.0 + slack) return false;
    sb_cross(w, e1, q);
    double v = sb_dot(d, q) / det;
    if (v < -slack || u + v > 1.0 + slack) return false;
    *s = sb_dot(e2, q) / det;
    return *s >= 0.0 && *s <= 1.0;
}

typedef struct sb_mesh_entry {
    bool entered;
    double lo, hi;
    uint32_t triangle;
} sb_mesh_entry;

static void sb_entry_in_leaf(const sb_mesh_shape* m, const sb_mesh_node* node, const double from[3], const double to[3],
                             const double d[3], double t, sb_mesh_entry* e) {
    for (uint32_t i = node->first; i < node->first + node->count; i++) {
        if (!sb_segment_meets_box(m->triangle_boxes + 6 * (size_t)i, t + m->tiny, from, d, e->entered ? e->lo : 1.0))
            continue;
        double below_from[3], height0, height1; /* both ends beyond t on one side of its plane: it is never reached */
        sb_sub(from, sb_corner(m, i, 0), below_from);
        height0 = sb_dot(m->face_normals + 3 * (size_t)i, below_from);
        height1 = height0 + sb_dot(m->face_normals + 3 * (size_t)i, d);
        if ((height0 > t && height1 > t) || (height0 < -t && height1 < -t)) continue;
        double lo, hi = INFINITY; /* t = 0: past a face crossed inward lies the volume */
        bool met = t > 0.0 ? sb_rounded_triangle_line(m, i, t, from, to, &lo, &hi) && lo < hi && lo <= 1.0 && hi >= 0.0
                           : sb_triangle_crossing(m, i, from, d, &lo);
        if (met && (!e->entered || lo < e->lo)) *e = (sb_mesh_entry){true, lo, hi, i};
    }
}

/* The earliest entry of the move into the solid, for a move from outside:
 * its interval's start lo and the end hi of the entered triangle's piece,
 * and the outward normal at lo. */
static bool sb_mesh_first_entry(const sb_mesh_shape* m, const double from[3], const double to[3], double t, double* lo,
                                double* hi, double normal[3]) {
    double d[3];
    sb_sub(to, from, d);
    sb_mesh_entry e = {false, INFINITY, INFINITY, 0};
    uint32_t stack[SB_MESH_STACK], top = 0;
    stack[top++] = 0;
    while (top) {
        uint32_t index = stack[--top];
        const sb_mesh_node* node = &m->nodes[index];
        if (!sb_segment_meets_box(node->box, t + m->tiny, from, d, fmin(e.lo, 1.0))) continue;
        if (node->count) {
            sb_entry_in_leaf(m, node, from, to, d, t, &e);
            continue;
        }
        stack[top++] = node->right;
        stack[top++] = index + 1;
    }
    if (!e.entered) return false;
    *lo = e.lo;
    *hi = e.hi;
    const double* face = m->face_normals + 3 * (size_t)e.triangle;
    double p[3], q[3], v[3];
    for (int k = 0; k < 3; k++) p[k] = from[k] + e.lo * d[k];
    sb_nearest_on_triangle(p, sb_corner(m, e.triangle, 0), sb_corner(m, e.triangle, 1), sb_corner(m, e.triangle, 2), q);
    sb_sub(p, q, v);
    bool direction = t > 0.0 && sb_normalize(v);
    memcpy(normal, direction ? v : face, 3 * sizeof *normal);
    return true;
}

bool sb_mesh_sweep(const sb_mesh_shape* m, const double from[3], const double to[3], double thickness, double* fraction,
                   double* depth, double normal[3]) {
    sb_sweep_end e0, e1;
    sb_mesh_end(m, from, thickness, &e0);
    if (e0.inside) {
        sb_mesh_end(m, to, thickness, &e1);
        return sb_sweep_from_inside(&e0, &e1, from, to, fraction, depth, normal);
    }
    double lo = 0.0, hi = 0.0, n[3] = {0.0, 0.0, 0.0};
    bool entered = sb_mesh_first_entry(m, from, to, thickness, &lo, &hi, n);
    memset(&e1, 0, sizeof e1);
    if (!entered) sb_mesh_end(m, to, thickness, &e1); /* `to` matters only when the entry was lost to rounding */
    return sb_sweep_from_outside(entered, lo, hi, n, &e1, fraction, depth, normal);
}

/* ---- the ridges against a triangle of a body's surface ----------------------------- */

static bool sb_boxes_overlap(const double a[6], const double b[6]) {
    for (int k = 0; k < 3; k++)
        if (a[k] > b[3 + k] || b[k] > a[3 + k]) return false;
    return true;
}

/* The ridges of a leaf's triangles in `box` against the triangle's move. */
static void sb_ridges_in_leaf(const sb_mesh_shape* m, const sb_mesh_node* node, const double box[6],
                              const double from[3][3], const double to[3][3], double* best, double w[3]) {
    for (uint32_t t = node->first; t < node->first + node->count; t++) {
        if (!sb_boxes_overlap(m->triangle_boxes + 6 * (size_t)t, box)) continue;
        for (int k = 0; k < 3; k++) {
            if (!m->sharp[3 * (size_t)t + k]) continue;
            double cw[3];
            double d2 = sb_triangle_swept_nearest(from, to, sb_corner(m, t, k), sb_corner(m, t, (k + 1) % 3), cw);
            if (d2 < *best) *best = d2, memcpy(w, cw, sizeof cw);
        }
    }
}

bool sb_mesh_triangle_point(const sb_mesh_shape* m, const double from[3][3], const double to[3][3], double reach,
                            double w[3]) {
    double box[6] = {INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY}, best = reach * reach;
    for (int j = 0; j < 3; j++)
        for (int k = 0; k < 3; k++) {
            box[k] = fmin(box[k], fmin(from[j][k], to[j][k]) - reach);
            box[3 + k] = fmax(box[3 + k], fmax(from[j][k], to[j][k]) + reach);
        }
    bool found = false;
    uint32_t stack[SB_MESH_STACK], top = 0;
    stack[top++] = 0;
    while (top) {
        uint32_t index = stack[--top];
        const sb_mesh_node* node = &m->nodes[index];
        if (!sb_boxes_overlap(node->box, box)) continue;
        if (node->count) {
            double before = best;
            sb_ridges_in_leaf(m, node, box, from, to, &best, w);
            found |= best < before;
            continue;
        }
        stack[top++] = node->right;
        stack[top++] = index + 1;
    }
    return found;
}
