/* sb_vicinity_pairs: every pair of points nearer than a radius, with a
 * uniform grid swept in order.
 *
 * The grid's cells are cubes of side `radius`, so the partners of a point
 * lie in its own cell or one of the 26 around it. Each point gets a cell
 * key, key = cx + nx (cy + ny cz) with the coordinates shifted by one so
 * that every neighbour's key is valid; the points are radix-sorted by key
 * and their positions copied in that order, so a cell's points are
 * contiguous. The cells are then swept in key order. Half of the 26
 * neighbours suffice (each pair is met once): the next cell in x, and the
 * rows (dy, dz) = (1, 0), (−1..1, 1), each three cells long in x. A row's
 * keys start at key + dy nx + dz nx ny − 1, which grows with the cell's own
 * key, so one cursor per row moves forward only through the sorted cells:
 * no hashing, no search, memory read in order. Time is linear in the number
 * of points plus the pairs tested (bounded when the radius is of the order
 * of the spacing); memory is a few arrays of n.
 *
 * A first version that hashed each point's 27 cells took two to five
 * times as long. Timings of 10⁶ points: bench/results/mesh_load.csv
 * (bench/mesh.sh; bench/results/README.md, "Mesh import"); the runs
 * first quoted here are in bench/results/notes/mesh.md. */
#include "mesh/builder_internal.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct sb_grid {
    uint64_t nx, nxy;   /* key strides of y and z */
    uint32_t n;         /* points */
    uint64_t* key;      /* per sorted point */
    uint32_t* index;    /* per sorted point: its original index */
    double* p;          /* 3 per sorted point */
    uint32_t* cell;     /* cell_count + 1 offsets into the sorted points */
    uint64_t* cell_key; /* per cell */
    uint32_t cell_count;
} sb_grid;

static void sb_grid_free(sb_grid* g) {
    free(g->key);
    free(g->index);
    free(g->p);
    free(g->cell);
    free(g->cell_key);
}

/* LSD radix sort of (key, index) by key, 11 bits a pass, passes over the
 * bits that are used only. */
static bool sb_radix_sort(uint64_t** key, uint32_t** index, uint32_t n, uint64_t max_key) {
    uint64_t* k2 = malloc((size_t)n * sizeof *k2);
    uint32_t* i2 = malloc((size_t)n * sizeof *i2);
    static const int bits = 11;
    uint32_t* count = malloc(((size_t)1 << bits) * sizeof *count);
    if (!k2 || !i2 || !count) {
        free(k2);
        free(i2);
        free(count);
        return false;
    }
    for (int shift = 0; shift < 64 && (max_key >> shift) != 0; shift += bits) {
        memset(count, 0, ((size_t)1 << bits) * sizeof *count);
        uint64_t mask = ((uint64_t)1 << bits) - 1;
        for (uint32_t i = 0; i < n; i++) count[((*key)[i] >> shift) & mask]++;
        uint32_t sum = 0;
        for (size_t d = 0; d <= mask; d++) {
            uint32_t c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (uint32_t i = 0; i < n; i++) {
            uint32_t to = count[((*key)[i] >> shift) & mask]++;
            k2[to] = (*key)[i];
            i2[to] = (*index)[i];
        }
        uint64_t* kt = *key;
        uint32_t* it = *index;
        *key = k2;
        *index = i2;
        k2 = kt;
        i2 = it;
    }
    free(k2);
    free(i2);
    free(count);
    return true;
}

static sb_status sb_grid_keys(sb_grid* g, const double* p, uint32_t n, double radius, uint64_t* max_key,
                              sb_error* err) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < 3 * (size_t)n; i++) {
        if (!isfinite(p[i])) return sb_error_set(err, SB_ERR_INVALID, "vicinity: point %zu is not finite", i / 3);
        lo[i % 3] = fmin(lo[i % 3], p[i]);
        hi[i % 3] = fmax(hi[i % 3], p[i]);
    }
    double inv = 1.0 / radius, cells[3];
    for (int c = 0; c < 3; c++) cells[c] = floor((hi[c] - lo[c]) * inv) + 3.0; /* +1 shift, +1 either side */
    if (cells[0] * cells[1] * cells[2] > 0x1p62)
        return sb_error_set(err, SB_ERR_INVALID, "vicinity: radius %g m is too small for the points' box", radius);
    g->nx = (uint64_t)cells[0];
    g->nxy = g->nx * (uint64_t)cells[1];
    *max_key = 0;
    for (uint32_t i = 0; i < n; i++) {
        const double* q = p + 3 * (size_t)i;
        uint64_t cx = (uint64_t)((q[0] - lo[0]) * inv) + 1, cy = (uint64_t)((q[1] - lo[1]) * inv) + 1;
        uint64_t cz = (uint64_t)((q[2] - lo[2]) * inv) + 1;
        g->key[i] = cx + g->nx * cy + g->nxy * cz;
        g->index[i] = i;
        if (g->key[i] > *max_key) *max_key = g->key[i];
    }
    return SB_OK;
}

