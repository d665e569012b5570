/* Private: the fast per-hinge kernel (kernels/forces/fast_hinges.c), as kernels/forces/fast_kernels.h says. */
#ifndef SB_FAST_HINGES_H
#define SB_FAST_HINGES_H

#include "kernels/forces/fast_kernels.h"

/* energy[0] bend */
int sb_fast_hinges(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end, bool serial,
                   double energy[1]);

#endif
