/* The compiled model's layout, shared by the library's own modules only.
 *
 * Structure of arrays: each vertex attribute, each element's vertex index
 * and each per-element constant is its own contiguous array, so a kernel
 * streams exactly the fields it needs and SIMD lanes load one element each.
 * Everything here is set by sb_builder_compile and never changed after. */
#ifndef SB_MODEL_INTERNAL_H
#define SB_MODEL_INTERNAL_H

#include "softbond/model.h"

/* A quadratic tetrahedron's nodes: its corners, then its edges' middles. */
enum { SB_TET_NODES = 10 };
/* The most vertices a plate's stencil takes (mesh/plate_stencils.c). */
enum { SB_PLATE_NODES = 10 };

struct sb_model {
    /* vertices */
    uint32_t vertex_count;
    double *rest_x, *rest_y, *rest_z; /* rest and initial positions */
    double *vel_x, *vel_y, *vel_z;    /* initial velocities */
    double* mass;                     /* kg (fixed vertices keep theirs) */
    double* inv_mass;                 /* 0 for fixed vertices */
    uint8_t* fixed;

    /* bonds: bond stretch (Eq. 3) and damped spring (Eq. 2) */
    uint32_t bond_count;
    uint32_t *bond_i, *bond_j;
    double* bond_r0;
    double* bond_k;                          /* N/m */
    double* spring_k;                        /* N/m */
    double* spring_damping;                  /* N·s/m */
    double *bond_break_min, *bond_break_max; /* m: 0 and +inf never break */
    bool breakable;                          /* some bond has a finite limit */

    /* triangles: three corners each; corner c sits at vertex tri_v[c] with
     * neighbours tri_v[(c+1)%3] and tri_v[(c+2)%3]. */
    uint32_t triangle_count;
    uint32_t* tri_v[3];
    double* tri_cos0[3];    /* rest cosine at each corner */
    double* tri_len0[3];    /* rest length of edge (v[c], v[(c+1)%3]) */
    double* angle_k;        /* J */
    double* stretch_bend_k; /* J/m */

    /* hinges: interior edges resisting folding */
    uint32_t hinge_count;
    uint32_t *hinge_e0, *hinge_e1, *hinge_o0, *hinge_o1;
    double* hinge_phi0; /* rest dihedral, rad */
    double* hinge_k;    /* J/rad² */

    /* tetrahedra: co-rotated elasticity (Müller & Gross 2004), linear (4
     * nodes) or quadratic (10). The rest shape enters as D_m⁻¹,
     * D_m = [x1 − x0, x2 − x0, x3 − x0] at rest (row-major,
     * tet_dm_inv[3 r + c]); volume > 0 (the corners are reordered at
     * compile so that it is). tet_v[4 + e] is the vertex at the middle of
     * edge e, in the order 01 02 03 12 13 23 (sb_tet_def's), of a quadratic one; a linear one repeats
     * its corner 0 there, so that every tetrahedron has SB_TET_NODES
     * vertices to color by. */
    uint32_t tet_count;
    uint32_t* tet_v[SB_TET_NODES];
    uint8_t* tet_nodes; /* 4 or 10 */
    double* tet_dm_inv[9];
    double* tet_volume; /* m³ */
    double* tet_mu;     /* Lamé μ, Pa */
    double* tet_lambda; /* Lamé λ, Pa */
    double* tet_beta;   /* Rayleigh's stiffness-proportional damping β, s */
    bool tet_damped;    /* some β > 0: only then do the passes compute the damping */

    /* membranes: a thin sheet's co-rotated linear plane-stress triangles
     * (kernels/forces/membrane.c). The rest shape enters as D_m⁻¹ (2 × 2
     * row-major) of the rest edges written in the triangle's own plane. */
    uint32_t membrane_count;
    uint32_t* membrane_v[3];
    double* membrane_dm_inv[4];
    double* membrane_volume; /* rest area × thickness, m³ */
    double* membrane_mu;     /* Lamé μ, Pa */
    double* membrane_lambda; /* plane-stress λ = E ν / (1 − ν²), Pa */
    double* membrane_beta;   /* Rayleigh's stiffness-proportional damping β, s */
    bool membrane_damped;    /* some β > 0: only then do the passes compute the damping */

    /* plates: a flat sheet's bending (kernels/forces/plate.c), one per
     * membrane when some membrane carries one (plate_count is then
     * membrane_count, else 0). Plate t, of membrane t's triangle, has
     * plate_nodes[t] vertices (0: none) plate_v[SB_PLATE_NODES t + a] and
     * the stencil of the second derivatives x_,11, x_,12, x_,22 at the
     * triangle, plate_c[SB_PLATE_NODES (3 t + ij) + a]; its energy is
     * ½ [a (|x_,11|² + |x_,22|² + 2 |x_,12|²) + b |x_,11 + x_,22|²] of
     * x − rest, a = A D (1 − ν) and b = A D ν (J·m²). */
    uint32_t plate_count;
    uint8_t* plate_nodes;
    uint32_t* plate_v;
    double* plate_c;
    double *plate_a, *plate_b;

    /* faces: triangles of the surface that carry no force, only contact
     * (kernels/contact/surface_triangles.c): a volume of springs's boundary */
    uint32_t face_count;
    uint32_t* face_v[3];

    bool term_enabled[SB_TERM_COUNT];
};

#endif
