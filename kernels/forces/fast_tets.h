/* Private: the fast pass of the co-rotated tetrahedra (kernels/forces/fast_tets.c), as kernels/forces/fast_kernels.h
 * says. */
#ifndef SB_FAST_TETS_H
#define SB_FAST_TETS_H

#include "kernels/forces/fast_kernels.h"

/* energy[0] corotated */
int sb_fast_tets(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end, bool serial,
                 double energy[1]);

/* implicit Euler's passes on the fast kernels (kernels/forces/fast_hessian.h's
 * frame): out += scale R K0 Rᵀ p, or each corner's diagonal block of it
 * into the blocks; no damping. */
int sb_fast_tets_hessian(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end, bool serial,
                         double* energy);

#endif
