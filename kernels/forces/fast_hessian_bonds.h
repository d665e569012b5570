/* Private: the bonds' second derivatives, kernels/forces/fast_hessian.h's passes (fast_hessian_bonds.c). */
#ifndef SB_FAST_HESSIAN_BONDS_H
#define SB_FAST_HESSIAN_BONDS_H

#include "kernels/forces/fast_kernels.h"

int sb_fast_bonds_hessian(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end, bool serial,
                          double* unused);

#endif
