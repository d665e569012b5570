/* The viewer's copy of a tearing solver's topology (viewer/topology.h). */
#include "viewer/topology.h"
#include "common/error.h"

#include <stdlib.h>
#include <string.h>

typedef struct room {
    size_t vertices, triangles, bonds;
} room;

static bool tears(const sb_solver* solver) {
    return sb_solver_vertex_capacity(solver) > sb_model_vertex_count(sb_solver_model(solver));
}

/* Room for the surface as it can grow: a cut through triangles
 * (sb_solver_def.cut_through) reserves 2 triangles and 4 bonds for each
 * vertex it may make (kernels/interaction/cut_mesh.c). */
static room room_of(const sb_solver* solver, const sb_mesh* mesh) {
    const sb_model* m = sb_solver_model(solver);
    size_t spare = sb_solver_vertex_capacity(solver) - sb_model_vertex_count(m);
    size_t triangles = !tears(solver)                   ? mesh->triangle_count
                       : sb_model_triangle_count(m) > 0 ? sb_model_triangle_count(m) + 2 * spare
                                                        : sb_solver_face_capacity(solver); /* a volume cut through */
    return (room){sb_solver_vertex_capacity(solver) + 1, triangles + 1, sb_model_bond_count(m) + 4 * spare + 1};
}

sb_status sb_view_topology_create(sb_view_topology* t, const sb_solver* solver, const sb_mesh* mesh, sb_error* err) {
    room r = room_of(solver, mesh);
    *t = (sb_view_topology){0};
    t->origins = malloc(r.vertices * sizeof *t->origins);
    t->triangles = malloc(3 * r.triangles * sizeof *t->triangles);
    t->edges = malloc(2 * r.bonds * sizeof *t->edges);
    t->bonds = malloc(r.bonds * sizeof *t->bonds);
    if (t->origins && t->triangles && t->edges && t->bonds) return SB_OK;
    sb_view_topology_free(t);
    return sb_error_set(err, SB_ERR_NOMEM, "view: out of memory for the topology");
}

void sb_view_topology_free(sb_view_topology* t) {
    free(t->origins);
    free(t->triangles);
    free(t->edges);
    free(t->bonds);
    *t = (sb_view_topology){0};
}

/* The surface: the mesh's triangles (a model of springs has no triangle
 * elements), or a tearing solver's live ones with their current vertices,
 * those a cut through triangles made included, or a volume's boundary
 * faces now when it is cut through its tetrahedra. */
static void read_triangles(sb_view_topology* t, const sb_solver* solver, const sb_mesh* mesh) {
    t->triangle_count = 0;
    if (!tears(solver)) {
        t->triangle_count = mesh->triangle_count;
        memcpy(t->triangles, mesh->triangles, 3 * (size_t)mesh->triangle_count * sizeof *t->triangles);
        return;
    }
    if (sb_model_triangle_count(sb_solver_model(solver)) == 0) {
        for (uint32_t k = 0; k < sb_solver_face_count(solver); k++)
            sb_solver_face(solver, k, t->triangles + 3 * (size_t)t->triangle_count++);
        return;
    }
    for (uint32_t k = 0; k < sb_solver_triangle_count(solver); k++)
        if (sb_solver_triangle_alive(solver, k))
            sb_solver_triangle(solver, k, t->triangles + 3 * (size_t)t->triangle_count++);
}

void sb_view_topology_read(sb_view_topology* t, const sb_solver* solver, const sb_mesh* mesh) {
    t->vertex_count = sb_solver_vertex_count(solver);
    for (uint32_t i = 0; i < t->vertex_count; i++) t->origins[i] = sb_solver_vertex_origin(solver, i);
    read_triangles(t, solver, mesh);
    t->edge_count = 0;
    for (uint32_t b = 0; b < sb_solver_bond_count(solver); b++) {
        if (sb_solver_bond_broken(solver, b)) continue;
        sb_solver_bond(solver, b, t->edges + 2 * (size_t)t->edge_count);
        t->bonds[t->edge_count++] = b;
    }
    t->version++;
}

void sb_view_topology_copy(sb_view_topology* to, const sb_view_topology* from) {
    to->vertex_count = from->vertex_count;
    to->triangle_count = from->triangle_count;
    to->edge_count = from->edge_count;
    to->version = from->version;
    memcpy(to->origins, from->origins, from->vertex_count * sizeof *to->origins);
    memcpy(to->triangles, from->triangles, 3 * (size_t)from->triangle_count * sizeof *to->triangles);
    memcpy(to->edges, from->edges, 2 * (size_t)from->edge_count * sizeof *to->edges);
    memcpy(to->bonds, from->bonds, from->edge_count * sizeof *to->bonds);
}
