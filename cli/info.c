/* `softbond info MESH`: what a mesh file holds, one "name: value" line per
 * fact — vertices, edges, triangles (and tetrahedra), boundary and
 * non-manifold edges, connected components, bounding box, whether the
 * surface is closed, and the element colors its model would get (greedy,
 * as the fast kernels color: no two elements of a color share a vertex). */
#include "cli/cli.h"
#include "common/error.h"
#include "kernels/forces/coloring.h"
#include "common/edge_map.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sb_cli_info_usage(FILE* stream) {
    fprintf(stream, "usage: softbond info MESH\n"
                    "Prints the mesh's vertices, edges, triangles (tetrahedra for .node/.ele/.msh),\n"
                    "boundary and non-manifold edges, connected components, bounding box, whether\n"
                    "the surface is closed, and the element colors its model would get.\n");
}

typedef struct info_job {
    sb_cli_args args;
    sb_mesh mesh;
    sb_tet_mesh volume; /* for a tetrahedral file */
    uint32_t* edges;    /* 2 per unique edge of the model: the triangles', or the tetrahedra's */
    uint32_t edge_count;
    sb_mesh_edge_counts surface; /* how the surface's edges are shared */
    sb_mesh_load_report load;    /* what the import dropped */
} info_job;

static int info_finish(info_job* job, int code) {
    free(job->edges);
    sb_tet_mesh_free(&job->volume);
    sb_mesh_free(&job->mesh);
    sb_cli_args_free(&job->args);
    return code;
}

/* Unique edges (pairs in edges[2e], edges[2e + 1]) of `count` triangles
 * (arity 3) or tetrahedra (arity 4). */
static bool unique_edges(const uint32_t* elements, uint32_t count, int arity, uint32_t** edges, uint32_t* edge_count) {
    size_t most = (size_t)count * (size_t)(arity * (arity - 1) / 2);
    sb_edge_map map;
    *edges = malloc((2 * most + 2) * sizeof **edges);
    if (!*edges || !sb_edge_map_init(&map, most)) return false;
    uint32_t n = 0;
    for (uint32_t e = 0; e < count; e++) {
        const uint32_t* v = elements + (size_t)arity * e;
        for (int a = 0; a < arity; a++)
            for (int b = a + 1; b < arity; b++) {
                bool inserted;
                sb_edge_map_upsert(&map, v[a], v[b], n, &inserted);
                if (inserted) {
                    (*edges)[2 * n] = v[a];
                    (*edges)[2 * n++ + 1] = v[b];
                }
            }
    }
    sb_edge_map_free(&map);
    *edge_count = n;
    return true;
}

static uint32_t find_root(uint32_t* parent, uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
}

/* Connected components through the model's edges (a volume's interior
 * vertices join through its tetrahedra); a vertex on no edge is one. */
static uint32_t components(const info_job* job) {
    uint32_t n = job->mesh.vertex_count, count = 0;
    uint32_t* parent = malloc((n ? n : 1) * sizeof *parent);
    if (!parent) return 0;
    for (uint32_t v = 0; v < n; v++) parent[v] = v;
    for (uint32_t e = 0; e < job->edge_count; e++) {
        uint32_t a = find_root(parent, job->edges[2 * e]), b = find_root(parent, job->edges[2 * e + 1]);
        if (a != b) parent[a < b ? b : a] = a < b ? a : b;
    }
    for (uint32_t v = 0; v < n; v++) count += find_root(parent, v) == v;
    free(parent);
    return count;
}

/* Greedy colors of `count` elements of `arity` vertices, stored interleaved. */
static int colors(uint32_t vertex_count, const uint32_t* elements, uint32_t count, int arity) {
    if (count == 0) return 0;
    uint32_t* columns[4] = {0};
    uint8_t* color = malloc(count);
    sb_colorer colorer;
    bool ok = color && sb_colorer_init(&colorer, vertex_count);
    for (int a = 0; a < arity && ok; a++) ok = (columns[a] = malloc(count * sizeof(uint32_t))) != NULL;
    int used = -1;
    if (ok) {
        for (uint32_t e = 0; e < count; e++)
            for (int a = 0; a < arity; a++) columns[a][e] = elements[(size_t)arity * e + a];
        used = (int)sb_colorer_run(&colorer, 0, count, arity, (const uint32_t* const*)columns, color);
        sb_colorer_free(&colorer);
    }
    for (int a = 0; a < arity; a++) free(columns[a]);
    free(color);
    return used;
}

/* The file's meshes merged into one, with the import's report. */
static sb_status load_surface(info_job* job, sb_error* err) {
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    sb_status status = sb_mesh_load_ex(job->args.input, NULL, &objects, &count, &job->load, err);
    if (status != SB_OK) return status;
    job->mesh = objects[0];
    free(objects);
    return SB_OK;
}

