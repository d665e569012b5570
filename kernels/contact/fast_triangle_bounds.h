/* Private: per-triangle bounds for the self-contact refit
 * (kernels/contact/fast_triangle_bounds.c). */
#ifndef SB_FAST_TRIANGLE_BOUNDS_H
#define SB_FAST_TRIANGLE_BOUNDS_H

#include "softbond/types.h"

/* The triangles' corners, one array per corner, in the hierarchy's leaf
 * order, padded with copies of the last triangle to a multiple of 16 past
 * the end (a block's loads stay in bounds). */
typedef struct sb_triangle_corners {
    uint32_t* corner[3];
} sb_triangle_corners;

/* Per triangle (same order): box lo x y z, hi x y z, unit normal x y z. */
typedef struct sb_triangle_bounds {
    sb_real* value[9];
} sb_triangle_bounds;

/* Fills out[first, last) from the packed positions (x y z w) at the start
 * (from4) and end (to4) of the step. */
void sb_fast_triangle_bounds(const sb_triangle_corners* corners, const sb_real* from4, const sb_real* to4,
                             uint32_t first, uint32_t last, const sb_triangle_bounds* out);

#endif
