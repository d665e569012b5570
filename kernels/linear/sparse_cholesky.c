/* A supernodal Cholesky factorization of the block matrix
 * (kernels/linear/sparse_cholesky.h): CHOLMOD's ordering and analysis, the
 * numeric factorization and the solve here on CHOLMOD's supernodal pattern,
 * the factor's values in float.
 *
 * The matrix's lower triangle in compressed columns (scalar column 3 i + c
 * holds, for each block (i, j) of block row i with j ≥ i, the rows 3 j + r,
 * r ≥ c on the diagonal block, whose values are A(3 j + r, 3 i + c) =
 * block(i, j)[3 c + r] by symmetry) gives AMD's ordering P. CHOLMOD then
 * gets P A Pᵀ itself, as its upper triangle, analysed in its own order:
 * given A with P it permutes A at every factorization (two passes of
 * cholmod_transpose_sym; cholmod_factorize still transposed the upper
 * triangle once, which the factorization here does not: each entry goes
 * straight to its place in the factor; their share of a run:
 * bench/results/notes/implicit_euler.md). Each entry keeps the index of its value in
 * the block matrix, its row and column in A and its place in the factor's
 * values; a solve permutes the right-hand side and the solution.
 *
 * The numeric factorization (sb_factor_supernodes) is cholmod_super_numeric's
 * left-looking supernodal algorithm on the same pattern and BLAS calls,
 * without its OpenMP regions: Debian's CHOLMOD opens a few for every
 * supernode and every update between two (clearing maps, assembling), each
 * ending in a futex system call even on one thread (about a thousand a step
 * on the default scene), and allocates its workspace per call. Here a
 * factorization takes about half the CPU that cholmod_factorize took, with
 * the same Newton iterations (bench/results/notes/implicit_euler.md), and
 * allocates nothing.
 *
 * The factor is kept in float (ssyrk, sgemm, spotrf, strsm) and solved in
 * double against it (sb_solve_supernodes): implicit Euler's Newton uses it
 * as a modified Newton's approximate inverse (a J kept over several
 * iterations, the residual always the exact one in double), which float's
 * rounding (a solve's relative residual about 3e-7 on the test matrices)
 * does not change: on the default scene the same Newton iterations as in
 * double, every step converged to 1e-8. It halves the bytes a
 * factorization and a solve move and doubles the SIMD width: each takes
 * about a quarter less time than in double (cholmod_solve2 on the double
 * factor before: a BLAS call or two per supernode;
 * bench/results/notes/implicit_euler.md). A matrix that is positive definite in double but not by
 * float's pivots (a condition near 1e7) fails to factor, and the caller
 * solves by CG. */
#include "kernels/linear/sparse_cholesky.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include <suitesparse/cholmod.h>

/* Debian's CHOLMOD runs a few short loops (clearing its maps, zeroing a
 * supernode) on four OpenMP threads of its own. Beside the solver's team on
 * a small machine they cost more CPU than they save, and they would make
 * the result's threads the runtime's, not the solver's: a call to CHOLMOD
 * (the analysis, a solve) runs with OpenMP's active levels at 0, so its
 * parallel loops run on the calling thread (the setting is libgomp's
 * global; it is restored after the call). */
typedef struct sb_serial_openmp {
    int saved;
} sb_serial_openmp;

static sb_serial_openmp sb_openmp_serial_begin(void) {
    sb_serial_openmp state = {omp_get_max_active_levels()};
    omp_set_max_active_levels(0);
    return state;
}

static void sb_openmp_serial_end(sb_serial_openmp state) { omp_set_max_active_levels(state.saved); }

