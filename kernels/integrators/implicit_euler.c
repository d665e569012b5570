/* Implicit (backward) Euler, solved by Newton's method on the exact
 * Jacobian, its systems by a sparse Cholesky factorization or by
 * block-Jacobi preconditioned conjugate gradients, with a backtracking line
 * search.
 *
 * Backward Euler, first order, unconditionally stable, and dissipative (it
 * damps an oscillation of frequency ω by 1/√(1 + (ω dt)²) per step):
 *   v⁺ = v + dt M⁻¹ f(x⁺, v⁺),  x⁺ = x + dt v⁺.
 * The unknown is the velocity change Δv = v⁺ − v, with x⁺ = x + dt (v + Δv).
 * Newton drives the residual
 *   R(Δv) = M Δv − dt f(x + dt (v + Δv), v + Δv)
 * to zero: each iteration solves J p = −R with
 *   J = M + dt D + dt² K,
 * K = −∂f/∂x the elements' exact stiffness (kernels/forces/hessian.h; a hinge's
 * Gauss-Newton part only, kernels/forces/hessian.h's sb_element_jacobian_blocks
 * says why), D = −∂f/∂v
 * the springs' damping blocks and the drag, assembled into
 * a 3 × 3 block matrix with the elements' pattern (kernels/linear/block_matrix.h),
 * on the solver's threads (sb_assemble_worker, sb_product_worker; one
 * thread on a small model: sb_implicit_width).
 * With a factorization (implicit_solver, kernels/linear/sparse_cholesky.h) the
 * step's first Newton system is solved roughly by CG, not factored
 * (SB_FIRST_CG_TOLERANCE), a J that is not positive definite is assembled
 * again from the positive semi-definite stand-ins, which always factor,
 * and a factored J serves the next Newton iterations while each halves |R|
 * (modified Newton: an assembly and a factorization cost about seven solves
 * and residuals), their steps Anderson-accelerated (sb_anderson_step). With CG, J is
 * assembled at every iteration, and where K is indefinite (a compressed
 * bond, a loaded corner, a bent hinge) CG stops at its first non-positive
 * curvature and keeps its iterate,
 * counted in sb_step_stats.cg_indefinite; with implicit_definite each
 * element's K is replaced by its positive semi-definite stand-in
 * (kernels/forces/hessian.h), J is positive definite and CG never meets one.
 *
 * What J leaves out — the stand-ins, the damped spring's dependence on x
 * through its direction (not symmetric), the soft handles and the external
 * callback — only changes the direction Newton takes: the residual is
 * always the exact one, from the scalar reference forces in double (each
 * term on a worker of the team, sb_residual_forces), so a converged step is
 * the backward Euler step. A step p is taken whole when it
 * lowers |R|, otherwise halved until it does (at most 5 times; the last
 * trial is kept). CG is preconditioned with the inverses of J's diagonal
 * blocks and stops at a relative residual of 1e-5 or its cap; Newton stops
 * when |R| is below implicit_tolerance × its first value or at rounding
 * level, or at its cap. Fixed vertices and those a hard handle holds are
 * masked out of every vector: a held vertex is at its target throughout, so
 * the forces the step sees are those of the placed handle. The new state then
 * goes through sb_solver_compute_forces, so its forces and energies come
 * from the chosen kernels. */
#include "kernels/integrators/implicit_fast.h"
#include "kernels/integrators/implicit_euler.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/linear/block_matrix.h"
#include "kernels/linear/sparse_cholesky.h"
#include "kernels/interaction/handle_internal.h"
#include "common/error.h"
#include "softbond/reference.h"

#include "common/geometry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A Newton iteration on a factored J that cut |R| at least this much leaves
 * J and its factors to the next (CG, whose cost is its iterations, always
 * assembles afresh). */
#define SB_REUSE_CONTRACTION 0.5
/* Where J is factored, the step's first Newton system is solved by CG to
 * this fraction of its residual instead. From the inertial guess x + dt v
 * the first iteration cuts |R| only 3 to 10 times however exactly it is
 * solved, and the J there (the bonds' tensions far from the step's) serves
 * later iterations badly: kept, it let |R| fall by only about half an
 * iteration, where the J of the second iterate cuts it five- to fiftyfold
 * (bench/results/notes/implicit_euler.md). A factorization there served
 * one solve. */