static sb_status load(info_job* job, sb_error* err) {
    const char* path = job->args.input;
    sb_status status = sb_tet_mesh_path(path) ? sb_tet_mesh_load(path, &job->volume, err) : load_surface(job, err);
    if (status == SB_OK && job->volume.tets) status = sb_tet_mesh_surface(&job->volume, &job->mesh, err);
    if (status == SB_OK) status = sb_mesh_count_edges(&job->mesh, &job->surface, err);
    if (status != SB_OK) return status;
    bool ok = job->volume.tets
                  ? unique_edges(job->volume.tets, job->volume.tet_count, 4, &job->edges, &job->edge_count)
                  : unique_edges(job->mesh.triangles, job->mesh.triangle_count, 3, &job->edges, &job->edge_count);
    return ok ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory");
}

static void print_box(const sb_mesh* mesh) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < 3 * (size_t)mesh->vertex_count; i++) {
        lo[i % 3] = fmin(lo[i % 3], mesh->positions[i]);
        hi[i % 3] = fmax(hi[i % 3], mesh->positions[i]);
    }
    if (mesh->vertex_count == 0)
        printf("bounding box: none\n");
    else
        printf("bounding box: [%.9g, %.9g, %.9g] .. [%.9g, %.9g, %.9g] m\n", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
}

static void print_volume(const info_job* job) {
    const sb_tet_mesh* v = &job->volume;
    double total = 0.0;
    for (uint32_t t = 0; t < v->tet_count; t++) {
        const uint32_t* c = v->tets + 4 * (size_t)t;
        total += fabs(sb_tet_volume(v->positions + 3 * (size_t)c[0], v->positions + 3 * (size_t)c[1],
                                    v->positions + 3 * (size_t)c[2], v->positions + 3 * (size_t)c[3]));
    }
    sb_error check;
    printf("tetrahedra: %u\n", v->tet_count);
    printf("volume: %.9g m^3\n", total);
    printf("tetrahedra check: %s\n", sb_tet_mesh_check(v, &check) == SB_OK ? "ok" : check.message);
}

/* The model's elements: tetrahedron edges for a volume; bonds and
 * triangles for a surface. */
static sb_status print_colors(const info_job* job, sb_error* err) {
    if (job->volume.tets) {
        int springs = colors(job->volume.vertex_count, job->edges, job->edge_count, 2);
        if (springs < 0) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
        printf("springs: %u\ncolors: springs %d\n", job->edge_count, springs);
        return SB_OK;
    }
    int bonds = colors(job->mesh.vertex_count, job->edges, job->edge_count, 2);
    int triangles = colors(job->mesh.vertex_count, job->mesh.triangles, job->mesh.triangle_count, 3);
    if (bonds < 0 || triangles < 0) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    printf("colors: bonds %d, triangles %d\n", bonds, triangles);
    return SB_OK;
}

static sb_status report(const info_job* job, sb_error* err) {
    printf("file: %s\n", job->args.input);
    printf("vertices: %u\n", job->mesh.vertex_count);
    printf("edges: %u\n", job->surface.edges);
    printf("triangles: %u%s\n", job->mesh.triangle_count, job->volume.tets ? " (the boundary)" : "");
    if (!job->volume.tets) printf("degenerate faces dropped: %u\n", job->load.degenerate_faces);
    if (job->volume.tets) print_volume(job);
    printf("boundary edges: %u\n", job->surface.boundary);
    printf("non-manifold edges: %u\n", job->surface.non_manifold);
    printf("components: %u\n", components(job));
    print_box(&job->mesh);
    printf("closed: %s\n", job->surface.closed ? "yes" : "no");
    return print_colors(job, err);
}

int sb_cli_info(int argc, char** argv) {
    static const char* const accepted[] = {NULL};
    info_job job = {0};
    sb_error err;
    if (sb_cli_parse(argc, argv, accepted, &job.args, &err) != SB_OK)
        return info_finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    if (job.args.help) {
        sb_cli_info_usage(stdout);
        return info_finish(&job, SB_EXIT_OK);
    }
    if (job.args.set_count > 0) {
        sb_error_set(&err, SB_ERR_INVALID, "info takes no --set (see softbond info --help)");
        return info_finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    }
    if (load(&job, &err) != SB_OK) return info_finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    if (report(&job, &err) != SB_OK) return info_finish(&job, sb_cli_fail(SB_EXIT_FAILURE, &err));
    return info_finish(&job, SB_EXIT_OK);
}
