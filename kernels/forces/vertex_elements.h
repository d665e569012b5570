/* Private: the elements at each vertex (kernels/forces/hessian.h's numbering),
 * as CSR ranges of entries (element << 4 | the vertex's place in it). Each
 * element contributes one entry per vertex whatever its vertices are, so the
 * arrays never grow: after tearing re-points elements, a rebuild fills the
 * same arrays again. Used by the block matrix's pattern and by vbd. */
#ifndef SB_VERTEX_ELEMENTS_H
#define SB_VERTEX_ELEMENTS_H

#include "kernels/forces/hessian.h"

typedef struct sb_vertex_elements {
    uint32_t vertices;
    uint32_t* start; /* vertices + 1 */
    uint32_t* entry;
} sb_vertex_elements;

/* NULL when out of memory or when the model has 2^28 elements or more. */
sb_vertex_elements* sb_vertex_elements_create(const sb_model* m);
void sb_vertex_elements_rebuild(sb_vertex_elements* v, const sb_model* m);
void sb_vertex_elements_destroy(sb_vertex_elements* v);

static inline uint32_t sb_entry_element(uint32_t entry) { return entry >> 4; }
static inline int sb_entry_place(uint32_t entry) { return (int)(entry & 15u); }

#endif
