/* Implicit Euler on the fast kernels (kernels: fast, systems solved by CG).
 *
 * The same Newton as kernels/integrators/implicit_euler.c (its design note: the
 * unknown Δv, the residual R(Δv) = M Δv − dt f(x + dt (v + Δv), v + Δv),
 * J = M (1 + dt drag) + dt D + dt² K, the line search, the mask of held
 * vertices), with every piece on the fast path and nothing assembled:
 *   - the residual from the fast force passes (sb_fast_forces_packed) at
 *     the packed trial state, in sb_real;
 *   - J's products matrix-free from the kernels of kernels/forces/fast_hessian.h,
 *     and its diagonal 3 × 3 blocks from their diagonal pass, inverted per
 *     vertex: block-Jacobi preconditioned CG;
 *   - K exact: CG stops at its first non-positive curvature and keeps its
 *     iterate (sb_step_stats.cg_indefinite), as the reference's CG does.
 *     The positive semi-definite stand-ins (implicit_definite) are the
 *     assembled path's; here the flag is not read (on a 100 × 100 sheet at
 *     10 × Verlet's step the stand-ins did not converge within the Newton
 *     cap, the exact K did: DESIGN.md).
 * Vectors are packed x y z w per vertex like the positions (the kernels'
 * loads); every vector operation runs on the team over the vertex chunks
 * (SB_CHUNK vertices), each chunk keeping its partial sums in double,
 * added in chunk order after the job: the same numbers for any thread
 * count, as the products' blocked coloring gives.
 *
 * Stopping rule: |R| below implicit_tolerance × its first value, or below
 * the level at which its own rounding hides any progress, the larger of
 *   SB_FAST_ROUNDING × (|M v⁺| + dt (|f| + |M g|)) (the reference's 1e-12 in
 *     double, 1e-5 in float) and
 *   ε/dt · √Σ (|x_i| tr(dt² K_ii + dt D_ii))², the rounding of the positions
 *     (ε |x_i|) carried through the stiffness into dt f: in float |R| stalls
 *     there (measured at about an eighth of it on tests/test_fast_hessian.c's
 *     sheet), far above the first term.
 * CG stops at its relative 1e-5 or at half of that Newton target, whichever
 * is larger.
 *
 * First guess: the last step's Δv, where the tolerance ended that step's
 * Newton (not the rounding level: there Δv carries the rounding, and on the
 * 100k sheet in float its |R| was 1.7 times |R(0)| on every step), for the
 * same dt. One more force pass gives |R(guess)|; the guess is kept only
 * when that is below |R(0)|, otherwise Newton starts from Δv = 0 as
 * before. |R(0)| is computed either way and stays the reference of the
 * relative test, so a good guess means fewer Newton and CG iterations (none
 * where |R(guess)| is already within the tolerance), never a stricter or
 * looser test. The guess is state a step carries over: a checkpoint saves
 * it (sb_implicit_fast_save).
 *
 * The step's last residual had the new state's forces: they and the
 * energies wait for sb_solver_settle unless what follows the step reads
 * them (sb_step_needs_forces). */
#include "kernels/integrators/implicit_fast.h"
#include "kernels/integrators/implicit_euler.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"
#include "kernels/forces/fast_hessian.h"
#include "kernels/forces/fast_hessian_bonds.h"
#include "kernels/forces/fast_hessian_corners.h"
#include "kernels/forces/fast_hessian_hinges.h"
#include "kernels/forces/fast_tets.h"
#include "kernels/forces/fast_membranes.h"
#include "kernels/interaction/handle_internal.h"
#include "kernels/runtime/wide.h"
#include "common/sections.h"

#include <float.h>
#include "common/geometry.h"

#include <math.h>
#if defined(__AVX512F__) && !SB_DOUBLE
#include <immintrin.h>
#endif
#include <stdlib.h>
#include <string.h>

#if SB_DOUBLE
#define SB_FAST_ROUNDING 1e-12
#define SB_REAL_EPSILON DBL_EPSILON
#else
#define SB_FAST_ROUNDING 1e-5
#define SB_REAL_EPSILON FLT_EPSILON
#endif

