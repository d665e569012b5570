/** @file
 * The compiled, immutable model: topology, rest values, constants, masses.
 * Read it through these accessors; its layout is private. */
#ifndef SOFTBOND_MODEL_H
#define SOFTBOND_MODEL_H

#include "softbond/export.h"

#include "softbond/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A compiled model (sb_builder_compile); opaque and never changed after
 * compilation, so any number of solvers and threads may read it at once. */
typedef struct sb_model sb_model;

/** Which force terms a model carries: a term with every constant 0 is off. */
typedef enum sb_term {
    SB_TERM_BOND = 0,     /**< bond stretch, Sekercioglu & Duysak 2009 Eq. 3 */
    SB_TERM_ANGLE,        /**< angle bend, Sekercioglu & Duysak 2009 Eq. 4 */
    SB_TERM_STRETCH_BEND, /**< stretch-bend, Sekercioglu & Duysak 2009 Eq. 5 */
    SB_TERM_SPRING,       /**< damped spring, Sekercioglu & Duysak 2009 Eq. 2 */
    SB_TERM_BEND,         /**< dihedral hinge */
    SB_TERM_COROTATED,    /**< co-rotated linear elasticity of tetrahedra (Müller & Gross 2004) */
    SB_TERM_MEMBRANE,     /**< co-rotated linear plane-stress triangles: a thin sheet's membrane */
    SB_TERM_COUNT
} sb_term;

/** "bond", "angle", "stretch_bend", "spring", "bend", "corotated", "membrane". */
SB_API const char* sb_term_name(sb_term term);

/** Frees the model; safe on NULL. Every solver made from it must be
 * destroyed first. */
SB_API void sb_model_destroy(sb_model* model);

/** The number of vertices. */
SB_API uint32_t sb_model_vertex_count(const sb_model* model);
/** The number of bonds, in the order they were added. */
SB_API uint32_t sb_model_bond_count(const sb_model* model);
/** The number of triangles, in the order they were added. */
SB_API uint32_t sb_model_triangle_count(const sb_model* model);
/** The number of hinges, in the order they were added. */
SB_API uint32_t sb_model_hinge_count(const sb_model* model);
/** Tetrahedra of the co-rotated elastic term (sb_builder_add_tet). */
SB_API uint32_t sb_model_tet_count(const sb_model* model);
/** Membrane triangles of a thin sheet (sb_builder_add_membrane). */
SB_API uint32_t sb_model_membrane_count(const sb_model* model);
/** Whether the model carries the term (some element has a constant > 0);
 * false for a term out of range. */
SB_API bool sb_model_term_enabled(const sb_model* model, sb_term term);

/** Rest (initial) position, initial velocity, mass and pin of a vertex.
 * The vertex index is not checked: it must be below sb_model_vertex_count. */
SB_API void sb_model_rest_position(const sb_model* model, uint32_t vertex, double out[3]);
/** The initial velocity (m/s) into out; zero for a fixed vertex. */
SB_API void sb_model_initial_velocity(const sb_model* model, uint32_t vertex, double out[3]);
/** The mass (kg), as given or as a factory's density gave it. */
SB_API double sb_model_mass(const sb_model* model, uint32_t vertex);
/** Whether the vertex is fixed (sb_vertex_def.fixed). */
SB_API bool sb_model_is_fixed(const sb_model* model, uint32_t vertex);

/** A compiled bond: its vertices, rest length (m) and constants. */
typedef struct sb_bond_info {
    /** @var i
     * the vertex at one end
     * @var j
     * the vertex at the other end */
    uint32_t i, j;
    /** @var rest_length
     * m: r0, as given or the distance at compile time
     * @var k
     * N/m: bond stretch (Sekercioglu & Duysak 2009, Eq. 3)
     * @var spring_k
     * N/m: damped spring (the same paper's Eq. 2)
     * @var spring_damping
     * N·s/m: the damped spring's damping along the bond */
    double rest_length, k, spring_k, spring_damping;
} sb_bond_info;

/** The compiled bond `bond` (below sb_model_bond_count; not checked). */
SB_API sb_bond_info sb_model_bond(const sb_model* model, uint32_t bond);

/** The three vertices of a compiled triangle, in its corner order. */
SB_API void sb_model_triangle(const sb_model* model, uint32_t triangle, uint32_t out[3]);

#ifdef __cplusplus
}
#endif
#endif
