/* The Spring Systems mesh factory (Juhasz & Bercovici): mass points and
 * damped springs from a triangle mesh.
 *
 *   - a vertex per mesh vertex, order kept; mass per vertex, or a third of
 *     each triangle's mass from an areal density;
 *   - a stretch spring per unique edge;
 *   - a bend spring across each edge shared by exactly two triangles,
 *     between the two vertices opposite it (an edge of three or more
 *     triangles has no single pair of neighbours and gets none);
 *   - a vicinity spring between each pair of vertices nearer than the
 *     vicinity threshold (sb_vicinity_pairs, vicinity.c: a grid sweep,
 *     linear time) that an edge or a bend spring does not join already.
 *
 * Every spring is an sb_bond_def with spring_k and spring_damping (the
 * classic damped spring, Eq. 2) and bond stretch k = 0; its rest length is
 * the current distance. No pair is joined twice — sb_builder_compile
 * rejects duplicate bonds — and the precedence is edge, then bend, then
 * vicinity. The pairs live in compressed rows by their lower vertex: the
 * 3T half-edges are counting-sorted into rows (two passes, no hashing) and
 * each row, a vertex's few neighbours, is folded onto its distinct
 * partners; the bend pairs get rows of their own; "is this pair joined?" is
 * a scan of one short row. Stretch springs come row by row (ordered by
 * their lower vertex), then the bend springs, then the vicinity springs.
 *
 * Compressed rows rather than a hash set of pairs: the factory on a
 * million-triangle sheet took less than half the time. Most of its time is
 * the first touch of the builder's 40-byte bond records (page faults), not
 * the pair search. Timings: bench/results/mesh_load.csv (bench/mesh.sh;
 * bench/results/README.md, "Mesh import"); the runs first quoted here are
 * in bench/results/notes/mesh.md. */
#include "mesh/builder_internal.h"
#include "common/error.h"
#include "common/geometry.h"

#include <math.h>
#include <stdlib.h>

sb_spring_mesh_def sb_default_spring_mesh_def(void) {
    /* vicinity springs are off (distance 0) but, once a distance is set,
     * as stiff as the stretch springs: a zero default would add springs of
     * no stiffness, silently */
    return (sb_spring_mesh_def){.stretch_k = 100.0,
                                .stretch_damping = 0.1,
                                .bend_k = 10.0,
                                .bend_damping = 0.01,
                                .vicinity_k = 100.0,
                                .vicinity_damping = 0.1,
                                .mass = 0.01};
}

/* Pairs of vertices grouped by their lower vertex (compressed rows): row
 * lo holds slots start[lo] .. start[lo] + unique[lo] of distinct partners. */
typedef struct sb_pair_rows {
    uint32_t* start;  /* vertex_count + 1 */
    uint32_t* unique; /* distinct partners per row, at the row's front */
    uint32_t* hi;     /* per slot: the higher vertex */
    uint32_t* o0;     /* per slot: first opposite vertex (edges only) */
    uint32_t* o1;     /* per slot: second opposite vertex (edges only) */
    uint32_t* uses;   /* per slot: triangles on the edge (edges only) */
} sb_pair_rows;

typedef struct sb_spring_job {
    sb_builder* builder;
    const sb_mesh* mesh;
    const sb_spring_mesh_def* def;
    uint32_t first; /* the builder's index of mesh vertex 0 */
    sb_pair_rows edges, bends;
} sb_spring_job;

static void sb_rows_free(sb_pair_rows* r) {
    free(r->start);
    free(r->unique);
    free(r->hi);
    free(r->o0);
    free(r->o1);
    free(r->uses);
}

static bool sb_rows_init(sb_pair_rows* r, uint32_t vertex_count, size_t slots, bool edges) {
    r->start = calloc((size_t)vertex_count + 1, sizeof *r->start);
    r->unique = calloc((size_t)vertex_count + 1, sizeof *r->unique);
    r->hi = malloc((slots ? slots : 1) * sizeof *r->hi);
    if (edges) {
        r->o0 = malloc((slots ? slots : 1) * sizeof *r->o0);
        r->o1 = malloc((slots ? slots : 1) * sizeof *r->o1);
        r->uses = malloc((slots ? slots : 1) * sizeof *r->uses);
    }
    return r->start && r->unique && r->hi && (!edges || (r->o0 && r->o1 && r->uses));
}

/* Whether row lo holds hi. */
static bool sb_rows_find(const sb_pair_rows* r, uint32_t lo, uint32_t hi) {
    for (uint32_t s = r->start[lo], end = s + r->unique[lo]; s < end; s++)
        if (r->hi[s] == hi) return true;
    return false;
}

/* Moves slot s to the row's front unless its partner is there already;
 * returns the slot that holds the partner. */
static uint32_t sb_rows_merge(sb_pair_rows* r, uint32_t lo, uint32_t s) {
    uint32_t front = r->start[lo];
    for (uint32_t u = front; u < front + r->unique[lo]; u++)
        if (r->hi[u] == r->hi[s]) return u;
    uint32_t to = front + r->unique[lo]++;
    r->hi[to] = r->hi[s];
    if (r->o0) {
        r->o0[to] = r->o0[s];
        r->uses[to] = 0;
    }
    return to;
}

