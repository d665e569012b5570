/* Private: a sparse matrix of 3 × 3 blocks, one block row per vertex, with
 * the pattern of a model's elements (two vertices couple when an element
 * holds both): the assembled Jacobian of implicit Euler
 * (kernels/integrators/implicit_euler.c). Rows are sorted; assembly and the product
 * run in a fixed order, so the result does not depend on the thread count. */
#ifndef SB_BLOCK_MATRIX_H
#define SB_BLOCK_MATRIX_H

#include "kernels/forces/vertex_elements.h"

typedef struct sb_block_matrix {
    uint32_t rows;
    uint32_t* row_start; /* rows + 1 */
    uint32_t* column;    /* per block */
    uint32_t* diagonal;  /* per row: its (i, i) block */
    double* block;       /* 9 per block, row-major */
    uint32_t capacity;   /* blocks the arrays hold */
    sb_vertex_elements* elements;
    uint32_t* scratch; /* one row's candidate columns */
    /* Where each element's blocks are: for element e (kernels/forces/hessian.h's
     * numbering), its count × count block indices, row-major by place, from
     * element_first[e]; so an assembly never searches a row. */
    uint64_t* element_first; /* elements + 1 */
    uint32_t* element_block;
} sb_block_matrix;

/* The pattern of m's elements (and every diagonal block), with room for
 * what `spare` vertex splits (tearing) can add; NULL when out of memory. */
sb_block_matrix* sb_block_matrix_create(const sb_model* m, uint32_t spare);
/* The pattern again, after the elements' vertices changed (tearing); the
 * values are undefined until zeroed. Never allocates; false (and the
 * pattern unchanged) if it would pass the room reserved. */
bool sb_block_matrix_rebuild(sb_block_matrix* a, const sb_model* m);
void sb_block_matrix_destroy(sb_block_matrix* a);

void sb_block_matrix_zero(sb_block_matrix* a);
/* The block (i, j), which must be in the pattern. */
double* sb_block_matrix_at(sb_block_matrix* a, uint32_t i, uint32_t j);
/* Adds scale × the 3 count × 3 count matrix k of element `id` (e), the
 * blocks of rows [begin, end) only: workers owning disjoint rows add an
 * element at once, and each block still sums its elements in their order. */
void sb_block_matrix_add_element(sb_block_matrix* a, uint64_t id, const sb_element* e, const double* k, double scale,
                                 uint32_t begin, uint32_t end);
/* The same for an element's blocks already block-major (block (r, c) of
 * its vertices at blocks + 9 (count r + c)) and scaled. */
void sb_block_matrix_add_blocks(sb_block_matrix* a, uint64_t id, const sb_element* e, const double* blocks,
                                uint32_t begin, uint32_t end);
/* out = A p (3 rows doubles each); the second form only rows [begin, end). */
void sb_block_matrix_multiply(const sb_block_matrix* a, const double* p, double* out);
void sb_block_matrix_multiply_rows(const sb_block_matrix* a, const double* p, double* out, uint32_t begin,
                                   uint32_t end);

#endif
