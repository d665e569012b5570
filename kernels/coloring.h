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

#endif
