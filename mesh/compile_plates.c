/* sb_builder_compile's part for the plates (a flat sheet's bending): each
 * checked (its membrane there, its vertices in range, finite weights),
 * then laid out per membrane (mesh/model_internal.h). */
#include "mesh/builder_internal.h"
#include "mesh/model_internal.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>

static sb_status sb_check_plate(const sb_builder* b, size_t index, sb_error* err) {
    const sb_plate_def* d = SB_ITEMS(b->plates, sb_plate_def) + index;
    if (d->membrane >= b->membranes.count)
        return sb_error_set(err, SB_ERR_INVALID, "plate %zu: membrane %u out of range (%zu membranes)", index,
                            d->membrane, b->membranes.count);
    if (d->stencil.count < 6 || d->stencil.count > SB_PLATE_NODES || !isfinite(d->a) || !isfinite(d->b))
        return sb_error_set(err, SB_ERR_INVALID, "plate %zu: a stencil of 6 to %d vertices and finite weights", index,
                            SB_PLATE_NODES);
    for (int a = 0; a < d->stencil.count; a++)
        if (d->stencil.v[a] >= b->vertices.count)
            return sb_error_set(err, SB_ERR_INVALID, "plate %zu: vertex index %u out of range (%zu vertices)", index,
                                d->stencil.v[a], b->vertices.count);
    return SB_OK;
}

sb_status sb_check_plates(const sb_builder* b, sb_error* err) {
    sb_status status = SB_OK;
    for (size_t i = 0; i < b->plates.count && status == SB_OK; i++) status = sb_check_plate(b, i, err);
    return status;
}

bool sb_fill_plates(sb_model* m, const sb_builder* b) {
    if (!b->plates.count) return true;
    size_t count = b->membranes.count;
    m->plate_count = (uint32_t)count;
    m->plate_nodes = calloc(count, sizeof *m->plate_nodes);
    m->plate_v = calloc(SB_PLATE_NODES * count, sizeof *m->plate_v);
    m->plate_c = calloc(3 * SB_PLATE_NODES * count, sizeof *m->plate_c);
    m->plate_a = calloc(count, sizeof *m->plate_a);
    m->plate_b = calloc(count, sizeof *m->plate_b);
    if (!m->plate_nodes || !m->plate_v || !m->plate_c || !m->plate_a || !m->plate_b) return false;
    const sb_plate_def* d = SB_ITEMS(b->plates, sb_plate_def);
    for (size_t p = 0; p < b->plates.count; p++) {
        size_t t = d[p].membrane;
        m->plate_nodes[t] = (uint8_t)d[p].stencil.count;
        for (int a = 0; a < d[p].stencil.count; a++) {
            m->plate_v[SB_PLATE_NODES * t + (size_t)a] = d[p].stencil.v[a];
            for (int ij = 0; ij < 3; ij++)
                m->plate_c[SB_PLATE_NODES * (3 * t + (size_t)ij) + (size_t)a] = d[p].stencil.c[ij][a];
        }
        m->plate_a[t] = d[p].a, m->plate_b[t] = d[p].b;
        m->term_enabled[SB_TERM_BEND] |= d[p].a != 0.0 || d[p].b != 0.0;
    }
    return true;
}