/* Packed work vectors, 4n sb_reals each; V_GUESS: the last step's Δv. */
enum { V_X0, V_V0, V_DV, V_DV_START, V_RHS, V_SOL, V_RES, V_Z, V_D, V_Q, V_MASK, V_GUESS, V_COUNT };

/* Partial sums kept per vertex chunk. */
enum { SB_PARTIALS = 4 };

struct sb_implicit_fast {
    sb_real* vectors; /* V_COUNT × 4n */
    sb_real* blocks;  /* SB_BLOCK_STRIDE n: J's diagonal blocks */
    sb_real* inverse; /* 6n: their inverses' upper triangles, 0 on held vertices */
    double* partials; /* SB_PARTIALS per vertex chunk */
    size_t n4;
    double guess_dt; /* the dt of the step whose Δv V_GUESS holds; 0: no guess */
};

typedef struct sb_fast_newton {
    sb_solver* s;
    struct sb_implicit_fast* im;
    sb_real* v[V_COUNT];
    double dt;
    uint32_t chunks;
    /* the operation's scalars */
    sb_real alpha, beta;
    double position_noise; /* |R|'s rounding from that of the positions (at the last preconditioner) */
} sb_fast_newton;

struct sb_implicit_fast* sb_implicit_fast_create(const sb_solver* s) {
    struct sb_implicit_fast* im = calloc(1, sizeof *im);
    if (!im) return NULL;
    size_t n = s->model->vertex_count, chunks = sb_chunk_count((uint32_t)n);
    im->n4 = 4 * n;
    size_t bytes = ((V_COUNT * im->n4 * sizeof(sb_real)) / 64 + 1) * 64;
    im->vectors = aligned_alloc(64, bytes); /* the kernels' packed loads */
    if (im->vectors) memset(im->vectors, 0, bytes);
    size_t block_bytes = ((SB_BLOCK_STRIDE * n * sizeof(sb_real)) / 64 + 1) * 64;
    im->blocks = aligned_alloc(64, block_bytes); /* the packed scatter's stores */
    if (im->blocks) memset(im->blocks, 0, block_bytes);
    im->inverse = calloc(6 * (n ? n : 1), sizeof(sb_real));
    im->partials = calloc(SB_PARTIALS * (chunks ? chunks : 1), sizeof(double));
    if (im->vectors && im->blocks && im->inverse && im->partials) return im;
    sb_implicit_fast_destroy(im);
    return NULL;
}

void sb_implicit_fast_destroy(struct sb_implicit_fast* im) {
    if (!im) return;
    free(im->vectors), free(im->blocks), free(im->inverse), free(im->partials);
    free(im);
}

/* ---- vector operations over the vertex chunks --------------------------- */

/* One chunk's operation on packed reals [begin, end); partial: its sums. */
typedef void (*sb_chunk_op)(sb_fast_newton* w, size_t begin, size_t end, double* partial);

typedef struct sb_chunk_job {
    sb_fast_newton* w;
    sb_chunk_op op;
} sb_chunk_job;

static void sb_chunks_run(const sb_worker* worker, sb_fast_newton* w, sb_chunk_op op) {
    int64_t first, last;
    sb_worker_range(worker, w->chunks, &first, &last);
    uint32_t n = w->s->model->vertex_count;
    for (int64_t c = first; c < last; c++) {
        size_t begin = (size_t)c * SB_CHUNK, end = begin + SB_CHUNK < n ? begin + SB_CHUNK : n;
        double* partial = w->im->partials + SB_PARTIALS * (size_t)c;
        memset(partial, 0, SB_PARTIALS * sizeof *partial);
        op(w, 4 * begin, 4 * end, partial);
    }
}

static void sb_chunk_worker(void* context, const sb_worker* worker) {
    sb_chunk_job* job = context;
    sb_chunks_run(worker, job->w, job->op);
}

/* Runs op over every chunk on the team (sb_total adds up the sums). */
static void sb_chunks(sb_fast_newton* w, sb_chunk_op op) {
    sb_chunk_job job = {w, op};
    sb_team_run(w->s->team, sb_implicit_width(w->s), sb_chunk_worker, &job);
}

