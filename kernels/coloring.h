/* Private: greedy graph coloring of mesh elements, so that the elements of
 * one color share no vertex and can scatter forces without atomics. */
#ifndef SB_COLORING_H
#define SB_COLORING_H

#include "softbond/types.h"

/* Colors are bits of a 64-bit mask per vertex; the last color is the
 * overflow class, for elements whose neighbours already use all the others:
 * it may share vertices and is processed one element at a time. */
#define SB_MAX_COLORS 64
#define SB_OVERFLOW_COLOR (SB_MAX_COLORS - 1)

/* Colors `count` elements of `arity` vertices each (vertices[a][e] is the
 * a-th vertex of element e). Each element gets the least used color that
 * none of its vertices has yet, which keeps colors balanced for SIMD and
 * threads. Writes color[e]; returns the number of colors used (overflow
 * counted as SB_MAX_COLORS), or 0 when out of memory. */
uint32_t sb_color_elements(uint32_t vertex_count, uint32_t count, int arity, const uint32_t* const* vertices,
                           uint8_t* color);

#endif