struct sb_sparse_cholesky {
    cholmod_common common;
    cholmod_sparse* a; /* P A Pᵀ, upper triangle */
    cholmod_factor* factor;
    size_t* source;    /* per entry of a: its value's index in the block matrix's values */
    int *row, *column; /* per entry of a: its row and column in A */
    size_t* target;    /* per entry of a: its place in the factor's values (the lower triangle's) */
    int* order;        /* P: row k of a is row order[k] of A */
    double* b;         /* P rhs */
    float* lx;         /* the factor's values, in float, on CHOLMOD's supernodal layout (f->factor's pattern) */
    /* the numeric factorization's workspace (sb_factor_supernodes) and the
     * solve's (a supernode's rows below its columns), sized by the analysis */
    int *map, *relative, *super_of, *head, *next, *position;
    float* update;
    double* below;
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
    free(f->source), free(f->row), free(f->column), free(f->target), free(f->order), free(f->b);
    f->source = NULL, f->row = f->column = f->order = NULL, f->b = NULL, f->target = NULL;
    free(f->map), free(f->relative), free(f->super_of), free(f->head), free(f->next), free(f->position);
    free(f->update), free(f->lx), free(f->below);
    f->map = f->relative = f->super_of = f->head = f->next = f->position = NULL, f->update = f->lx = NULL;
    f->below = NULL;
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

/* The numeric factorization's plan on CHOLMOD's supernodal pattern: each
 * column's supernode, the workspace, and where each entry of a goes in the
 * factor's values (entry (r, c), r ≤ c, of P A Pᵀ's upper triangle is
 * (c, r) of the lower one: in r's supernode, column r, at c's row there).
 * False when out of memory or the pattern is not the sorted one assumed. */
static bool sb_map_supernodes(sb_sparse_cholesky* f) {
    const cholmod_factor* L = f->factor;
    const int *super = L->super, *pi = L->pi, *px = L->px, *ls = L->s;
    size_t n = L->n, nsuper = L->nsuper, count = (size_t)((const int*)f->a->p)[f->a->ncol];
    f->map = malloc((n ? n : 1) * sizeof *f->map);
    f->relative = malloc((n ? n : 1) * sizeof *f->relative);
    f->super_of = malloc((n ? n : 1) * sizeof *f->super_of);
    f->head = malloc((nsuper ? nsuper : 1) * sizeof *f->head);
    f->next = malloc((nsuper ? nsuper : 1) * sizeof *f->next);
    f->position = malloc((nsuper ? nsuper : 1) * sizeof *f->position);
    f->update = malloc((L->maxcsize ? L->maxcsize : 1) * sizeof *f->update);
    f->lx = malloc((L->xsize ? L->xsize : 1) * sizeof *f->lx);
    f->below = malloc((n ? n : 1) * sizeof *f->below);
    f->target = malloc((count ? count : 1) * sizeof *f->target);
    if (!f->map || !f->relative || !f->super_of || !f->head || !f->next || !f->position || !f->update || !f->lx ||
        !f->below || !f->target)
        return false;
    for (size_t s = 0; s < nsuper; s++) {
        int columns = super[s + 1] - super[s];
        if (pi[s + 1] - pi[s] < columns) return false;
        for (int k = pi[s]; k < pi[s + 1]; k++) /* the supernode's own columns first, then rows ascending */
            if ((k < pi[s] + columns && ls[k] != super[s] + (k - pi[s])) || (k > pi[s] && ls[k] <= ls[k - 1]))
                return false;
        for (int col = super[s]; col < super[s + 1]; col++) f->super_of[col] = (int)s;
    }
    const int *ap = f->a->p, *ai = f->a->i;
    for (size_t c = 0; c < n; c++)
        for (int k = ap[c]; k < ap[c + 1]; k++) {
            int r = ai[k], s = f->super_of[r], rows = pi[s + 1] - pi[s], lo = pi[s], hi = pi[s + 1];
            while (lo < hi) { /* c among the rows of r's supernode */
                int mid = lo + (hi - lo) / 2;
                if (ls[mid] < (int)c)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            if (lo == pi[s + 1] || ls[lo] != (int)c) return false;
            f->target[k] = (size_t)px[s] + (size_t)(r - super[s]) * (size_t)rows + (size_t)(lo - pi[s]);
        }
    return true;
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
    return f->factor && f->factor->is_super && sb_map_supernodes(f);
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
    if (!sb_sparse_cholesky_analyze(f, a)) {
        sb_sparse_cholesky_destroy(f);
        return NULL;
    }
    return f;
}

void sb_sparse_cholesky_destroy(sb_sparse_cholesky* f) {
    if (!f) return;
    sb_cholesky_free_matrices(f);
    cholmod_finish(&f->common);
    free(f);
}

/* BLAS and LAPACK (Fortran calling convention, string lengths last). */
void ssyrk_(const char* uplo, const char* trans, const int* n, const int* k, const float* alpha, const float* a,
            const int* lda, const float* beta, float* c, const int* ldc, size_t uplo_length, size_t trans_length);
void sgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const float* alpha,
            const float* a, const int* lda, const float* b, const int* ldb, const float* beta, float* c, const int* ldc,
            size_t transa_length, size_t transb_length);
void strsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const float* alpha, const float* a, const int* lda, float* b, const int* ldb, size_t side_length,
            size_t uplo_length, size_t transa_length, size_t diag_length);
