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

typedef struct sb_model sb_model;

/** Which force terms a model carries: a term with every constant 0 is off. */
typedef enum sb_term {
    SB_TERM_BOND = 0,     /**< bond stretch, Sekercioglu & Duysak 2009 Eq. 3 */
    SB_TERM_ANGLE,        /**< angle bend, Sekercioglu & Duysak 2009 Eq. 4 */
    SB_TERM_STRETCH_BEND, /**< stretch-bend, Sekercioglu & Duysak 2009 Eq. 5 */
    SB_TERM_SPRING,       /**< damped spring, Sekercioglu & Duysak 2009 Eq. 2 */
    SB_TERM_BEND,         /**< dihedral hinge */
    SB_TERM_COROTATED,    /**< co-rotated linear elasticity of tetrahedra (Müller & Gross 2004) */
    SB_TERM_COUNT
} sb_term;

/** "bond", "angle", "stretch_bend", "spring", "bend". */
SB_API const char* sb_term_name(sb_term term);

SB_API void sb_model_destroy(sb_model* model);

SB_API uint32_t sb_model_vertex_count(const sb_model* model);
SB_API uint32_t sb_model_bond_count(const sb_model* model);
SB_API uint32_t sb_model_triangle_count(const sb_model* model);
SB_API uint32_t sb_model_hinge_count(const sb_model* model);
/** Tetrahedra of the co-rotated elastic term (sb_builder_add_tet). */
SB_API uint32_t sb_model_tet_count(const sb_model* model);
SB_API bool sb_model_term_enabled(const sb_model* model, sb_term term);

/** Rest (initial) position, initial velocity, mass and pin of a vertex. */
SB_API void sb_model_rest_position(const sb_model* model, uint32_t vertex, double out[3]);
SB_API void sb_model_initial_velocity(const sb_model* model, uint32_t vertex, double out[3]);
SB_API double sb_model_mass(const sb_model* model, uint32_t vertex);
SB_API bool sb_model_is_fixed(const sb_model* model, uint32_t vertex);

/** A compiled bond: its vertices, rest length (m) and constants. */
typedef struct sb_bond_info {
    uint32_t i, j;
    double rest_length, k, spring_k, spring_damping;
} sb_bond_info;

SB_API sb_bond_info sb_model_bond(const sb_model* model, uint32_t bond);

/** The three vertices of a compiled triangle, in its corner order. */
SB_API void sb_model_triangle(const sb_model* model, uint32_t triangle, uint32_t out[3]);

#ifdef __cplusplus
}
#endif
#endif
