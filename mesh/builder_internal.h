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
    sb_array tets;      /* sb_tet_def */
    sb_array membranes; /* sb_membrane_def */
    sb_array faces;     /* uint32_t[3]: surface triangles for contact only */
};

#define SB_ITEMS(array, type) ((const type*)(array).items)

/* The membranes (mesh/compile_membranes.c): each checked, naming the
 * first bad one; then laid out into the model (false when out of memory). */
sb_status sb_check_membranes(const sb_builder* b, sb_error* err);
bool sb_fill_membranes(sb_model* m, const sb_builder* b);

#endif
