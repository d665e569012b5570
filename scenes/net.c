/* The net factory (see net.h). */
#include "scenes/net.h"
#include "common/error.h"
#include "scenes/scene_model.h"

static sb_status add_bond(sb_builder* builder, uint32_t first, const sb_mesh* mesh, uint32_t a, uint32_t b,
                          const sb_material_def* material, sb_error* err) {
    sb_bond_def def = sb_default_bond_def();
    def.i = first + a;
    def.j = first + b;
    def.k = material->bond_k;
    def.spring_k = material->spring_k;
    def.spring_damping = material->spring_damping;
    def.break_max = sb_strain_break_length(mesh, a, b, material->break_strain);
    if (sb_builder_add_bond(builder, &def) < 0) return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding bonds");
    return SB_OK;
}

sb_status sb_scene_add_net(const sb_scene* scene, const sb_mesh* mesh, sb_builder* builder, sb_error* err) {
    uint32_t nx = (uint32_t)sb_scene_integer(scene, SB_KEY_MESH_NX);
    uint32_t ny = (uint32_t)sb_scene_integer(scene, SB_KEY_MESH_NY);
    if ((uint64_t)nx * ny != mesh->vertex_count)
        return sb_error_set(err, SB_ERR_INVALID, "net: the mesh is not the %u x %u sheet", nx, ny);
    sb_material_def material = sb_scene_material(scene);
    /* the molecular factory with every term off adds the vertices and their masses only */
    sb_material_def masses = {.mass = material.mass, .density = material.density};
    uint32_t first = sb_builder_vertex_count(builder);
    sb_status status = sb_builder_add_mesh(builder, mesh, &masses, err);
    bool bonds = material.bond_k > 0.0 || material.spring_k > 0.0 || material.spring_damping > 0.0;
    for (uint32_t row = 0; status == SB_OK && bonds && row < ny; row++)
        for (uint32_t col = 0; status == SB_OK && col < nx; col++) {
            uint32_t v = row * nx + col;
            if (col + 1 < nx) status = add_bond(builder, first, mesh, v, v + 1, &material, err);
            if (status == SB_OK && row + 1 < ny) status = add_bond(builder, first, mesh, v, v + nx, &material, err);
        }
    return status;
}
