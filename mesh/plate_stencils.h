/* Private: the plate bending's stencils of a flat sheet (plate_stencils.c). */
#ifndef SB_PLATE_STENCILS_H
#define SB_PLATE_STENCILS_H

#include "mesh/model_internal.h"
#include "softbond/mesh.h"

#include <stdbool.h>

/* One triangle's stencil: the second derivatives of a position field over
 * the rest plane at the triangle, x_,ij ≈ Σ_a c[ij][a] x[v[a]] (ij = 11,
 * 12, 22), exact for every quadratic field; count vertices (its three
 * corners first), the unused entries zero. */
typedef struct sb_plate_stencil {
    int count;
    uint32_t v[SB_PLATE_NODES];
    double c[3][SB_PLATE_NODES];
    double area; /* the triangle's rest area, m² */
} sb_plate_stencil;

/* Whether the plate's stencils suit the mesh: it lies in one plane (every
 * vertex within 1e-9 of its size of the first triangle's plane) and no
 * interior vertex has four neighbours or fewer. Where it has (a grid cut
 * along alternating diagonals: every other vertex has four), the stencils
 * sum, at each vertex, to a curvature of the checkerboard oscillation,
 * which the bend then drives: a clamped plate comes out 40 to 65 % too
 * soft, the error growing with refinement (docs/materials.md). */
bool sb_plate_suits(const sb_mesh* mesh);

/* The stencil of every triangle of a flat mesh into out[triangle_count];
 * false when out of memory or when a triangle's neighbourhood cannot fix
 * a quadratic (a mesh of a few collinear triangles). */
bool sb_plate_stencils(const sb_mesh* mesh, sb_plate_stencil* out);

#endif