#define SB_FIRST_CG_TOLERANCE 0.03
/* `auto` factors J when its stiffness outweighs the mass this many times. */
#define SB_AUTO_FACTOR_RATIO 100.0

/* A job of an implicit step has a barrier or two for every few microseconds
 * of work on a small model: on the default scene (900 vertices) the fast
 * CG step took more than twice as long on 2 threads as on 1
 * (bench/results/notes/implicit_euler.md). A thread per this many
 * vertices. */
#define SB_IMPLICIT_VERTICES_PER_THREAD 4096

/* Steps of a kept factorization whose differences accelerate the next
 * (sb_anderson_step: about a tenth fewer Newton iterations on the default
 * scene, the depth 4 a little better than 1 or 2;
 * bench/results/notes/implicit_euler.md). */
enum { SB_ANDERSON_DEPTH = 4 };

/* The work vectors, 3n doubles each, allocated once per solver; W_DX and
 * W_DF start SB_ANDERSON_DEPTH vectors each. */
enum {
    W_X0,
    W_V0,
    W_DV,
    W_DV_START,
    W_XT,
    W_VT,
    W_F,
    W_RHS,
    W_SOL,
    W_RES,
    W_Z,
    W_D,
    W_Q,
    W_MASK,
    W_DV_LAST,
    W_SOL_LAST,
    W_DX,
    W_DF = W_DX + SB_ANDERSON_DEPTH,
    W_COUNT = W_DF + SB_ANDERSON_DEPTH
};

/* Elements a worker computes between two scatters. */
#define SB_ASSEMBLY_CHUNK 64

struct sb_implicit {
    double* work;                  /* W_COUNT × 3n */
    double* term_forces;           /* SB_TERM_COUNT × 3n: the residual's forces, term by term */
    double* element_matrices;      /* the team's chunks: width × SB_ASSEMBLY_CHUNK × SB_ELEMENT_MATRIX */
    double* inverse_blocks;        /* 9n: the preconditioner */
    sb_block_matrix* matrix;       /* J */
    sb_sparse_cholesky* cholesky;  /* its factorization; NULL when CG solves */
    uint32_t pattern_vertices;     /* live_vertices when its pattern was built */
    uint64_t pattern_elements;     /* the model's elements then (a cut adds some) */
    struct sb_implicit_fast* fast; /* kernels: fast, solved by CG: kernels/integrators/implicit_fast.c, nothing above */
};

typedef struct sb_newton {
    sb_solver* s;
    size_t n3;
    double dt;
    double* a[W_COUNT]; /* W_MASK: 1 on a vertex that moves, 0 on one held */
    sb_block_matrix* j;
    double* inverse_blocks;
    sb_sparse_cholesky* cholesky;
    bool factored;       /* J's factorization is current: solve with it, not CG */
    double cg_tolerance; /* CG's relative residual target for this system */
} sb_newton;

static double sb_dot(const double* a, const double* b, size_t n) {
    double sum = 0.0;
    for (size_t k = 0; k < n; k++) sum += a[k] * b[k];
    return sum;
}

static void sb_apply_mask(const sb_newton* w, double* a) {
    for (size_t k = 0; k < w->n3; k++) a[k] *= w->a[W_MASK][k];
}

/* The residual's internal forces on the team: each term of the scalar
 * reference (kernels/forces/reference.c) into a buffer of its own, term t on
 * worker t mod width, then their sum in term order over each worker's
 * share of the entries. The same bits for any thread count (not the
 * reference's own sum, which adds each term onto the last). */
typedef struct sb_term_forces {
    const sb_model* m;
    const double *x, *v;
    double *f, *buffers;
    size_t n3;
    sb_status status[SB_TERM_COUNT];
    sb_error error[SB_TERM_COUNT];
} sb_term_forces;

static void sb_term_forces_worker(void* context, const sb_worker* w) {
    sb_term_forces* job = context;
    double energy;
    for (int t = w->index; t < SB_TERM_COUNT; t += w->width) {
        double* f = job->buffers + (size_t)t * job->n3;
        memset(f, 0, job->n3 * sizeof *f);
        job->status[t] = sb_reference_term(job->m, (sb_term)t, job->x, job->v, f, &energy, &job->error[t]);
    }
    sb_worker_barrier(w);
    int64_t begin, end;
    sb_worker_range(w, (int64_t)job->n3, &begin, &end);
    for (int64_t k = begin; k < end; k++) {
        double sum = 0.0;
        for (int t = 0; t < SB_TERM_COUNT; t++) sum += job->buffers[(size_t)t * job->n3 + (size_t)k];
        job->f[k] = sum;
    }
}

