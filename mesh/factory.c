/* The mesh factory for molecular mechanics: a mesh's vertices, unique edges,
 * triangle corners and interior edges become vertices, bonds, angles and
 * hinges. A term whose constants are all zero adds no elements. */
#include "mesh/builder_internal.h"
#include "common/edge_map.h"
#include "common/error.h"
#include "common/geometry.h"

#include <math.h>
#include <stdlib.h>

sb_material_def sb_default_material_def(void) {
    return (sb_material_def){.bond_k = 100.0, .angle_k = 0.1, .mass = 0.01};
}

/* What the factory learns about each unique edge: its first orientation,
 * the vertex opposite it in its first two triangles, its triangle count. */
typedef struct sb_edge_info {
    uint32_t e0, e1, o0, o1;
    uint32_t triangles;
} sb_edge_info;

static double sb_mesh_triangle_area(const sb_mesh* mesh, const uint32_t* t) {
    sb_vec3 p = sb_v3(mesh->positions + 3 * t[0]);
    sb_vec3 a = sb_v3_sub(sb_v3(mesh->positions + 3 * t[1]), p);
    sb_vec3 b = sb_v3_sub(sb_v3(mesh->positions + 3 * t[2]), p);
    return 0.5 * sb_v3_length(sb_v3_cross(a, b));
}

static sb_status sb_add_vertices(sb_builder* b, const sb_mesh* mesh, const sb_material_def* mat, sb_error* err) {
    uint32_t first = sb_builder_vertex_count(b);
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        sb_vertex_def def = sb_default_vertex_def();
        for (int c = 0; c < 3; c++) def.position[c] = mesh->positions[3 * v + c];
        def.mass = mat->density > 0.0 ? 0.0 : mat->mass;
        if (sb_builder_add_vertex(b, &def) < 0) return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding vertices");
    }
    if (mat->density > 0.0)
        for (uint32_t t = 0; t < mesh->triangle_count; t++) {
            const uint32_t* tri = mesh->triangles + 3 * t;
            double share = mat->density * sb_mesh_triangle_area(mesh, tri) / 3.0;
            for (int c = 0; c < 3; c++) sb_builder_vertex(b, first + tri[c])->mass += share;
        }
    return SB_OK;
}

/* Finds the unique edges in order of first appearance. */
static sb_status sb_collect_edges(const sb_mesh* mesh, sb_edge_info** out, uint32_t* count, sb_error* err) {
    sb_edge_map map;
    size_t max_edges = 3 * (size_t)mesh->triangle_count;
    sb_edge_info* edges = malloc((max_edges ? max_edges : 1) * sizeof *edges);
    if (!edges || !sb_edge_map_init(&map, max_edges)) {
        free(edges);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory finding the edges of %u triangles", mesh->triangle_count);
    }
    uint32_t n = 0;
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t* tri = mesh->triangles + 3 * t;
        for (int c = 0; c < 3; c++) {
            uint32_t a = tri[c], b = tri[(c + 1) % 3], opposite = tri[(c + 2) % 3];
            bool inserted;
            uint32_t id = *sb_edge_map_upsert(&map, a, b, n, &inserted);
            if (inserted) edges[n++] = (sb_edge_info){a, b, opposite, 0, 0};
            if (edges[id].triangles == 1) edges[id].o1 = opposite;
            edges[id].triangles++;
        }
    }
    sb_edge_map_free(&map);
    *out = edges;
    *count = n;
    return SB_OK;
}

static sb_status sb_add_edge_elements(sb_builder* b, uint32_t first, const sb_mesh* mesh, const sb_edge_info* edges,
                                      uint32_t count, const sb_material_def* mat, sb_error* err) {
    bool bonds = mat->bond_k > 0.0 || mat->spring_k > 0.0 || mat->spring_damping > 0.0;
    for (uint32_t e = 0; e < count && bonds; e++) {
        sb_bond_def def = sb_default_bond_def();
        def.i = first + edges[e].e0;
        def.j = first + edges[e].e1;
        def.k = mat->bond_k;
        def.spring_k = mat->spring_k;
        def.spring_damping = mat->spring_damping;
        def.break_max = sb_strain_break_length(mesh, edges[e].e0, edges[e].e1, mat->break_strain);
        if (sb_builder_add_bond(b, &def) < 0) return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding bonds");
    }
    for (uint32_t e = 0; e < count && mat->bend_k > 0.0; e++) {
        if (edges[e].triangles > 2)
            return sb_error_set(err, SB_ERR_INVALID, "edge (%u, %u) is shared by %u triangles: no hinge can bend it",
                                edges[e].e0, edges[e].e1, edges[e].triangles);
        if (edges[e].triangles < 2) continue;
        sb_hinge_def def = {first + edges[e].e0, first + edges[e].e1, first + edges[e].o0, first + edges[e].o1,
                            mat->bend_k};
        if (sb_builder_add_hinge(b, &def) < 0) return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding hinges");
    }
    return SB_OK;
}

static sb_status sb_add_triangles(sb_builder* b, uint32_t first, const sb_mesh* mesh, const sb_material_def* mat,
                                  sb_error* err) {
    if (mat->angle_k <= 0.0 && mat->stretch_bend_k <= 0.0) return SB_OK;
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t* tri = mesh->triangles + 3 * t;
        sb_triangle_def def = {first + tri[0], first + tri[1], first + tri[2], mat->angle_k, mat->stretch_bend_k};
        if (sb_builder_add_triangle(b, &def) < 0)
            return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding triangles");
    }
    return SB_OK;
}

static sb_status sb_check_mesh(const sb_mesh* mesh, const sb_material_def* mat, sb_error* err) {
    double constants[] = {mat->bond_k, mat->angle_k, mat->stretch_bend_k, mat->spring_k,    mat->spring_damping,
                          mat->bend_k, mat->mass,    mat->density,        mat->break_strain};
    for (size_t c = 0; c < sizeof constants / sizeof *constants; c++)
        if (!isfinite(constants[c]) || constants[c] < 0.0)
            return sb_error_set(err, SB_ERR_INVALID, "material constants must be finite and >= 0");
    for (size_t i = 0; i < 3 * (size_t)mesh->triangle_count; i++)
        if (mesh->triangles[i] >= mesh->vertex_count)
            return sb_error_set(err, SB_ERR_INVALID, "mesh triangle %zu: vertex index %u out of range (%u vertices)",
                                i / 3, mesh->triangles[i], mesh->vertex_count);
    return SB_OK;
}

sb_status sb_builder_add_mesh(sb_builder* b, const sb_mesh* mesh, const sb_material_def* mat, sb_error* err) {
    sb_status status = sb_check_mesh(mesh, mat, err);
    if (status != SB_OK) return status;
    uint32_t first = sb_builder_vertex_count(b);
    status = sb_add_vertices(b, mesh, mat, err);
    if (status != SB_OK) return status;
    sb_edge_info* edges = NULL;
    uint32_t edge_count = 0;
    status = sb_collect_edges(mesh, &edges, &edge_count, err);
    if (status == SB_OK) status = sb_add_edge_elements(b, first, mesh, edges, edge_count, mat, err);
    if (status == SB_OK) status = sb_add_triangles(b, first, mesh, mat, err);
    free(edges);
    return status;
}
