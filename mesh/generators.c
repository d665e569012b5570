/* Procedural meshes for tests, the demo and benchmarks: a rectangular sheet
 * and an icosphere.
 *
 * Sheet. Vertex (row, col) is row * nx + col at x = col * width / (nx - 1),
 * y = row * height / (ny - 1), z = 0. Quad (row, col) is split along the
 * diagonal (row, col)-(row+1, col+1) when row + col is even and along the
 * other one when it is odd, a checkerboard, so the sheet has no preferred
 * shear direction; with parallel_diagonals every quad along (row, col)-
 * (row+1, col+1), which the plate bending's stencils suit (every interior
 * vertex has six neighbours; at the checkerboard's four-neighbour vertices
 * they feel an oscillation, mesh/plate_stencils.h). Every triangle is counter-clockwise seen from +z. Jitter
 * moves each interior vertex by independent uniform offsets in
 * [-jitter * dx, jitter * dx] and [-jitter * dy, jitter * dy] (dx, dy the
 * spacings), drawn from splitmix64 seeded with `seed`, two draws per
 * interior vertex in vertex order: the same def gives the same mesh on every
 * machine. jitter < 1/6 keeps every triangle counter-clockwise whatever the
 * draws (the worst case doubled area is (1 - 6 jitter) dx dy); up to the
 * limit of 0.5 a triangle can, rarely, fold over.
 *
 * Icosphere. The 12 vertices (0, ±1, ±φ) and cyclic permutations, and the
 * 20 faces, found as the triples of mutually adjacent vertices, each turned
 * to face outwards. Each subdivision splits every triangle into four through
 * its edge midpoints, projected onto the unit sphere. A midpoint is shared by
 * the two triangles of its edge through per-vertex edge lists (each edge
 * stored once, under its lower vertex, found by a scan of about three
 * entries), built by a counting pass: a level costs time linear in its size
 * and touches memory mostly in order, so a 2.6M-vertex sphere (s = 9) takes
 * a fraction of a second. Vertices are the 12
 * corners, then each level's midpoints in order of creation; the sphere is
 * scaled by the radius at the end. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/error.h"
#include "softbond/mesh.h"

/* ---- sheet --------------------------------------------------------------- */

sb_sheet_def sb_default_sheet_def(void) {
    sb_sheet_def def = {
        .nx = 10, .ny = 10, .width = 1.0, .height = 1.0, .jitter = 0.0, .seed = 1, .parallel_diagonals = false};
    return def;
}