/* Keys, sort, positions in sorted order, and the cells. */
static sb_status sb_grid_build(sb_grid* g, const double* p, uint32_t n, double radius, sb_error* err) {
    g->n = n;
    g->key = malloc((size_t)n * sizeof *g->key);
    g->index = malloc((size_t)n * sizeof *g->index);
    g->p = malloc(3 * (size_t)n * sizeof *g->p);
    g->cell = malloc(((size_t)n + 1) * sizeof *g->cell);
    g->cell_key = malloc((size_t)n * sizeof *g->cell_key);
    if (!g->key || !g->index || !g->p || !g->cell || !g->cell_key)
        return sb_error_set(err, SB_ERR_NOMEM, "vicinity: out of memory");
    uint64_t max_key = 0;
    sb_status status = sb_grid_keys(g, p, n, radius, &max_key, err);
    if (status != SB_OK) return status;
    if (!sb_radix_sort(&g->key, &g->index, n, max_key))
        return sb_error_set(err, SB_ERR_NOMEM, "vicinity: out of memory");
    g->cell_count = 0;
    for (uint32_t s = 0; s < n; s++) {
        memcpy(g->p + 3 * (size_t)s, p + 3 * (size_t)g->index[s], 3 * sizeof(double));
        if (s == 0 || g->key[s] != g->key[s - 1]) {
            g->cell_key[g->cell_count] = g->key[s];
            g->cell[g->cell_count++] = s;
        }
    }
    g->cell[g->cell_count] = n;
    return SB_OK;
}

typedef struct sb_pair_list {
    uint32_t* items;
    size_t count, capacity; /* in pairs */
} sb_pair_list;

static bool sb_pair_push(sb_pair_list* list, uint32_t i, uint32_t j) {
    if (list->count == list->capacity) {
        size_t capacity = list->capacity ? 2 * list->capacity : 4096;
        uint32_t* items = realloc(list->items, 2 * capacity * sizeof *items);
        if (!items) return false;
        list->items = items;
        list->capacity = capacity;
    }
    list->items[2 * list->count] = i < j ? i : j;
    list->items[2 * list->count + 1] = i < j ? j : i;
    list->count++;
    return true;
}

/* Pairs between sorted points [a0, a1) and [b0, b1); same = one range. */
static bool sb_range_pairs(const sb_grid* g, uint32_t a0, uint32_t a1, uint32_t b0, uint32_t b1, bool same, double r2,
                           sb_pair_list* list) {
    for (uint32_t a = a0; a < a1; a++) {
        const double* pa = g->p + 3 * (size_t)a;
        for (uint32_t b = same ? a + 1 : b0; b < b1; b++) {
            const double* pb = g->p + 3 * (size_t)b;
            double dx = pb[0] - pa[0], dy = pb[1] - pa[1], dz = pb[2] - pa[2];
            double d2 = dx * dx + dy * dy + dz * dz;
            if (d2 < r2 && d2 > 0.0 && !sb_pair_push(list, g->index[a], g->index[b])) return false;
        }
    }
    return true;
}

enum { SB_ROWS = 4 };

static bool sb_grid_sweep(const sb_grid* g, double r2, sb_pair_list* list) {
    /* rows (dy, dz): (1, 0), (-1, 1), (0, 1), (1, 1) */
    const int64_t row_dy[SB_ROWS] = {1, -1, 0, 1}, row_dz[SB_ROWS] = {0, 1, 1, 1};
    uint32_t cursor[SB_ROWS] = {0};
    for (uint32_t c = 0; c < g->cell_count; c++) {
        uint64_t key = g->cell_key[c];
        uint32_t a0 = g->cell[c], a1 = g->cell[c + 1];
        if (!sb_range_pairs(g, a0, a1, a0, a1, true, r2, list)) return false;
        if (c + 1 < g->cell_count && g->cell_key[c + 1] == key + 1 &&
            !sb_range_pairs(g, a0, a1, a1, g->cell[c + 2], false, r2, list))
            return false;
        for (int r = 0; r < SB_ROWS; r++) {
            uint64_t first = key + (uint64_t)(row_dy[r] * (int64_t)g->nx + row_dz[r] * (int64_t)g->nxy) - 1;
            while (cursor[r] < g->cell_count && g->cell_key[cursor[r]] < first) cursor[r]++;
            for (uint32_t n = cursor[r]; n < g->cell_count && g->cell_key[n] <= first + 2; n++)
                if (!sb_range_pairs(g, a0, a1, g->cell[n], g->cell[n + 1], false, r2, list)) return false;
        }
    }
    return true;
}

sb_status sb_vicinity_pairs(const double* positions, uint32_t count, double radius, uint32_t** pairs,
                            size_t* pair_count, sb_error* err) {
    *pairs = NULL;
    *pair_count = 0;
    if (!isfinite(radius) || radius < 0.0)
        return sb_error_set(err, SB_ERR_INVALID, "vicinity: radius %g m must be finite and >= 0", radius);
    if (radius == 0.0 || count < 2) return SB_OK;
    sb_grid grid = {0};
    sb_status status = sb_grid_build(&grid, positions, count, radius, err);
    sb_pair_list list = {0};
    if (status == SB_OK && !sb_grid_sweep(&grid, radius * radius, &list))
        status = sb_error_set(err, SB_ERR_NOMEM, "vicinity: out of memory after %zu pairs", list.count);
    sb_grid_free(&grid);
    if (status != SB_OK) {
        free(list.items);
        return status;
    }
    *pairs = list.items;
    *pair_count = list.count;
    return SB_OK;
}
