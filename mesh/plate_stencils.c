/* The plate bending's stencils (mesh/plate_stencils.h).
 *
 * A triangle's stencil fits a quadratic to the rest-plane coordinates of
 * its corners, the three vertices across its edges (the flaps) and, where
 * those do not fix a quadratic (a triangle on the boundary, whose flaps
 * are missing, or six points on two lines), the nearest vertices of the
 * growing ring around it, one at a time, until they do: least squares over
 * those points, (Mᵀ M)⁻¹ Mᵀ with M's rows (1, x, y, x²/2, x y, y²/2),
 * coordinates about the triangle's centroid in units of its first edge.
 * The three last rows of (Mᵀ M)⁻¹ Mᵀ are the stencil: exact for every
 * quadratic field, so a plate bent to any constant curvature gets it on
 * every triangle. Six points of a corner and its flaps interpolate; a
 * boundary triangle's are a least-squares fit. */
#include "mesh/plate_stencils.h"
#include "common/geometry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A set of "well spread" points: the Cholesky pivots of Mᵀ M (scaled
 * coordinates) all above this fraction of their diagonal entries. */
#define SB_PLATE_PIVOT 1e-3

typedef struct sb_plane {
    sb_vec3 origin, u, w;
} sb_plane;

static sb_vec3 sb_mesh_point(const sb_mesh* mesh, uint32_t v) { return sb_v3(mesh->positions + 3 * (size_t)v); }

static bool sb_first_plane(const sb_mesh* mesh, sb_plane* plane, double* size) {
    if (!mesh->triangle_count) return false;
    const uint32_t* t = mesh->triangles;
    sb_vec3 a = sb_mesh_point(mesh, t[0]), e1 = sb_v3_sub(sb_mesh_point(mesh, t[1]), a),
            e2 = sb_v3_sub(sb_mesh_point(mesh, t[2]), a), n = sb_v3_cross(e1, e2);
    double ln = sb_v3_length(n), l1 = sb_v3_length(e1);
    if (!(ln > 0.0) || !(l1 > 0.0)) return false;
    n = sb_v3_scale(n, 1.0 / ln);
    plane->origin = a, plane->u = sb_v3_scale(e1, 1.0 / l1), plane->w = sb_v3_cross(n, plane->u);
    *size = 0.0;
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        *size = fmax(*size, sb_v3_length(sb_v3_sub(sb_mesh_point(mesh, v), a)));
    return true;
}

static bool sb_mesh_is_flat(const sb_mesh* mesh) {
    sb_plane plane;
    double size;
    if (!sb_first_plane(mesh, &plane, &size)) return false;
    sb_vec3 n = sb_v3_cross(plane.u, plane.w);
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        if (fabs(sb_v3_dot(sb_v3_sub(sb_mesh_point(mesh, v), plane.origin), n)) > 1e-9 * size) return false;
    return true;
}

/* The triangles at each vertex (CSR: start[v] .. start[v + 1]). */
typedef struct sb_vertex_triangles {
    uint32_t *start, *triangle;
} sb_vertex_triangles;

static bool sb_vertex_triangles_build(const sb_mesh* mesh, sb_vertex_triangles* vt) {
    vt->start = calloc((size_t)mesh->vertex_count + 1, sizeof *vt->start);
    vt->triangle = malloc(3 * (size_t)mesh->triangle_count * sizeof *vt->triangle + 1);
    if (!vt->start || !vt->triangle) return false;
    for (size_t k = 0; k < 3 * (size_t)mesh->triangle_count; k++) vt->start[mesh->triangles[k] + 1]++;
    for (uint32_t v = 0; v < mesh->vertex_count; v++) vt->start[v + 1] += vt->start[v];
    uint32_t* fill = malloc(((size_t)mesh->vertex_count + 1) * sizeof *fill);
    if (!fill) return false;
    memcpy(fill, vt->start, ((size_t)mesh->vertex_count + 1) * sizeof *fill);
    for (size_t k = 0; k < 3 * (size_t)mesh->triangle_count; k++)
        vt->triangle[fill[mesh->triangles[k]]++] = (uint32_t)(k / 3);
    free(fill);
    return true;
}

