/* CHOLMOD's supernodal Cholesky on the block matrix (kernels/sparse_cholesky.h).
 *
 * The matrix's lower triangle in compressed columns (scalar column 3 i + c
 * holds, for each block (i, j) of block row i with j ≥ i, the rows 3 j + r,
 * r ≥ c on the diagonal block, whose values are A(3 j + r, 3 i + c) =
 * block(i, j)[3 c + r] by symmetry) gives AMD's ordering P. CHOLMOD then
 * gets P A Pᵀ itself, as its upper triangle, analysed in its own order:
 * given A with P it permutes A at every factorization (two passes of
 * cholmod_transpose_sym: 3.2 % of the default scene's run at dt = 10 ms,
 * 1.0 % for the one pass left). Each entry keeps the index of its value in
 * the block matrix and its row and column in A; a solve permutes the
 * right-hand side and the solution. */
#include "kernels/sparse_cholesky.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include <suitesparse/cholmod.h>

/* Debian's CHOLMOD runs a few short loops (clearing its maps, zeroing a
 * supernode) on four OpenMP threads of its own. Beside the solver's team on
 * a small machine they cost a fifth more CPU than they save, and they would
 * make the result's threads the runtime's, not the solver's: a call runs
 * with OpenMP's active levels at 0, so its parallel loops run on the calling
 * thread (the setting is libgomp's global; it is restored after the call). */
typedef struct sb_serial_openmp {
    int saved;
} sb_serial_openmp;

static sb_serial_openmp sb_openmp_serial_begin(void) {
    sb_serial_openmp state = {omp_get_max_active_levels()};
    omp_set_max_active_levels(0);
    return state;
}

static void sb_openmp_serial_end(sb_serial_openmp state) { omp_set_max_active_levels(state.saved); }

/* Fewer, larger supernodes than CHOLMOD's default relaxation (nrelax 4, 16,
 * 48; zrelax 0.8, 0.1, 0.05) allows: each supernode costs a few OpenMP
 * regions, and Debian's libgomp ends even a serial one with a futex system
 * call (4 200 a step on the default scene at dt = 10 ms, a fifth of the
 * step's time on this virtual machine), besides BLAS calls on small blocks.
 * Amalgamating more, at the price of some explicit zeros, took a factored
 * step 15-20 % less CPU on the 30 x 30 sheet and 7 % on the 100 x 100. */
static void sb_relax_supernodes(cholmod_common* common) {
    const size_t columns[3] = {16, 48, 128};
    const double zeros[3] = {0.8, 0.2, 0.1};
    for (int q = 0; q < 3; q++) common->nrelax[q] = columns[q], common->zrelax[q] = zeros[q];
}

struct sb_sparse_cholesky {
    cholmod_common common;
    cholmod_sparse* a; /* P A Pᵀ, upper triangle */
    cholmod_factor* factor;
    size_t* source;           /* per entry of a: its value's index in the block matrix's values */
    int *row, *column;        /* per entry of a: its row and column in A */
    int* order;               /* P: row k of a is row order[k] of A */
    double* b;                /* P rhs */
    cholmod_dense *x, *y, *e; /* cholmod_solve2's solution and workspaces, kept */
};

/* The lower triangle's entries column by column: counts them, and where p
 * is given writes the column starts, rows and sources. */
static size_t sb_lower_pattern(const sb_block_matrix* a, int* p, int* row, size_t* source) {
    size_t count = 0;
    for (uint32_t i = 0; i < a->rows; i++)
        for (uint32_t c = 0; c < 3; c++) {
            if (p) p[3 * i + c] = (int)count;
            for (uint32_t k = a->diagonal[i]; k < a->row_start[i + 1]; k++) {
                uint32_t j = a->column[k];
                for (uint32_t r = j == i ? c : 0; r < 3; r++, count++)
                    if (p) row[count] = (int)(3 * j + r), source[count] = 9 * (size_t)k + 3 * c + r;
            }
        }
    if (p) p[3 * (size_t)a->rows] = (int)count;
    return count;
}

