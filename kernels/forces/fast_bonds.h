/* Private: the fast per-bond kernel (kernels/forces/fast_bonds.c), as kernels/forces/fast_kernels.h says. */
#ifndef SB_FAST_BONDS_H
#define SB_FAST_BONDS_H

#include "kernels/forces/fast_kernels.h"

/* energy[0] bond stretch, energy[1] spring */
int sb_fast_bonds(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end, bool serial,
                  double energy[2]);

#endif
