/* sb_mesh_simplify: level of detail with meshoptimizer's quadric edge
 * collapse (meshopt_simplify, C API of Debian's libmeshoptimizer 0.18).
 *
 * - Boundary vertices: meshopt_SimplifyLockBorder (present in 0.18) locks
 *   every vertex on an open edge, so a sheet keeps its outline.
 * - Locked (fixed) vertices: 0.18 has no per-vertex lock (vertex_lock came
 *   in 0.21). meshopt classifies a position shared by three or more vertex
 *   copies ("wedges") as locked, and an edge whose reverse is missing as
 *   open. So each locked vertex is given one private copy per triangle
 *   around it before simplifying: it becomes locked, and its ring
 *   neighbours see open edges and are locked as border vertices too. The
 *   copies are mapped back afterwards. A locked vertex therefore keeps its
 *   1-ring as well (conservative: a few vertices more than asked).
 * - The target vertex count is met by a few passes from the original: meshopt
 *   takes a triangle count, started at T * target / V and scaled by the
 *   ratio of the vertices obtained to those wanted.
 * - The result keeps the vertices still used, in their original order;
 *   with keep_locked_indices each locked vertex is then swapped to its own
 *   original index (so a scene's `fixed` indices still name them).
 * Positions go to meshopt in float; the output positions are the original
 * doubles, bitwise. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <meshoptimizer.h>

#include "common/error.h"
#include "softbond/mesh.h"

sb_simplify_def sb_default_simplify_def(void) { return (sb_simplify_def){.target_vertices = 0, .target_error = 0.0}; }

/* The input to meshopt: float positions and indices, each locked vertex
 * split into one copy per incident triangle. copy_of[v] = source vertex. */
typedef struct work {
    float* positions;
    unsigned* indices;
    uint32_t* copy_of;
    size_t vertex_count, index_count;
} work;

static void work_free(work* w) {
    free(w->positions);
    free(w->indices);
    free(w->copy_of);
}

static bool work_build(const sb_mesh* mesh, const bool* locked, work* w) {
    size_t n = mesh->vertex_count, ni = 3 * (size_t)mesh->triangle_count, extra = 0;
    for (size_t i = 0; i < ni; i++) {
        extra += locked[mesh->triangles[i]];
    }
    w->vertex_count = n + extra;
    w->index_count = ni;
    w->positions = malloc(3 * w->vertex_count * sizeof(float));
    w->indices = malloc((ni ? ni : 1) * sizeof(unsigned));
    w->copy_of = malloc(w->vertex_count * sizeof(uint32_t));
    if (!w->positions || !w->indices || !w->copy_of) {
        return false;
    }
    for (size_t v = 0; v < n; v++) {
        for (int k = 0; k < 3; k++) {
            w->positions[3 * v + k] = (float)mesh->positions[3 * v + k];
        }
        w->copy_of[v] = (uint32_t)v;
    }
    size_t next = n;
    for (size_t i = 0; i < ni; i++) {
        uint32_t v = mesh->triangles[i];
        if (!locked[v]) {
            w->indices[i] = v;
            continue;
        }
        memcpy(w->positions + 3 * next, w->positions + 3 * (size_t)v, 3 * sizeof(float));
        w->copy_of[next] = v;
        w->indices[i] = (unsigned)next++;
    }
    return true;
}

/* Vertices used by the indices (source numbering). */
static size_t count_used(const work* w, const unsigned* indices, size_t count, uint8_t* used, size_t n) {
    memset(used, 0, n);
    size_t total = 0;
    for (size_t i = 0; i < count; i++) {
        uint32_t v = w->copy_of[indices[i]];
        total += !used[v];
        used[v] = 1;
    }
    return total;
}

/* Twice the area squared against the longest edge: zero to rounding. The
 * middle vertex (opposite the longest edge) is returned in *middle. */
