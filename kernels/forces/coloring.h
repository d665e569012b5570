/* Private: greedy graph coloring, so that the elements of one color share no
 * vertex and can scatter forces without atomics. */
#ifndef SB_COLORING_H
#define SB_COLORING_H

#include "softbond/types.h"

/* Colors are bits of a 64-bit mask per vertex; the last color is the
 * overflow class, for items whose neighbours already use all the others:
 * it may share vertices and is processed one item at a time. */
#define SB_MAX_COLORS 64
#define SB_OVERFLOW_COLOR (SB_MAX_COLORS - 1)

/* Greedy coloring state: per vertex, the colors of the items touching it. */
typedef struct sb_colorer {
    uint64_t* used;
    uint32_t sizes[SB_MAX_COLORS]; /* items per color so far */
    uint32_t opened;               /* colors in use */
} sb_colorer;

bool sb_colorer_init(sb_colorer* colorer, uint32_t vertex_count);
void sb_colorer_free(sb_colorer* colorer);

/* The least used of the opened colors that none of the item's vertices
 * has (taken = the OR of their masks), a new color when all are taken, the
 * overflow color when none is left. Counts the item in. */
int sb_colorer_pick(sb_colorer* colorer, uint64_t taken);

/* Colors elements [begin, end) of `arity` vertices each (vertices[a][e]),
 * writes color[e − begin], and then clears the marks it made, so the next
 * call starts afresh. Returns the number of colors used. */
uint32_t sb_colorer_run(sb_colorer* colorer, uint32_t begin, uint32_t end, int arity, const uint32_t* const* vertices,
                        uint8_t* color);

/* A blocked coloring (the scheme kernels/forces/fast_model.h describes, for
 * position-based sweeps): the items, in their given order, are cut into
 * blocks of block_size consecutive items; blocks are colored so that blocks
 * of one block color share no vertex (the overflow block color's may), and
 * within a block, items so that items of one color share no vertex. A run
 * is one color of one block. Sweeping block color by block color, a
 * block's runs in order, synchronises threads once per block color. */
typedef struct sb_blocked {
    uint32_t count, run_count, block_count;
    uint32_t* order;           /* count: the items (0 … count − 1) run by run, in given order within a run */
    uint32_t* run_first;       /* run_count + 1: run r is order[run_first[r], run_first[r + 1]) */
    bool* run_serial;          /* run_count: the overflow color, whose items may share vertices */
    uint32_t* block_first_run; /* block_count + 1: block b's runs */
    uint32_t color_first_block[SB_MAX_COLORS + 1]; /* block color k: blocks [k], [k + 1]) */
} sb_blocked;

/* Colors `count` items of `arity` vertices each (vertices[a][e]); false
 * when out of memory. */
bool sb_blocked_build(sb_blocked* blocked, uint32_t vertex_count, uint32_t count, uint32_t block_size, int arity,
                      const uint32_t* const* vertices);
void sb_blocked_free(sb_blocked* blocked);
/* The block colors that have blocks. */
uint32_t sb_blocked_colors(const sb_blocked* blocked);

#endif
