/* The patch of the surface that a collider with a footprint presses.
 *
 * Design. A contact of vertex or face contact holds one vertex, or the
 * three corners of a triangle, at the collider; a spring net is softer
 * under a load on one vertex than under one shared by neighbours, so a
 * tool smaller than the spacing feels a bump at each vertex. A collider
 * with a footprint of radius ρ presses a patch instead: the vertices
 * within ρ (at rest) of the point of contact, each weighted by the cubic
 * spline kernel φ(d / ρ) of its distance d, the weights divided by their
 * sum. The weights are a smooth function of where on the surface the
 * contact lies, and for ρ of about twice the spacing they make the net's
 * stiffness under the patch nearly the same wherever it lies (a membrane
 * under tension, the default sheet: within 1 % at 2.5 spacings, against
 * 13 and 30 % for the corners' barycentric weights). Distances at rest:
 * the patch is the same piece of material whatever the body's shape now,
 * and the room it needs is known when the solver is made.
 *
 * The patch is gathered from the triangle's corners through each
 * vertex's neighbours on the surface, only through vertices within ρ (the
 * other side of a thin fold is not pressed), in a fixed order: the same for
 * any thread count. ρ is at least the longest edge, so a corner of the
 * triangle lies within it. */
#include "kernels/contact/footprint.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int sb_pair_order(const void* a, const void* b) {
    uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
    return x < y ? -1 : x > y;
}

/* Each vertex's neighbours from the triangles' edges: each edge both ways,
 * as (vertex, neighbour) pairs sorted and made unique. */
static bool sb_footprint_neighbours(sb_footprint* fp, uint32_t vertices, const sb_surface_triangles* tris) {
    size_t pairs = 6 * (size_t)tris->count, unique = 0;
    uint64_t* pair = malloc((pairs + 1) * sizeof *pair);
    fp->first = calloc((size_t)vertices + 1, sizeof *fp->first);
    fp->vertex = malloc((pairs + 1) * sizeof *fp->vertex);
    if (!pair || !fp->first || !fp->vertex) {
        free(pair);
        return false;
    }
    for (uint32_t t = 0; t < tris->count; t++)
        for (int c = 0; c < 3; c++) {
            uint64_t a = tris->v[c][t], b = tris->v[(c + 1) % 3][t];
            pair[6 * (size_t)t + 2 * c] = a << 32 | b;
            pair[6 * (size_t)t + 2 * c + 1] = b << 32 | a;
        }
    qsort(pair, pairs, sizeof *pair, sb_pair_order);
    for (size_t k = 0; k < pairs; k++) {
        if (k > 0 && pair[k] == pair[k - 1]) continue;
        fp->vertex[unique++] = (uint32_t)pair[k];
        fp->first[(pair[k] >> 32) + 1]++;
    }
    for (uint32_t i = 0; i < vertices; i++) fp->first[i + 1] += fp->first[i];
    free(pair);
    return true;
}

