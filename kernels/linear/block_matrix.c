/* A sparse matrix of 3 × 3 blocks with the pattern of a model's elements
 * (kernels/linear/block_matrix.h): row i holds i and every vertex of every element
 * at i, sorted and unique, in arrays with room for what tearing can add (so
 * a rebuild never allocates). */
#include "kernels/linear/block_matrix.h"

#include <stdlib.h>
#include <string.h>

static int sb_compare_u32(const void* a, const void* b) {
    uint32_t x = *(const uint32_t*)a, y = *(const uint32_t*)b;
    return (x > y) - (x < y);
}

/* Row i's columns, sorted and unique, into out (the scratch); returns how many. */
static uint32_t sb_row_columns(const sb_block_matrix* a, const sb_model* m, uint32_t i, uint32_t* out) {
    const sb_vertex_elements* v = a->elements;
    uint32_t count = 0;
    out[count++] = i;
    for (uint32_t k = v->start[i]; k < v->start[i + 1]; k++) {
        sb_element e = sb_element_at(m, sb_entry_element(v->entry[k]));
        for (int b = 0; b < e.count; b++) out[count++] = e.vertex[b];
    }
    qsort(out, count, sizeof *out, sb_compare_u32);
    uint32_t kept = 0;
    for (uint32_t k = 0; k < count; k++)
        if (k == 0 || out[k] != out[k - 1]) out[kept++] = out[k];
    return kept;
}

/* The blocks of the current pattern and its longest row. */
static uint64_t sb_pattern_size(const sb_block_matrix* a, const sb_model* m, uint32_t* longest) {
    uint64_t total = 0;
    *longest = 0;
    for (uint32_t i = 0; i < a->rows; i++) {
        uint32_t length = sb_row_columns(a, m, i, a->scratch);
        total += length;
        if (length > *longest) *longest = length;
    }
    return total;
}

sb_block_matrix* sb_block_matrix_create(const sb_model* m, uint32_t spare) {
    uint32_t n = m->vertex_count;
    sb_block_matrix* a = calloc(1, sizeof *a);
    if (!a) return NULL;
    a->rows = n;
    a->elements = sb_vertex_elements_create(m);
    uint32_t widest = 1; /* the most candidates a row can have: 1 + SB_ELEMENT_MAX per element entry */
    for (uint32_t i = 0; a->elements && i < n; i++) {
        uint32_t width = 1 + SB_ELEMENT_MAX * (a->elements->start[i + 1] - a->elements->start[i]);
        if (width > widest) widest = width;
    }
    a->scratch = malloc(widest * sizeof *a->scratch);
    if (!a->elements || !a->scratch) {
        sb_block_matrix_destroy(a);
        return NULL;
    }
    /* A split of v adds at most two blocks per block of v's row, which is at
     * most the longest row plus one per earlier split. */
    uint32_t longest;
    uint64_t capacity = sb_pattern_size(a, m, &longest) + 2 * (uint64_t)spare * ((uint64_t)longest + spare);
    a->row_start = malloc(((size_t)n + 1) * sizeof *a->row_start);
    a->diagonal = malloc((n ? n : 1) * sizeof *a->diagonal);
    a->column = capacity <= UINT32_MAX ? malloc(capacity * sizeof *a->column) : NULL;
    a->block = capacity <= UINT32_MAX ? malloc(9 * capacity * sizeof *a->block) : NULL;
    a->capacity = (uint32_t)capacity;
    uint64_t elements = sb_element_count(m), element_blocks = 0;
    for (uint64_t id = 0; id < elements; id++)
        element_blocks += (uint64_t)sb_element_at(m, id).count * sb_element_at(m, id).count;
    a->element_first = malloc((elements + 1) * sizeof *a->element_first);
    a->element_block = malloc((element_blocks ? element_blocks : 1) * sizeof *a->element_block);
    if (!a->row_start || !a->diagonal || !a->column || !a->block || !a->element_first || !a->element_block ||
        !sb_block_matrix_rebuild(a, m)) {
        sb_block_matrix_destroy(a);
        return NULL;
    }
    return a;
}

static uint32_t sb_block_index(sb_block_matrix* a, uint32_t i, uint32_t j) {
    return (uint32_t)((sb_block_matrix_at(a, i, j) - a->block) / 9);
}

/* Each element's block indices (tearing re-points elements, never adds). */
static void sb_map_element_blocks(sb_block_matrix* a, const sb_model* m) {
    uint64_t elements = sb_element_count(m), next = 0;
    for (uint64_t id = 0; id < elements; id++) {
        sb_element e = sb_element_at(m, id);
        a->element_first[id] = next;
        for (int r = 0; r < e.count; r++)
            for (int c = 0; c < e.count; c++) a->element_block[next++] = sb_block_index(a, e.vertex[r], e.vertex[c]);
    }
    a->element_first[elements] = next;
}

