/* Private: the builder's layout, shared by builder.c, compile.c and factory.c. */
#ifndef SB_BUILDER_INTERNAL_H
#define SB_BUILDER_INTERNAL_H

#include "softbond/builder.h"

typedef struct sb_array {
    void* items;
    size_t count, capacity;
} sb_array;

struct sb_builder {
    sb_array vertices;  /* sb_vertex_def */
    sb_array bonds;     /* sb_bond_def */
    sb_array triangles; /* sb_triangle_def */
    sb_array hinges;    /* sb_hinge_def */
};

/* The factories' strain rule: the length beyond which the bond between
 * mesh vertices a and b breaks, r0 (1 + strain), r0 their distance; +inf
 * when strain is 0. */
double sb_strain_break_length(const sb_mesh* mesh, uint32_t a, uint32_t b, double strain);

#define SB_ITEMS(array, type) ((const type*)(array).items)

#endif