static double sb_total(const sb_fast_newton* w, int k) {
    double sum = 0.0;
    for (uint32_t c = 0; c < w->chunks; c++) sum += w->im->partials[SB_PARTIALS * (size_t)c + k];
    return sum;
}

/* The trial state at Δv: v⁺ = v + Δv, x⁺ = x + dt v⁺. */
static void sb_op_trial(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    (void)partial;
    sb_real *x = w->s->positions4, *v = w->s->velocities4, **a = w->v;
    const sb_real dt = (sb_real)w->dt;
    for (size_t k = begin; k < end; k++) {
        v[k] = a[V_V0][k] + a[V_DV][k];
        x[k] = a[V_X0][k] + dt * v[k];
    }
}

/* Δv = the guess on the free vertices, then the trial state. */
static void sb_op_guess(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    sb_real** a = w->v;
    for (size_t k = begin; k < end; k++)
        if (a[V_MASK][k] != 0) a[V_DV][k] = a[V_GUESS][k];
    sb_op_trial(w, begin, end, partial);
}

/* Δv = Δv_start + α sol, then the trial state. */
static void sb_op_line_point(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    sb_real** a = w->v;
    for (size_t k = begin; k < end; k++) a[V_DV][k] = a[V_DV_START][k] + w->alpha * a[V_SOL][k];
    sb_op_trial(w, begin, end, partial);
}

/* The partial sums' accumulators: SB_LANES of them a sum, lane j adding
 * the packed reals k with k mod SB_LANES = j (chunks start at multiples of
 * SB_LANES), then added in lane order into the chunk's partial. Independent
 * chains the compiler keeps in SIMD registers (one chain a sum was latency
 * bound: half of the CG's vector passes), the same order for any thread
 * count. */
enum { SB_LANES = 16 };

static void sb_lanes_add(const double lanes[SB_LANES], double* partial) {
    double sum = 0.0;
    for (int j = 0; j < SB_LANES; j++) sum += lanes[j];
    *partial += sum;
}

/* lanes += a · b over [begin, end) */
static void sb_lanes_dot(double lanes[SB_LANES], const sb_real* a, const sb_real* b, size_t begin, size_t end) {
    size_t k = begin;
#if defined(__AVX512F__) && !SB_DOUBLE
    /* the same sums as below: each product in double, lane j's own chain */
    __m512d low = _mm512_loadu_pd(lanes), high = _mm512_loadu_pd(lanes + 8);
    for (; k + SB_LANES <= end; k += SB_LANES) {
        __m512 x = _mm512_loadu_ps(a + k), y = _mm512_loadu_ps(b + k);
        low = _mm512_add_pd(
            low, _mm512_mul_pd(_mm512_cvtps_pd(_mm512_castps512_ps256(x)), _mm512_cvtps_pd(_mm512_castps512_ps256(y))));
        high = _mm512_add_pd(
            high, _mm512_mul_pd(_mm512_cvtps_pd(_mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(x), 1))),
                                _mm512_cvtps_pd(_mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(y), 1)))));
    }
    _mm512_storeu_pd(lanes, low);
    _mm512_storeu_pd(lanes + 8, high);
#endif
    for (; k + SB_LANES <= end; k += SB_LANES)
        for (int j = 0; j < SB_LANES; j++) lanes[j] += (double)a[k + j] * b[k + j];
    for (; k < end; k++) lanes[k % SB_LANES] += (double)a[k] * b[k];
}

