/* The sheet factory: a thin sheet stated by E, ν, thickness and density.
 *
 * Membrane: a co-rotated linear plane-stress triangle per mesh triangle
 * (sb_membrane_def).
 *
 * Bending of a flat sheet: the plate's own energy density
 *     ½ D [(1 − ν)(κ11² + κ22² + 2 κ12²) + ν (κ11 + κ22)²],
 * D = E t³ / 12 (1 − ν²), with the curvatures κ_ij taken, as in Bergou et
 * al.'s quadratic bending model (2006), from the second derivatives x_,ij
 * of the positions over the rest plane: for a bend that keeps lengths
 * (isometric) x_,ij = κ_ij n exactly, so |x_,11|² + |x_,22|² + 2 |x_,12|²
 * is κ11² + κ22² + 2 κ12² and |x_,11 + x_,22|² is (κ11 + κ22)². Per
 * triangle, x_,ij from the stencil of mesh/plate_stencils.c (exact for
 * quadratic fields) times the triangle's rest area: a quadratic form of
 * the positions, its Hessian constant (kernels/forces/plate.c), zero for
 * any rigid motion and any uniform stretch. It is exact where the hinge
 * below is not: twist and the ν coupling (docs/materials.md, "Sheets").
 *
 * Bending of a curved sheet (the quadratic form holds only about a flat
 * rest), and of a flat one whose mesh the stencils do not suit
 * (sb_plate_suits: interior vertices of four neighbours, as the sheet
 * generator's alternating diagonals have): the discrete shell's hinge (Grinspun et al. 2003),
 * ½ k (φ − φ0)² on each interior edge, with its own constant
 *     k = D |e|² / (A0 + A1),
 * |e| the edge's rest length and A0, A1 its two triangles' rest areas.
 * Why this constant: a flat sheet bent to curvature κ across an edge folds
 * it by φ = κ h̄, h̄ = (h0 + h1) / 2 the mean of the two triangles' heights
 * over the edge, and A0 + A1 = |e| h̄, so that ½ k φ² = ½ D κ² (A0 + A1),
 * the plate's energy over the pair's area. It is exact for a grid of right triangles bent along its rows or
 * columns (the diagonals' pairs stay flat) and it is Seung & Nelson's
 * bending rigidity D = (√3/2) k for equilateral triangles; Grinspun et
 * al.'s 3 |e|² / (A0 + A1), which spreads each triangle's area over its
 * three edges, is three times stiffer on both. Like every hinge energy it
 * depends on the mesh's directions: on a grid, the twist κ_xy and the
 * coupling ν κ_xx κ_yy are not seen.
 *
 * Vertices (and a curved sheet's hinges) come from the molecular factory
 * (sb_builder_add_mesh with only the hinge term and the areal density
 * ρ t), whose hinge constants are then set per hinge here. */
#include "mesh/builder_internal.h"
#include "common/error.h"
#include "common/geometry.h"

#include <math.h>
#include <stdlib.h>

sb_sheet_material_def sb_default_sheet_material_def(void) {
    return (sb_sheet_material_def){
        .young_modulus = 30e3, .poisson_ratio = 0.45, .thickness = 1e-3, .density = 1060.0, .stiffness_damping = 0.0};
}

static sb_status sb_check_sheet(const sb_sheet_material_def* d, sb_error* err) {
    if (!isfinite(d->young_modulus) || !(d->young_modulus > 0.0))
        return sb_error_set(err, SB_ERR_INVALID, "sheet: Young's modulus %g Pa must be finite and > 0",
                            d->young_modulus);
    if (!(d->poisson_ratio > -1.0 && d->poisson_ratio < 0.5))
        return sb_error_set(err, SB_ERR_INVALID, "sheet: Poisson's ratio %g must be in (-1, 0.5)", d->poisson_ratio);
    if (!isfinite(d->thickness) || !(d->thickness > 0.0))
        return sb_error_set(err, SB_ERR_INVALID, "sheet: thickness %g m must be finite and > 0", d->thickness);
    if (!isfinite(d->density) || !(d->density > 0.0))
        return sb_error_set(err, SB_ERR_INVALID, "sheet: density %g kg/m^3 must be finite and > 0", d->density);
    if (!isfinite(d->stiffness_damping) || d->stiffness_damping < 0.0)
        return sb_error_set(err, SB_ERR_INVALID, "sheet: stiffness damping %g s must be finite and >= 0",
                            d->stiffness_damping);
    return SB_OK;
}

