/** @file
 * Volumetric models: tetrahedral meshes from TetGen and Gmsh files, and the
 * mass-spring parameters of Sudhamani & Merriliance (2019) after Lloyd et
 * al. (2007): vertex mass from a density, spring stiffness from Young's
 * modulus, a damping rule, and named soft-tissue materials. */
#ifndef SOFTBOND_VOLUME_H
#define SOFTBOND_VOLUME_H

#include "softbond/export.h"

#include "softbond/types.h"
#include "softbond/mesh.h"
#include "softbond/builder.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A tetrahedral mesh. One the library made owns its two arrays (malloc'd:
 * sb_tet_mesh_free releases them). A zeroed sb_tet_mesh is the empty mesh. */
typedef struct sb_tet_mesh {
    uint32_t vertex_count; /**< vertices in positions */
    double* positions;     /**< 3 * vertex_count, x y z interleaved, metres */
    uint32_t tet_count;    /**< tetrahedra in tets */
    uint32_t* tets;        /**< 4 * tet_count vertex indices (the corners) */
} sb_tet_mesh;

/** Releases the arrays and zeroes the struct; safe on a zeroed mesh. */
SB_API void sb_tet_mesh_free(sb_tet_mesh* mesh);

/** TetGen: a .node file (points; its first point's number, 0 or 1, is the
 * numbering base) and an .ele file (tetrahedra of 4 or 10 nodes: the first
 * four are the corners). Comments (#) and blank lines are skipped; extra
 * columns (attributes, markers) are ignored. Vertex order is the file's. */
SB_API sb_status sb_tet_mesh_load_tetgen(const char* node_path, const char* ele_path, sb_tet_mesh* out, sb_error* err);

/** Gmsh .msh version 4 (4.0 or 4.1), ASCII: the nodes and the tetrahedra
 * (element types 4 and 11, corners only); every other element type is
 * skipped. Vertices are the nodes that some tetrahedron uses, in the order
 * of the file. */
SB_API sb_status sb_tet_mesh_load_gmsh(const char* path, sb_tet_mesh* out, sb_error* err);

/** By extension, ignoring case: ".node" or ".ele" (the other file of the
 * pair is the same name with the other extension) or ".msh". Errors are
 * one line naming the file and line. */
SB_API sb_status sb_tet_mesh_load(const char* path, sb_tet_mesh* out, sb_error* err);

/** Whether sb_tet_mesh_load reads this path (".node", ".ele", ".msh"). */
SB_API bool sb_tet_mesh_path(const char* path);

/** Signed volume of (a, b, c, d): (b − a) · ((c − a) × (d − a)) / 6, m³. */
SB_API double sb_tet_volume(const double* a, const double* b, const double* c, const double* d);

/** Indices in range and not repeated, positions finite, every tetrahedron
 * with a proper volume: an orientation opposite to the mesh's (the sign
 * most of its tetrahedra share; files differ in convention) is inverted,
 * |V| <= 1e-12 × (longest edge)³ is zero volume. The error names the first
 * bad tetrahedron by index and counts the others. */
SB_API sb_status sb_tet_mesh_check(const sb_tet_mesh* mesh, sb_error* err);

/** The boundary: every face that belongs to exactly one tetrahedron, as a
 * triangle facing out of it. All vertices are kept, with their indices, so
 * the surface can stand for the volume in frames, pins and `info`. */
SB_API sb_status sb_tet_mesh_surface(const sb_tet_mesh* mesh, sb_mesh* out, sb_error* err);

/** The surface of the quadratic tissue (SB_TISSUE_COROTATED_QUADRATIC) of
 * this mesh: the mesh's vertices, then one at the middle of each unique
 * edge, numbered as sb_builder_add_tet_mesh numbers them (in order of first
 * appearance, tetrahedron by tetrahedron, edges 01 02 03 12 13 23), so that
 * it stands for the model's vertices; each boundary triangle of
 * sb_tet_mesh_surface split in four by its edges' middles. */
SB_API sb_status sb_tet_mesh_quadratic_surface(const sb_tet_mesh* mesh, sb_mesh* out, sb_error* err);