/* rhs = −R = mask (dt f − M Δv); partials |R|², |M v⁺|², |f|², |M g|². */
static void sb_op_residual(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    const sb_real *m = w->s->fast->mass, *f = w->s->forces4, *v = w->s->velocities4;
    const double* g = w->s->def.gravity;
    sb_real** a = w->v;
    const sb_real dt = (sb_real)w->dt;
    double weight = 0.0;
    for (size_t i = begin / 4; i < end / 4; i++) {
        const sb_real mi = m[i];
        for (int u = 0; u < 4; u++) {
            size_t k = 4 * i + (size_t)u;
            a[V_RHS][k] = a[V_MASK][k] * (dt * f[k] - (u < 3 ? mi : 0) * a[V_DV][k]);
        }
        weight += (double)mi * mi;
    }
    /* |M v⁺|² = Σ m_i² |v_i|², the w lanes 0 */
    double rr[SB_LANES] = {0}, vv[SB_LANES] = {0}, ff[SB_LANES] = {0};
    sb_lanes_dot(rr, a[V_RHS], a[V_RHS], begin, end);
    sb_lanes_dot(ff, f, f, begin, end);
    for (size_t i = begin / 4; i < end / 4; i++)
        for (int u = 0; u < 4; u++) {
            double momentum = (double)m[i] * (u < 3 ? v[4 * i + (size_t)u] : 0);
            vv[(4 * i + (size_t)u) % SB_LANES] += momentum * momentum;
        }
    sb_lanes_add(rr, partial);
    sb_lanes_add(vv, partial + 1);
    sb_lanes_add(ff, partial + 2);
    partial[3] += weight * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
}

/* z = P res over [begin, end); partials res·z, |res|². */
static void sb_op_precondition(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    sb_real** a = w->v;
    const sb_real* inverse = w->im->inverse;
    const sb_real* res = a[V_RES];
    sb_real* z = a[V_Z];
    size_t k = begin;
#if defined(__AVX512F__) && !SB_DOUBLE
    /* four vertices at a time, the scalar loop's sums in its order (no FMA):
     * lane u of a vertex gets b[row u] · r with the row's three entries
     * picked from the vertices' six, r's axes spread over the vertex */
    const __m512i row_x = _mm512_set_epi32(0, 20, 19, 18, 0, 14, 13, 12, 0, 8, 7, 6, 0, 2, 1, 0),
                  row_y = _mm512_set_epi32(0, 22, 21, 19, 0, 16, 15, 13, 0, 10, 9, 7, 0, 4, 3, 1),
                  row_z = _mm512_set_epi32(0, 23, 22, 20, 0, 17, 16, 14, 0, 11, 10, 8, 0, 5, 4, 2),
                  axis_x = _mm512_set_epi32(12, 12, 12, 12, 8, 8, 8, 8, 4, 4, 4, 4, 0, 0, 0, 0),
                  axis_y = _mm512_set_epi32(13, 13, 13, 13, 9, 9, 9, 9, 5, 5, 5, 5, 1, 1, 1, 1),
                  axis_z = _mm512_set_epi32(14, 14, 14, 14, 10, 10, 10, 10, 6, 6, 6, 6, 2, 2, 2, 2);
    const __mmask16 xyz = 0x7777;
    for (; k + 16 <= end; k += 16) {
        const sb_real* b = inverse + 6 * (k / 4);
        __m512 b0 = _mm512_loadu_ps(b), b1 = _mm512_castps256_ps512(_mm256_loadu_ps(b + 16));
        __m512 r = _mm512_loadu_ps(res + k);
        __m512 cx = _mm512_maskz_permutex2var_ps(xyz, b0, row_x, b1),
               cy = _mm512_maskz_permutex2var_ps(xyz, b0, row_y, b1),
               cz = _mm512_maskz_permutex2var_ps(xyz, b0, row_z, b1);
        __m512 rx = _mm512_permutexvar_ps(axis_x, r), ry = _mm512_permutexvar_ps(axis_y, r),
               rz = _mm512_permutexvar_ps(axis_z, r);
        __m512 out = _mm512_add_ps(_mm512_add_ps(_mm512_mul_ps(cx, rx), _mm512_mul_ps(cy, ry)), _mm512_mul_ps(cz, rz));
        _mm512_storeu_ps(z + k, _mm512_maskz_mov_ps(xyz, out)); /* w lanes 0 */
    }
#endif
    for (; k < end; k += 4) {
        const sb_real *b = inverse + 6 * (k / 4), *r = res + k;
        z[k] = b[0] * r[0] + b[1] * r[1] + b[2] * r[2];
        z[k + 1] = b[1] * r[0] + b[3] * r[1] + b[4] * r[2];
        z[k + 2] = b[2] * r[0] + b[4] * r[1] + b[5] * r[2];
        z[k + 3] = 0;
    }
    double rz[SB_LANES] = {0}, rr[SB_LANES] = {0};
    sb_lanes_dot(rz, res, z, begin, end);
    sb_lanes_dot(rr, res, res, begin, end);
    sb_lanes_add(rz, partial);
    sb_lanes_add(rr, partial + 1);
}

