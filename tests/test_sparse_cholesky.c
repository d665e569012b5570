/* The sparse direct solve of implicit Euler's Newton systems
 * (kernels/linear/sparse_cholesky.h): its numeric factorization is softbond's own
 * supernodal code on CHOLMOD's analysis, so it is checked here directly,
 * not only through Newton's convergence, on random symmetric positive
 * definite matrices with the pattern of a 30 × 30 sheet's elements (every
 * term, hinges included: 900 block rows, many supernodes with updates).
 * The factor is kept in float (kernels/linear/sparse_cholesky.c says why): one
 * solve is as accurate as float's rounding allows, and each sweep of
 * iterative refinement in double (x += solve(b − A x)) gains as much again,
 * which a factor wrong beyond its rounding would not. */
#include "test_util.h"

#include "kernels/linear/block_matrix.h"
#include "kernels/linear/sparse_cholesky.h"

/* Each case's fixture: the sheet's matrix (values unset), its analysis, a
 * mask of ones (nothing held), a random right-hand side b from the case's
 * seed (the prestate) and the solution's x. */
typedef struct system {
    sb_model* model;
    sb_block_matrix* a;
    sb_sparse_cholesky* f;
    size_t n3;
    double *mask, *b, *x;
} system_t;

/* Random symmetric values in every block of the pattern, the diagonal raised
 * above the sum of its row's magnitudes times `dominance` (> 1: strictly
 * diagonally dominant, so positive definite) with the diagonal's scale
 * varying by `spread` across rows (a condition number of about spread²). */
static void fill_spd(sb_block_matrix* a, uint64_t seed, double dominance, double spread) {
    tu_rng rng = {seed};
    sb_block_matrix_zero(a);
    for (uint32_t i = 0; i < a->rows; i++)
        for (uint32_t k = a->row_start[i]; k < a->row_start[i + 1]; k++) {
            uint32_t j = a->column[k];
            if (j < i) continue;
            double* upper = a->block + 9 * (size_t)k;
            double* lower = sb_block_matrix_at(a, j, i);
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++) {
                    if (i == j && c < r) continue;
                    double value = tu_uniform(&rng, -1.0, 1.0);
                    upper[3 * r + c] = value;
                    lower[3 * c + r] = value;
                }
        }
    for (uint32_t i = 0; i < a->rows; i++) {
        double scale = pow(spread, (double)i / a->rows);
        for (int r = 0; r < 3; r++) {
            double off = 0.0;
            for (uint32_t k = a->row_start[i]; k < a->row_start[i + 1]; k++)
                for (int c = 0; c < 3; c++)
                    if (a->column[k] != i || c != r) off += fabs(a->block[9 * (size_t)k + 3 * r + c]);
            a->block[9 * (size_t)a->diagonal[i] + 4 * r] = dominance * off * scale + 1e-3;
        }
    }
}

static double* random_vector(size_t n, uint64_t seed) {
    tu_rng rng = {seed};
    double* v = malloc(n * sizeof *v);
    for (size_t k = 0; k < n; k++) v[k] = tu_uniform(&rng, -1.0, 1.0);
    return v;
}

static double* ones(size_t n) {
    double* v = malloc(n * sizeof *v);
    for (size_t k = 0; k < n; k++) v[k] = 1.0;
    return v;
}

static int setup_system(void** state) {
    uint64_t seed = *(const uint64_t*)*state;
    system_t* s = calloc(1, sizeof *s);
    if (!s) return -1;
    s->model = tu_every_term_sheet(30, false);
    s->a = sb_block_matrix_create(s->model, 0);
    if (!s->a) return -1;
    s->f = sb_sparse_cholesky_create(s->a);
    s->n3 = 3 * (size_t)s->a->rows;
    s->mask = ones(s->n3);
    s->b = random_vector(s->n3, seed);
    s->x = malloc(s->n3 * sizeof *s->x);
    *state = s;
    return s->f && s->mask && s->b && s->x ? 0 : -1;
}

static int teardown_system(void** state) {
    system_t* s = *state;
    free(s->mask), free(s->b), free(s->x);
    sb_sparse_cholesky_destroy(s->f);
    sb_block_matrix_destroy(s->a);
    sb_model_destroy(s->model);
    free(s);
    return 0;
}

/* Masked A x (held rows and columns the identity's) into ax. */
static void masked_product(const sb_block_matrix* a, const double* mask, const double* x, double* ax, size_t n3) {
    double* free_x = malloc(n3 * sizeof *free_x);
    for (size_t k = 0; k < n3; k++) free_x[k] = mask[k] != 0.0 ? x[k] : 0.0;
    sb_block_matrix_multiply(a, free_x, ax);
    for (size_t k = 0; k < n3; k++)
        if (mask[k] == 0.0) ax[k] = x[k];
    free(free_x);
}

/* x = the solve of b, then `sweeps` sweeps of iterative refinement in
 * double on the masked A; |A x − b|∞ over |b|∞ after each in
 * residual[0 .. sweeps]. */