/* The vertex across edge (a, b) from triangle t, or UINT32_MAX. */
static uint32_t sb_flap(const sb_mesh* mesh, const sb_vertex_triangles* vt, uint32_t t, uint32_t a, uint32_t b) {
    for (uint32_t k = vt->start[a]; k < vt->start[a + 1]; k++) {
        uint32_t s = vt->triangle[k];
        if (s == t) continue;
        const uint32_t* q = mesh->triangles + 3 * (size_t)s;
        for (int c = 0; c < 3; c++)
            if (q[c] == b) return q[0] + q[1] + q[2] - a - b;
    }
    return UINT32_MAX;
}

static bool sb_has(const sb_plate_stencil* s, uint32_t v) {
    for (int a = 0; a < s->count; a++)
        if (s->v[a] == v) return true;
    return false;
}

/* The rows (1, x, y, x²/2, x y, y²/2) of the stencil's points about
 * `center`, in units of `unit`. */
static void sb_fit_rows(const sb_mesh* mesh, const sb_plane* plane, const sb_plate_stencil* s, sb_vec3 center,
                        double unit, double rows[SB_PLATE_NODES][6]) {
    for (int a = 0; a < s->count; a++) {
        sb_vec3 d = sb_v3_sub(sb_mesh_point(mesh, s->v[a]), center);
        double x = sb_v3_dot(d, plane->u) / unit, y = sb_v3_dot(d, plane->w) / unit;
        const double r[6] = {1.0, x, y, 0.5 * x * x, x * y, 0.5 * y * y};
        memcpy(rows[a], r, sizeof r);
    }
}

/* Cholesky of the 6 × 6 normal matrix in place (lower); false when a
 * pivot falls under SB_PLATE_PIVOT of its diagonal entry. */
static bool sb_normal_cholesky(double n[6][6]) {
    for (int j = 0; j < 6; j++) {
        double d = n[j][j];
        for (int p = 0; p < j; p++) d -= n[j][p] * n[j][p];
        if (!(d > SB_PLATE_PIVOT * n[j][j])) return false;
        n[j][j] = sqrt(d);
        for (int i = j + 1; i < 6; i++) {
            double v = n[i][j];
            for (int p = 0; p < j; p++) v -= n[i][p] * n[j][p];
            n[i][j] = v / n[j][j];
        }
    }
    return true;
}

/* The stencil's coefficients when its points fix a quadratic. */
static bool sb_fit(const sb_mesh* mesh, const sb_plane* plane, sb_plate_stencil* s, sb_vec3 center, double unit) {
    if (s->count < 6) return false;
    double rows[SB_PLATE_NODES][6], n[6][6] = {{0}};
    sb_fit_rows(mesh, plane, s, center, unit, rows);
    for (int a = 0; a < s->count; a++)
        for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++) n[i][j] += rows[a][i] * rows[a][j];
    if (!sb_normal_cholesky(n)) return false;
    for (int a = 0; a < s->count; a++) { /* column a of (Mᵀ M)⁻¹ Mᵀ: solve for row a of M */
        double y[6];
        for (int i = 0; i < 6; i++) {
            y[i] = rows[a][i];
            for (int p = 0; p < i; p++) y[i] -= n[i][p] * y[p];
            y[i] /= n[i][i];
        }
        for (int i = 6; i-- > 0;) {
            for (int p = i + 1; p < 6; p++) y[i] -= n[p][i] * y[p];
            y[i] /= n[i][i];
        }
        for (int ij = 0; ij < 3; ij++) s->c[ij][a] = y[3 + ij] / (unit * unit);
    }
    return true;
}

/* The vertex of the ring around the stencil's points nearest `center`,
 * not yet in it; UINT32_MAX when the ring is empty. */