/* CG's start: sol = 0, res = rhs, z = P res, d = 0; partials res·z, |res|². */
static void sb_op_cg_start(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    sb_real** a = w->v;
    for (size_t k = begin; k < end; k++) {
        a[V_SOL][k] = 0;
        a[V_RES][k] = a[V_RHS][k];
        a[V_D][k] = 0;
    }
    sb_op_precondition(w, begin, end, partial);
}

/* sol += α d, res −= α q, z = P res; partials res·z, |res|². */
static void sb_op_cg_update(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    sb_real** a = w->v;
    const sb_real alpha = w->alpha;
    sb_real *sol = a[V_SOL], *res = a[V_RES];
    const sb_real *d = a[V_D], *q = a[V_Q];
    for (size_t k = begin; k < end; k++) {
        sol[k] += alpha * d[k];
        res[k] -= alpha * q[k];
    }
    sb_op_precondition(w, begin, end, partial);
}

/* d = z + β d, q = M (1 + dt drag) d: the product's start (the w lanes of
 * z, and so of d, are 0). */
static void sb_op_direction(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    (void)partial;
    sb_real** a = w->v;
    const sb_real* m = w->s->fast->mass;
    const sb_real drag = (sb_real)(1.0 + w->dt * w->s->def.drag), beta = w->beta;
    sb_real* d = a[V_D];
    const sb_real* z = a[V_Z];
    sb_real* q = a[V_Q];
    for (size_t k = begin; k < end; k++) d[k] = z[k] + beta * d[k];
    for (size_t i = begin / 4; i < end / 4; i++) {
        const sb_real mi = drag * m[i];
        for (int u = 0; u < 4; u++) q[4 * i + (size_t)u] = (u < 3 ? mi : 0) * d[4 * i + (size_t)u];
    }
}

/* q masked; partial d·q. */
static void sb_op_curvature(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    sb_real** a = w->v;
    sb_real* q = a[V_Q];
    const sb_real* mask = a[V_MASK];
    for (size_t k = begin; k < end; k++) q[k] *= mask[k];
    double dq[SB_LANES] = {0};
    sb_lanes_dot(dq, a[V_D], q, begin, end);
    sb_lanes_add(dq, partial);
}

/* ---- J's product and its diagonal blocks --------------------------------- */

static const sb_fast_kernel sb_hessian_kernels[5] = {sb_fast_bonds_hessian, sb_fast_corners_hessian,
                                                     sb_fast_hinges_hessian, sb_fast_tets_hessian,
                                                     sb_fast_membranes_hessian};

static sb_hessian_frame sb_jacobian_frame(const sb_fast_newton* w, const sb_real* p, sb_real* out) {
    return (sb_hessian_frame){.base = {w->s->positions4, w->s->carry4, p, out},
                              .scale = (sb_real)(w->dt * w->dt),
                              .damping = (sb_real)(1.0 / w->dt),
                              .blocks = w->im->blocks};
}

/* d = z + β d, q = J d masked; partial d·q. One job. */
static void sb_product_worker(void* context, const sb_worker* worker) {
    sb_fast_newton* w = context;
    sb_chunks_run(worker, w, sb_op_direction);
    sb_worker_barrier(worker);
    sb_hessian_frame frame = sb_jacobian_frame(w, w->v[V_D], w->v[V_Q]);
    sb_fast_element_passes(worker, w->s, sb_hessian_kernels, &frame.base);
    sb_chunks_run(worker, w, sb_op_curvature);
}

