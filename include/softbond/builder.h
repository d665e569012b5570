/** @file
 * Construction mode: add vertices, bonds and triangles, then compile them
 * into an immutable sb_model (the Spring Systems library's SpringGraph). */
#ifndef SOFTBOND_BUILDER_H
#define SOFTBOND_BUILDER_H

#include "softbond/export.h"

#include "softbond/types.h"
#include "softbond/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A model under construction: growable arrays of vertex, bond, triangle
 * and hinge definitions, compiled by sb_builder_compile. Opaque. */
typedef struct sb_builder sb_builder;
/** The compiled, immutable model (softbond/model.h). */
typedef struct sb_model sb_model;

/** A mass point. */
typedef struct sb_vertex_def {
    double position[3]; /**< m; also the rest position */
    double velocity[3]; /**< m/s, initial */
    double mass;        /**< kg; must be > 0 unless fixed */
    bool fixed;         /**< pinned: stays at its rest position, velocity taken as 0; its mass may be 0 */
} sb_vertex_def;

/** A bond between two vertices carries two edge terms: the molecular bond
 * stretch ½ k (r − r0)² (Sekercioglu & Duysak 2009, Eq. 3) and the classic
 * damped spring (the same paper's Eq. 2)
 * ½ spring_k (r − r0)² with damping spring_damping along the bond. */
typedef struct sb_bond_def {
    /** @var i
     * the vertex at one end (an index into the builder's vertices)
     * @var j
     * the vertex at the other end; not i */
    uint32_t i, j;
    double rest_length;    /**< m; negative means the current distance */
    double k;              /**< N/m, bond stretch */
    double spring_k;       /**< N/m, damped spring */
    double spring_damping; /**< N·s/m */
    /** Breakage (the Spring Systems library's l_min, l_max): a solver breaks
     * the bond at the first step whose end length is below break_min or
     * above break_max — its stiffness and damping become zero for the rest
     * of the run (sb_solver_def.on_break; DESIGN.md, section Breakage). break_min 0
     * and break_max +inf (or 0) never break; a finite limit must leave the
     * rest length strictly inside (break_min, break_max). */
    double break_min, break_max; /**< m */
} sb_bond_def;

/** A triangle contributes one angle per corner: angle bend
 * ½ angle_k (cos θ − cos θ0)² (Sekercioglu & Duysak 2009, Eq. 4) and
 * stretch-bend stretch_bend_k (cos θ − cos θ0)[(rA − rA0) + (rB − rB0)]
 * (the same paper's Eq. 5, which leaves the constant out). Rest
 * values come from the vertices' positions. */
typedef struct sb_triangle_def {
    /** @var i
     * the first corner (an index into the builder's vertices)
     * @var j
     * the second corner
     * @var k
     * the third corner; the three distinct */
    uint32_t i, j, k;
    double angle_k;        /**< J */
    double stretch_bend_k; /**< J/m */
} sb_triangle_def;

/** A hinge is an interior edge (e0, e1) shared by the triangles (e0, e1, o0)
 * and (e1, e0, o1); it resists folding with ½ k (φ − φ0)², φ the signed
 * dihedral angle (0 when flat), φ0 taken from the positions. */
typedef struct sb_hinge_def {
    /** @var e0
     * the shared edge's first vertex
     * @var e1
     * the shared edge's second vertex
     * @var o0
     * the vertex opposite the edge in the triangle (e0, e1, o0)
     * @var o1
     * the vertex opposite the edge in the triangle (e1, e0, o1) */
    uint32_t e0, e1, o0, o1;
    double k; /**< J/rad² */
} sb_hinge_def;

/** A tetrahedron of co-rotated elastic material (Müller & Gross 2004):
 * energy ½ (Rᵀx − x0)ᵀ K0 (Rᵀx − x0), K0 the element's stiffness from E, ν
 * and the rest shape (the corners' positions), R the rotation of the polar
 * decomposition of the deformation gradient of the corners. Linear (4
 * nodes): forces are the energy's exact negative gradient. Quadratic (10
 * nodes, `quadratic` true): a vertex at the middle of each edge, shared by
 * the edge's tetrahedra; its rest place is taken at the middle of its edge
 * (straight edges); forces f = −R K0 (Rᵀx − x0) with R held (not the
 * gradient of the energy; kernels/forces/corotated_quadratic.h). The
 * quadratic element does not lock in bending as the linear one does. The
 * vertex order may be either orientation; the volume must not be zero.
 * Damping: Rayleigh's stiffness-proportional f = −β R K0 Rᵀ v (v the
 * nodes' velocities, R the rotation at the current positions; linear and
 * quadratic elements), zero for a translation and for a rotation of the
 * unstrained element; a mode of angular frequency ω decays with damping
 * ratio β ω / 2. The solver's drag is the mass-proportional part. */