static void sb_cholesky_free_matrices(sb_sparse_cholesky* f) {
    cholmod_free_sparse(&f->a, &f->common);
    cholmod_free_factor(&f->factor, &f->common);
    free(f->source), free(f->row), free(f->column), free(f->order), free(f->b);
    f->source = NULL, f->row = f->column = f->order = NULL, f->b = NULL;
}

/* A placeholder of the identity's values on the pattern. */
static void sb_fill_identity(cholmod_sparse* s) {
    const int *p = s->p, *row = s->i;
    double* x = s->x;
    for (size_t col = 0; col < s->ncol; col++)
        for (int k = p[col]; k < p[col + 1]; k++) x[k] = (size_t)row[k] == col ? 1.0 : 0.0;
}

/* AMD's ordering of the lower triangle `lower` (postordered) into f->order. */
static bool sb_order(sb_sparse_cholesky* f, cholmod_sparse* lower) {
    f->common.method[0].ordering = CHOLMOD_AMD;
    f->common.postorder = true;
    cholmod_factor* analysis = cholmod_analyze(lower, &f->common);
    if (!analysis) return false;
    memcpy(f->order, analysis->Perm, lower->nrow * sizeof *f->order);
    cholmod_free_factor(&analysis, &f->common);
    return true;
}

/* f->a = P A Pᵀ's upper triangle from A's lower one, each column's rows
 * sorted; f->source, f->row and f->column follow its entries. */
static void sb_permute_upper(sb_sparse_cholesky* f, const cholmod_sparse* lower, const size_t* lower_source,
                             int* place) {
    size_t n = lower->nrow;
    const int *lp = lower->p, *li = lower->i;
    int* p = f->a->p;
    for (size_t k = 0; k < n; k++) place[f->order[k]] = (int)k;
    memset(p, 0, (n + 1) * sizeof *p);
    for (size_t col = 0; col < n; col++)
        for (int k = lp[col]; k < lp[col + 1]; k++) {
            int r = place[li[k]], c = place[col];
            p[(r > c ? r : c) + 1]++;
        }
    for (size_t col = 0; col < n; col++) p[col + 1] += p[col];
    int* next = place + n;
    memcpy(next, p, n * sizeof *next);
    int* rows = f->a->i;
    for (size_t col = 0; col < n; col++)
        for (int k = lp[col]; k < lp[col + 1]; k++) {
            int r = place[li[k]], c = place[col], at = next[r > c ? r : c]++;
            rows[at] = r < c ? r : c;
            f->source[at] = lower_source[k], f->row[at] = li[k], f->column[at] = (int)col;
            for (; at > p[r > c ? r : c] && rows[at - 1] > rows[at]; at--) { /* insertion: columns are short */
                int t = rows[at], tr = f->row[at], tc = f->column[at];
                size_t ts = f->source[at];
                rows[at] = rows[at - 1], f->row[at] = f->row[at - 1], f->column[at] = f->column[at - 1];
                f->source[at] = f->source[at - 1];
                rows[at - 1] = t, f->row[at - 1] = tr, f->column[at - 1] = tc, f->source[at - 1] = ts;
            }
        }
}

static bool sb_analyze(sb_sparse_cholesky* f, const sb_block_matrix* a) {
    sb_cholesky_free_matrices(f);
    size_t n = 3 * (size_t)a->rows, count = sb_lower_pattern(a, NULL, NULL, NULL);
    cholmod_sparse* lower = cholmod_allocate_sparse(n, n, count, 1, 1, -1, CHOLMOD_REAL, &f->common);
    size_t* lower_source = malloc((count ? count : 1) * sizeof *lower_source);
    int* place = malloc((2 * n + 1) * sizeof *place);
    f->a = cholmod_allocate_sparse(n, n, count, 1, 1, 1, CHOLMOD_REAL, &f->common);
    f->source = malloc((count ? count : 1) * sizeof *f->source);
    f->row = malloc((count ? count : 1) * sizeof *f->row);
    f->column = malloc((count ? count : 1) * sizeof *f->column);
    f->order = malloc((n ? n : 1) * sizeof *f->order);
    f->b = malloc((n ? n : 1) * sizeof *f->b);
    bool ok = lower && lower_source && place && f->a && f->source && f->row && f->column && f->order && f->b;
    if (ok) {
        sb_lower_pattern(a, lower->p, lower->i, lower_source);
        ok = sb_order(f, lower);
    }
    if (ok) sb_permute_upper(f, lower, lower_source, place);
    cholmod_free_sparse(&lower, &f->common);
    free(lower_source), free(place);
    if (!ok) return false;
    f->common.method[0].ordering = CHOLMOD_NATURAL; /* already in AMD's order, postordered */
    f->common.postorder = false;
    f->factor = cholmod_analyze(f->a, &f->common);
    if (!f->factor) return false;
    /* the first numeric factorization allocates the factor's values: do it now */
    sb_fill_identity(f->a);
    return cholmod_factorize(f->a, f->factor, &f->common) && f->common.status == CHOLMOD_OK;
}

