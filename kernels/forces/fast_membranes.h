/* Private: the fast pass of a sheet's membranes (kernels/forces/fast_membranes.c), as kernels/forces/fast_kernels.h
 * says. */
#ifndef SB_FAST_MEMBRANES_H
#define SB_FAST_MEMBRANES_H

#include "kernels/forces/fast_kernels.h"

/* energy[0] membrane, energy[1] bend (the plates') */
int sb_fast_membranes(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end, bool serial,
                      double energy[2]);

/* implicit Euler's passes on the fast kernels (kernels/forces/fast_hessian.h's
 * frame): out += scale K p with K the membrane's co-rotated stiffness, or
 * each corner's diagonal block of it into the blocks; no damping. */
int sb_fast_membranes_hessian(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end,
                              bool serial, double* energy);

#endif
