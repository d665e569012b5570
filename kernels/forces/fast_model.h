/* Private: the fast kernels' view of a model — sb_real arrays, elements
 * grouped by color, each color padded to whole SIMD blocks. Built once per
 * solver from the immutable model. */
#ifndef SB_FAST_MODEL_H
#define SB_FAST_MODEL_H

#include "mesh/model_internal.h"
#include "kernels/forces/coloring.h"

/* A per-element constant: an array, or one value for all when uniform. */
typedef struct sb_fast_constant {
    sb_real* values;
    sb_real uniform;
} sb_fast_constant;

/* Whether a constant is nonzero somewhere. */
static inline bool sb_constant_on(sb_fast_constant c) { return c.values || c.uniform != 0; }

/* Blocked coloring. The elements (in model order, which follows the mesh's
 * vertex order and so space) are cut into blocks of consecutive elements.
 * Within a block, elements are colored so that no two of a color share a
 * vertex: SIMD lanes never collide. The blocks themselves are colored the
 * same way, so that blocks of one block color share no vertex: threads
 * never collide. A step runs the block colors in order, the blocks of one
 * color in parallel, and inside a block its element colors in order; every
 * vertex therefore sums its forces in the same order for any thread count.
 * A block's vertices stay in cache while all its colors run, which an
 * element coloring of the whole mesh (every color sweeping every vertex)
 * does not give. */

/* One element color of one block: slots [begin, end), padded with copies of
 * a real element up to the next multiple of SB_WIDTH. */
typedef struct sb_color_range {
    uint32_t begin, end;
    bool serial; /* the overflow color: one element at a time */
} sb_color_range;

typedef struct sb_block {
    uint32_t first_range, range_count;
} sb_block;

typedef struct sb_element_group {
    uint32_t count;    /* real elements */
    uint32_t capacity; /* slots, with padding */
    sb_color_range* ranges;
    uint32_t range_count;
    sb_block* blocks; /* in block-color order; energies are summed per block */
    uint32_t block_count;
    uint32_t block_colors;
    uint32_t color_first_block[SB_MAX_COLORS + 1];
    uint32_t* source; /* the model's index of each slot (padding repeats one) */
} sb_element_group;