/* f = the total force at xt, vt: internal (as above), gravity, drag, external and soft handles. */
static sb_status sb_residual_forces(sb_newton* w) {
    sb_solver* s = w->s;
    sb_term_forces job = {.m = s->model,
                          .x = w->a[W_XT],
                          .v = w->a[W_VT],
                          .f = w->a[W_F],
                          .buffers = s->implicit->term_forces,
                          .n3 = w->n3};
    sb_team_run(s->team, sb_implicit_width(s), sb_term_forces_worker, &job);
    for (int t = 0; t < SB_TERM_COUNT; t++)
        if (job.status[t] != SB_OK) {
            s->error = job.error[t];
            return job.status[t];
        }
    sb_solver_add_body_forces(s, w->a[W_XT], w->a[W_VT], w->a[W_F], NULL);
    return SB_OK;
}

/* xt, vt at the current Δv, f the total force there, rhs = −R(Δv). */
static sb_status sb_newton_point(sb_newton* w) {
    double **a = w->a, dt = w->dt;
    const double* mass = w->s->model->mass;
    for (size_t k = 0; k < w->n3; k++) {
        a[W_VT][k] = a[W_V0][k] + a[W_DV][k];
        a[W_XT][k] = a[W_X0][k] + dt * a[W_VT][k];
    }
    sb_status status = sb_residual_forces(w);
    for (size_t k = 0; k < w->n3; k++) a[W_RHS][k] = dt * a[W_F][k] - mass[k / 3] * a[W_DV][k];
    sb_apply_mask(w, a[W_RHS]);
    return status;
}

/* The stiffness pass, on the team: in rounds, each worker computes the
 * matrices of its chunk of SB_ASSEMBLY_CHUNK elements (chunk r·width + w),
 * then every worker adds the round's matrices in element order to the block
 * rows it owns (an equal share of the rows). Each block sums its elements in
 * element order whoever adds them: J is bitwise the same for any thread
 * count. A collapsed element raises `collapsed` (the lowest one's number
 * kept by worker 0). */
typedef struct sb_assembly {
    sb_newton* w;
    double* matrices;
    uint64_t count, collapsed;
    bool definite; /* the positive semi-definite stand-ins */
} sb_assembly;

static void sb_assemble_worker(void* context, const sb_worker* worker) {
    sb_assembly* job = context;
    const sb_solver* s = job->w->s;
    const sb_model* m = s->model;
    const double* x = job->w->a[W_XT];
    uint64_t per_round = (uint64_t)worker->width * SB_ASSEMBLY_CHUNK, rows = job->w->j->rows;
    uint32_t rows_begin = (uint32_t)(rows * worker->index / worker->width);
    uint32_t rows_end = (uint32_t)(rows * (worker->index + 1) / worker->width);
    for (uint64_t round = 0; round < job->count; round += per_round) {
        uint64_t first = round + (uint64_t)worker->index * SB_ASSEMBLY_CHUNK;
        double* mine = job->matrices + (size_t)worker->index * SB_ASSEMBLY_CHUNK * SB_ELEMENT_MATRIX;
        for (uint64_t id = first; id < first + SB_ASSEMBLY_CHUNK && id < job->count; id++) {
            sb_element e = sb_element_at(m, id);
            double* k = mine + (id - first) * SB_ELEMENT_MATRIX;
            if (!sb_element_jacobian_blocks(m, &e, x, job->definite, job->w->dt, k)) k[0] = NAN; /* worker 0 names it */
        }
        sb_worker_barrier(worker);
        for (uint64_t id = round; id < round + per_round && id < job->count; id++) {
            const double* k = job->matrices + (id - round) * SB_ELEMENT_MATRIX;
            if (isnan(k[0])) {
                if (worker->index == 0 && job->collapsed == UINT64_MAX) job->collapsed = id;
                continue;
            }
            sb_element e = sb_element_at(m, id);
            sb_block_matrix_add_blocks(job->w->j, id, &e, k, rows_begin, rows_end);
        }
        sb_worker_barrier(worker);
    }
}