/** How a tissue's tetrahedra resist deformation. */
typedef enum sb_tissue_model {
    SB_TISSUE_SPRINGS = 0, /**< Lloyd's damped edge springs (the papers'): E only, no ν; see sb_builder_add_tet_mesh */
    SB_TISSUE_COROTATED,   /**< co-rotated linear finite elements (sb_tet_def): E and ν; lock in bending */
    /** co-rotated quadratic finite elements (sb_tet_def, quadratic): a vertex added at each edge's middle; E and ν;
     * right in bending */
    SB_TISSUE_COROTATED_QUADRATIC
} sb_tissue_model;

/** A soft tissue: Young's modulus, density, its damping (a factor on the
 * papers' rule, 1 = the rule, 0 = none; and Rayleigh's stiffness-proportional
 * β, a material property that does not depend on the mesh); the model, and
 * Poisson's ratio for the corotated one. */
typedef struct sb_tissue_def {
    double young_modulus; /**< Pa */
    double density;       /**< kg/m³ */
    double damping;       /**< dimensionless factor on the papers' rule (springs only) */
    double
        stiffness_damping; /**< Rayleigh's β, s: damping β × stiffness (springs and both corotated orders), 0 = none */
    double poisson_ratio;  /**< ν (the finite elements only), in (−1, 0.5) */
    sb_tissue_model model; /**< springs (the default), corotated or corotated quadratic */
} sb_tissue_def;

/** Liver: E = 3.5 kPa, density 1060 kg/m³, damping factor 1. */
SB_API sb_tissue_def sb_default_tissue_def(void);

/** "liver" (E = 3.5 kPa) and "gallbladder" (E = 1.5 kPa), the moduli of
 * Sudhamani & Merriliance (2019), which give no density; both get
 * 1060 kg/m³, the adult liver's 1.06 g/cm³ in ICRU Report 46 (1992),
 * typical of soft tissue (the gallbladder is taken the same). Returns false
 * for any other name. */
SB_API bool sb_tissue_from_name(const char* name, sb_tissue_def* out);

/** The volumetric factory. Springs (SB_TISSUE_SPRINGS, the papers'): a
 * vertex per mesh vertex (order kept),
 * mass m_i = Σ_{t∋i} ρ V_t / 4; a damped spring (sb_bond_def spring_k and
 * spring_damping, bond stretch k = 0, rest length the current distance)
 * per unique tetrahedron edge with
 *     k_ij = Σ_{t∋ij} (√2/25) l_t E,   l_t = (6√2 V_t)^{1/3}
 * (l_t: the edge of the regular tetrahedron of volume V_t) and
 *     d_ij = damping × √(k_ij (m_i + m_j)) / l0_ij.
 * The damping rule is printed garbled in the source; this is the reading
 * we use, a default and not physics: √(k m) is kg/s, so d_ij in N·s/m
 * depends on the length unit (SI here), and it damps strongly for short
 * springs — scale it with `damping`. `stiffness_damping` β adds β k_ij to
 * each spring's damping (the corotated models: β to each sb_tet_def), the
 * stiffness-proportional damping D = β K, whose modes of angular frequency
 * ω decay with damping ratio ζ = β ω / 2 whatever the mesh.
 * Corotated: the same vertices and
 * masses, a linear sb_tet_def per tetrahedron. Quadratic corotated: after
 * the mesh's vertices one at the middle of each unique edge (numbered as
 * sb_tet_mesh_quadratic_surface says), a quadratic sb_tet_def per
 * tetrahedron, and HRZ-lumped masses (the consistent mass matrix's
 * diagonal scaled to the element's mass): ρ V_t / 36 to each corner and
 * 4 ρ V_t / 27 to each middle. Fails (nothing added) when the mesh
 * fails sb_tet_mesh_check or a vertex belongs to no tetrahedron. */
SB_API sb_status sb_builder_add_tet_mesh(sb_builder* builder, const sb_tet_mesh* mesh, const sb_tissue_def* tissue,
                                         sb_error* err);

#ifdef __cplusplus
}
#endif
#endif