static bool sliver(const double* p, const uint32_t* t, int* middle) {
    const double *a = p + 3 * (size_t)t[0], *b = p + 3 * (size_t)t[1], *c = p + 3 * (size_t)t[2];
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k], v[k] = c[k] - a[k], w[k] = c[k] - b[k];
    }
    double n0 = u[1] * v[2] - u[2] * v[1], n1 = u[2] * v[0] - u[0] * v[2], n2 = u[0] * v[1] - u[1] * v[0];
    double ab = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    double ac = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    double bc = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    double longest = fmax(ab, fmax(ac, bc));
    *middle = longest == bc ? 0 : longest == ac ? 1 : 2;
    return n0 * n0 + n1 * n1 + n2 * n2 <= 1e-24 * longest * longest;
}

/* On a flat region meshopt may leave a sliver: three collinear vertices,
 * (a, b, c) with b between a and c, typically along a locked boundary. Its
 * neighbour across a-c, (a, c, x), and it form the quad a b c x: flipping
 * the diagonal gives (a, b, x) and (b, c, x), both with area. A sliver with
 * no neighbour across its long edge is left for the compile to report. */
static size_t repair_pass(const double* positions, uint32_t* tri, size_t triangle_count) {
    size_t flips = 0;
    for (size_t s = 0; s < triangle_count; s++) {
        int m;
        uint32_t* t = tri + 3 * s;
        if (!sliver(positions, t, &m)) {
            continue;
        }
        uint32_t b = t[m], c = t[(m + 1) % 3], a = t[(m + 2) % 3];
        for (size_t o = 0; o < triangle_count; o++) {
            uint32_t* u = tri + 3 * o;
            int k = 0;
            while (k < 3 && !(u[k] == a && u[(k + 1) % 3] == c)) {
                k++;
            }
            if (o == s || k == 3) {
                continue;
            }
            uint32_t x = u[(k + 2) % 3];
            t[0] = a, t[1] = b, t[2] = x;
            u[0] = b, u[1] = c, u[2] = x;
            flips++;
            break;
        }
    }
    return flips;
}

/* Flips until no sliver is left or a pass changes nothing (at most 16). */
static void repair_slivers(const double* positions, uint32_t* tri, size_t triangle_count) {
    for (int pass = 0; pass < 16 && repair_pass(positions, tri, triangle_count) > 0; pass++) {
    }
}

/* The new mesh from the simplified indices; origin[new] = old. */
static sb_status compact(sb_mesh* mesh, const work* w, const unsigned* indices, size_t count, const uint8_t* used,
                         size_t kept, const sb_simplify_def* def, uint32_t* origin_out, sb_error* err) {
    size_t n = mesh->vertex_count;
    uint32_t* origin = malloc((kept ? kept : 1) * sizeof(uint32_t));
    uint32_t* place = malloc(n * sizeof(uint32_t));
    double* positions = malloc(3 * (kept ? kept : 1) * sizeof(double));
    uint32_t* triangles = malloc((count ? count : 1) * sizeof(uint32_t));
    if (!origin || !place || !positions || !triangles) {
        free(origin), free(place), free(positions), free(triangles);
        return sb_error_set(err, SB_ERR_NOMEM, "sb_mesh_simplify: out of memory");
    }
    size_t next = 0;
    for (size_t v = 0; v < n; v++) {
        place[v] = used[v] ? (uint32_t)next : UINT32_MAX;
        if (used[v]) {
            origin[next++] = (uint32_t)v;
        }
    }
    for (uint32_t i = 0; def->keep_locked_indices && i < def->locked_count; i++) {
        uint32_t f = def->locked[i], at = place[f];
        if (at == UINT32_MAX || f >= kept) {
            free(origin), free(place), free(positions), free(triangles);
            return sb_error_set(err, SB_ERR_INVALID,
                                "sb_mesh_simplify: a locked vertex's index is beyond the simplified vertex count "
                                "(cannot keep its index)");
        }
        uint32_t other = origin[f];
        origin[f] = f, place[f] = f;
        origin[at] = other, place[other] = at;
    }
    for (size_t v = 0; v < kept; v++) {
        memcpy(positions + 3 * v, mesh->positions + 3 * (size_t)origin[v], 3 * sizeof(double));
    }
    for (size_t i = 0; i < count; i++) {
        triangles[i] = place[w->copy_of[indices[i]]];
    }
    repair_slivers(positions, triangles, count / 3);
    if (origin_out != NULL) {
        memcpy(origin_out, origin, kept * sizeof(uint32_t));
    }
    free(origin);
    free(place);
    sb_mesh_free(mesh);
    mesh->positions = positions;
    mesh->vertex_count = (uint32_t)kept;
    mesh->triangles = triangles;
    mesh->triangle_count = (uint32_t)(count / 3);
    return SB_OK;
}