void spotrf_(const char* uplo, const int* n, float* a, const int* lda, int* info, size_t uplo_length);

/* Supernode s's place in the list of the first supernode that its rows
 * below position `from` reach (CHOLMOD's left-looking linked lists). */
static void sb_link_supernode(sb_sparse_cholesky* f, int s, int from) {
    const int *pi = f->factor->pi, *ls = f->factor->s;
    f->position[s] = from;
    if (pi[s] + from >= pi[s + 1]) return;
    int ancestor = f->super_of[ls[pi[s] + from]];
    f->next[s] = f->head[ancestor], f->head[ancestor] = s;
}

/* Whether the diagonal of a factored supernode (columns × columns, leading
 * dimension rows) is finite. dpotrf stops at a non-positive pivot but not
 * at a NaN; a NaN or an infinity anywhere in the matrix's lower triangle
 * reaches the diagonal of its column or a later one (L_ii = √(a_ii − Σ
 * L_ik²)), so checking the diagonal catches every one. */
static bool sb_diagonal_finite(const float* x, int columns, int rows) {
    for (int k = 0; k < columns; k++)
        if (!isfinite(x[(size_t)k * (size_t)rows + (size_t)k])) return false;
    return true;
}

/* The left-looking supernodal Cholesky factorization of the values already
 * in the factor (LLᵀ, lower, each supernode a dense column-major block of
 * its rows × its columns, CHOLMOD's layout): supernode by supernode, the
 * updates of every earlier supernode with rows in its columns (dsyrk and
 * dgemm into the update matrix, subtracted through the row map), then
 * dpotrf on its diagonal block and dtrsm below it. The same arithmetic as
 * cholmod_super_numeric without its OpenMP regions, one thread; false when
 * a diagonal block is not positive definite or not finite. */
static bool sb_factor_supernodes(sb_sparse_cholesky* f) {
    const cholmod_factor* L = f->factor;
    const int *super = L->super, *pi = L->pi, *px = L->px, *ls = L->s;
    float *lx = f->lx, *c = f->update;
    int nsuper = (int)L->nsuper;
    const float one = 1.0f, zero = 0.0f;
    for (int s = 0; s < nsuper; s++) f->head[s] = -1;
    for (int s = 0; s < nsuper; s++) {
        int k1 = super[s], k2 = super[s + 1], columns = k2 - k1, rows = pi[s + 1] - pi[s];
        float* ls_x = lx + px[s];
        for (int k = 0; k < rows; k++) f->map[ls[pi[s] + k]] = k;
        for (int d = f->head[s], d_next; d != -1; d = d_next) {
            d_next = f->next[d];
            int d_columns = super[d + 1] - super[d], d_rows = pi[d + 1] - pi[d], first = pi[d] + f->position[d];
            int end = first;
            while (end < pi[d + 1] && ls[end] < k2) end++;
            int rows1 = end - first, rows2 = pi[d + 1] - first, rows3 = rows2 - rows1;
            const float* d_x = lx + px[d] + f->position[d];
            /* c = L_d(rows, :) L_d(rows in s's columns, :)ᵀ, rows2 × rows1 */
            ssyrk_("L", "N", &rows1, &d_columns, &one, d_x, &d_rows, &zero, c, &rows2, 1, 1);
            if (rows3 > 0)
                sgemm_("N", "T", &rows3, &rows1, &d_columns, &one, d_x + rows1, &d_rows, d_x, &d_rows, &zero, c + rows1,
                       &rows2, 1, 1);
            for (int i = 0; i < rows2; i++) f->relative[i] = f->map[ls[first + i]];
            for (int j = 0; j < rows1; j++) {
                float* column = ls_x + (size_t)f->relative[j] * (size_t)rows;
                const float* cj = c + (size_t)j * (size_t)rows2;
                for (int i = j; i < rows2; i++) column[f->relative[i]] -= cj[i];
            }
            sb_link_supernode(f, d, f->position[d] + rows1);
        }
        int info = 0;
        spotrf_("L", &columns, ls_x, &rows, &info, 1);
        if (info != 0 || !sb_diagonal_finite(ls_x, columns, rows)) return false;
        int below = rows - columns;
        if (below > 0)
            strsm_("R", "L", "T", "N", &below, &columns, &one, ls_x, &rows, ls_x + columns, &rows, 1, 1, 1, 1);
        sb_link_supernode(f, s, columns);
    }
    return true;
}