/* J = M (1 + dt drag) + dt D + dt² K at the current point. */
static sb_status sb_assemble(sb_newton* w, bool definite) {
    sb_solver* s = w->s;
    const sb_model* m = s->model;
    sb_block_matrix_zero(w->j);
    sb_assembly job = {w, s->implicit->element_matrices, sb_element_count(m), UINT64_MAX, definite};
    sb_team_run(s->team, sb_implicit_width(s), sb_assemble_worker, &job);
    if (job.collapsed != UINT64_MAX) {
        sb_element e = sb_element_at(m, job.collapsed);
        return sb_error_set(&s->error, SB_ERR_DEGENERATE,
                            "implicit_euler: element %llu (vertices %u, %u, ...) collapsed",
                            (unsigned long long)job.collapsed, e.vertex[0], e.vertex[1]);
    }
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        double* block = w->j->block + 9 * (size_t)w->j->diagonal[i];
        double diagonal = m->mass[i] * (1.0 + w->dt * s->def.drag);
        block[0] += diagonal, block[4] += diagonal, block[8] += diagonal;
    }
    return SB_OK;
}

/* q = J d on the team, each worker its own rows. */
typedef struct sb_product {
    const sb_block_matrix* j;
    const double* d;
    double* q;
} sb_product;

static void sb_product_worker(void* context, const sb_worker* worker) {
    const sb_product* job = context;
    int64_t begin, end;
    sb_worker_range(worker, job->j->rows, &begin, &end);
    sb_block_matrix_multiply_rows(job->j, job->d, job->q, (uint32_t)begin, (uint32_t)end);
}

/* The block-Jacobi preconditioner: the inverse of each diagonal block (of
 * the mass alone where a block is singular: possible with an indefinite K). */
static void sb_prepare_preconditioner(sb_newton* w) {
    const sb_model* m = w->s->model;
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        double* inverse = w->inverse_blocks + 9 * (size_t)i;
        if (sb_m3_invert(w->j->block + 9 * (size_t)w->j->diagonal[i], inverse)) continue;
        memset(inverse, 0, 9 * sizeof *inverse); /* held, fixed and dormant vertices are masked anyway */
        if (m->inv_mass[i] > 0) inverse[0] = inverse[4] = inverse[8] = m->inv_mass[i];
    }
}

static void sb_precondition(const sb_newton* w, const double* r, double* z) {
    for (size_t i = 0; i < w->n3 / 3; i++) {
        const double *b = w->inverse_blocks + 9 * i, *ri = r + 3 * i;
        for (int u = 0; u < 3; u++) z[3 * i + u] = b[3 * u] * ri[0] + b[3 * u + 1] * ri[1] + b[3 * u + 2] * ri[2];
    }
    sb_apply_mask(w, z);
}

/* Solves J sol = rhs by preconditioned CG from sol = 0; counts iterations. */
static void sb_conjugate_gradients(sb_newton* w, int cap, sb_step_stats* stats) {
    double **a = w->a, *sol = a[W_SOL], *res = a[W_RES], *z = a[W_Z], *d = a[W_D], *q = a[W_Q];
    size_t n3 = w->n3;
    memset(sol, 0, n3 * sizeof *sol);
    memcpy(res, a[W_RHS], n3 * sizeof *res);
    sb_precondition(w, res, z);
    memcpy(d, z, n3 * sizeof *d);
    double rz = sb_dot(res, z, n3), target = w->cg_tolerance * sqrt(sb_dot(res, res, n3));
    for (int it = 0; it < cap; it++) {
        sb_product product = {w->j, d, q};
        sb_team_run(w->s->team, sb_implicit_width(w->s), sb_product_worker, &product);
        sb_apply_mask(w, q);
        double curvature = sb_dot(d, q, n3);
        if (!(curvature > 0.0)) { /* not positive definite here: keep what we have */
            stats->cg_indefinite++;
            if (it == 0) memcpy(sol, z, n3 * sizeof *sol); /* the preconditioned residual */
            break;
        }
        double alpha = rz / curvature;
        for (size_t k = 0; k < n3; k++) {
            sol[k] += alpha * d[k];
            res[k] -= alpha * q[k];
        }
        stats->cg_iterations++;
        if (sqrt(sb_dot(res, res, n3)) <= target) break;
        sb_precondition(w, res, z);
        double rz_next = sb_dot(res, z, n3), beta = rz_next / rz;
        rz = rz_next;
        for (size_t k = 0; k < n3; k++) d[k] = z[k] + beta * d[k];
    }
}