static void sb_op_zero_blocks(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    (void)partial;
    memset(w->im->blocks + SB_BLOCK_STRIDE * (begin / 4), 0, SB_BLOCK_STRIDE * ((end - begin) / 4) * sizeof(sb_real));
}

/* Each block J_ii = M_i (1 + dt drag) + dt² K_ii + dt D_ii inverted (the
 * inverse mass where it is singular: possible with an indefinite K), its
 * upper triangle kept (J_ii is symmetric) times the mask: the
 * preconditioner reads 6 numbers a vertex, not 9 and the mask's 4;
 * partial: Σ (|x_i| tr(dt² K_ii + dt D_ii))², for the residual's floor. */
static void sb_op_invert_blocks(sb_fast_newton* w, size_t begin, size_t end, double* partial) {
    static const int upper[SB_BLOCK_SIZE] = {0, 1, 2, 4, 5, 8}, lower[3][2] = {{3, 1}, {6, 2}, {7, 5}};
    const sb_model* m = w->s->model;
    const sb_real* x = w->s->positions4;
    for (size_t i = begin / 4; i < end / 4; i++) {
        const sb_real* block = w->im->blocks + SB_BLOCK_STRIDE * i;
        double j[9], inverse[9] = {0};
        for (int k = 0; k < SB_BLOCK_SIZE; k++) j[upper[k]] = block[sb_block_offset[k]];
        for (int k = 0; k < 3; k++) j[lower[k][0]] = j[lower[k][1]];
        double reach = fmax(fabs(x[4 * i]), fmax(fabs(x[4 * i + 1]), fabs(x[4 * i + 2])));
        double stiffness = reach * fabs(j[0] + j[4] + j[8]) * w->v[V_MASK][4 * i];
        partial[0] += stiffness * stiffness;
        double diagonal = m->mass[i] * (1.0 + w->dt * w->s->def.drag);
        j[0] += diagonal, j[4] += diagonal, j[8] += diagonal;
        if (!sb_m3_invert(j, inverse) && m->inv_mass[i] > 0) inverse[0] = inverse[4] = inverse[8] = m->inv_mass[i];
        for (int k = 0; k < SB_BLOCK_SIZE; k++)
            w->im->inverse[6 * i + k] = (sb_real)(w->v[V_MASK][4 * i] * inverse[upper[k]]);
    }
}

static void sb_preconditioner_worker(void* context, const sb_worker* worker) {
    sb_fast_newton* w = context;
    sb_chunks_run(worker, w, sb_op_zero_blocks);
    sb_worker_barrier(worker);
    sb_hessian_frame frame = sb_jacobian_frame(w, NULL, NULL);
    sb_fast_element_passes(worker, w->s, sb_hessian_kernels, &frame.base);
    sb_chunks_run(worker, w, sb_op_invert_blocks);
}

/* ---- Newton -------------------------------------------------------------- */

/* The residual at the trial state; *norm = |R|, *floor its rounding level. */
static sb_status sb_fast_residual(sb_fast_newton* w, double* norm, double* floor) {
    sb_status status = sb_fast_forces_packed(w->s);
    if (status != SB_OK) return status;
    sb_chunks(w, sb_op_residual);
    *norm = sqrt(sb_total(w, 0));
    double magnitudes = sqrt(sb_total(w, 1)) + w->dt * (sqrt(sb_total(w, 2)) + sqrt(sb_total(w, 3)));
    *floor = fmax(SB_FAST_ROUNDING * magnitudes, w->position_noise) + 1e-300;
    return SB_OK;
}

/* Solves J sol = rhs by block-Jacobi preconditioned CG from sol = 0, to
 * SB_CG_RELATIVE_TOLERANCE or to half the residual Newton stops at
 * (`enough`), whichever is larger: the linear residual is what the full
 * step leaves of R (to second order), so a smaller one cannot show. */
