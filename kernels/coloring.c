#include "kernels/coloring.h"

#include <stdlib.h>

/* The least used of the `opened` colors not set in `used`; a new color
 * when all are taken; the overflow color when no new one is left. */
static int sb_pick_color(uint64_t used, const uint32_t* sizes, uint32_t opened) {
    int best = -1;
    for (int c = 0; c < (int)opened; c++)
        if (!(used >> c & 1u) && (best < 0 || sizes[c] < sizes[best])) best = c;
    if (best >= 0) return best;
    return opened < SB_OVERFLOW_COLOR ? (int)opened : SB_OVERFLOW_COLOR;
}

uint32_t sb_color_elements(uint32_t vertex_count, uint32_t count, int arity, const uint32_t* const* vertices,
                           uint8_t* color) {
    uint64_t* used = calloc(vertex_count ? vertex_count : 1, sizeof *used);
    if (!used) return 0;
    uint32_t sizes[SB_MAX_COLORS] = {0};
    uint32_t opened = 0;
    for (uint32_t e = 0; e < count; e++) {
        uint64_t taken = 0;
        for (int a = 0; a < arity; a++) taken |= used[vertices[a][e]];
        int c = sb_pick_color(taken, sizes, opened);
        color[e] = (uint8_t)c;
        sizes[c]++;
        if (c != SB_OVERFLOW_COLOR)
            for (int a = 0; a < arity; a++) used[vertices[a][e]] |= UINT64_C(1) << c;
        if (c == (int)opened && opened < SB_OVERFLOW_COLOR) opened++;
    }
    free(used);
    bool overflow = false;
    for (uint32_t e = 0; e < count && !overflow; e++) overflow = color[e] == SB_OVERFLOW_COLOR;
    return overflow ? SB_MAX_COLORS : (opened ? opened : 1);
}
