/* Private: the triangles' second derivatives, kernels/forces/fast_hessian.h's passes (fast_hessian_corners.c). */
#ifndef SB_FAST_HESSIAN_CORNERS_H
#define SB_FAST_HESSIAN_CORNERS_H

#include "kernels/forces/fast_kernels.h"

int sb_fast_corners_hessian(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end,
                            bool serial, double* unused);

#endif
