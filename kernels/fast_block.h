/* Private: iterating a color's elements in SIMD blocks, shared by the fast
 * kernels. */
#ifndef SB_FAST_BLOCK_H
#define SB_FAST_BLOCK_H

#include "kernels/fast_model.h"
#include "kernels/wide.h"

/* Lanes per block: SB_WIDTH, or 1 for the serial overflow color. */
static inline uint32_t sb_block_step(bool serial) { return serial ? 1u : SB_WIDTH; }

/* Real elements in the block starting at s. */
static inline int sb_block_count(uint32_t s, uint32_t end, uint32_t step) {
    return (int)(end - s < step ? end - s : step);
}

static inline sb_wide sb_w_constant(sb_fast_constant c, uint32_t s) {
    return c.values ? sb_w_load(c.values + s) : sb_w_set(c.uniform);
}

#endif