static bool sb_factor(sb_sparse_cholesky* f, const sb_block_matrix* a, const double* mask) {
    const int *row = f->row, *column = f->column;
    float* lx = f->lx;
    size_t count = (size_t)((const int*)f->a->p)[f->a->ncol];
    memset(lx, 0, f->factor->xsize * sizeof *lx);
    for (size_t k = 0; k < count; k++)
        lx[f->target[k]] = mask[row[k]] != 0.0 && mask[column[k]] != 0.0 ? (float)a->block[f->source[k]]
                           : row[k] == column[k]                         ? 1.0f
                                                                         : 0.0f;
    return sb_factor_supernodes(f);
}

/* Σ column[i] t[i] over i < n in 8 partial sums (added in order at the
 * end), which vectorize: one chain of dependent additions bounded the
 * backward sweep. */
static double sb_dot_below(const float* column, const double* t, int n) {
    double part[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    int i = 0;
    for (; i + 8 <= n; i += 8)
        for (int u = 0; u < 8; u++) part[u] += column[i + u] * t[i + u];
    for (; i < n; i++) part[i % 8] += column[i] * t[i];
    return ((part[0] + part[1]) + (part[2] + part[3])) + ((part[4] + part[5]) + (part[6] + part[7]));
}

/* b = (L Lᵀ)⁻¹ b in place (b permuted: P rhs), in double on the float
 * factor, supernode by supernode on its layout (each a dense column-major
 * block, its own columns' rows first, then the rows below them, which
 * f->below gathers): L y = b forward, each supernode's triangle then its
 * rows below, and Lᵀ x = y backward. A sweep reads each value of the factor
 * once. */
static void sb_solve_supernodes(sb_sparse_cholesky* f, double* b) {
    const cholmod_factor* L = f->factor;
    const int *super = L->super, *pi = L->pi, *px = L->px, *ls = L->s;
    double* t = f->below;
    int nsuper = (int)L->nsuper;
    for (int s = 0; s < nsuper; s++) {
        int columns = super[s + 1] - super[s], rows = pi[s + 1] - pi[s], below = rows - columns;
        const float* l = f->lx + px[s];
        const int* row = ls + pi[s] + columns;
        double* xs = b + super[s];
        for (int j = 0; j < columns; j++) {
            const float* column = l + (size_t)j * (size_t)rows;
            double xj = xs[j] / column[j];
            xs[j] = xj;
            for (int i = j + 1; i < columns; i++) xs[i] -= column[i] * xj;
        }
        for (int i = 0; i < below; i++) t[i] = 0.0;
        for (int j = 0; j < columns; j++) {
            const float* column = l + (size_t)j * (size_t)rows + columns;
            double xj = xs[j];
            for (int i = 0; i < below; i++) t[i] += column[i] * xj;
        }
        for (int i = 0; i < below; i++) b[row[i]] -= t[i];
    }
    for (int s = nsuper - 1; s >= 0; s--) {
        int columns = super[s + 1] - super[s], rows = pi[s + 1] - pi[s], below = rows - columns;
        const float* l = f->lx + px[s];
        const int* row = ls + pi[s] + columns;
        double* xs = b + super[s];
        for (int i = 0; i < below; i++) t[i] = b[row[i]];
        for (int j = columns - 1; j >= 0; j--) {
            const float* column = l + (size_t)j * (size_t)rows;
            double sum = sb_dot_below(column + columns, t, below);
            for (int i = j + 1; i < columns; i++) sum += column[i] * xs[i];
            xs[j] = (xs[j] - sum) / column[j];
        }
    }
}

void sb_sparse_cholesky_solve(sb_sparse_cholesky* f, const double* rhs, double* out) {
    size_t n = f->a->nrow;
    for (size_t k = 0; k < n; k++) f->b[k] = rhs[f->order[k]];
    sb_solve_supernodes(f, f->b);
    for (size_t k = 0; k < n; k++) out[f->order[k]] = f->b[k];
}

bool sb_sparse_cholesky_factor(sb_sparse_cholesky* f, const sb_block_matrix* a, const double* mask) {
    return sb_factor(f, a, mask);
}
