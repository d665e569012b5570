/* A sparse matrix of 3 × 3 blocks with the pattern of a model's elements
 * (kernels/block_matrix.h): every element lists each ordered pair of its
 * vertices, each row's columns are sorted and made unique, in place in
 * arrays sized for every pair (so a rebuild after tearing never allocates). */
#include "kernels/block_matrix.h"

#include <stdlib.h>
#include <string.h>

static int sb_compare_u32(const void* a, const void* b) {
    uint32_t x = *(const uint32_t*)a, y = *(const uint32_t*)b;
    return (x > y) - (x < y);
}

/* Every element lists each ordered pair of its vertices: at most this many
 * blocks whatever the elements' vertices are (tearing re-points them). */
static uint64_t sb_block_capacity(const sb_model* m) {
    uint64_t capacity = m->vertex_count, count = sb_element_count(m);
    for (uint64_t id = 0; id < count; id++) {
        sb_element e = sb_element_at(m, id);
        capacity += (uint64_t)e.count * (uint64_t)e.count;
    }
    return capacity;
}

sb_block_matrix* sb_block_matrix_create(const sb_model* m) {
    uint32_t n = m->vertex_count;
    uint64_t capacity = sb_block_capacity(m);
    sb_block_matrix* a = calloc(1, sizeof *a);
    if (!a || capacity > UINT32_MAX) {
        free(a);
        return NULL;
    }
    a->rows = n;
    a->row_start = malloc(((size_t)n + 1) * sizeof *a->row_start);
    a->fill = malloc(((size_t)n + 1) * sizeof *a->fill);
    a->diagonal = malloc((n ? n : 1) * sizeof *a->diagonal);
    a->column = malloc(capacity * sizeof *a->column);
    a->block = malloc(9 * capacity * sizeof *a->block);
    if (!a->row_start || !a->fill || !a->diagonal || !a->column || !a->block) {
        sb_block_matrix_destroy(a);
        return NULL;
    }
    sb_block_matrix_rebuild(a, m);
    return a;
}

void sb_block_matrix_rebuild(sb_block_matrix* a, const sb_model* m) {
    uint32_t n = a->rows, *start = a->fill, *columns = a->column;
    uint64_t count = sb_element_count(m);
    /* each row's candidates: itself, then every vertex of every element it is in */
    memset(start, 0, ((size_t)n + 1) * sizeof *start);
    for (uint64_t id = 0; id < count; id++) {
        sb_element e = sb_element_at(m, id);
        for (int v = 0; v < e.count; v++) start[e.vertex[v] + 1] += (uint32_t)e.count;
    }
    for (uint32_t i = 0; i < n; i++) start[i + 1] += start[i] + 1;
    for (uint32_t i = 0; i < n; i++) { /* row_start: where each row's next candidate goes */
        a->row_start[i] = start[i] + 1;
        columns[start[i]] = i;
    }
    for (uint64_t id = 0; id < count; id++) {
        sb_element e = sb_element_at(m, id);
        for (int v = 0; v < e.count; v++)
            for (int w = 0; w < e.count; w++) columns[a->row_start[e.vertex[v]]++] = e.vertex[w];
    }
    uint32_t kept = 0;
    for (uint32_t i = 0; i < n; i++) { /* sort each row and keep its unique columns, in place */
        uint32_t first = start[i], length = a->row_start[i] - first;
        qsort(columns + first, length, sizeof *columns, sb_compare_u32);
        a->row_start[i] = kept;
        for (uint32_t k = 0; k < length; k++)
            if (k == 0 || columns[first + k] != columns[first + k - 1]) columns[kept++] = columns[first + k];
    }
    a->row_start[n] = kept;
    for (uint32_t i = 0; i < n; i++) a->diagonal[i] = (uint32_t)((sb_block_matrix_at(a, i, i) - a->block) / 9);
}

void sb_block_matrix_destroy(sb_block_matrix* a) {
    if (!a) return;
    free(a->row_start), free(a->fill), free(a->column), free(a->diagonal), free(a->block);
    free(a);
}

void sb_block_matrix_zero(sb_block_matrix* a) {
    memset(a->block, 0, 9 * (size_t)a->row_start[a->rows] * sizeof(double));
}

double* sb_block_matrix_at(sb_block_matrix* a, uint32_t i, uint32_t j) {
    uint32_t lo = a->row_start[i], hi = a->row_start[i + 1];
    while (lo < hi) { /* binary search in the sorted row */
        uint32_t mid = lo + (hi - lo) / 2;
        if (a->column[mid] < j)
            lo = mid + 1;
        else
            hi = mid;
    }
    return a->block + 9 * (size_t)lo;
}

void sb_block_matrix_add_element(sb_block_matrix* a, const sb_element* e, const double* k, double scale) {
    int size = 3 * e->count;
    for (int r = 0; r < e->count; r++)
        for (int c = 0; c < e->count; c++) {
            double* block = sb_block_matrix_at(a, e->vertex[r], e->vertex[c]);
            for (int u = 0; u < 3; u++)
                for (int w = 0; w < 3; w++) block[3 * u + w] += scale * k[(3 * r + u) * size + 3 * c + w];
        }
}

void sb_block_matrix_multiply(const sb_block_matrix* a, const double* p, double* out) {
    for (uint32_t i = 0; i < a->rows; i++) {
        double sum[3] = {0, 0, 0};
        for (uint32_t b = a->row_start[i]; b < a->row_start[i + 1]; b++) {
            const double *block = a->block + 9 * (size_t)b, *q = p + 3 * (size_t)a->column[b];
            for (int u = 0; u < 3; u++)
                sum[u] += block[3 * u] * q[0] + block[3 * u + 1] * q[1] + block[3 * u + 2] * q[2];
        }
        memcpy(out + 3 * (size_t)i, sum, sizeof sum);
    }
}