static sb_status sb_spring_check(const sb_mesh* mesh, const sb_spring_mesh_def* d, sb_error* err) {
    double constants[] = {d->stretch_k,  d->stretch_damping,  d->bend_k, d->bend_damping, d->vicinity,
                          d->vicinity_k, d->vicinity_damping, d->mass,   d->density,      d->break_strain};
    for (size_t c = 0; c < sizeof constants / sizeof *constants; c++)
        if (!isfinite(constants[c]) || constants[c] < 0.0)
            return sb_error_set(err, SB_ERR_INVALID, "spring mesh constants must be finite and >= 0");
    for (size_t i = 0; i < 3 * (size_t)mesh->triangle_count; i++)
        if (mesh->triangles[i] >= mesh->vertex_count)
            return sb_error_set(err, SB_ERR_INVALID, "mesh triangle %zu: vertex index %u out of range (%u vertices)",
                                i / 3, mesh->triangles[i], mesh->vertex_count);
    return SB_OK;
}

static double sb_area(const sb_mesh* mesh, const uint32_t* t) {
    sb_vec3 p = sb_v3(mesh->positions + 3 * (size_t)t[0]);
    sb_vec3 a = sb_v3_sub(sb_v3(mesh->positions + 3 * (size_t)t[1]), p);
    sb_vec3 b = sb_v3_sub(sb_v3(mesh->positions + 3 * (size_t)t[2]), p);
    return 0.5 * sb_v3_length(sb_v3_cross(a, b));
}

static sb_status sb_spring_vertices(sb_spring_job* job, sb_error* err) {
    const sb_mesh* mesh = job->mesh;
    double density = job->def->density;
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        sb_vertex_def def = sb_default_vertex_def();
        for (int c = 0; c < 3; c++) def.position[c] = mesh->positions[3 * (size_t)v + c];
        def.mass = density > 0.0 ? 0.0 : job->def->mass;
        if (sb_builder_add_vertex(job->builder, &def) < 0)
            return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding vertices");
    }
    for (uint32_t t = 0; t < mesh->triangle_count && density > 0.0; t++) {
        const uint32_t* tri = mesh->triangles + 3 * (size_t)t;
        double share = density * sb_area(mesh, tri) / 3.0;
        for (int c = 0; c < 3; c++) sb_builder_vertex(job->builder, job->first + tri[c])->mass += share;
    }
    return SB_OK;
}

/* The distinct edges, each with its triangle count and first two opposite
 * vertices: the 3T half-edges are counting-sorted into rows by their lower
 * vertex, then each row is folded onto its distinct partners. */
static sb_status sb_spring_edges(sb_spring_job* job, sb_error* err) {
    const sb_mesh* mesh = job->mesh;
    sb_pair_rows* r = &job->edges;
    size_t half_edges = 3 * (size_t)mesh->triangle_count;
    if (!sb_rows_init(r, mesh->vertex_count, half_edges, true))
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory finding the edges of %u triangles", mesh->triangle_count);
    for (size_t h = 0; h < half_edges; h++) {
        uint32_t a = mesh->triangles[h], b = mesh->triangles[h % 3 == 2 ? h - 2 : h + 1];
        if (a == b) return sb_error_set(err, SB_ERR_INVALID, "mesh triangle %zu: vertex %u repeated", h / 3, a);
        r->start[(a < b ? a : b) + 1]++;
    }
    for (uint32_t v = 0; v < mesh->vertex_count; v++) r->start[v + 1] += r->start[v];
    for (size_t h = 0; h < half_edges; h++) { /* fill: unique[] counts the slots used so far */
        size_t t = h / 3 * 3;
        uint32_t a = mesh->triangles[h], b = mesh->triangles[h % 3 == 2 ? t : h + 1];
        uint32_t opposite = mesh->triangles[t + (h - t + 2) % 3], lo = a < b ? a : b;
        uint32_t slot = r->start[lo] + r->unique[lo]++;
        r->hi[slot] = a ^ b ^ lo;
        r->o0[slot] = opposite;
    }
    for (uint32_t lo = 0; lo < mesh->vertex_count; lo++) {
        uint32_t slots = r->unique[lo];
        r->unique[lo] = 0;
        for (uint32_t s = r->start[lo]; s < r->start[lo] + slots; s++) {
            uint32_t opposite = r->o0[s], u = sb_rows_merge(r, lo, s);
            if (r->uses[u] == 1) r->o1[u] = opposite;
            r->uses[u]++;
        }
    }
    return SB_OK;
}

/* The bend pair across edge slot s: the two opposite vertices of an edge
 * of exactly two triangles, when they are not joined by an edge. */