typedef struct sb_fast_model {
    uint32_t vertex_count;
    /* One real a vertex (kernels/state/solver_fast.c spreads a chunk's over its
     * packed lanes in L1); 0 inverse mass when fixed or held by a hard handle. */
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
    /* Fused bonds (see kernels/forces/fast_corners.c): edge c of a triangle slot
     * carries the bond it owns when bit c of tri_owned is set, with that
     * bond's constants (one value when uniform, else per slot) and rest
     * length: tri_edge_r0[c], or, when NULL, the triangle's own tri_len0[c]
     * (every owned bond's rest length is its edge's). Bit SB_TRIANGLE_LIVE
     * of tri_owned (every triangle slot has one byte, bonds or not) is set
     * while the triangle's corners are on: a breakable model's dying
     * triangle clears it (mortal_triangles: the kernels then mask the
     * corners' constants and collapse checks with it), and a breaking
     * fused bond its edge's bit, so that a breakable model's constants are
     * folded to one value as a plain model's are. */
    bool fused_bonds, fused_damping, mortal_triangles;
    uint8_t* tri_owned;
    sb_real* tri_edge_r0[3];
    sb_fast_constant tri_edge_bond_k[3], tri_edge_spring_k[3], tri_edge_damping[3];

    /* Fused hinges (see kernels/forces/fast_corners.c): when every hinge's edge
     * is an edge of one of its wings, each hinge is carried by one such
     * triangle and computed in its slot, and the hinge pass does not run
     * (the hinges group below is still built for other kernels and kept
     * up to date). A triangle slot carries up to 3, its hinge slots j in
     * edge order: bits 2j, 2j + 1 of tri_hinge_edges hold 1 + the edge of
     * hinge slot j (0: none). The triangle's vertices of that edge and its
     * opposite vertex are e0, e1, o0 of the hinge as the triangle orders
     * them (its normal is n0); tri_hinge_other[j] is o1, tri_hinge_phi0[j]
     * the rest angle in that order (the model's φ0, negated where that
     * order mirrors the model's). The triangles are then colored with
     * those other vertices too, and ordered within each color by how many
     * hinges they carry, most first. */
    bool fused_hinges;
    uint8_t* tri_hinge_edges;
    uint32_t* tri_hinge_other[3];
    sb_real* tri_hinge_phi0[3];
    sb_fast_constant tri_hinge_k[3];

    sb_element_group hinges;
    uint32_t* hinge_v[4]; /* e0, e1, o0, o1 */
    sb_real* hinge_phi0;
    sb_fast_constant hinge_k;
    bool has_hinges;

    /* Co-rotated tetrahedra (kernels/forces/fast_tets.c), linear or
     * quadratic (tet_nodes 4 or 10), colored by all their SB_TET_NODES
     * vertices (a linear one's repeat its corner 0: mesh/model_internal.h);
     * the constants stay in double, in which the element is computed
     * (kernels/forces/tet_element.h). Empty without tetrahedra, and then no
     * pass runs. */
    sb_element_group tets;
    uint32_t* tet_v[SB_TET_NODES];
    uint8_t* tet_nodes;
    double* tet_dm_inv[9];
    double *tet_volume, *tet_mu, *tet_lambda, *tet_beta;
    /* The same constants in sb_real, which the lane-wise pass loads. */
    sb_real *tet_lane_dm_inv[9], *tet_lane_volume, *tet_lane_mu, *tet_lane_lambda, *tet_lane_beta;
    bool has_tets, tet_damped; /* tet_damped: some β > 0 */

    /* A sheet's membranes (kernels/forces/fast_membranes.c), colored by
     * their three corners (and, for a flat sheet, by their plates' stencils:
     * a slot runs its membrane's plate too), constants in double like the
     * tetrahedra's; the plates' are read from plate_model (not owned, NULL
     * when the model has none) by the slot's source. */
    sb_element_group membranes;
    const sb_model* plate_model;
    uint32_t* membrane_v[3];
    double* membrane_dm_inv[4];
    double *membrane_volume, *membrane_mu, *membrane_lambda, *membrane_beta;
    /* The same constants in sb_real, which the lane-wise pass loads. */
    sb_real *membrane_lane_dm_inv[4], *membrane_lane_volume, *membrane_lane_mu, *membrane_lane_lambda,
        *membrane_lane_beta;
    bool has_membranes, membrane_damped; /* membrane_damped: some β > 0 */

    /* Breakage (kernels/interaction/breakage.c), only for a breakable model,
     * whose bond group's and hinges' constants are then never folded to one
     * value (the triangles' and fused bonds' are: tri_owned's bits say
     * which are on): where each model element sits. bond_place[b] >= 0 is a
     * slot of the bond group, else −1 − (3 slot + c) for edge c of a
     * triangle slot (a fused bond). */
    int64_t* bond_place;
    uint32_t *triangle_slot, *hinge_slot;
    /* With fused hinges: 2 (3 slot + j) + r for hinge slot j of a triangle
     * slot, r = 1 when tri_hinge_other is the model's o1, 0 when o0. */
    uint32_t* hinge_fused_at;
    /* The break limits' margins (a model with limits only), which the
     * kernels compare every bond's squared length with, so that the fused
     * step needs no pass of its own over the bonds: a bond inside them is
     * not past its limits, one outside is flagged to breakage
     * (SB_KERNEL_NEAR_LIMIT). Per bond slot: the squared max length shrunk
     * by SB_LIMIT_MARGIN (+inf for none; NULL without limits) and, when
     * some bond has a min length, the squared min grown by it. Per fused
     * edge, relative to the squared rest length the kernel has in hand:
     * (max / r0)² shrunk and (min / r0)² grown by the margin, one value
     * when every fused bond's are the same (a material's break strain),
     * the max's +inf and the min's 0 for none; fused_limits says whether
     * any fused bond has a limit. */
    sb_real *bond_near_max2, *bond_near_min2;
    sb_fast_constant tri_edge_max_ratio2[3], tri_edge_min_ratio2[3];
    bool fused_limits;
    bool limits_measured; /* every bond with a limit is in a pass that runs (the bond pass may not) */
} sb_fast_model;

/* Relative margin of the squared break limits, far above sb_real's rounding. */
#define SB_LIMIT_MARGIN 1e-5

sb_fast_model* sb_fast_model_create(const sb_model* model, sb_error* err);
void sb_fast_model_destroy(sb_fast_model* fast);

/* The bit of a triangle slot's tri_owned byte set while its corners are on. */
#define SB_TRIANGLE_LIVE 3

/* Breakage, in place (a breakable model only): bond `bond` loses its
 * stiffness, damping and rest length (so no collapse check either) and
 * its limits' margins; a triangle its corners (their constants and
 * collapse checks); a hinge its constant. */
void sb_fast_break_bond(sb_fast_model* fast, uint32_t bond);
/* Every bond's limits' margins widened by `factor` (> 0): break_max times
 * it, break_min over it; a broken bond's stay off. Nothing for a model
 * without limits. */
void sb_fast_widen_limits(sb_fast_model* fast, double factor);
void sb_fast_drop_triangle(sb_fast_model* fast, uint32_t triangle);
void sb_fast_drop_hinge(sb_fast_model* fast, uint32_t hinge);

/* Tearing (kernels/interaction/topology.c), in place: an element's vertex becomes
 * another (a split vertex's copy). A bond fused into a triangle follows
 * its triangle's vertices and has no slot of its own to move. */
void sb_fast_move_corner(sb_fast_model* fast, uint32_t triangle, int corner, uint32_t vertex);
void sb_fast_move_bond_end(sb_fast_model* fast, uint32_t bond, int end, uint32_t vertex);
void sb_fast_move_hinge_vertex(sb_fast_model* fast, uint32_t hinge, int role, uint32_t vertex);

#endif
