/* Private: the triangles' diagonal blocks in closed form (kernels/forces/fast_hessian_corner_blocks.c). */
#ifndef SB_FAST_HESSIAN_CORNER_BLOCKS_H
#define SB_FAST_HESSIAN_CORNER_BLOCKS_H

#include "kernels/forces/fast_hessian.h"

/* The triangles' diagonal pass in closed form
 * (kernels/forces/fast_hessian_corner_blocks.c). */
void sb_fast_corner_blocks(const sb_fast_model* m, const sb_hessian_frame* frame, uint32_t begin, uint32_t end,
                           bool serial);

#endif
