/* Private: the builder's layout, shared by builder.c, compile.c and factory.c. */
#ifndef SB_BUILDER_INTERNAL_H
#define SB_BUILDER_INTERNAL_H

#include "softbond/builder.h"
#include "mesh/plate_stencils.h"

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
    sb_array plates;    /* sb_plate_def */
    sb_array faces;     /* uint32_t[3]: surface triangles for contact only */
};

#define SB_ITEMS(array, type) ((const type*)(array).items)

/* A membrane's plate bending (sb_builder_add_sheet): its triangle's
 * stencil (builder vertex indices) and the weights a = A D (1 − ν),
 * b = A D ν (mesh/model_internal.h). */
typedef struct sb_plate_def {
    uint32_t membrane;
    sb_plate_stencil stencil;
    double a, b;
} sb_plate_def;

/* Adds a plate; its index, or −1 when out of memory. */
int64_t sb_builder_add_plate(sb_builder* builder, const sb_plate_def* def);

/* The plates laid out per membrane (mesh/compile_plates.c; false when out
 * of memory); a plate naming a membrane that is not there is refused by
 * sb_check_plates. */
sb_status sb_check_plates(const sb_builder* b, sb_error* err);
bool sb_fill_plates(sb_model* m, const sb_builder* b);

/* The membranes (mesh/compile_membranes.c): each checked, naming the
 * first bad one; then laid out into the model (false when out of memory). */
sb_status sb_check_membranes(const sb_builder* b, sb_error* err);
bool sb_fill_membranes(sb_model* m, const sb_builder* b);

#endif
