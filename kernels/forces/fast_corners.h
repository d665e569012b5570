/* Private: the fast per-triangle kernel (kernels/forces/fast_corners.c), as kernels/forces/fast_kernels.h says. */
#ifndef SB_FAST_CORNERS_H
#define SB_FAST_CORNERS_H

#include "kernels/forces/fast_kernels.h"

/* energy[0] angle bend, [1] stretch-bend, [2] bond stretch and [3] spring
 * of the fused bonds, [4] bend of the fused hinges */
int sb_fast_corners(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end, bool serial,
                    double energy[5]);

#endif
