/* Vertex and triangle reordering for locality (Morton / Z-order curve). */
#include "softbond/mesh.h"
#include "common/error.h"
#include "mesh/sort_key.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Spreads the low 21 bits of v three bits apart. */
static uint64_t sb_spread_bits(uint64_t v) {
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

static void sb_morton_keys(const sb_mesh* mesh, sb_sort_key* keys) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < mesh->vertex_count; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], mesh->positions[3 * i + c]);
            hi[c] = fmax(hi[c], mesh->positions[3 * i + c]);
        }
    double extent = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    double scale = extent > 0.0 ? 2097151.0 / extent : 0.0; /* 21 bits per axis, one cube */
    for (uint32_t i = 0; i < mesh->vertex_count; i++) {
        uint64_t key = 0;
        for (int c = 0; c < 3; c++)
            key |= sb_spread_bits((uint64_t)((mesh->positions[3 * i + c] - lo[c]) * scale)) << c;
        keys[i] = (sb_sort_key){key, i};
    }
}

static void sb_renumber_triangles(sb_mesh* mesh, const uint32_t* new_index, sb_sort_key* keys) {
    uint32_t* t = mesh->triangles;
    for (uint32_t f = 0; f < mesh->triangle_count; f++) {
        uint32_t lowest = UINT32_MAX;
        for (int c = 0; c < 3; c++) {
            t[3 * f + c] = new_index[t[3 * f + c]];
            lowest = t[3 * f + c] < lowest ? t[3 * f + c] : lowest;
        }
        keys[f] = (sb_sort_key){lowest, f};
    }
    qsort(keys, mesh->triangle_count, sizeof *keys, sb_sort_key_compare);
}

sb_status sb_mesh_reorder(sb_mesh* mesh, uint32_t* order, sb_error* err) {
    uint32_t n = mesh->vertex_count, nt = mesh->triangle_count, most = n > nt ? n : nt;
    sb_sort_key* keys = malloc((most ? most : 1) * sizeof *keys);
    uint32_t* new_index = malloc((n ? n : 1) * sizeof *new_index);
    double* positions = malloc((n ? n : 1) * 3 * sizeof *positions);
    uint32_t* triangles = malloc((nt ? nt : 1) * 3 * sizeof *triangles);
    sb_status status = SB_OK;
    if (!keys || !new_index || !positions || !triangles) {
        status = sb_error_set(err, SB_ERR_NOMEM, "out of memory reordering %u vertices", n);
    } else {
        sb_morton_keys(mesh, keys);
        qsort(keys, n, sizeof *keys, sb_sort_key_compare);
        for (uint32_t i = 0; i < n; i++) {
            new_index[keys[i].index] = i;
            memcpy(positions + 3 * i, mesh->positions + 3 * keys[i].index, 3 * sizeof *positions);
            if (order) order[i] = keys[i].index;
        }
        memcpy(mesh->positions, positions, 3 * (size_t)n * sizeof *positions);
        sb_renumber_triangles(mesh, new_index, keys);
        for (uint32_t f = 0; f < nt; f++)
            memcpy(triangles + 3 * f, mesh->triangles + 3 * keys[f].index, 3 * sizeof *triangles);
        memcpy(mesh->triangles, triangles, 3 * (size_t)nt * sizeof *triangles);
    }
    free(keys);
    free(new_index);
    free(positions);
    free(triangles);
    return status;
}
