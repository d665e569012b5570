#include "kernels/coloring.h"

#include <stdlib.h>
#include <string.h>

bool sb_colorer_init(sb_colorer* c, uint32_t vertex_count) {
    memset(c, 0, sizeof *c);
    c->used = calloc(vertex_count ? vertex_count : 1, sizeof *c->used);
    return c->used != NULL;
}

void sb_colorer_free(sb_colorer* c) {
    free(c->used);
    c->used = NULL;
}

int sb_colorer_pick(sb_colorer* c, uint64_t taken) {
    int best = -1;
    for (int k = 0; k < (int)c->opened; k++)
        if (!(taken >> k & 1u) && (best < 0 || c->sizes[k] < c->sizes[best])) best = k;
    if (best < 0) best = c->opened < SB_OVERFLOW_COLOR ? (int)c->opened++ : SB_OVERFLOW_COLOR;
    c->sizes[best]++;
    return best;
}

uint32_t sb_colorer_run(sb_colorer* c, uint32_t begin, uint32_t end, int arity, const uint32_t* const* vertices,
                        uint8_t* color) {
    memset(c->sizes, 0, sizeof c->sizes);
    c->opened = 0;
    bool overflow = false;
    for (uint32_t e = begin; e < end; e++) {
        uint64_t taken = 0;
        for (int a = 0; a < arity; a++) taken |= c->used[vertices[a][e]];
        int k = sb_colorer_pick(c, taken);
        color[e - begin] = (uint8_t)k;
        overflow |= k == SB_OVERFLOW_COLOR;
        if (k != SB_OVERFLOW_COLOR)
            for (int a = 0; a < arity; a++) c->used[vertices[a][e]] |= UINT64_C(1) << k;
    }
    for (uint32_t e = begin; e < end; e++)
        for (int a = 0; a < arity; a++) c->used[vertices[a][e]] = 0;
    return overflow ? SB_MAX_COLORS : c->opened;
}
