/* Private: the fast kernels' view of a model — sb_real arrays, elements
 * grouped by color, each color padded to whole SIMD blocks. Built once per
 * solver from the immutable model. */
#ifndef SB_FAST_MODEL_H
#define SB_FAST_MODEL_H

#include "mesh/model_internal.h"
#include "kernels/coloring.h"

/* Work is split into chunks of this many elements (a multiple of every
 * SIMD width). Chunks, not threads, own the partial energy sums, so the
 * totals are the same for any thread count. */
#define SB_CHUNK 256

/* A per-element constant: an array, or one value for all when uniform. */
typedef struct sb_fast_constant {
    sb_real* values;
    sb_real uniform;
} sb_fast_constant;

/* One color's slice of an element group: real elements [begin, end),
 * padding up to the next multiple of SB_WIDTH after end. */
typedef struct sb_color_range {
    uint32_t begin, end;
    uint32_t first_chunk; /* index of its first chunk among the group's */
    bool serial;          /* the overflow color: one element at a time */
} sb_color_range;

typedef struct sb_element_group {
    uint32_t count;     /* real elements */
    uint32_t capacity;  /* with padding */
    uint32_t color_count;
    sb_color_range colors[SB_MAX_COLORS];
    uint32_t chunk_count;
    uint32_t* source; /* the model's index of each slot (padding repeats one) */
} sb_element_group;

typedef struct sb_fast_model {
    uint32_t vertex_count;
    sb_real *mass, *inv_mass;

    sb_element_group bonds; /* the bonds no triangle owns */
    uint32_t *bond_i, *bond_j;
    sb_real* bond_r0;
    sb_fast_constant bond_k, spring_k, spring_damping;
    bool has_bond, has_spring, has_damping;

    sb_element_group triangles;
    uint32_t* tri_v[3];
    sb_real *tri_cos0[3], *tri_len0[3];
    sb_fast_constant angle_k, stretch_bend_k;
    bool has_corners;
    /* fused bonds (see kernels/fast_corners.c): edge c of a triangle slot
     * carries its bond with weight tri_edge_owned[c] (1 or 0), rest length
     * tri_edge_r0[c] and the uniform bond_k and spring_k */
    bool fused_bonds;
    sb_real *tri_edge_owned[3], *tri_edge_r0[3];

    sb_element_group hinges;
    uint32_t *hinge_v[4]; /* e0, e1, o0, o1 */
    sb_real* hinge_phi0;
    sb_fast_constant hinge_k;
    bool has_hinges;
} sb_fast_model;

sb_fast_model* sb_fast_model_create(const sb_model* model, sb_error* err);
void sb_fast_model_destroy(sb_fast_model* fast);

#endif