static double sb_vertex_triangle_area(const sb_vertex_def* v, uint32_t a, uint32_t b, uint32_t c) {
    sb_vec3 p = sb_v3(v[a].position);
    return 0.5 * sb_v3_length(sb_v3_cross(sb_v3_sub(sb_v3(v[b].position), p), sb_v3_sub(sb_v3(v[c].position), p)));
}

/* The hinges from `first` on get k = D |e|² / (A0 + A1). */
static void sb_set_hinge_constants(sb_builder* b, size_t first, double bending_stiffness) {
    const sb_vertex_def* v = SB_ITEMS(b->vertices, sb_vertex_def);
    sb_hinge_def* hinges = b->hinges.items;
    for (size_t h = first; h < b->hinges.count; h++) {
        sb_hinge_def* d = hinges + h;
        sb_vec3 edge = sb_v3_sub(sb_v3(v[d->e1].position), sb_v3(v[d->e0].position));
        double areas =
            sb_vertex_triangle_area(v, d->e0, d->e1, d->o0) + sb_vertex_triangle_area(v, d->e1, d->e0, d->o1);
        d->k = areas > 0.0 ? bending_stiffness * sb_v3_dot(edge, edge) / areas : 0.0; /* compile names a flat wing */
    }
}

static sb_status sb_add_membranes(sb_builder* b, uint32_t first, const sb_mesh* mesh, const sb_sheet_material_def* d,
                                  sb_error* err) {
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t* tri = mesh->triangles + 3 * (size_t)t;
        sb_membrane_def def = {{first + tri[0], first + tri[1], first + tri[2]},
                               d->young_modulus,
                               d->poisson_ratio,
                               d->thickness,
                               d->stiffness_damping};
        if (sb_builder_add_membrane(b, &def) < 0)
            return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding membranes");
    }
    return SB_OK;
}

/* The plates' stencils of a mesh they suit (sb_plate_suits; each
 * triangle's neighbourhood fixing a quadratic, which a mesh of fewer than
 * six vertices does not), else NULL: the sheet then gets the hinges. A
 * triangle index out of range gives NULL too, for sb_builder_add_mesh to
 * name. */
static sb_plate_stencil* sb_sheet_stencils(const sb_mesh* mesh) {
    for (size_t k = 0; k < 3 * (size_t)mesh->triangle_count; k++)
        if (mesh->triangles[k] >= mesh->vertex_count) return NULL;
    if (!sb_plate_suits(mesh)) return NULL;
    sb_plate_stencil* stencils = malloc(mesh->triangle_count * sizeof *stencils);
    if (stencils && !sb_plate_stencils(mesh, stencils)) {
        free(stencils);
        return NULL;
    }
    return stencils;
}

/* Each membrane from `first_membrane` on (one per mesh triangle, in its
 * order) gets its triangle's plate, of bending stiffness D. */
static sb_status sb_add_plates(sb_builder* b, uint32_t first, size_t first_membrane, const sb_mesh* mesh,
                               const sb_plate_stencil* stencils, double bending_stiffness, double nu, sb_error* err) {
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        sb_plate_def def = {(uint32_t)first_membrane + t, stencils[t],
                            stencils[t].area * bending_stiffness * (1.0 - nu),
                            stencils[t].area * bending_stiffness * nu};
        for (int a = 0; a < def.stencil.count; a++) def.stencil.v[a] += first;
        if (sb_builder_add_plate(b, &def) < 0)
            return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding a sheet's plates");
    }
    return SB_OK;
}

sb_status sb_builder_add_sheet(sb_builder* b, const sb_mesh* mesh, const sb_sheet_material_def* d, sb_error* err) {
    sb_status status = sb_check_sheet(d, err);
    if (status != SB_OK) return status;
    sb_plate_stencil* stencils = sb_sheet_stencils(mesh);
    sb_material_def vertices = {.bend_k = stencils ? 0.0 : 1.0, .density = d->density * d->thickness};
    uint32_t first = sb_builder_vertex_count(b);
    size_t first_hinge = b->hinges.count, first_membrane = b->membranes.count;
    status = sb_builder_add_mesh(b, mesh, &vertices, err);
    double nu = d->poisson_ratio,
           bending_stiffness = d->young_modulus * pow(d->thickness, 3) / (12.0 * (1.0 - nu * nu));
    if (status == SB_OK) {
        sb_set_hinge_constants(b, first_hinge, bending_stiffness);
        status = sb_add_membranes(b, first, mesh, d, err);
    }
    if (status == SB_OK && stencils)
        status = sb_add_plates(b, first, first_membrane, mesh, stencils, bending_stiffness, nu, err);
    free(stencils);
    return status;
}
