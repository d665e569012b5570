/* sb_mesh_count_edges: how a triangle mesh's edges are shared, and so
 * whether its surface is closed. */
#include <stdlib.h>

#include "common/edge_map.h"
#include "common/error.h"
#include "softbond/mesh.h"

sb_status sb_mesh_count_edges(const sb_mesh* mesh, sb_mesh_edge_counts* out, sb_error* err) {
    *out = (sb_mesh_edge_counts){0};
    size_t half_edges = 3 * (size_t)mesh->triangle_count;
    uint32_t* uses = calloc(half_edges + 1, sizeof *uses);
    sb_edge_map map;
    if (uses == NULL || !sb_edge_map_init(&map, half_edges)) {
        free(uses);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    }
    for (size_t h = 0; h < half_edges; h++) {
        const uint32_t* t = mesh->triangles + 3 * (h / 3);
        bool inserted;
        uint32_t id = *sb_edge_map_upsert(&map, t[h % 3], t[(h + 1) % 3], out->edges, &inserted);
        out->edges += inserted;
        uses[id]++;
    }
    for (uint32_t e = 0; e < out->edges; e++) {
        out->boundary += uses[e] == 1;
        out->non_manifold += uses[e] > 2;
    }
    out->closed = mesh->triangle_count > 0 && out->boundary == 0 && out->non_manifold == 0;
    sb_edge_map_free(&map);
    free(uses);
    return SB_OK;
}
