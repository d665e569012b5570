#include "kernels/forces/coloring.h"

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

void sb_blocked_free(sb_blocked* b) {
    free(b->order);
    free(b->run_first);
    free(b->run_serial);
    free(b->block_first_run);
    *b = (sb_blocked){0};
}

uint32_t sb_blocked_colors(const sb_blocked* b) {
    uint32_t colors = 0;
    for (int k = 0; k < SB_MAX_COLORS; k++) colors += b->color_first_block[k + 1] > b->color_first_block[k];
    return colors;
}

/* Colors the blocks with the shared `blocks` colorer (its marks kept). */
static void sb_blocked_color_blocks(sb_colorer* blocks, uint32_t count, uint32_t block_size, int arity,
                                    const uint32_t* const* vertices, uint8_t* block_color, uint32_t block_count) {
    for (uint32_t k = 0; k < block_count; k++) {
        uint32_t first = k * block_size, end = first + block_size < count ? first + block_size : count;
        uint64_t taken = 0;
        for (uint32_t e = first; e < end; e++)
            for (int a = 0; a < arity; a++) taken |= blocks->used[vertices[a][e]];
        int color = sb_colorer_pick(blocks, taken);
        block_color[k] = (uint8_t)color;
        for (uint32_t e = first; color != SB_OVERFLOW_COLOR && e < end; e++)
            for (int a = 0; a < arity; a++) blocks->used[vertices[a][e]] |= UINT64_C(1) << color;
    }
}

/* Appends block [first, end), its items colored by color[], as runs. */
static void sb_blocked_append(sb_blocked* b, uint32_t first, uint32_t end, const uint8_t* color) {
    uint32_t sizes[SB_MAX_COLORS] = {0}, cursor[SB_MAX_COLORS], at = b->run_first[b->run_count];
    for (uint32_t e = first; e < end; e++) sizes[color[e]]++;
    b->block_first_run[b->block_count++] = b->run_count;
    for (int k = 0; k < SB_MAX_COLORS; k++) {
        if (!sizes[k]) continue;
        cursor[k] = at;
        b->run_serial[b->run_count] = k == SB_OVERFLOW_COLOR;
        b->run_first[b->run_count++] = at;
        at += sizes[k];
    }
    b->run_first[b->run_count] = at;
    for (uint32_t e = first; e < end; e++) b->order[cursor[color[e]]++] = e;
}

bool sb_blocked_build(sb_blocked* b, uint32_t vertex_count, uint32_t count, uint32_t block_size, int arity,
                      const uint32_t* const* vertices) {
    *b = (sb_blocked){.count = count};
    uint32_t blocks = (count + block_size - 1) / block_size, most_runs = blocks * SB_MAX_COLORS;
    uint8_t *color = malloc(count ? count : 1), *block_color = malloc(blocks ? blocks : 1);
    b->order = malloc((count ? count : 1) * sizeof *b->order);
    b->run_first = malloc((most_runs + 1) * sizeof *b->run_first);
    b->run_serial = malloc((most_runs ? most_runs : 1) * sizeof *b->run_serial);
    b->block_first_run = malloc((blocks + 1) * sizeof *b->block_first_run);
    sb_colorer inner, outer;
    bool ok = color && block_color && b->order && b->run_first && b->run_serial && b->block_first_run &&
              sb_colorer_init(&inner, vertex_count);
    if (ok && !(ok = sb_colorer_init(&outer, vertex_count))) sb_colorer_free(&inner);
    if (ok) {
        for (uint32_t first = 0; first < count; first += block_size)
            sb_colorer_run(&inner, first, first + block_size < count ? first + block_size : count, arity, vertices,
                           color + first);
        sb_blocked_color_blocks(&outer, count, block_size, arity, vertices, block_color, blocks);
        sb_colorer_free(&inner);
        sb_colorer_free(&outer);
        b->run_first[0] = 0;
        for (int k = 0; k < SB_MAX_COLORS; k++) {
            b->color_first_block[k] = b->block_count;
            for (uint32_t block = 0; block < blocks; block++)
                if (block_color[block] == k)
                    sb_blocked_append(b, block * block_size,
                                      (block + 1) * block_size < count ? (block + 1) * block_size : count, color);
        }
        b->color_first_block[SB_MAX_COLORS] = b->block_count;
        b->block_first_run[b->block_count] = b->run_count;
    }
    free(color);
    free(block_color);
    if (!ok) sb_blocked_free(b);
    return ok;
}