sb_status sb_mesh_simplify(sb_mesh* mesh, const sb_simplify_def* def, uint32_t* origin, sb_simplify_report* report,
                           sb_error* err) {
    if (mesh == NULL || def == NULL) {
        return sb_error_set(err, SB_ERR_INVALID, "sb_mesh_simplify: no mesh or no settings");
    }
    if (!(def->target_error >= 0.0) || !isfinite(def->target_error)) {
        return sb_error_set(err, SB_ERR_INVALID, "sb_mesh_simplify: target_error must be finite and >= 0");
    }
    size_t n = mesh->vertex_count;
    for (uint32_t i = 0; i < def->locked_count; i++) {
        if (def->locked[i] >= n) {
            return sb_error_set(err, SB_ERR_INVALID, "sb_mesh_simplify: a locked vertex is out of range");
        }
    }
    sb_simplify_report r = {.vertices_before = mesh->vertex_count, .triangles_before = mesh->triangle_count};
    bool* locked = calloc(n ? n : 1, sizeof(bool));
    uint8_t* used = malloc(n ? n : 1);
    work w = {0};
    unsigned* out = NULL;
    sb_status status = SB_OK;
    if (!locked || !used) {
        status = sb_error_set(err, SB_ERR_NOMEM, "sb_mesh_simplify: out of memory");
        goto done;
    }
    for (uint32_t i = 0; i < def->locked_count; i++) {
        locked[def->locked[i]] = true;
    }
    if (!work_build(mesh, locked, &w) || !(out = malloc((w.index_count ? w.index_count : 1) * sizeof(unsigned)))) {
        status = sb_error_set(err, SB_ERR_NOMEM, "sb_mesh_simplify: out of memory");
        goto done;
    }
    float target_error = def->target_error > 0.0 ? (float)def->target_error : FLT_MAX;
    size_t count = w.index_count, kept = count_used(&w, w.indices, count, used, n);
    float error = 0.0f;
    if (def->target_vertices == 0 && def->target_error > 0.0) {
        count = meshopt_simplify(out, w.indices, w.index_count, w.positions, w.vertex_count, 3 * sizeof(float), 0,
                                 target_error, meshopt_SimplifyLockBorder, &error);
        kept = count_used(&w, out, count, used, n);
    } else if (def->target_vertices > 0 && def->target_vertices < kept) {
        double want = def->target_vertices, triangles = (double)mesh->triangle_count * want / (double)kept;
        for (int pass = 0; pass < 6; pass++) {
            size_t target = 3 * (size_t)fmax(1.0, floor(triangles));
            count = meshopt_simplify(out, w.indices, w.index_count, w.positions, w.vertex_count, 3 * sizeof(float),
                                     target, target_error, meshopt_SimplifyLockBorder, &error);
            kept = count_used(&w, out, count, used, n);
            if (kept <= want * 1.02 || count <= 3 || count > target * 1.5) {
                break; /* near enough, or locked vertices stop it */
            }
            triangles *= want / (double)kept;
        }
    } else {
        memcpy(out, w.indices, count * sizeof(unsigned));
    }
    count_used(&w, out, count, used, n);
    status = compact(mesh, &w, out, count, used, kept, def, origin, err);
    r.vertices_after = mesh->vertex_count;
    r.triangles_after = mesh->triangle_count;
    r.error = error;
done:
    if (report != NULL && status == SB_OK) {
        *report = r;
    }
    free(locked);
    free(used);
    free(out);
    work_free(&w);
    return status;
}