static void sb_fast_cg(sb_fast_newton* w, int cap, double enough, sb_step_stats* stats) {
    sb_team* team = w->s->team;
    int width = sb_implicit_width(w->s);
    sb_chunks(w, sb_op_cg_start);
    double rz = sb_total(w, 0), target = fmax(SB_CG_RELATIVE_TOLERANCE * sqrt(sb_total(w, 1)), 0.5 * enough);
    w->beta = 0;
    for (int it = 0; it < cap; it++) {
        sb_team_run(team, width, sb_product_worker, w);
        double curvature = sb_total(w, 0);
        if (!(curvature > 0.0)) { /* not positive definite here: keep what we have */
            stats->cg_indefinite++;
            if (it == 0) memcpy(w->v[V_SOL], w->v[V_Z], w->im->n4 * sizeof(sb_real));
            break;
        }
        w->alpha = (sb_real)(rz / curvature);
        sb_chunks(w, sb_op_cg_update);
        stats->cg_iterations++;
        double rz_next = sb_total(w, 0);
        if (sqrt(sb_total(w, 1)) <= target) break;
        w->beta = (sb_real)(rz_next / rz);
        rz = rz_next;
    }
}

/* Δv += α sol, α = 1, ½, ¼, … until |R| falls below `norm` (the last trial
 * stays); returns the new |R| and its floor. */
static sb_status sb_fast_line_search(sb_fast_newton* w, double* norm, double* floor) {
    memcpy(w->v[V_DV_START], w->v[V_DV], w->im->n4 * sizeof(sb_real));
    double previous = *norm;
    w->alpha = 1;
    for (int halving = 0; halving <= SB_LINE_SEARCH_HALVINGS; halving++, w->alpha *= (sb_real)0.5) {
        sb_chunks(w, sb_op_line_point);
        sb_status status = sb_fast_residual(w, norm, floor);
        if (status != SB_OK) return status;
        if (*norm < previous) break;
    }
    return SB_OK;
}

/* The last step's Δv as the first guess: kept, with its |R| and floor
 * into `norm` and `floor`, when its |R| is below `norm` (|R(0)|);
 * otherwise Δv, the trial state and R are those at the start again (R
 * kept in V_SOL meanwhile: CG starts by overwriting it). */
static sb_status sb_fast_try_guess(sb_fast_newton* w, double* norm, double* floor) {
    sb_real** a = w->v;
    size_t bytes = w->im->n4 * sizeof(sb_real);
    memcpy(a[V_DV_START], a[V_DV], bytes);
    memcpy(a[V_SOL], a[V_RHS], bytes);
    sb_chunks(w, sb_op_guess);
    double guess_norm, guess_floor;
    sb_status status = sb_fast_residual(w, &guess_norm, &guess_floor);
    if (status != SB_OK) return status;
    if (guess_norm < *norm) {
        *norm = guess_norm, *floor = guess_floor;
        return SB_OK;
    }
    memcpy(a[V_DV], a[V_DV_START], bytes);
    memcpy(a[V_RHS], a[V_SOL], bytes);
    sb_chunks(w, sb_op_trial);
    return SB_OK;
}

/* The step's start: x, v packed, the mask, Δv = 0 except where a hard
 * handle holds a vertex (the Δv that puts it at its target). */
static void sb_fast_newton_init(sb_fast_newton* w) {
    sb_solver* s = w->s;
    const sb_state* st = &s->state;
    const double* inv_mass = sb_inv_mass(s);
    const sb_real* x[3] = {st->x, st->y, st->z};
    const sb_real* v[3] = {st->vx, st->vy, st->vz};
    for (size_t i = 0; i < st->vertex_count; i++)
        for (int a = 0; a < 4; a++) {
            size_t k = 4 * i + (size_t)a;
            w->v[V_X0][k] = a < 3 ? x[a][i] : 0;
            w->v[V_V0][k] = a < 3 ? v[a][i] : 0;
            w->v[V_MASK][k] = a < 3 && inv_mass[i] > 0.0 ? 1 : 0;
            w->v[V_DV][k] = 0;
        }
    if (!s->pinned_inv_mass) return;
    double* target = s->scratch_x;
    for (size_t i = 0; i < st->vertex_count; i++)
        for (int a = 0; a < 3; a++) target[3 * i + a] = (double)x[a][i] + w->dt * v[a][i];
    sb_handles_place_predicted(s, target);
    for (size_t i = 0; i < st->vertex_count; i++)
        for (int a = 0; a < 3; a++)
            if (w->v[V_MASK][4 * i + a] == 0 && !s->model->fixed[i])
                w->v[V_DV][4 * i + a] = (sb_real)((target[3 * i + a] - x[a][i]) / w->dt - v[a][i]);
}