typedef struct sb_tet_def {
    uint32_t v[4];            /**< the corners, either orientation */
    double young_modulus;     /**< E, Pa (>= 0) */
    double poisson_ratio;     /**< ν, in (−1, 0.5) */
    double stiffness_damping; /**< Rayleigh's β, s (>= 0; 0 = undamped) */
    bool quadratic;           /**< 10 nodes: mid[] is used */
    /** quadratic only: the vertex at the middle of edge (v[0], v[1]),
     * (v[0], v[2]), (v[0], v[3]), (v[1], v[2]), (v[1], v[3]), (v[2], v[3]) */
    uint32_t mid[6];
} sb_tet_def;

/** A triangle of a thin sheet's membrane: co-rotated linear plane-stress
 * elasticity of a constant-strain triangle (kernels/forces/membrane.c),
 * energy A t (μ ‖F − R‖² + ½ λ (tr RᵀF − 2)²) with μ = E / 2(1 + ν),
 * λ = E ν / (1 − ν²), F the map from the rest triangle's plane and R its
 * rotation; the rest shape from the vertices' positions. Damping:
 * Rayleigh's stiffness-proportional −β K v (K the co-rotated stiffness, v
 * the corners' velocities), zero for a translation and for a rotation of
 * the unstrained triangle; an in-plane mode of angular frequency ω decays
 * with damping ratio β ω / 2. The solver's drag is the mass-proportional
 * part. */
typedef struct sb_membrane_def {
    uint32_t v[3];            /**< the corners, either orientation */
    double young_modulus;     /**< E, Pa (>= 0) */
    double poisson_ratio;     /**< ν, in (−1, 0.5) */
    double thickness;         /**< t, m (> 0) */
    double stiffness_damping; /**< Rayleigh's β, s (>= 0; 0 = undamped) */
} sb_membrane_def;

/** A free vertex of 1 kg at rest at the origin. */
SB_API sb_vertex_def sb_default_vertex_def(void);
/** A bond between vertices 0 and 0 (set i and j) with no stiffness and no
 * damping, its rest length the distance at compile time (-1), never
 * breaking (break_min 0, break_max +inf). */
SB_API sb_bond_def sb_default_bond_def(void);
/** A triangle of vertices 0, 0, 0 (set i, j and k) with no constants: all
 * zeros. */
SB_API sb_triangle_def sb_default_triangle_def(void);
/** The factories' strain rule, for a bond's break_max: the length beyond
 * which the bond between mesh vertices a and b breaks, r0 (1 + strain), r0
 * their distance, m; +inf when strain is 0. Public so that a factory built
 * outside the library (the scene loader's net) breaks by the same rule. */
SB_API double sb_strain_break_length(const sb_mesh* mesh, uint32_t a, uint32_t b, double strain);

/** An empty builder, or NULL when out of memory. Free it with
 * sb_builder_destroy; the models it compiles do not depend on it. */
SB_API sb_builder* sb_builder_create(void);
/** Frees the builder and everything added to it; safe on NULL. */
SB_API void sb_builder_destroy(sb_builder* builder);

/** Each add returns the new element's index, or -1 when out of memory.
 * Nothing is checked here: compile validates everything at once. */
SB_API int64_t sb_builder_add_vertex(sb_builder* builder, const sb_vertex_def* def);
/** Adds a copy of *def; the index or -1 as sb_builder_add_vertex. */
SB_API int64_t sb_builder_add_bond(sb_builder* builder, const sb_bond_def* def);
/** Adds a copy of *def; the index or -1 as sb_builder_add_vertex. */
SB_API int64_t sb_builder_add_triangle(sb_builder* builder, const sb_triangle_def* def);
/** Adds a copy of *def; the index or -1 as sb_builder_add_vertex. */
SB_API int64_t sb_builder_add_hinge(sb_builder* builder, const sb_hinge_def* def);
/** Adds a face: a triangle of the body's surface (corners, indices into
 * the builder's vertices) that carries no force, only contact: the
 * colliders stop at it between its corners (docs/contact.md). For a body
 * whose surface is not otherwise made of triangles or membranes: a volume
 * of springs (sb_builder_add_tet_mesh adds its boundary). Returns its index
 * or −1 as sb_builder_add_vertex. */
