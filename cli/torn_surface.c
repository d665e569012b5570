#include "cli/torn_surface.h"
#include "common/error.h"

#include <stdlib.h>

sb_status sb_torn_surface_init(sb_torn_surface* s, const sb_solver* solver, sb_error* err) {
    const sb_model* model = sb_solver_model(solver);
    *s = (sb_torn_surface){.tears = sb_solver_vertex_capacity(solver) > sb_model_vertex_count(model)};
    if (!s->tears) return SB_OK;
    s->room = sb_model_triangle_count(model);
    s->mesh.triangles = malloc((3 * (size_t)s->room + 1) * sizeof *s->mesh.triangles);
    return s->mesh.triangles ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory for the torn surface");
}

void sb_torn_surface_free(sb_torn_surface* s) {
    free(s->mesh.triangles);
    *s = (sb_torn_surface){0};
}

const sb_mesh* sb_torn_surface_update(sb_torn_surface* s, const sb_solver* solver, const sb_mesh* whole,
                                      double* positions) {
    if (!s->tears) return whole;
    bool faces = sb_model_triangle_count(sb_solver_model(solver)) == 0; /* a volume: its boundary faces */
    uint32_t count = 0, triangles = faces ? sb_solver_face_count(solver) : sb_solver_triangle_count(solver);
    if (triangles > s->room) {
        uint32_t* grown = realloc(s->mesh.triangles, (3 * (size_t)triangles + 1) * sizeof *grown);
        if (!grown) return NULL;
        s->mesh.triangles = grown;
        s->room = triangles;
    }
    for (uint32_t t = 0; t < triangles; t++)
        if (faces)
            sb_solver_face(solver, t, s->mesh.triangles + 3 * (size_t)count++);
        else if (sb_solver_triangle_alive(solver, t))
            sb_solver_triangle(solver, t, s->mesh.triangles + 3 * (size_t)count++);
    s->mesh.triangle_count = count;
    s->mesh.vertex_count = sb_solver_vertex_count(solver);
    s->mesh.positions = positions;
    return &s->mesh;
}
