/* Private: union-find over vertex indices (parent[i] == i at a root), the
 * root of a set always its lowest index, so that the labels it gives do not
 * depend on the order of the joins. */
#ifndef SB_UNION_FIND_H
#define SB_UNION_FIND_H

#include <stdint.h>

/* The root of i's set, halving the path as it goes. */
static inline uint32_t sb_find(uint32_t* parent, uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

/* Joins the sets of i and j under the lower root. */
static inline void sb_join(uint32_t* parent, uint32_t i, uint32_t j) {
    uint32_t a = sb_find(parent, i), b = sb_find(parent, j);
    if (a < b) parent[b] = a;
    if (b < a) parent[a] = b;
}

#endif