bool sb_block_matrix_rebuild(sb_block_matrix* a, const sb_model* m) {
    sb_vertex_elements_rebuild(a->elements, m);
    uint32_t longest;
    if (sb_pattern_size(a, m, &longest) > a->capacity) return false;
    uint32_t kept = 0;
    for (uint32_t i = 0; i < a->rows; i++) {
        a->row_start[i] = kept;
        uint32_t length = sb_row_columns(a, m, i, a->scratch);
        memcpy(a->column + kept, a->scratch, length * sizeof *a->column);
        kept += length;
    }
    a->row_start[a->rows] = kept;
    for (uint32_t i = 0; i < a->rows; i++) a->diagonal[i] = (uint32_t)((sb_block_matrix_at(a, i, i) - a->block) / 9);
    sb_map_element_blocks(a, m);
    return true;
}

void sb_block_matrix_destroy(sb_block_matrix* a) {
    if (!a) return;
    free(a->row_start), free(a->column), free(a->diagonal), free(a->block), free(a->scratch);
    free(a->element_first), free(a->element_block);
    sb_vertex_elements_destroy(a->elements);
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

void sb_block_matrix_add_element(sb_block_matrix* a, uint64_t id, const sb_element* e, const double* k, double scale,
                                 uint32_t begin, uint32_t end) {
    int size = 3 * e->count;
    const uint32_t* blocks = a->element_block + a->element_first[id];
    for (int r = 0; r < e->count; r++) {
        if (e->vertex[r] < begin || e->vertex[r] >= end) continue;
        for (int c = 0; c < e->count; c++) {
            double* block = a->block + 9 * (size_t)blocks[e->count * r + c];
            for (int u = 0; u < 3; u++)
                for (int w = 0; w < 3; w++) block[3 * u + w] += scale * k[(3 * r + u) * size + 3 * c + w];
        }
    }
}

void sb_block_matrix_add_blocks(sb_block_matrix* a, uint64_t id, const sb_element* e, const double* blocks,
                                uint32_t begin, uint32_t end) {
    const uint32_t* at = a->element_block + a->element_first[id];
    for (int r = 0; r < e->count; r++) {
        if (e->vertex[r] < begin || e->vertex[r] >= end) continue;
        for (int c = 0; c < e->count; c++) {
            double* block = a->block + 9 * (size_t)at[e->count * r + c];
            const double* add = blocks + 9 * (e->count * r + c);
            for (int k = 0; k < 9; k++) block[k] += add[k];
        }
    }
}

void sb_block_matrix_multiply_rows(const sb_block_matrix* a, const double* p, double* out, uint32_t begin,
                                   uint32_t end) {
    /* Two sums a row, even and odd blocks, added at its end: one chain of
     * dependent additions a block was the loop's bound (the default scene's
     * CG: bench/results/notes/implicit_euler.md). */
    for (uint32_t i = begin; i < end; i++) {
        double even[3] = {0, 0, 0}, odd[3] = {0, 0, 0};
        uint32_t b = a->row_start[i], stop = a->row_start[i + 1];
        for (; b + 1 < stop; b += 2) {
            const double *m0 = a->block + 9 * (size_t)b, *q0 = p + 3 * (size_t)a->column[b];
            const double *m1 = m0 + 9, *q1 = p + 3 * (size_t)a->column[b + 1];
            for (int u = 0; u < 3; u++) {
                even[u] += m0[3 * u] * q0[0] + m0[3 * u + 1] * q0[1] + m0[3 * u + 2] * q0[2];
                odd[u] += m1[3 * u] * q1[0] + m1[3 * u + 1] * q1[1] + m1[3 * u + 2] * q1[2];
            }
        }
        if (b < stop) {
            const double *m0 = a->block + 9 * (size_t)b, *q0 = p + 3 * (size_t)a->column[b];
            for (int u = 0; u < 3; u++) even[u] += m0[3 * u] * q0[0] + m0[3 * u + 1] * q0[1] + m0[3 * u + 2] * q0[2];
        }
        for (int u = 0; u < 3; u++) out[3 * (size_t)i + u] = even[u] + odd[u];
    }
}

void sb_block_matrix_multiply(const sb_block_matrix* a, const double* p, double* out) {
    sb_block_matrix_multiply_rows(a, p, out, 0, a->rows);
}
