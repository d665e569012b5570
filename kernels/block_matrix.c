/* A sparse matrix of 3 × 3 blocks with the pattern of a model's elements
 * (kernels/block_matrix.h). The pattern is built once: every element lists
 * each ordered pair of its vertices, each row's columns are sorted and made
 * unique. */
#include "kernels/block_matrix.h"

#include <stdlib.h>
#include <string.h>

static int sb_compare_u32(const void* a, const void* b) {
    uint32_t x = *(const uint32_t*)a, y = *(const uint32_t*)b;
    return (x > y) - (x < y);
}

/* Each row's candidate columns: itself and every vertex of every element it is in. */
static uint32_t* sb_candidate_columns(const sb_model* m, uint32_t* start) {
    uint32_t n = m->vertex_count;
    uint64_t count = sb_element_count(m);
    memset(start, 0, (n + 1) * sizeof *start);
    for (uint32_t i = 0; i < n; i++) start[i + 1] = 1;
    for (uint64_t id = 0; id < count; id++) {
        sb_element e = sb_element_at(m, id);
        for (int a = 0; a < e.count; a++) start[e.vertex[a] + 1] += (uint32_t)e.count;
    }
    for (uint32_t i = 0; i < n; i++) start[i + 1] += start[i];
    uint32_t* columns = malloc((start[n] ? start[n] : 1) * sizeof *columns);
    uint32_t* fill = malloc((n ? n : 1) * sizeof *fill);
    if (!columns || !fill) {
        free(columns), free(fill);
        return NULL;
    }
    for (uint32_t i = 0; i < n; i++) {
        fill[i] = start[i] + 1;
        columns[start[i]] = i;
    }
    for (uint64_t id = 0; id < count; id++) {
        sb_element e = sb_element_at(m, id);
        for (int a = 0; a < e.count; a++)
            for (int b = 0; b < e.count; b++) columns[fill[e.vertex[a]]++] = e.vertex[b];
    }
    free(fill);
    return columns;
}

sb_block_matrix* sb_block_matrix_create(const sb_model* m) {
    uint32_t n = m->vertex_count;
    sb_block_matrix* a = calloc(1, sizeof *a);
    uint32_t* start = malloc((n + 1) * sizeof *start);
    uint32_t* candidates = start ? sb_candidate_columns(m, start) : NULL;
    if (a) a->row_start = malloc((n + 1) * sizeof *a->row_start);
    if (a && a->row_start) a->diagonal = malloc((n ? n : 1) * sizeof *a->diagonal);
    if (!candidates || !a || !a->diagonal) {
        free(start), free(candidates);
        sb_block_matrix_destroy(a);
        return NULL;
    }
    a->rows = n;
    uint32_t kept = 0;
    for (uint32_t i = 0; i < n; i++) { /* sort and keep the unique columns in place */
        uint32_t* row = candidates + start[i];
        uint32_t length = start[i + 1] - start[i];
        qsort(row, length, sizeof *row, sb_compare_u32);
        a->row_start[i] = kept;
        for (uint32_t k = 0; k < length; k++)
            if (k == 0 || row[k] != row[k - 1]) candidates[kept++] = row[k];
    }
    a->row_start[n] = kept;
    free(start);
    a->column = realloc(candidates, (kept ? kept : 1) * sizeof *a->column);
    a->block = malloc(9 * (size_t)(kept ? kept : 1) * sizeof *a->block);
    if (!a->column || !a->block) {
        if (!a->column) free(candidates);
        sb_block_matrix_destroy(a);
        return NULL;
    }
    for (uint32_t i = 0; i < n; i++) a->diagonal[i] = (uint32_t)(sb_block_matrix_at(a, i, i) - a->block) / 9;
    return a;
}

void sb_block_matrix_destroy(sb_block_matrix* a) {
    if (!a) return;
    free(a->row_start), free(a->column), free(a->diagonal), free(a->block);
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