static double sb_rest_distance(const sb_model* m, uint32_t i, const double p[3]) {
    double dx = m->rest_x[i] - p[0], dy = m->rest_y[i] - p[1], dz = m->rest_z[i] - p[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* A new stamp for the marks (on wrapping, every mark cleared). */
static void sb_footprint_new_stamp(sb_footprint* fp, uint32_t vertices) {
    if (++fp->stamp != 0) return;
    memset(fp->mark, 0, (size_t)vertices * sizeof *fp->mark);
    fp->stamp = 1;
}

/* The vertices within `radius` of p at rest reached from `seeds` through
 * vertices within it, in order, into vertex[] (their distances into d[]);
 * returns how many. */
static uint32_t sb_footprint_reach(sb_footprint* fp, const sb_model* m, const uint32_t* seeds, int seed_count,
                                   const double p[3], double radius, uint32_t* vertex, double* d) {
    uint32_t count = 0;
    sb_footprint_new_stamp(fp, m->vertex_count);
    for (int k = 0; k < seed_count; k++) {
        uint32_t i = seeds[k];
        if (fp->mark[i] == fp->stamp) continue;
        fp->mark[i] = fp->stamp;
        double di = sb_rest_distance(m, i, p);
        if (di < radius) vertex[count] = i, d[count++] = di;
    }
    for (uint32_t k = 0; k < count; k++)
        for (uint32_t r = fp->first[vertex[k]]; r < fp->first[vertex[k] + 1]; r++) {
            uint32_t i = fp->vertex[r];
            if (fp->mark[i] == fp->stamp) continue;
            fp->mark[i] = fp->stamp;
            double di = sb_rest_distance(m, i, p);
            if (di < radius) vertex[count] = i, d[count++] = di;
        }
    return count;
}

double sb_footprint_longest_edge(const sb_model* m, const sb_surface_triangles* tris) {
    double longest = 0.0;
    for (uint32_t t = 0; t < tris->count; t++)
        for (int c = 0; c < 3; c++) {
            uint32_t a = tris->v[c][t], b = tris->v[(c + 1) % 3][t];
            double p[3] = {m->rest_x[b], m->rest_y[b], m->rest_z[b]}, d = sb_rest_distance(m, a, p);
            longest = d > longest ? d : longest;
        }
    return longest;
}

/* The room: a patch about a point of a triangle lies within radius of it,
 * so within radius + the longest edge of each corner, and is reached from
 * any corner through such vertices (the corners are neighbours); the most
 * any corner reaches so bounds it. */
static bool sb_footprint_room(sb_footprint* fp, const sb_model* m, const sb_surface_triangles* tris, double radius) {
    uint32_t n = m->vertex_count, *vertex = malloc(((size_t)n + 1) * sizeof *vertex);
    double* d = malloc(((size_t)n + 1) * sizeof *d);
    double reach = radius + sb_footprint_longest_edge(m, tris);
    bool ok = vertex && d;
    for (uint32_t i = 0; ok && i < n; i++) {
        if (fp->first[i] == fp->first[i + 1]) continue; /* not on the surface */
        double p[3] = {m->rest_x[i], m->rest_y[i], m->rest_z[i]};
        uint32_t count = sb_footprint_reach(fp, m, &i, 1, p, reach * (1.0 + 1e-9), vertex, d);
        fp->room = count > fp->room ? count : fp->room;
    }
    free(vertex);
    free(d);
    return ok;
}

bool sb_footprint_make(const sb_model* m, const sb_surface_triangles* tris, double radius, sb_footprint* fp) {
    memset(fp, 0, sizeof *fp);
    fp->mark = calloc((size_t)m->vertex_count + 1, sizeof *fp->mark);
    return fp->mark && sb_footprint_neighbours(fp, m->vertex_count, tris) && sb_footprint_room(fp, m, tris, radius);
}

void sb_footprint_free(sb_footprint* fp) {
    free(fp->first);
    free(fp->vertex);
    free(fp->mark);
    memset(fp, 0, sizeof *fp);
}

/* The cubic spline kernel, 1 at q = 0, 0 from q = 1 on, with continuous
 * first and second derivatives. */
static double sb_kernel(double q) {
    if (q >= 1.0) return 0.0;
    if (q < 0.5) return 1.0 - 6.0 * q * q + 6.0 * q * q * q;
    return 2.0 * (1.0 - q) * (1.0 - q) * (1.0 - q);
}

uint32_t sb_footprint_patch(sb_footprint* fp, const sb_model* m, const uint32_t corners[3], const double w[3],
                            double radius, uint32_t* vertex, double* weight) {
    double p[3] = {0.0, 0.0, 0.0}, sum = 0.0;
    for (int j = 0; j < 3; j++) {
        p[0] += w[j] * m->rest_x[corners[j]];
        p[1] += w[j] * m->rest_y[corners[j]];
        p[2] += w[j] * m->rest_z[corners[j]];
    }
    uint32_t count = sb_footprint_reach(fp, m, corners, 3, p, radius, vertex, weight);
    for (uint32_t k = 0; k < count; k++) sum += weight[k] = sb_kernel(weight[k] / radius);
    for (uint32_t k = 0; k < count; k++) weight[k] /= sum;
    return count;
}