bool sb_sparse_cholesky_analyze(sb_sparse_cholesky* f, const sb_block_matrix* a) {
    sb_serial_openmp openmp = sb_openmp_serial_begin();
    bool ok = sb_analyze(f, a);
    sb_openmp_serial_end(openmp);
    return ok;
}

sb_sparse_cholesky* sb_sparse_cholesky_create(const sb_block_matrix* a) {
    sb_sparse_cholesky* f = calloc(1, sizeof *f);
    if (!f) return NULL;
    cholmod_start(&f->common);
    f->common.print = 0;
    f->common.error_handler = NULL;
    f->common.supernodal = CHOLMOD_SUPERNODAL;
    f->common.nmethods = 1;
    sb_relax_supernodes(&f->common);
    if (!sb_sparse_cholesky_analyze(f, a)) {
        sb_sparse_cholesky_destroy(f);
        return NULL;
    }
    return f;
}

void sb_sparse_cholesky_destroy(sb_sparse_cholesky* f) {
    if (!f) return;
    sb_cholesky_free_matrices(f);
    cholmod_free_dense(&f->x, &f->common);
    cholmod_free_dense(&f->y, &f->common);
    cholmod_free_dense(&f->e, &f->common);
    cholmod_finish(&f->common);
    free(f);
}

static bool sb_factor(sb_sparse_cholesky* f, const sb_block_matrix* a, const double* mask) {
    const int *row = f->row, *column = f->column;
    double* x = f->a->x;
    size_t count = (size_t)((const int*)f->a->p)[f->a->ncol];
    for (size_t k = 0; k < count; k++)
        x[k] = mask[row[k]] != 0.0 && mask[column[k]] != 0.0 ? a->block[f->source[k]] : row[k] == column[k] ? 1.0 : 0.0;
    return cholmod_factorize(f->a, f->factor, &f->common) && f->common.status == CHOLMOD_OK;
}

static bool sb_solve(sb_sparse_cholesky* f, const double* rhs, double* out) {
    size_t n = f->a->nrow;

    for (size_t k = 0; k < n; k++) f->b[k] = rhs[f->order[k]];
    cholmod_dense b = {
        .nrow = n, .ncol = 1, .nzmax = n, .d = n, .x = f->b, .xtype = CHOLMOD_REAL, .dtype = CHOLMOD_DOUBLE};
    if (!cholmod_solve2(CHOLMOD_A, f->factor, &b, NULL, &f->x, NULL, &f->y, &f->e, &f->common)) return false;
    const double* solution = f->x->x;
    for (size_t k = 0; k < n; k++) out[f->order[k]] = solution[k];
    return true;
}

bool sb_sparse_cholesky_factor(sb_sparse_cholesky* f, const sb_block_matrix* a, const double* mask) {
    sb_serial_openmp openmp = sb_openmp_serial_begin();
    bool ok = sb_factor(f, a, mask);
    sb_openmp_serial_end(openmp);
    return ok;
}

bool sb_sparse_cholesky_solve(sb_sparse_cholesky* f, const double* rhs, double* out) {
    sb_serial_openmp openmp = sb_openmp_serial_begin();
    bool ok = sb_solve(f, rhs, out);
    sb_openmp_serial_end(openmp);
    return ok;
}