/* The free vertices' new positions and velocities into the state. */
static void sb_fast_newton_store(sb_solver* s) {
    sb_state* st = &s->state;
    sb_real* x[3] = {st->x, st->y, st->z};
    sb_real* v[3] = {st->vx, st->vy, st->vz};
    for (size_t i = 0; i < st->vertex_count; i++) {
        if (s->model->fixed[i]) continue;
        for (int a = 0; a < 3; a++) {
            x[a][i] = s->positions4[4 * i + (size_t)a];
            v[a][i] = s->velocities4[4 * i + (size_t)a];
        }
    }
}

sb_status sb_implicit_fast_step(sb_solver* s, struct sb_implicit_fast* im, double dt) {
    sb_fast_newton w = {.s = s, .im = im, .dt = dt, .chunks = sb_chunk_count(s->model->vertex_count)};
    for (int k = 0; k < V_COUNT; k++) w.v[k] = im->vectors + (size_t)k * im->n4;
    sb_newton_limits limits = sb_newton_limits_of(s);
    sb_fast_newton_init(&w);
    sb_chunks(&w, sb_op_trial);
    double norm, floor;
    sb_status status = sb_fast_residual(&w, &norm, &floor);
    if (status != SB_OK) return status;
    const double first = norm; /* |R(0)|: the relative test's reference, guess or not */
    if (im->guess_dt == dt && isfinite(norm)) {
        status = sb_fast_try_guess(&w, &norm, &floor);
        if (status != SB_OK) return status;
    }
    bool converged = false, by_tolerance = false;
    for (int it = 0; isfinite(norm); it++) { /* a non-finite residual: the state check names the vertex */
        by_tolerance = norm <= limits.tolerance * first;
        if (by_tolerance || norm <= floor) {
            converged = true;
            break;
        }
        if (it == limits.newton_cap) break;
        sb_team_run(s->team, sb_implicit_width(s), sb_preconditioner_worker, &w);
        w.position_noise = SB_REAL_EPSILON / dt * sqrt(sb_total(&w, 0));
        sb_fast_cg(&w, limits.cg_cap, fmax(limits.tolerance * first, floor), &s->stats);
        status = sb_fast_line_search(&w, &norm, &floor);
        if (status != SB_OK) return status;
        s->stats.newton_iterations++;
    }
    if (!converged) s->stats.converged = false;
    /* the next step's guess: this Δv, where the tolerance ended Newton */
    im->guess_dt = by_tolerance ? dt : 0.0;
    if (by_tolerance) memcpy(w.v[V_GUESS], w.v[V_DV], im->n4 * sizeof(sb_real));
    sb_fast_newton_store(s);
    s->has_displacement = false;
    /* the line search's last residual had the forces, but not the energies
     * and the state's arrays: a force pass saved where nothing reads them */
    s->forces_stale = !sb_step_needs_forces(s);
    return s->forces_stale ? sb_check_state(s) : sb_solver_compute_forces(s);
}

/* The checkpoint's part (kernels/solver/solver_state.c): the guess and its dt. */
void sb_implicit_fast_save(const sb_solver* s, sb_sections_writer* w) {
    const struct sb_implicit_fast* im = sb_implicit_fast_of(s);
    sb_sections_put(w, &im->guess_dt, sizeof im->guess_dt);
    sb_sections_put(w, im->vectors + (size_t)V_GUESS * im->n4, im->n4 * sizeof(sb_real));
}

void sb_implicit_fast_load(sb_solver* s, sb_cursor* r) {
    struct sb_implicit_fast* im = sb_implicit_fast_of(s);
    sb_cursor_take(r, &im->guess_dt, sizeof im->guess_dt);
    sb_cursor_take(r, im->vectors + (size_t)V_GUESS * im->n4, im->n4 * sizeof(sb_real));
}