/* Whether dt² K outweighs the mass SB_AUTO_FACTOR_RATIO times at some
 * moving vertex (by the traces of J's diagonal blocks): CG's iterations grow
 * as the square root of that ratio, and about a hundred cost what a
 * factorization does, so `auto` factors only past it. It depends on the
 * state alone, not on earlier steps: a resumed run chooses alike. */
static bool sb_stiffness_dominates(const sb_newton* w) {
    const sb_solver* s = w->s;
    for (uint32_t i = 0; i < s->model->vertex_count; i++) {
        if (w->a[W_MASK][3 * (size_t)i] == 0.0) continue;
        const double* block = w->j->block + 9 * (size_t)w->j->diagonal[i];
        double mass = s->model->mass[i] * (1.0 + w->dt * s->def.drag);
        if (block[0] + block[4] + block[8] > 3.0 * (1.0 + SB_AUTO_FACTOR_RATIO) * mass) return true;
    }
    return false;
}

/* J at the current point, factored or its preconditioner prepared. A J
 * that does not factor (not positive definite: a compressed bond's sideways
 * stiffness outweighs its vertices' mass) is assembled again from the
 * positive semi-definite stand-ins, which always factors: Newton's direction
 * is then that of a modified Newton, the residual still the exact one. The
 * step's first system (`first`) is not factored but solved roughly by CG
 * (SB_FIRST_CG_TOLERANCE): a factorization there would serve one solve. */
static sb_status sb_prepare_jacobian(sb_newton* w, bool first) {
    bool definite = w->s->def.implicit_definite;
    sb_status status = sb_assemble(w, definite);
    if (status != SB_OK) return status;
    bool factor = w->cholesky && (w->s->def.implicit_solver == SB_LINEAR_CHOLESKY || sb_stiffness_dominates(w));
    w->cg_tolerance = factor && first ? SB_FIRST_CG_TOLERANCE : SB_CG_RELATIVE_TOLERANCE;
    factor = factor && !first;
    w->factored = factor && sb_sparse_cholesky_factor(w->cholesky, w->j, w->a[W_MASK]);
    if (factor && !w->factored && !definite) {
        status = sb_assemble(w, true);
        if (status != SB_OK) return status;
        w->factored = sb_sparse_cholesky_factor(w->cholesky, w->j, w->a[W_MASK]);
    }
    if (w->factored) w->s->stats.factorizations++;
    if (!w->factored) sb_prepare_preconditioner(w);
    return SB_OK;
}

/* sol = J⁻¹ rhs: by the factorization, or by CG where there is none. */
static void sb_solve_newton_system(sb_newton* w, int cg_cap, sb_step_stats* stats) {
    if (w->factored)
        sb_sparse_cholesky_solve(w->cholesky, w->a[W_RHS], w->a[W_SOL]);
    else
        sb_conjugate_gradients(w, cg_cap, stats);
}

/* Anderson acceleration of the modified Newton iteration on a kept
 * factorization (Walker and Ni, SIAM J. Numer. Anal. 2011). With J fixed,
 * Δv ← Δv + J⁻¹(−R(Δv)) is a fixed-point iteration whose step g = sol
 * shrinks only linearly; the last SB_ANDERSON_DEPTH differences of Δv and
 * g (ΔX, ΔG) give the combination γ = argmin |g − ΔG γ|, and the step
 * becomes g − (ΔX + ΔG) γ — on a linear residual GMRES's on the
 * preconditioned system. The history belongs to one factorization: a new
 * one (`fresh`) or CG starts it again. */
typedef struct sb_anderson {
    int count, next; /* differences kept; the ring's next slot */
    bool has_last;   /* W_DV_LAST and W_SOL_LAST hold the last iterate's Δv and step */
} sb_anderson;

/* Solves the m × m symmetric g y = b by Cholesky (g overwritten); false
 * when g is not safely positive definite (nearly dependent differences). */