static uint32_t sb_nearest_neighbour(const sb_mesh* mesh, const sb_vertex_triangles* vt, const sb_plate_stencil* s,
                                     sb_vec3 center) {
    uint32_t best = UINT32_MAX;
    double best_d = INFINITY;
    for (int a = 0; a < s->count; a++)
        for (uint32_t k = vt->start[s->v[a]]; k < vt->start[s->v[a] + 1]; k++) {
            const uint32_t* q = mesh->triangles + 3 * (size_t)vt->triangle[k];
            for (int c = 0; c < 3; c++) {
                double d = sb_v3_length(sb_v3_sub(sb_mesh_point(mesh, q[c]), center));
                if (!sb_has(s, q[c]) && (d < best_d || (d == best_d && q[c] < best))) best = q[c], best_d = d;
            }
        }
    return best;
}

static bool sb_triangle_stencil(const sb_mesh* mesh, const sb_vertex_triangles* vt, const sb_plane* plane, uint32_t t,
                                sb_plate_stencil* s) {
    const uint32_t* q = mesh->triangles + 3 * (size_t)t;
    memset(s, 0, sizeof *s);
    sb_vec3 p[3], center = {0.0, 0.0, 0.0};
    for (int c = 0; c < 3; c++) {
        s->v[s->count++] = q[c];
        p[c] = sb_mesh_point(mesh, q[c]);
        center = sb_v3_add(center, sb_v3_scale(p[c], 1.0 / 3.0));
    }
    s->area = 0.5 * sb_v3_length(sb_v3_cross(sb_v3_sub(p[1], p[0]), sb_v3_sub(p[2], p[0])));
    for (int c = 0; c < 3; c++) {
        uint32_t flap = sb_flap(mesh, vt, t, q[c], q[(c + 1) % 3]);
        if (flap != UINT32_MAX && !sb_has(s, flap)) s->v[s->count++] = flap;
    }
    double unit = sb_v3_length(sb_v3_sub(p[1], p[0]));
    while (!sb_fit(mesh, plane, s, center, unit)) {
        uint32_t next = s->count < SB_PLATE_NODES ? sb_nearest_neighbour(mesh, vt, s, center) : UINT32_MAX;
        if (next == UINT32_MAX) return false;
        s->v[s->count++] = next;
    }
    return true;
}

/* Whether vertex v is interior (its triangles close a fan: as many
 * neighbours as triangles) with four neighbours or fewer. */
static bool sb_interior_valence4(const sb_mesh* mesh, const sb_vertex_triangles* vt, uint32_t v) {
    uint32_t triangles = vt->start[v + 1] - vt->start[v], neighbours[8], count = 0;
    if (triangles > 4) return false;
    for (uint32_t k = vt->start[v]; k < vt->start[v + 1]; k++) {
        const uint32_t* q = mesh->triangles + 3 * (size_t)vt->triangle[k];
        for (int c = 0; c < 3; c++) {
            bool seen = q[c] == v;
            for (uint32_t n = 0; n < count && !seen; n++) seen = neighbours[n] == q[c];
            if (!seen) neighbours[count++] = q[c];
        }
    }
    return count == triangles;
}

bool sb_plate_suits(const sb_mesh* mesh) {
    if (!sb_mesh_is_flat(mesh)) return false;
    sb_vertex_triangles vt = {NULL, NULL};
    bool ok = sb_vertex_triangles_build(mesh, &vt);
    for (uint32_t v = 0; ok && v < mesh->vertex_count; v++) ok = !sb_interior_valence4(mesh, &vt, v);
    free(vt.start), free(vt.triangle);
    return ok;
}

bool sb_plate_stencils(const sb_mesh* mesh, sb_plate_stencil* out) {
    sb_plane plane;
    double size;
    sb_vertex_triangles vt = {NULL, NULL};
    bool ok = sb_first_plane(mesh, &plane, &size) && sb_vertex_triangles_build(mesh, &vt);
    for (uint32_t t = 0; ok && t < mesh->triangle_count; t++) ok = sb_triangle_stencil(mesh, &vt, &plane, t, out + t);
    free(vt.start), free(vt.triangle);
    return ok;
}