SB_API int64_t sb_builder_add_face(sb_builder* builder, const uint32_t corners[3]);
/** Adds a co-rotated tetrahedron (sb_tet_def); returns its index or −1. */
SB_API int64_t sb_builder_add_tet(sb_builder* builder, const sb_tet_def* def);
/** Adds a membrane triangle (sb_membrane_def); returns its index or −1. */
SB_API int64_t sb_builder_add_membrane(sb_builder* builder, const sb_membrane_def* def);

/** The vertices added so far: the index the next one gets (a factory adds
 * its mesh's vertices from there). */
SB_API uint32_t sb_builder_vertex_count(const sb_builder* builder);
/** Changes a vertex after it was added (to pin it, give it a mass, ...). */
SB_API sb_vertex_def* sb_builder_vertex(sb_builder* builder, uint32_t index);

/** Validates and compiles. On failure returns NULL and err names the first
 * bad element: an index out of range, a bond from a vertex to itself, a
 * duplicate bond (rejected, never merged: the caller decides which constants
 * win), a degenerate triangle or hinge, a non-finite number, a free vertex
 * with zero or negative mass, a negative constant. The builder is unchanged
 * and may be compiled again. */
SB_API sb_model* sb_builder_compile(const sb_builder* builder, sb_error* err);

/** Constants for the mesh factory: every term is per element, uniform here. */
typedef struct sb_material_def {
    double bond_k;         /**< N/m, Sekercioglu & Duysak 2009 Eq. 3, 0 = off */
    double angle_k;        /**< J, Sekercioglu & Duysak 2009 Eq. 4, 0 = off */
    double stretch_bend_k; /**< J/m, Sekercioglu & Duysak 2009 Eq. 5, 0 = off */
    double spring_k;       /**< N/m, Sekercioglu & Duysak 2009 Eq. 2, 0 = off */
    double spring_damping; /**< N·s/m, Sekercioglu & Duysak 2009 Eq. 2 */
    double bend_k;         /**< J/rad², hinge term, 0 = off */
    double mass;           /**< kg per vertex, used when density is 0 */
    double density;        /**< kg/m², areal: each vertex gets a third of its triangles' mass */
    double break_strain;   /**< every bond breaks beyond r0 (1 + break_strain); 0 = never */
} sb_material_def;

/** bond_k 100 N/m, angle_k 0.1 J, 0.01 kg per vertex; every other term off,
 * density 0, no breakage. */
SB_API sb_material_def sb_default_material_def(void);

/** The mesh factory for molecular mechanics: a vertex per mesh vertex (order
 * kept), a bond per unique edge (in order of first appearance), a triangle
 * per face (all three corners), a hinge per edge shared by exactly two
 * triangles (only when bend_k > 0). Fails when an edge is shared by more than
 * two triangles and bend_k > 0 (the hinge would be ambiguous). */
SB_API sb_status sb_builder_add_mesh(sb_builder* builder, const sb_mesh* mesh, const sb_material_def* material,
                                     sb_error* err);

/** The Spring Systems mesh factory (Juhasz & Bercovici): a mass point per
 * vertex (order kept), a damped spring (sb_bond_def spring_k and
 * spring_damping, bond stretch k = 0) per unique edge, a bend spring across
 * each edge shared by exactly two triangles (between the two opposite
 * vertices), and a vicinity spring between each pair of vertices nearer
 * than `vicinity` that no stretch or bend spring joins already. Rest lengths
 * are the current distances; no pair is joined twice. Springs whose
 * stiffness and damping are both 0 are not added (stretch, bend or
 * vicinity); vicinity = 0 adds none. */