static bool sb_small_cholesky_solve(double* g, const double* b, double* y, int m) {
    for (int j = 0; j < m; j++) {
        double d = g[j * m + j];
        for (int k = 0; k < j; k++) d -= g[j * m + k] * g[j * m + k];
        if (!(d > 1e-12 * g[j * m + j])) return false;
        g[j * m + j] = sqrt(d);
        for (int i = j + 1; i < m; i++) {
            double v = g[i * m + j];
            for (int k = 0; k < j; k++) v -= g[i * m + k] * g[j * m + k];
            g[i * m + j] = v / g[j * m + j];
        }
    }
    for (int i = 0; i < m; i++) {
        double v = b[i];
        for (int k = 0; k < i; k++) v -= g[i * m + k] * y[k];
        y[i] = v / g[i * m + i];
    }
    for (int i = m - 1; i >= 0; i--) {
        double v = y[i];
        for (int k = i + 1; k < m; k++) v -= g[k * m + i] * y[k];
        y[i] = v / g[i * m + i];
    }
    return true;
}

/* Records the iterate (Δv, sol) and replaces sol by the accelerated step. */
static void sb_anderson_step(sb_newton* w, sb_anderson* h, bool fresh) {
    double** a = w->a;
    size_t n3 = w->n3;
    if (fresh) *h = (sb_anderson){0, 0, false};
    if (h->has_last) {
        double *dx = a[W_DX + h->next], *dg = a[W_DF + h->next];
        for (size_t k = 0; k < n3; k++) {
            dx[k] = a[W_DV][k] - a[W_DV_LAST][k];
            dg[k] = a[W_SOL][k] - a[W_SOL_LAST][k];
        }
        h->next = (h->next + 1) % SB_ANDERSON_DEPTH;
        if (h->count < SB_ANDERSON_DEPTH) h->count++;
    }
    memcpy(a[W_DV_LAST], a[W_DV], n3 * sizeof(double));
    memcpy(a[W_SOL_LAST], a[W_SOL], n3 * sizeof(double));
    h->has_last = true;
    int m = h->count;
    double g[SB_ANDERSON_DEPTH * SB_ANDERSON_DEPTH], b[SB_ANDERSON_DEPTH], gamma[SB_ANDERSON_DEPTH];
    for (int i = 0; i < m; i++) {
        b[i] = sb_dot(a[W_DF + i], a[W_SOL], n3);
        for (int j = 0; j < m; j++) g[i * m + j] = sb_dot(a[W_DF + i], a[W_DF + j], n3);
    }
    if (!sb_small_cholesky_solve(g, b, gamma, m)) { /* keep the plain step; start the history again */
        h->count = h->next = 0;
        return;
    }
    for (int i = 0; i < m; i++)
        for (size_t k = 0; k < n3; k++) a[W_SOL][k] -= gamma[i] * (a[W_DX + i][k] + a[W_DF + i][k]);
}

/* Δv += α sol with α = 1, ½, ¼, … until |R| falls below `norm` (at most
 * SB_LINE_SEARCH_HALVINGS halvings; the last trial stays). Leaves the new
 * point evaluated; returns its |R| (NaN on a failed evaluation: status). */
static double sb_line_search(sb_newton* w, double norm, sb_status* status) {
    double **a = w->a, alpha = 1.0, trial = NAN;
    memcpy(a[W_DV_START], a[W_DV], w->n3 * sizeof(double));
    for (int halving = 0; halving <= SB_LINE_SEARCH_HALVINGS; halving++, alpha *= 0.5) {
        for (size_t k = 0; k < w->n3; k++) a[W_DV][k] = a[W_DV_START][k] + alpha * a[W_SOL][k];
        *status = sb_newton_point(w);
        if (*status != SB_OK) return NAN;
        trial = sqrt(sb_dot(a[W_RHS], a[W_RHS], w->n3));
        if (trial < norm) break;
    }
    return trial;
}

/* The residual's rounding level: 1e-12 of the magnitudes it is made of. */
static double sb_residual_floor(const sb_newton* w) {
    const sb_solver* s = w->s;
    const double* g = s->def.gravity;
    double momentum = 0.0, weight = 0.0, g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    for (size_t k = 0; k < w->n3; k++) {
        double m = s->model->mass[k / 3];
        momentum += m * m * w->a[W_VT][k] * w->a[W_VT][k];
        if (k % 3 == 0) weight += m * m * g2;
    }
    double force = sqrt(sb_dot(w->a[W_F], w->a[W_F], w->n3));
    return 1e-12 * (sqrt(momentum) + w->dt * (force + sqrt(weight))) + 1e-300;
}

