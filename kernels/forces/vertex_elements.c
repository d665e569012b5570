/* The elements at each vertex (kernels/forces/vertex_elements.h): a counting sort
 * of the elements' (vertex, entry) pairs, in element order within a vertex. */
#include "kernels/forces/vertex_elements.h"

#include <stdlib.h>
#include <string.h>

static uint64_t sb_entry_count(const sb_model* m) {
    uint64_t node_entries = 0;
    for (uint32_t t = 0; t < m->tet_count; t++) node_entries += m->tet_nodes[t];
    for (uint32_t t = 0; t < m->plate_count; t++) node_entries += m->plate_nodes[t];
    return 2 * (uint64_t)m->bond_count + 3 * (uint64_t)m->triangle_count + 4 * (uint64_t)m->hinge_count + node_entries +
           3 * (uint64_t)m->membrane_count;
}

sb_vertex_elements* sb_vertex_elements_create(const sb_model* m) {
    uint64_t entries = sb_entry_count(m);
    if (sb_element_count(m) >= (1u << 28) || entries > UINT32_MAX) return NULL;
    sb_vertex_elements* v = calloc(1, sizeof *v);
    if (!v) return NULL;
    v->vertices = m->vertex_count;
    v->start = malloc(((size_t)m->vertex_count + 1) * sizeof *v->start);
    v->entry = malloc((entries ? entries : 1) * sizeof *v->entry);
    if (!v->start || !v->entry) {
        sb_vertex_elements_destroy(v);
        return NULL;
    }
    sb_vertex_elements_rebuild(v, m);
    return v;
}

void sb_vertex_elements_rebuild(sb_vertex_elements* v, const sb_model* m) {
    uint32_t n = v->vertices;
    uint64_t count = sb_element_count(m);
    memset(v->start, 0, ((size_t)n + 1) * sizeof *v->start);
    for (uint64_t id = 0; id < count; id++) {
        sb_element e = sb_element_at(m, id);
        for (int a = 0; a < e.count; a++) v->start[e.vertex[a] + 1]++;
    }
    for (uint32_t i = 0; i < n; i++) v->start[i + 1] += v->start[i];
    for (uint64_t id = 0; id < count; id++) { /* start[i] runs ahead while filling ... */
        sb_element e = sb_element_at(m, id);
        for (int a = 0; a < e.count; a++) v->entry[v->start[e.vertex[a]]++] = (uint32_t)(id << 4) | (uint32_t)a;
    }
    for (uint32_t i = n; i > 0; i--) v->start[i] = v->start[i - 1]; /* ... and is shifted back */
    v->start[0] = 0;
}

void sb_vertex_elements_destroy(sb_vertex_elements* v) {
    if (!v) return;
    free(v->start), free(v->entry);
    free(v);
}