static void refined_solve(const system_t* s, int sweeps, double* residual) {
    size_t n3 = s->n3;
    double *ax = malloc(n3 * sizeof *ax), *r = malloc(n3 * sizeof *r), *dx = malloc(n3 * sizeof *dx);
    sb_sparse_cholesky_solve(s->f, s->b, s->x);
    for (int sweep = 0;; sweep++) {
        masked_product(s->a, s->mask, s->x, ax, n3);
        double worst = 0.0;
        for (size_t k = 0; k < n3; k++) r[k] = s->b[k] - ax[k], worst = fmax(worst, fabs(r[k]));
        residual[sweep] = worst / tu_max_abs(s->b, n3);
        if (sweep == sweeps) break;
        sb_sparse_cholesky_solve(s->f, r, dx);
        for (size_t k = 0; k < n3; k++) s->x[k] += dx[k];
    }
    free(ax), free(r), free(dx);
}

/* The solve inverts the matrix, and a second factorization on the same
 * analysis with other values (what each Newton iteration does) inverts the
 * new values, not a mix of the old and new. */
static void test_solves_spd_systems(void** state) {
    system_t* s = *state;
    const double dominance[3] = {1.05, 1.5, 1.01}, spread[3] = {1.0, 1e3, 10.0};
    for (int round = 0; round < 3; round++) {
        fill_spd(s->a, 11 + round, dominance[round], spread[round]);
        assert_true(sb_sparse_cholesky_factor(s->f, s->a, s->mask));
        double residual[4];
        refined_solve(s, 3, residual);
        print_message("round %d: |Ax - b| / |b| = %.3g, refined %.3g %.3g %.3g\n", round, residual[0], residual[1],
                      residual[2], residual[3]);
        TU_ASSERT_LE(residual[0], 5e-6);
        TU_ASSERT_LE(residual[1], fmax(1e-4 * residual[0], 1e-14));
        TU_ASSERT_LE(residual[3], 1e-13);
    }
}

/* Rows and columns of held vertices (mask 0) act as the identity's: the
 * solution there is the right-hand side, and the other rows solve their own
 * system with those columns left out. */
static void test_masked_rows_are_the_identity(void** state) {
    system_t* s = *state;
    double *mask = s->mask, *b = s->b, *x = s->x;
    fill_spd(s->a, 23, 1.2, 100.0);
    const uint32_t held[] = {0, 29, 450, 899};
    for (size_t h = 0; h < sizeof held / sizeof *held; h++)
        for (int c = 0; c < 3; c++) mask[3 * held[h] + c] = 0.0;
    assert_true(sb_sparse_cholesky_factor(s->f, s->a, mask));
    /* The held rows: x = b exactly, after one solve and after refinement; the
     * free rows: Σ over free columns of A x = b (masked_product). */
    sb_sparse_cholesky_solve(s->f, b, x);
    for (size_t k = 0; k < s->n3; k++)
        if (mask[k] == 0.0) TU_ASSERT_NEAR(x[k], b[k], 1e-14);
    double residual[4];
    refined_solve(s, 3, residual);
    print_message("|Ax - b| / |b| = %.3g, refined %.3g\n", residual[0], residual[3]);
    TU_ASSERT_LE(residual[0], 5e-6);
    TU_ASSERT_LE(residual[3], 1e-13);
    for (size_t k = 0; k < s->n3; k++)
        if (mask[k] == 0.0) TU_ASSERT_NEAR(x[k], b[k], 1e-14);
}

/* A matrix that is not positive definite, or holds a NaN, does not factor
 * (the caller then solves by CG), and the factorization after it, of a good
 * matrix, is right again. */
static void test_rejects_indefinite_and_nan(void** state) {
    system_t* s = *state;
    sb_block_matrix* a = s->a;
    const uint32_t rows[] = {0, 437, 899};
    for (size_t r = 0; r < sizeof rows / sizeof *rows; r++) {
        fill_spd(a, 37 + r, 1.1, 1.0);
        a->block[9 * (size_t)a->diagonal[rows[r]] + 4] = -1.0;
        assert_false(sb_sparse_cholesky_factor(s->f, a, s->mask));
        fill_spd(a, 41 + r, 1.1, 1.0);
        a->block[9 * (size_t)a->diagonal[rows[r]] + 8] = NAN;
        assert_false(sb_sparse_cholesky_factor(s->f, a, s->mask));
    }
    fill_spd(a, 43, 1.1, 1.0);
    assert_true(sb_sparse_cholesky_factor(s->f, a, s->mask));
    double residual[4];
    refined_solve(s, 3, residual);
    TU_ASSERT_LE(residual[0], 5e-6);
    TU_ASSERT_LE(residual[3], 1e-13);
}

int main(void) {
    static const uint64_t seeds[] = {5, 29, 31}; /* each case's right-hand side */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_prestate_setup_teardown(test_solves_spd_systems, setup_system, teardown_system,
                                                 (void*)&seeds[0]),
        cmocka_unit_test_prestate_setup_teardown(test_masked_rows_are_the_identity, setup_system, teardown_system,
                                                 (void*)&seeds[1]),
        cmocka_unit_test_prestate_setup_teardown(test_rejects_indefinite_and_nan, setup_system, teardown_system,
                                                 (void*)&seeds[2]),
    };
    return TU_RUN_TESTS(tests);
}