/* Whether the Newton systems are factored (implicit_solver, kernels/integrators/implicit_euler.c). */
static bool sb_implicit_factors(const sb_solver* s) {
    if (s->def.implicit_solver == SB_LINEAR_AUTO) return s->model->vertex_count <= SB_CHOLESKY_AUTO_VERTICES;
    return s->def.implicit_solver == SB_LINEAR_CHOLESKY;
}

bool sb_implicit_prepare(sb_solver* s) {
    size_t n = s->model->vertex_count, n3 = 3 * n;
    struct sb_implicit* im = calloc(1, sizeof *im);
    s->implicit = im;
    if (!im) return false;
    if (s->def.kernels == SB_KERNELS_FAST && !sb_implicit_factors(s))
        return (im->fast = sb_implicit_fast_create(s)) != NULL;
    im->work = calloc(W_COUNT * (n3 ? n3 : 1), sizeof(double));
    im->term_forces = calloc(SB_TERM_COUNT * (n3 ? n3 : 1), sizeof(double));
    im->inverse_blocks = calloc(9 * (n ? n : 1), sizeof(double));
    im->element_matrices =
        malloc((size_t)sb_team_size(s->team) * SB_ASSEMBLY_CHUNK * SB_ELEMENT_MATRIX * sizeof(double));
    im->matrix = sb_block_matrix_create(s->model, s->model->vertex_count - s->live_vertices);
    im->pattern_vertices = s->live_vertices;
    im->pattern_elements = sb_element_count(s->model);
    if (!im->work || !im->term_forces || !im->inverse_blocks || !im->matrix || !im->element_matrices) return false;
    if (!sb_implicit_factors(s)) return true;
    im->cholesky = sb_sparse_cholesky_create(im->matrix);
    return im->cholesky != NULL;
}

void sb_implicit_destroy(sb_solver* s) {
    struct sb_implicit* im = s->implicit;
    if (!im) return;
    free(im->work), free(im->term_forces), free(im->inverse_blocks), free(im->element_matrices);
    sb_block_matrix_destroy(im->matrix);
    sb_sparse_cholesky_destroy(im->cholesky);
    sb_implicit_fast_destroy(im->fast);
    free(im);
    s->implicit = NULL;
}

struct sb_implicit_fast* sb_implicit_fast_of(const sb_solver* s) {
    return s->implicit ? s->implicit->fast : NULL;
}

/* The step's start; a vertex a hard handle holds gets the Δv that puts it
 * at its target, and the mask keeps it there. */
static sb_newton sb_newton_init(sb_solver* s, double dt) {
    const struct sb_implicit* im = s->implicit;
    sb_newton w = {.s = s,
                   .n3 = 3 * (size_t)s->model->vertex_count,
                   .dt = dt,
                   .j = im->matrix,
                   .inverse_blocks = im->inverse_blocks,
                   .cholesky = im->cholesky};
    for (int k = 0; k < W_COUNT; k++) w.a[k] = im->work + (size_t)k * w.n3;
    const sb_state* st = &s->state;
    sb_interleave(w.a[W_X0], st->x, st->y, st->z, st->vertex_count);
    sb_interleave(w.a[W_V0], st->vx, st->vy, st->vz, st->vertex_count);
    const double* inv_mass = sb_inv_mass(s);
    for (size_t k = 0; k < w.n3; k++) w.a[W_MASK][k] = inv_mass[k / 3] > 0.0 ? 1.0 : 0.0;
    memset(w.a[W_DV], 0, w.n3 * sizeof(double));
    if (s->pinned_inv_mass) {
        double* target = w.a[W_XT];
        for (size_t k = 0; k < w.n3; k++) target[k] = w.a[W_X0][k] + dt * w.a[W_V0][k];
        sb_handles_place_predicted(s, target);
        for (size_t k = 0; k < w.n3; k++)
            if (w.a[W_MASK][k] == 0.0 && !s->model->fixed[k / 3])
                w.a[W_DV][k] = (target[k] - w.a[W_X0][k]) / dt - w.a[W_V0][k];
    }
    return w;
}

int sb_implicit_width(const sb_solver* s) {
    uint32_t share = s->model->vertex_count / SB_IMPLICIT_VERTICES_PER_THREAD;
    int team = sb_team_size(s->team);
    return share < 1 ? 1 : share < (uint32_t)team ? (int)share : team;
}

