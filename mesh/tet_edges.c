/* The unique edges of a tetrahedral mesh: see mesh/tet_edges.h. */
#include "mesh/tet_edges.h"
#include "common/error.h"

#include <stdlib.h>
#include <string.h>

const int sb_tet_edge_corners[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

sb_status sb_tet_edge_set_find(const sb_tet_mesh* m, sb_tet_edge_set* out, sb_error* err) {
    memset(out, 0, sizeof *out);
    size_t most = 6 * (size_t)m->tet_count;
    out->ends = malloc(2 * (most ? most : 1) * sizeof *out->ends);
    out->of_tet = malloc((most ? most : 1) * sizeof *out->of_tet);
    if (!out->ends || !out->of_tet || !sb_edge_map_init(&out->map, most)) {
        sb_tet_edge_set_free(out);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory finding the edges of %u tetrahedra", m->tet_count);
    }
    for (uint32_t t = 0; t < m->tet_count; t++) {
        const uint32_t* v = m->tets + 4 * (size_t)t;
        for (int e = 0; e < 6; e++) {
            uint32_t a = v[sb_tet_edge_corners[e][0]], b = v[sb_tet_edge_corners[e][1]];
            bool inserted;
            uint32_t id = *sb_edge_map_upsert(&out->map, a, b, out->count, &inserted);
            if (inserted) {
                out->ends[2 * (size_t)id] = a;
                out->ends[2 * (size_t)id + 1] = b;
                out->count++;
            }
            out->of_tet[6 * (size_t)t + e] = id;
        }
    }
    return SB_OK;
}

void sb_tet_edge_set_free(sb_tet_edge_set* set) {
    free(set->ends);
    free(set->of_tet);
    sb_edge_map_free(&set->map);
    memset(set, 0, sizeof *set);
}

sb_status sb_tet_mesh_quadratic_surface(const sb_tet_mesh* m, sb_mesh* out, sb_error* err) {
    sb_mesh corners;
    sb_status status = sb_tet_mesh_surface(m, &corners, err);
    if (status != SB_OK) return status;
    sb_tet_edge_set edges;
    status = sb_tet_edge_set_find(m, &edges, err);
    memset(out, 0, sizeof *out);
    if (status == SB_OK) {
        out->vertex_count = m->vertex_count + edges.count;
        out->triangle_count = 4 * corners.triangle_count;
        out->positions = malloc(3 * (size_t)out->vertex_count * sizeof(double));
        out->triangles = malloc((3 * (size_t)out->triangle_count + 1) * sizeof(uint32_t));
        if (!out->positions || !out->triangles) {
            sb_mesh_free(out);
            status = sb_error_set(err, SB_ERR_NOMEM, "out of memory splitting the surface");
        }
    }
    if (status == SB_OK) {
        memcpy(out->positions, m->positions, 3 * (size_t)m->vertex_count * sizeof(double));
        for (uint32_t e = 0; e < edges.count; e++)
            for (int k = 0; k < 3; k++)
                out->positions[3 * ((size_t)m->vertex_count + e) + k] =
                    0.5 * (m->positions[3 * (size_t)edges.ends[2 * e] + k] +
                           m->positions[3 * (size_t)edges.ends[2 * e + 1] + k]);
        for (uint32_t t = 0; t < corners.triangle_count; t++) { /* corners a b c, middles ab bc ca */
            const uint32_t* v = corners.triangles + 3 * (size_t)t;
            uint32_t mid[3];
            for (int c = 0; c < 3; c++) mid[c] = m->vertex_count + *sb_edge_map_find(&edges.map, v[c], v[(c + 1) % 3]);
            uint32_t split[4][3] = {
                {v[0], mid[0], mid[2]}, {mid[0], v[1], mid[1]}, {mid[2], mid[1], v[2]}, {mid[0], mid[1], mid[2]}};
            memcpy(out->triangles + 12 * (size_t)t, split, sizeof split);
        }
    }
    sb_tet_edge_set_free(&edges);
    sb_mesh_free(&corners);
    return status;
}