typedef struct sb_spring_mesh_def {
    /** N/m: the stretch springs' stiffness, per edge */
    double stretch_k, stretch_damping; /**< N/m, N·s/m: per edge */
    /** N/m: the bend springs' stiffness, across adjacent triangles */
    double bend_k, bend_damping; /**< N/m, N·s/m: across adjacent triangles */
    double vicinity;             /**< m: join vertices nearer than this; 0 = none */
    /** N/m: the vicinity springs' stiffness */
    double vicinity_k, vicinity_damping; /**< N/m, N·s/m */
    double mass;                         /**< kg per vertex, used when density is 0 */
    double density;                      /**< kg/m², areal: a third of each triangle's mass */
    double break_strain;                 /**< every spring breaks beyond r0 (1 + break_strain); 0 = never */
} sb_spring_mesh_def;

/** stretch 100 N/m and 0.1 N·s/m, bend 10 N/m and 0.01 N·s/m, no vicinity
 * springs (distance 0; 100 N/m and 0.1 N·s/m once one is set), 0.01 kg per
 * vertex: the scene keys' defaults. */
SB_API sb_spring_mesh_def sb_default_spring_mesh_def(void);
/** Adds the mesh's springs as described at sb_spring_mesh_def, the mesh's
 * vertices after those already in the builder (its vertex v becomes
 * sb_builder_vertex_count() + v). SB_ERR_INVALID, with nothing added, for a
 * negative or non-finite constant or a triangle index out of range;
 * SB_ERR_NOMEM when out of memory (what was added so far stays). */
SB_API sb_status sb_builder_add_spring_mesh(sb_builder* builder, const sb_mesh* mesh, const sb_spring_mesh_def* def,
                                            sb_error* err);

/** A thin sheet stated by its material (a cloth, a membrane of tissue):
 * Young's modulus, Poisson's ratio, thickness and density. */
typedef struct sb_sheet_material_def {
    double young_modulus;     /**< E, Pa (> 0) */
    double poisson_ratio;     /**< ν, in (−1, 0.5) */
    double thickness;         /**< t, m (> 0) */
    double density;           /**< ρ, kg/m³ (> 0): each vertex gets a third of its triangles' ρ t A */
    double stiffness_damping; /**< the membranes' Rayleigh β, s (>= 0; 0 = undamped; the bending is undamped) */
} sb_sheet_material_def;

/** E 30 kPa, ν 0.45, 1 mm, 1060 kg/m³, undamped: a soft tissue's membrane. */
SB_API sb_sheet_material_def sb_default_sheet_material_def(void);
/** The sheet factory: the mesh's vertices after those already in the
 * builder (masses ρ t A / 3 from each triangle), a membrane per triangle
 * (sb_membrane_def: in-plane stiffness E t / (1 − ν²)) and the bending of
 * stiffness D = E t³ / 12 (1 − ν²). A flat mesh without interior vertices
 * of four neighbours bends by the plate's energy
 * ½ D [(1 − ν)(κ11² + κ22² + 2 κ12²) + ν (κ11 + κ22)²], its curvatures
 * from a stencil per triangle (the `bend` term; mesh/sheet_factory.c says
 * why); any other (curved, the sheet generator's alternating diagonals,
 * fewer than six vertices) by a hinge per edge shared by exactly two
 * triangles, the discrete shell's bending (Grinspun et al. 2003) with its
 * own constant k = D |e|² / (A0 + A1) from the edge's length |e| and its
 * two triangles' areas.
 * SB_ERR_INVALID, with nothing added, for a constant out of range, a
 * triangle index out of range or an edge shared by more than two
 * triangles; SB_ERR_NOMEM when out of memory. */
SB_API sb_status sb_builder_add_sheet(sb_builder* builder, const sb_mesh* mesh, const sb_sheet_material_def* def,
                                      sb_error* err);

/** The pairs (i < j) of points nearer than radius (0 < distance < radius),
 * found with a uniform grid (cells of side radius, sorted by cell) in time
 * linear in count: *pairs receives 2 * *pair_count indices (caller frees),
 * i < j in each pair, pairs in a deterministic order (by cell, not sorted).
 * Coincident points (distance 0) are not paired. */
SB_API sb_status sb_vicinity_pairs(const double* positions, uint32_t count, double radius, uint32_t** pairs,
                                   size_t* pair_count, sb_error* err);

#ifdef __cplusplus
}
#endif
#endif
