/* sb_mesh_concatenate: meshes one after the other, as separate bodies. */
#include <stdlib.h>
#include <string.h>

#include "common/error.h"
#include "softbond/mesh.h"

sb_status sb_mesh_concatenate(const sb_mesh* meshes, uint32_t count, sb_mesh* out, sb_error* err) {
    size_t vertices = 0, triangles = 0;
    for (uint32_t i = 0; i < count; i++) {
        vertices += meshes[i].vertex_count;
        triangles += meshes[i].triangle_count;
    }
    *out = (sb_mesh){0};
    if (vertices > UINT32_MAX || triangles > UINT32_MAX) {
        return sb_error_set(err, SB_ERR_INVALID, "more than 2^32-1 vertices or triangles");
    }
    out->positions = malloc((3 * vertices + 1) * sizeof(double));
    out->triangles = malloc((3 * triangles + 1) * sizeof(uint32_t));
    if (out->positions == NULL || out->triangles == NULL) {
        sb_mesh_free(out);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    }
    for (uint32_t i = 0; i < count; i++) {
        const sb_mesh* m = &meshes[i];
        memcpy(out->positions + 3 * (size_t)out->vertex_count, m->positions,
               3 * (size_t)m->vertex_count * sizeof(double));
        for (size_t t = 0; t < 3 * (size_t)m->triangle_count; t++) {
            out->triangles[3 * (size_t)out->triangle_count + t] = m->triangles[t] + out->vertex_count;
        }
        out->vertex_count += m->vertex_count;
        out->triangle_count += m->triangle_count;
    }
    return SB_OK;
}