static uint64_t splitmix64(uint64_t* state) {
    uint64_t z = (*state += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return z ^ (z >> 31);
}

/* Uniform in [-1, 1). */
static double uniform_signed(uint64_t* state) { return (double)(splitmix64(state) >> 11) * 0x1.0p-52 - 1.0; }

static sb_status check_sheet(const sb_sheet_def* def, sb_error* err) {
    if (def->nx < 2 || def->ny < 2) {
        return sb_error_set(err, SB_ERR_INVALID, "sheet: nx and ny must be at least 2 (got %u x %u)", def->nx, def->ny);
    }
    if (!(isfinite(def->width) && def->width > 0) || !(isfinite(def->height) && def->height > 0)) {
        return sb_error_set(err, SB_ERR_INVALID, "sheet: width and height must be positive and finite (got %g x %g)",
                            def->width, def->height);
    }
    if (!(def->jitter >= 0 && def->jitter < 0.5)) {
        return sb_error_set(err, SB_ERR_INVALID, "sheet: jitter must be in [0, 0.5) (got %g)", def->jitter);
    }
    uint64_t vertices = (uint64_t)def->nx * def->ny;
    uint64_t triangles = 2 * (uint64_t)(def->nx - 1) * (def->ny - 1);
    if (vertices > UINT32_MAX || triangles > UINT32_MAX) {
        return sb_error_set(err, SB_ERR_INVALID, "sheet: %u x %u needs more than 2^32-1 vertices or triangles", def->nx,
                            def->ny);
    }
    return SB_OK;
}

static double grid_coordinate(uint32_t index, uint32_t count, double length) {
    return index == count - 1 ? length : (double)index * length / (double)(count - 1);
}

static void sheet_positions(const sb_sheet_def* def, double* positions) {
    uint32_t nx = def->nx, ny = def->ny;
    double dx = def->width / (nx - 1), dy = def->height / (ny - 1);
    uint64_t rng = def->seed;
    for (uint32_t row = 0; row < ny; row++) {
        for (uint32_t col = 0; col < nx; col++) {
            double* p = positions + 3 * ((size_t)row * nx + col);
            p[0] = grid_coordinate(col, nx, def->width);
            p[1] = grid_coordinate(row, ny, def->height);
            p[2] = 0.0;
            bool interior = row > 0 && row + 1 < ny && col > 0 && col + 1 < nx;
            if (interior && def->jitter > 0) {
                p[0] += def->jitter * dx * uniform_signed(&rng);
                p[1] += def->jitter * dy * uniform_signed(&rng);
            }
        }
    }
}

static void sheet_triangles(uint32_t nx, uint32_t ny, bool parallel_diagonals, uint32_t* triangles) {
    uint32_t* t = triangles;
    for (uint32_t row = 0; row + 1 < ny; row++) {
        for (uint32_t col = 0; col + 1 < nx; col++) {
            uint32_t a = row * nx + col; /* (col, row) */
            uint32_t b = a + 1;          /* (col+1, row) */
            uint32_t c = a + nx;         /* (col, row+1) */
            uint32_t d = c + 1;          /* (col+1, row+1) */
            uint32_t quad[6];
            if (parallel_diagonals || (row + col) % 2 == 0) { /* diagonal a-d */
                uint32_t q[6] = {a, b, d, a, d, c};
                memcpy(quad, q, sizeof q);
            } else { /* diagonal b-c */
                uint32_t q[6] = {a, b, c, b, d, c};
                memcpy(quad, q, sizeof q);
            }
            memcpy(t, quad, sizeof quad);
            t += 6;
        }
    }
}

sb_status sb_mesh_generate_sheet(const sb_sheet_def* def, sb_mesh* out, sb_error* err) {
    if (out == NULL) {
        return sb_error_set(err, SB_ERR_INVALID, "sheet: no output mesh");
    }
    memset(out, 0, sizeof *out);
    if (def == NULL) {
        return sb_error_set(err, SB_ERR_INVALID, "sheet: no definition");
    }
    sb_status status = check_sheet(def, err);
    if (status != SB_OK) {
        return status;
    }
    size_t vertices = (size_t)def->nx * def->ny;
    size_t triangles = 2 * (size_t)(def->nx - 1) * (def->ny - 1);
    double* positions = malloc(3 * vertices * sizeof(double));
    uint32_t* indices = malloc(3 * triangles * sizeof(uint32_t));
    if (positions == NULL || indices == NULL) {
        free(positions);
        free(indices);
        return sb_error_set(err, SB_ERR_NOMEM, "sheet: out of memory");
    }
    sheet_positions(def, positions);
    sheet_triangles(def->nx, def->ny, def->parallel_diagonals, indices);
    out->vertex_count = (uint32_t)vertices;
    out->positions = positions;
    out->triangle_count = (uint32_t)triangles;
    out->triangles = indices;
    return SB_OK;
}

/* ---- icosphere ----------------------------------------------------------- */

enum { ICOSPHERE_MAX_SUBDIVISIONS = 10 }; /* 10,485,762 vertices */

static void icosahedron_vertices(double* p) {
    const double phi = (1.0 + sqrt(5.0)) / 2.0;
    const double s = 1.0 / sqrt(1.0 + phi * phi); /* onto the unit sphere */
    int v = 0;
    for (int axis = 0; axis < 3; axis++) {
        for (int a = -1; a <= 1; a += 2) {
            for (int b = -1; b <= 1; b += 2) {
                double q[3];
                q[axis] = 0.0;
                q[(axis + 1) % 3] = a * s;
                q[(axis + 2) % 3] = b * phi * s;
                memcpy(p + 3 * v++, q, sizeof q);
            }
        }
    }
}

static double distance2(const double* a, const double* b) {
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

/* The 20 faces: triples of vertices at edge distance from each other. */
static void icosahedron_faces(const double* p, uint32_t* t) {
    double edge2 = INFINITY;
    for (int i = 1; i < 12; i++) {
        edge2 = fmin(edge2, distance2(p, p + 3 * i));
    }
    int f = 0;
    for (uint32_t i = 0; i < 12; i++) {
        for (uint32_t j = i + 1; j < 12; j++) {
            for (uint32_t k = j + 1; k < 12; k++) {
                const double *a = p + 3 * i, *b = p + 3 * j, *c = p + 3 * k;
                double tol = 1e-9;
                if (fabs(distance2(a, b) - edge2) > tol || fabs(distance2(b, c) - edge2) > tol ||
                    fabs(distance2(c, a) - edge2) > tol) {
                    continue;
                }
                double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
                double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
                double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
                bool outward =
                    n[0] * (a[0] + b[0] + c[0]) + n[1] * (a[1] + b[1] + c[1]) + n[2] * (a[2] + b[2] + c[2]) > 0;
                t[3 * f + 0] = i;
                t[3 * f + 1] = outward ? j : k;
                t[3 * f + 2] = outward ? k : j;
                f++;
            }
        }
    }
}

/* The edges of a closed, consistently oriented mesh, each stored once under
 * its lower vertex (in a closed oriented mesh every edge a-b, a < b, is
 * walked a->b by exactly one triangle): edges of vertex a are
 * upper[first[a] .. first[a + 1]) with their midpoints in mid[]. */
typedef struct edge_lists {
    uint32_t* first; /* vertex_count + 1 */
    uint32_t* upper;
    uint32_t* mid;
} edge_lists;

static void edge_lists_free(edge_lists* e) {
    free(e->first);
    free(e->upper);
    free(e->mid);
}

static bool edge_lists_alloc(edge_lists* e, uint32_t vertex_count, uint32_t triangle_count) {
    size_t edges = (size_t)triangle_count * 3 / 2;
    e->first = calloc((size_t)vertex_count + 1, sizeof(uint32_t));
    e->upper = malloc(edges * sizeof(uint32_t));
    e->mid = malloc(edges * sizeof(uint32_t));
    if (e->first == NULL || e->upper == NULL || e->mid == NULL) {
        edge_lists_free(e);
        return false;
    }
    return true;
}

/* Creates the midpoint of every edge, numbered in order of the triangles
 * that walk the edge upwards, and appends its position. */
static void make_midpoints(edge_lists* e, double* positions, uint32_t* vertex_count, const uint32_t* triangles,
                           uint32_t triangle_count) {
    uint32_t n = *vertex_count;
    for (size_t i = 0; i < 3 * (size_t)triangle_count; i++) {
        uint32_t a = triangles[i], b = triangles[i % 3 == 2 ? i - 2 : i + 1];
        if (a < b) {
            e->first[a + 1]++;
        }
    }
    for (uint32_t v = 0; v < n; v++) {
        e->first[v + 1] += e->first[v];
    }
    for (size_t i = 0; i < 3 * (size_t)triangle_count; i++) {
        uint32_t a = triangles[i], b = triangles[i % 3 == 2 ? i - 2 : i + 1];
        if (a >= b) {
            continue;
        }
        uint32_t slot = e->first[a]++; /* first[a] now runs ahead; fixed below */
        uint32_t v = (*vertex_count)++;
        const double *pa = positions + 3 * (size_t)a, *pb = positions + 3 * (size_t)b;
        double m[3] = {pa[0] + pb[0], pa[1] + pb[1], pa[2] + pb[2]};
        double scale = 1.0 / sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        double* pv = positions + 3 * (size_t)v;
        pv[0] = m[0] * scale;
        pv[1] = m[1] * scale;
        pv[2] = m[2] * scale;
        e->upper[slot] = b;
        e->mid[slot] = v;
    }
    /* Each first[a] advanced to the start of a + 1: shift back. */
    for (uint32_t v = n; v > 0; v--) {
        e->first[v] = e->first[v - 1];
    }
    e->first[0] = 0;
}

static uint32_t midpoint(const edge_lists* e, uint32_t a, uint32_t b) {
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    uint32_t i = e->first[lo];
    while (e->upper[i] != hi) {
        i++; /* the edge exists: the mesh is closed */
    }
    return e->mid[i];
}

/* One level: `triangle_count` triangles in `from` become four times as many
 * in `to`; new vertices are appended to positions. */
static void subdivide(edge_lists* e, double* positions, uint32_t* vertex_count, const uint32_t* from,
                      uint32_t triangle_count, uint32_t* to) {
    make_midpoints(e, positions, vertex_count, from, triangle_count);
    for (uint32_t f = 0; f < triangle_count; f++) {
        uint32_t a = from[3 * f], b = from[3 * f + 1], c = from[3 * f + 2];
        uint32_t ab = midpoint(e, a, b);
        uint32_t bc = midpoint(e, b, c);
        uint32_t ca = midpoint(e, c, a);
        uint32_t q[12] = {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca};
        memcpy(to + 12 * (size_t)f, q, sizeof q);
    }
}

sb_status sb_mesh_generate_icosphere(uint32_t subdivisions, double radius, sb_mesh* out, sb_error* err) {
    if (out == NULL) {
        return sb_error_set(err, SB_ERR_INVALID, "icosphere: no output mesh");
    }
    memset(out, 0, sizeof *out);
    if (subdivisions > ICOSPHERE_MAX_SUBDIVISIONS) {
        return sb_error_set(err, SB_ERR_INVALID, "icosphere: subdivisions must be at most %d (got %u)",
                            ICOSPHERE_MAX_SUBDIVISIONS, subdivisions);
    }
    if (!(isfinite(radius) && radius > 0)) {
        return sb_error_set(err, SB_ERR_INVALID, "icosphere: radius must be positive and finite (got %g)", radius);
    }
    size_t levels = (size_t)1 << (2 * subdivisions); /* 4^s */
    size_t vertices = 10 * levels + 2, triangles = 20 * levels;
    double* positions = malloc(3 * vertices * sizeof(double));
    uint32_t* current = malloc(3 * triangles * sizeof(uint32_t));
    uint32_t* next = subdivisions > 0 ? malloc(3 * triangles * sizeof(uint32_t)) : NULL;
    if (positions == NULL || current == NULL || (subdivisions > 0 && next == NULL)) {
        free(positions);
        free(current);
        free(next);
        return sb_error_set(err, SB_ERR_NOMEM, "icosphere: out of memory");
    }
    icosahedron_vertices(positions);
    icosahedron_faces(positions, current);
    uint32_t vertex_count = 12, triangle_count = 20;
    for (uint32_t level = 0; level < subdivisions; level++) {
        edge_lists edges;
        if (!edge_lists_alloc(&edges, vertex_count, triangle_count)) {
            free(positions);
            free(current);
            free(next);
            return sb_error_set(err, SB_ERR_NOMEM, "icosphere: out of memory");
        }
        subdivide(&edges, positions, &vertex_count, current, triangle_count, next);
        edge_lists_free(&edges);
        triangle_count *= 4;
        uint32_t* swap = current;
        current = next;
        next = swap;
    }
    for (size_t i = 0; i < 3 * (size_t)vertex_count; i++) {
        positions[i] *= radius;
    }
    free(next);
    out->vertex_count = vertex_count;
    out->positions = positions;
    out->triangle_count = triangle_count;
    out->triangles = current;
    return SB_OK;
}