sb_newton_limits sb_newton_limits_of(const sb_solver* s) {
    const sb_solver_def* d = &s->def;
    return (sb_newton_limits){.tolerance = d->implicit_tolerance > 0 ? d->implicit_tolerance : 1e-8,
                              .newton_cap = d->implicit_newton_iterations > 0 ? d->implicit_newton_iterations : 20,
                              .cg_cap = d->implicit_cg_iterations > 0 ? d->implicit_cg_iterations : 200};
}

/* J and its factorization built anew after a cut added elements
 * (kernels/interaction/cut_mesh.c, cut_volume.c): the matrix's per-element
 * arrays are sized by the element count at creation. */
static sb_status sb_renew_pattern(sb_solver* s, struct sb_implicit* im) {
    sb_block_matrix* matrix = sb_block_matrix_create(s->model, s->model->vertex_count - s->live_vertices);
    sb_sparse_cholesky* cholesky = matrix && im->cholesky ? sb_sparse_cholesky_create(matrix) : NULL;
    if (!matrix || (im->cholesky && !cholesky)) {
        sb_block_matrix_destroy(matrix);
        return sb_error_set(&s->error, SB_ERR_NOMEM, "implicit_euler: out of memory for the cut mesh's matrix");
    }
    sb_block_matrix_destroy(im->matrix);
    im->matrix = matrix;
    if (cholesky) {
        sb_sparse_cholesky_destroy(im->cholesky);
        im->cholesky = cholesky;
    }
    return SB_OK;
}

/* J's pattern after the model changed: re-pointed in place where tearing
 * split vertices (its elements the same), built anew where a cut added
 * elements. */
static sb_status sb_refresh_pattern(sb_solver* s, struct sb_implicit* im) {
    uint64_t elements = sb_element_count(s->model);
    if (im->pattern_vertices == s->live_vertices && im->pattern_elements == elements) return SB_OK;
    if (elements != im->pattern_elements) {
        sb_status status = sb_renew_pattern(s, im);
        if (status != SB_OK) return status;
    } else {
        if (!sb_block_matrix_rebuild(im->matrix, s->model))
            return sb_error_set(&s->error, SB_ERR_NOMEM,
                                "implicit_euler: the torn surface's matrix outgrew its reserve");
        if (im->cholesky && !sb_sparse_cholesky_analyze(im->cholesky, im->matrix))
            return sb_error_set(&s->error, SB_ERR_NOMEM, "implicit_euler: out of memory factoring the torn surface");
    }
    im->pattern_vertices = s->live_vertices;
    im->pattern_elements = elements;
    return SB_OK;
}

sb_status sb_integrate_implicit_euler(sb_solver* s, double dt) {
    struct sb_implicit* im = s->implicit;
    if (im->fast) return sb_implicit_fast_step(s, im->fast, dt);
    sb_status status = sb_refresh_pattern(s, im);
    if (status != SB_OK) return status;
    sb_newton w = sb_newton_init(s, dt);
    const sb_newton_limits limits = sb_newton_limits_of(s);
    status = sb_newton_point(&w);
    if (status != SB_OK) return status;
    double first = sqrt(sb_dot(w.a[W_RHS], w.a[W_RHS], w.n3)), norm = first;
    bool converged = false, stale = true;
    sb_anderson history = {0, 0, false};
    for (int it = 0; isfinite(norm); it++) { /* a non-finite residual: the state check names the vertex */
        if (norm <= limits.tolerance * first || norm <= sb_residual_floor(&w)) {
            converged = true;
            break;
        }
        if (it == limits.newton_cap) break;
        if (stale) {
            status = sb_prepare_jacobian(&w, it == 0);
            if (status != SB_OK) return status;
        }
        sb_solve_newton_system(&w, limits.cg_cap, &s->stats);
        if (w.factored)
            sb_anderson_step(&w, &history, stale);
        else
            history.has_last = false;
        double previous = norm;
        norm = sb_line_search(&w, norm, &status);
        if (status != SB_OK) return status;
        stale = !w.factored || !(norm <= SB_REUSE_CONTRACTION * previous);
        s->stats.newton_iterations++;
    }
    if (!converged) s->stats.converged = false;
    sb_store_free_vertices(s, w.a[W_XT], w.a[W_VT]);
    s->has_displacement = false;
    return sb_solver_compute_forces(s);
}