static bool sb_bend_pair(const sb_pair_rows* e, uint32_t s, uint32_t* lo, uint32_t* hi) {
    if (e->uses[s] != 2 || e->o0[s] == e->o1[s]) return false;
    *lo = e->o0[s] < e->o1[s] ? e->o0[s] : e->o1[s];
    *hi = e->o0[s] ^ e->o1[s] ^ *lo;
    return !sb_rows_find(e, *lo, *hi);
}

/* Distinct bend pairs, in rows like the edges: count, place, fold. */
static sb_status sb_spring_bends(sb_spring_job* job, sb_error* err) {
    const sb_pair_rows* e = &job->edges;
    sb_pair_rows* r = &job->bends;
    uint32_t n = job->mesh->vertex_count, a, b;
    size_t count = 0;
    for (uint32_t lo = 0; lo < n; lo++)
        for (uint32_t s = e->start[lo]; s < e->start[lo] + e->unique[lo]; s++) count += sb_bend_pair(e, s, &a, &b);
    if (!sb_rows_init(r, n, count, false))
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory finding %zu bend springs", count);
    for (uint32_t lo = 0; lo < n; lo++)
        for (uint32_t s = e->start[lo]; s < e->start[lo] + e->unique[lo]; s++)
            if (sb_bend_pair(e, s, &a, &b)) r->start[a + 1]++;
    for (uint32_t v = 0; v < n; v++) r->start[v + 1] += r->start[v];
    for (uint32_t lo = 0; lo < n; lo++)
        for (uint32_t s = e->start[lo]; s < e->start[lo] + e->unique[lo]; s++)
            if (sb_bend_pair(e, s, &a, &b)) r->hi[r->start[a] + r->unique[a]++] = b;
    for (uint32_t lo = 0; lo < n; lo++) {
        uint32_t slots = r->unique[lo];
        r->unique[lo] = 0;
        for (uint32_t s = r->start[lo]; s < r->start[lo] + slots; s++) sb_rows_merge(r, lo, s);
    }
    return SB_OK;
}

static sb_status sb_spring_add(sb_spring_job* job, uint32_t i, uint32_t j, double k, double damping, sb_error* err) {
    sb_bond_def def = sb_default_bond_def();
    def.i = job->first + i;
    def.j = job->first + j;
    def.rest_length = -1.0;
    def.k = 0.0;
    def.spring_k = k;
    def.spring_damping = damping;
    def.break_max = sb_strain_break_length(job->mesh, i, j, job->def->break_strain);
    if (sb_builder_add_bond(job->builder, &def) < 0)
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding springs");
    return SB_OK;
}

/* A spring per pair of the rows, in row order. */
static sb_status sb_spring_add_rows(sb_spring_job* job, const sb_pair_rows* r, double k, double damping,
                                    sb_error* err) {
    if (k <= 0.0 && damping <= 0.0) return SB_OK;
    sb_status status = SB_OK;
    for (uint32_t lo = 0; lo < job->mesh->vertex_count && status == SB_OK; lo++)
        for (uint32_t s = r->start[lo]; s < r->start[lo] + r->unique[lo] && status == SB_OK; s++)
            status = sb_spring_add(job, lo, r->hi[s], k, damping, err);
    return status;
}

static sb_status sb_spring_vicinity(sb_spring_job* job, sb_error* err) {
    const sb_spring_mesh_def* d = job->def;
    if (d->vicinity <= 0.0 || (d->vicinity_k <= 0.0 && d->vicinity_damping <= 0.0)) return SB_OK;
    uint32_t* pairs;
    size_t count;
    sb_status status =
        sb_vicinity_pairs(job->mesh->positions, job->mesh->vertex_count, d->vicinity, &pairs, &count, err);
    for (size_t p = 0; p < count && status == SB_OK; p++) {
        uint32_t lo = pairs[2 * p], hi = pairs[2 * p + 1];
        if (!sb_rows_find(&job->edges, lo, hi) && !sb_rows_find(&job->bends, lo, hi))
            status = sb_spring_add(job, lo, hi, d->vicinity_k, d->vicinity_damping, err);
    }
    free(pairs);
    return status;
}

sb_status sb_builder_add_spring_mesh(sb_builder* builder, const sb_mesh* mesh, const sb_spring_mesh_def* def,
                                     sb_error* err) {
    sb_status status = sb_spring_check(mesh, def, err);
    if (status != SB_OK) return status;
    sb_spring_job job = {.builder = builder, .mesh = mesh, .def = def, .first = sb_builder_vertex_count(builder)};
    status = sb_spring_vertices(&job, err);
    if (status == SB_OK) status = sb_spring_edges(&job, err);
    if (status == SB_OK) status = sb_spring_bends(&job, err);
    if (status == SB_OK) status = sb_spring_add_rows(&job, &job.edges, def->stretch_k, def->stretch_damping, err);
    if (status == SB_OK) status = sb_spring_add_rows(&job, &job.bends, def->bend_k, def->bend_damping, err);
    if (status == SB_OK) status = sb_spring_vicinity(&job, err);
    sb_rows_free(&job.edges);
    sb_rows_free(&job.bends);
    return status;
}
