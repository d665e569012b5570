/* Vertex Block Descent (Chen, Liu, Yang and Yuksel, ACM TOG 2024),
 * integrator `vbd`.
 *
 * A step minimises backward Euler's incremental potential
 *   G(x) = Σ_i m_i/(2 dt²) |x_i − y_i|² + E(x),  y = x⁰ + dt v⁰ + dt² (g + f_ext/m),
 * by block coordinate descent: each vertex in turn takes one Newton step on
 * G with every other vertex held, a 3 × 3 solve
 *   H_i Δx_i = −g_i,  H_i = m_i/dt² I + Σ_e K_e,ii (+ damping),
 *   g_i = m_i/dt² (x_i − y_i) − Σ_e f_e,i(x),
 * with each incident element's exact force and a positive semi-definite
 * diagonal block (sb_element_vertex_share, kernels/forces/hessian.h, in
 * closed form: the vertex's block of implicit Euler's definiteness fix, a
 * compressed bond without its negative sideways stiffness, each triangle
 * corner's Gauss-Newton λ w wᵀ, each hinge's k u_p u_pᵀ). H_i is then
 * positive definite (the inertia m_i/dt² I) and the step a descent
 * direction on G. The exact blocks are not: on the seed-sized sheets at
 * dt = 1 ms the corners' g ∇²c made H_i indefinite or its step climb G
 * once the sheet stretched, and 1 or 2 sweeps ran away within 0.6 s
 * (bench/results/implicit.md). vbd_iterations sweeps run per step;
 * v = (x − x⁰)/dt at the end. Converged, it is backward Euler (the blocks
 * change the path, not the fixed point: g_i = 0).
 *
 * Chebyshev acceleration (vbd_chebyshev_rho > 0, the paper's): after sweep
 * n ≥ 3 every position moves to ω_n (x − x⁽ⁿ⁻²⁾) + x⁽ⁿ⁻²⁾ (fast_vbd.h's
 * weights), each worker on its own vertices, then a barrier. Too few plain
 * sweeps do not just leave the step unconverged: a sweep carries a
 * correction about one neighbour while a stress wave crosses dt √(k/m)
 * edges a step, and the sheet stretches as if softer, storing energy it
 * never had (docs/integrators.md); acceleration carries it further.
 *
 * Over-relaxation (vbd_relaxation = ω, 1 plain): each vertex moves ω
 * times its Newton step, successive over-relaxation; the fixed point is the
 * same. Beside Chebyshev's acceleration a mild ω (1.3) carries a sweep's
 * correction further: the threshold sheets need 4 sweeps on 100 × 100 and
 * 3 on 57 × 57 instead of 6 and 4 (docs/integrators.md).
 *
 * Damping acts through v = (x − x⁰)/dt: a damped spring's force D (v_j − v_i)
 * with D = d u uᵀ adds D/dt to H_i; a co-rotated element's Rayleigh
 * damping −β K v (a tetrahedron's or a membrane's) adds its row of β K/dt;
 * drag, −m c v, adds m c/dt. External
 * forces and soft handles are taken at the start of the step (in y);
 * vertices a hard handle holds sit at their targets and are not moved.
 *
 * Parallel and deterministic: the vertices are colored so that no two of a
 * color share an element (greedy, in vertex order); the vertices of one
 * color depend only on other colors, so they are updated at once, split
 * over the team, with a barrier between colors. Each update reads and
 * writes the same values whatever the split: the state is bitwise the same
 * for any thread count. The greedy colors are refined by a partition fixed
 * by the model, never by the team: two parts (vertex indices below and
 * above n/2), each part's interface (its vertices that share an element
 * with the other part) and the rest of part 0 cut at n/4, swept as part
 * 0's far band, part 1's interface, part 1's rest, part 0's interface,
 * part 0's near band, each band by color (sb_vbd_refine). It is another
 * Gauss-Seidel order of the same vertex steps (on the 100 × 100 sheet the
 * 7 colors become 34, and 4 sweeps leave the same part of the step
 * undone: bench/results/vbd_sweeps.md); the fast sweeps run each part on
 * its own worker of a team of 2, the interfaces the only meeting points,
 * each met about half a part's sweep after the other worker passed it
 * (fast_vbd.c). Tearing: a vertex split off keeps its origin's
 * color (it shares elements only with vertices its origin shared them
 * with), and the elements at each vertex and the color lists are rebuilt in
 * place when the vertex count changed.
 *
 * With the reference kernels the sweeps run here, in double on the model's
 * arrays. With the fast kernels they run in kernels/integrators/fast_vbd.c: the same
 * shares in sb_real, SIMD over the vertices of a color, on a layout built
 * at creation; a model that may break or tear keeps this file's sweeps
 * (its constants and elements change under the layout), and so does one
 * with co-rotated tetrahedra (no fast share for them yet). The first guess,
 * y and the final velocities are this file's either way; the new state's
 * forces and energies come from the chosen kernels. */
#include "kernels/state/solver_data.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"
#include "kernels/integrators/vbd.h"
#include "kernels/interaction/breakage.h"
#include "kernels/interaction/handle_internal.h"
#include "kernels/forces/vertex_elements.h"
#include "kernels/forces/hessian_edges.h"
#include "kernels/forces/hessian_tets.h"
#include "kernels/forces/hessian_membranes.h"
#include "kernels/integrators/fast_vbd.h"
#include "common/sections.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct sb_vbd {
    sb_vertex_elements* elements;
    uint32_t *color, *color_start, *order; /* per vertex; colors + 1; vertices by color */
    uint32_t color_count;                  /* the sweep's colors (sb_vbd_refine) */
    uint8_t* color_part;                   /* per color: the part of the partition it lies in */
    uint32_t built_vertices;               /* live_vertices when the lists were built */
    double *x, *x0, *y;                    /* 3n each */
    double *last, *before;                 /* 3n each, with Chebyshev: the iterates one and two sweeps back */
    double* previous_v;                    /* 3n: the velocities at the start of the last step */
    bool has_previous;
    sb_fast_vbd* fast; /* the fast sweep (kernels/integrators/fast_vbd.c); NULL: the reference's */
};

typedef struct sb_vbd_job {
    sb_solver* s;
    struct sb_vbd* vbd;
    double dt;
    int iterations;
    double rho;           /* Chebyshev's; 0: off */
    double relaxation;    /* ω of each vertex's step; 1: plain */
    atomic_int collapsed; /* the fast sweep met a collapsed element */
    atomic_int unsound;   /* a worker's range of the new state is not finite or ran away (fast sweeps) */
} sb_vbd_job;

int sb_vbd_iterations(const sb_solver_def* def) { return def->vbd_iterations > 0 ? def->vbd_iterations : 10; }

/* Greedy coloring in vertex order: the smallest color no earlier neighbour
 * (a vertex sharing an element) has; `used` marks colors per vertex. */
static void sb_vbd_color(struct sb_vbd* v, const sb_model* m, uint32_t* used) {
    const sb_vertex_elements* at = v->elements;
    v->color_count = 0;
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        for (uint32_t k = at->start[i]; k < at->start[i + 1]; k++) {
            sb_element e = sb_element_at(m, sb_entry_element(at->entry[k]));
            for (int b = 0; b < e.count; b++)
                if (e.vertex[b] < i) used[v->color[e.vertex[b]]] = i + 1;
        }
        uint32_t c = 0;
        while (used[c] == i + 1) c++;
        v->color[i] = c;
        if (c + 1 > v->color_count) v->color_count = c + 1;
    }
}

/* The sweep's bands, in the order a sweep visits them: part 0 is the
 * vertices [0, n/2), part 1 the rest; a part's interface is its vertices
 * that share an element with the other part. Part 0's far vertices (below
 * n/4) come first, then part 1's interface, part 1's rest, part 0's
 * interface, part 0's near vertices (the design note says why). */
enum { SB_VBD_FAR0, SB_VBD_INTERFACE1, SB_VBD_REST1, SB_VBD_INTERFACE0, SB_VBD_NEAR0, SB_VBD_BANDS };

static int sb_vbd_band(const sb_model* m, const sb_vertex_elements* at, uint32_t i) {
    uint32_t half = m->vertex_count / 2;
    bool part1 = i >= half, interface = false;
    for (uint32_t k = at->start[i]; k < at->start[i + 1] && !interface; k++) {
        sb_element e = sb_element_at(m, sb_entry_element(at->entry[k]));
        for (int b = 0; b < e.count; b++) interface |= (e.vertex[b] >= half) != part1;
    }
    if (part1) return interface ? SB_VBD_INTERFACE1 : SB_VBD_REST1;
    return interface ? SB_VBD_INTERFACE0 : i < m->vertex_count / 4 ? SB_VBD_FAR0 : SB_VBD_NEAR0;
}

/* The sweep's colors: each greedy color split by band, ordered by band,
 * then color; the empty ones dropped. Still a coloring (no two vertices of
 * one share an element), numbered in the sweep's order, with each color's
 * part in color_part; `slot` has SB_VBD_BANDS × color_count entries. */
static void sb_vbd_refine(struct sb_vbd* v, const sb_model* m, uint32_t* slot) {
    uint32_t colors = v->color_count, slots = SB_VBD_BANDS * colors;
    for (uint32_t q = 0; q < slots; q++) slot[q] = UINT32_MAX;
    for (uint32_t i = 0; i < m->vertex_count; i++)
        v->color[i] += (uint32_t)sb_vbd_band(m, v->elements, i) * colors, slot[v->color[i]] = 0;
    v->color_count = 0;
    for (uint32_t q = 0; q < slots; q++)
        if (slot[q] == 0) {
            int band = (int)(q / colors);
            v->color_part[v->color_count] = band == SB_VBD_INTERFACE1 || band == SB_VBD_REST1;
            slot[q] = v->color_count++;
        }
    for (uint32_t i = 0; i < m->vertex_count; i++) v->color[i] = slot[v->color[i]];
}

/* The vertices that move (not fixed, not dormant), by color, in vertex order
 * within a color: a counting sort. */
static void sb_vbd_order(struct sb_vbd* v, const sb_model* m) {
    memset(v->color_start, 0, ((size_t)v->color_count + 1) * sizeof *v->color_start);
    for (uint32_t i = 0; i < m->vertex_count; i++)
        if (!m->fixed[i]) v->color_start[v->color[i] + 1]++;
    for (uint32_t c = 0; c < v->color_count; c++) v->color_start[c + 1] += v->color_start[c];
    for (uint32_t i = 0; i < m->vertex_count; i++)
        if (!m->fixed[i]) v->order[v->color_start[v->color[i]]++] = i;
    for (uint32_t c = v->color_count; c > 0; c--) v->color_start[c] = v->color_start[c - 1];
    v->color_start[0] = 0;
}

void sb_vbd_destroy(struct sb_vbd* v) {
    if (!v) return;
    sb_vertex_elements_destroy(v->elements);
    sb_fast_vbd_destroy(v->fast);
    free(v->color), free(v->color_start), free(v->order), free(v->x), free(v->x0), free(v->y), free(v->previous_v);
    free(v->last), free(v->before), free(v->color_part);
    free(v);
}

bool sb_vbd_prepare(sb_solver* s) {
    const sb_model* m = s->model;
    size_t n = m->vertex_count, n3 = 3 * n + 1;
    struct sb_vbd* v = calloc(1, sizeof *v);
    s->vbd = v;
    if (!v) return false;
    v->elements = sb_vertex_elements_create(m);
    v->color = calloc(n + 1, sizeof *v->color);
    v->order = malloc((n + 1) * sizeof *v->order);
    v->x = malloc(n3 * sizeof *v->x), v->x0 = malloc(n3 * sizeof *v->x0), v->y = malloc(n3 * sizeof *v->y);
    v->previous_v = malloc(n3 * sizeof *v->previous_v);
    bool chebyshev = s->def.vbd_chebyshev_rho > 0.0;
    if (chebyshev) v->last = malloc(n3 * sizeof *v->last), v->before = malloc(n3 * sizeof *v->before);
    /* a vertex has fewer neighbours than 4 per element entry: so many colors at most */
    size_t widest = 1;
    for (size_t i = 0; v->elements && i < n; i++)
        if (4 * (size_t)(v->elements->start[i + 1] - v->elements->start[i]) + 1 > widest)
            widest = 4 * (size_t)(v->elements->start[i + 1] - v->elements->start[i]) + 1;
    /* the greedy colors, then their refinement by band: SB_VBD_BANDS slots per color at most */
    uint32_t* used = calloc(SB_VBD_BANDS * widest + 1, sizeof *used);
    v->color_part = malloc(SB_VBD_BANDS * widest + 1);
    bool ok = v->elements && v->color && v->order && v->x && v->x0 && v->y && v->previous_v && used && v->color_part &&
              (!chebyshev || (v->last && v->before));
    if (ok) sb_vbd_color(v, m, used), sb_vbd_refine(v, m, used);
    free(used);
    ok = ok && (v->color_start = malloc(((size_t)v->color_count + 1) * sizeof *v->color_start)) != NULL;
    if (ok) sb_vbd_order(v, m);
    v->built_vertices = s->live_vertices;
    /* a model that may break or tear changes under the sweep: the reference's, which reads it live; and
     * the fast sweep has no share for the co-rotated tetrahedra or the membranes */
    if (ok && s->fast && !s->breakage && !m->tet_count && !m->membrane_count) {
        int width = sb_runtime_threads(s->def.runtime.threads, NULL); /* the team's size (made after this) */
        ok = (v->fast = sb_fast_vbd_create(m, v->elements, v->color_start, v->color_count, v->color_part, v->order,
                                           chebyshev, width)) != NULL;
    }
    return ok;
}

/* After tearing split vertices: the new ones take their origin's color. */
static void sb_vbd_follow_topology(sb_solver* s, struct sb_vbd* v) {
    uint32_t count = s->live_vertices;
    if (count == v->built_vertices) return;
    const sb_topology* topology = sb_breakage_topology(s->breakage);
    for (uint32_t i = v->built_vertices; i < count; i++) v->color[i] = v->color[sb_topology_origin(topology, i)];
    sb_vertex_elements_rebuild(v->elements, s->model);
    sb_vbd_order(v, s->model);
    v->built_vertices = count;
}

/* Solves the symmetric 3 × 3 system h d = r by Cholesky; false when h is
 * not positive definite. */
static bool sb_solve3(const double* h, const double* r, double* d) {
    double l00 = h[0];
    if (!(l00 > 0.0)) return false;
    l00 = sqrt(l00);
    double l10 = h[3] / l00, l20 = h[6] / l00;
    double l11 = h[4] - l10 * l10;
    if (!(l11 > 0.0)) return false;
    l11 = sqrt(l11);
    double l21 = (h[7] - l20 * l10) / l11;
    double l22 = h[8] - l20 * l20 - l21 * l21;
    if (!(l22 > 0.0)) return false;
    l22 = sqrt(l22);
    double z0 = r[0] / l00, z1 = (r[1] - l10 * z0) / l11, z2 = (r[2] - l20 * z0 - l21 * z1) / l22;
    d[2] = z2 / l22;
    d[1] = (z1 - l21 * d[2]) / l11;
    d[0] = (z0 - l10 * d[1] - l20 * d[2]) / l00;
    return true;
}

/* A damped spring on vertex `place` of bond b: D (v_other − v_self) with
 * v = (x − x⁰)/dt, and D/dt on the diagonal. */
static void sb_vbd_damping(const sb_model* m, uint32_t b, int place, const double* x, const double* x0, double dt,
                           double* f, double* h) {
    double d[9];
    if (!sb_bond_damping_block(m, b, x, d)) return;
    uint32_t self = place == 0 ? m->bond_i[b] : m->bond_j[b], other = place == 0 ? m->bond_j[b] : m->bond_i[b];
    double relative[3];
    for (int c = 0; c < 3; c++)
        relative[c] = ((x[3 * other + c] - x0[3 * other + c]) - (x[3 * self + c] - x0[3 * self + c])) / dt;
    for (int r = 0; r < 3; r++) {
        f[r] += d[3 * r] * relative[0] + d[3 * r + 1] * relative[1] + d[3 * r + 2] * relative[2];
        for (int c = 0; c < 3; c++) h[3 * r + c] += d[3 * r + c] / dt;
    }
}

/* An element's Rayleigh damping −β K v on its vertex `place`, v = (x − x⁰)/dt
 * (K its co-rotated stiffness at x: a tetrahedron's R K0 Rᵀ, 4 or 10
 * nodes, or a membrane's), and β K_pp / dt on the diagonal. */
static void sb_vbd_rayleigh(const sb_model* m, const sb_element* e, int place, const double* x, const double* x0,
                            double dt, double* f, double* h) {
    bool tet = e->kind == SB_ELEMENT_TET;
    double beta = tet ? m->tet_beta[e->index] : m->membrane_beta[e->index], k[SB_ELEMENT_MATRIX],
           velocity[3 * SB_ELEMENT_MAX];
    if (beta == 0.0) return;
    int size = 3 * e->count;
    sb_vec3 local[SB_ELEMENT_MAX];
    for (int c = 0; c < e->count; c++) {
        const double *now = x + 3 * (size_t)e->vertex[c], *before = x0 + 3 * (size_t)e->vertex[c];
        local[c] = sb_v3(now);
        for (int a = 0; a < 3; a++) velocity[3 * c + a] = (now[a] - before[a]) / dt;
    }
    if (!(tet ? sb_tet_stiffness(m, e->index, local, NULL, k)
              : sb_membrane_element_stiffness(m, e->index, local, NULL, k)))
        return;
    for (int r = 0; r < 3; r++) {
        const double* row = k + (3 * place + r) * size;
        double sum = 0.0;
        for (int c = 0; c < size; c++) sum += row[c] * velocity[c];
        f[r] -= beta * sum;
        for (int c = 0; c < 3; c++) h[3 * r + c] += beta * row[3 * place + c] / dt;
    }
}

/* One vertex's Newton step on the incremental potential. */
static void sb_vbd_vertex(const sb_vbd_job* job, uint32_t i) {
    const sb_solver* s = job->s;
    const sb_model* m = s->model;
    const struct sb_vbd* v = job->vbd;
    double dt = job->dt, *x = v->x;
    double inertia = m->mass[i] / (dt * dt), drag = m->mass[i] * s->def.drag / dt;
    double f[3] = {0, 0, 0}, h[9] = {0};
    for (int c = 0; c < 3; c++) {
        f[c] = -inertia * (x[3 * i + c] - v->y[3 * i + c]) - drag * (x[3 * i + c] - v->x0[3 * i + c]);
        h[4 * c] = inertia + drag;
    }
    for (uint32_t k = v->elements->start[i]; k < v->elements->start[i + 1]; k++) {
        uint32_t id = sb_entry_element(v->elements->entry[k]);
        sb_element e = sb_element_at(m, id);
        /* a collapsed element adds nothing: the step's force check reports it */
        sb_element_vertex_share(m, &e, x, sb_entry_place(v->elements->entry[k]), f, h);
        if (e.kind == SB_ELEMENT_BOND)
            sb_vbd_damping(m, e.index, sb_entry_place(v->elements->entry[k]), x, v->x0, dt, f, h);
        else if ((e.kind == SB_ELEMENT_TET && m->tet_damped) || (e.kind == SB_ELEMENT_MEMBRANE && m->membrane_damped))
            sb_vbd_rayleigh(m, &e, sb_entry_place(v->elements->entry[k]), x, v->x0, dt, f, h);
    }
    double step[3];
    if (!sb_solve3(h, f, step)) return; /* not finite (a collapsed element): this vertex waits */
    for (int c = 0; c < 3; c++) x[3 * i + c] += job->relaxation * step[c];
}

/* Chebyshev's step after sweep `sweep` on the worker's vertices [begin,
 * end) (fast_vbd.h's weight); returns the weight for the next. */
static double sb_vbd_accelerate(const sb_vbd_job* job, int sweep, double weight, int64_t begin, int64_t end) {
    const struct sb_vbd* v = job->vbd;
    weight = sb_vbd_chebyshev_weight(job->rho, sweep, weight);
    for (size_t q = 3 * (size_t)begin; q < 3 * (size_t)end; q++) {
        if (sweep >= SB_VBD_CHEBYSHEV_FIRST) v->x[q] = weight * (v->x[q] - v->before[q]) + v->before[q];
        v->before[q] = v->last[q];
        v->last[q] = v->x[q];
    }
    return weight;
}

static void sb_vbd_sweeps(sb_vbd_job* job, const sb_worker* w) {
    const struct sb_vbd* v = job->vbd;
    const double* inv_mass = sb_inv_mass(job->s);
    int64_t first, past, begin, end;
    sb_worker_range(w, job->s->state.vertex_count, &first, &past);
    if (job->rho > 0.0) memcpy(v->last + 3 * first, v->x + 3 * first, 3 * (size_t)(past - first) * sizeof *v->x);
    double weight = 1.0;
    for (int it = 0; it < job->iterations; it++) {
        for (uint32_t c = 0; c < v->color_count; c++) {
            int64_t count = v->color_start[c + 1] - v->color_start[c];
            sb_worker_range(w, count, &begin, &end);
            for (int64_t k = begin; k < end; k++) {
                uint32_t i = v->order[v->color_start[c] + k];
                if (inv_mass[i] > 0.0) sb_vbd_vertex(job, i);
            }
            sb_worker_barrier(w);
        }
        if (job->rho > 0.0) {
            weight = sb_vbd_accelerate(job, it + 1, weight, first, past);
            sb_worker_barrier(w);
        }
    }
}

static void sb_vbd_fast_sweeps(sb_vbd_job* job, const sb_worker* w) {
    struct sb_vbd* v = job->vbd;
    sb_fast_vbd_step step = {v->x,
                             v->x0,
                             v->y,
                             sb_inv_mass(job->s),
                             job->dt,
                             job->s->def.drag,
                             job->iterations,
                             job->rho,
                             job->relaxation,
                             job->s->positions4,
                             &job->collapsed};
    sb_fast_vbd_run(v->fast, &step, w);
}

/* The first guess (the paper's adaptive initialisation): x⁰ + dt v⁰ +
 * dt² ã ĝ, where ã is the vertex's last acceleration along gravity, clamped
 * to [0, |g|]. Guessing y itself moves a hanging sheet's every vertex down
 * by dt² g each step, and the few sweeps cannot carry the support back
 * across a large sheet: it stretches more each step. */
static double sb_vbd_guess_acceleration(const struct sb_vbd* v, const double* along_g, double length,
                                        const double* velocity, size_t i) {
    if (!v->has_previous || length == 0.0) return 0.0;
    double along = 0.0;
    for (int c = 0; c < 3; c++) along += (velocity[c] - v->previous_v[3 * i + c]) * along_g[c];
    along = along > 0.0 ? along : 0.0; /* NaN: 0, as fmax */
    return along < length ? along : length;
}

/* x⁰, the inertial target y and the first guess of vertices [begin, end);
 * v⁰ is kept for the next step's guess. The divisions by dt and |g| are
 * taken once, not per vertex (per vertex they were a few % of a step:
 * bench/results/notes/vbd.md). */
static void sb_vbd_predict(const sb_solver* s, struct sb_vbd* v, double dt, int64_t begin, int64_t end) {
    const sb_model* m = s->model;
    const sb_state* st = &s->state;
    const double* g = s->def.gravity;
    double length = sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    /* ĝ/dt: a velocity change times it is the acceleration along g; dt² ĝ scales the guess */
    double along_g[3], guess_g[3];
    for (int c = 0; c < 3; c++) {
        along_g[c] = length > 0 ? g[c] / (length * dt) : 0.0;
        guess_g[c] = length > 0 ? dt * dt * g[c] / length : 0.0;
    }
    const sb_real *position[3] = {st->x, st->y, st->z}, *velocity[3] = {st->vx, st->vy, st->vz};
    for (int64_t i = begin; i < end; i++) {
        const double now[3] = {velocity[0][i], velocity[1][i], velocity[2][i]};
        double guess = m->fixed[i] ? 0.0 : sb_vbd_guess_acceleration(v, along_g, length, now, (size_t)i);
        for (int c = 0; c < 3; c++) {
            size_t q = 3 * (size_t)i + c;
            v->x0[q] = position[c][i];
            v->previous_v[q] = velocity[c][i];
            if (m->fixed[i]) {
                v->x[q] = v->y[q] = v->x0[q];
                continue;
            }
            double acceleration = g[c] + (s->external ? s->external[q] * m->inv_mass[i] : 0.0);
            v->y[q] = v->x0[q] + dt * velocity[c][i] + dt * dt * acceleration;
            v->x[q] = v->x0[q] + dt * velocity[c][i] + guess * guess_g[c];
        }
    }
}

/* v = (x − x⁰)/dt (into y, no longer needed) and the new state of vertices
 * [begin, end). */
static void sb_vbd_finish(sb_solver* s, struct sb_vbd* v, double dt, int64_t begin, int64_t end) {
    for (size_t q = 3 * (size_t)begin; q < 3 * (size_t)end; q++) v->y[q] = (v->x[q] - v->x0[q]) / dt;
    sb_store_free_range(s, v->x, v->y, (uint32_t)begin, (uint32_t)end);
}

/* Whether the state of vertices [begin, end) passes sb_check_state's test
 * (sb_vertex_fault): the fast step checks each worker's range on the team,
 * and only a failure runs sb_check_state, which names the vertex. */
static bool sb_vbd_range_sound(const sb_solver* s, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; i++)
        if (sb_vertex_fault(s, (uint32_t)i)) return false;
    return true;
}

/* A step on the team: the prediction (then the held vertices at their
 * targets, on worker 0), the sweeps, the new state; each worker predicts
 * and finishes its own range of vertices. The fast sweeps pack and unpack
 * the same ranges (sb_fast_vbd_run): without held vertices no barrier is
 * needed between a worker's prediction and its packing, nor between its
 * unpacking and its finish, and it checks its range of the new state. */
static void sb_vbd_step(void* context, const sb_worker* w) {
    sb_vbd_job* job = context;
    sb_solver* s = job->s;
    bool fast = job->vbd->fast != NULL;
    int64_t begin, end;
    sb_worker_range(w, s->state.vertex_count, &begin, &end);
    sb_vbd_predict(s, job->vbd, job->dt, begin, end);
    if (!fast || s->pinned_inv_mass) sb_worker_barrier(w);
    if (s->pinned_inv_mass) {
        if (w->index == 0) sb_handles_place_predicted(s, job->vbd->x);
        sb_worker_barrier(w);
    }
    if (fast) {
        sb_vbd_fast_sweeps(job, w);
    } else {
        sb_vbd_sweeps(job, w);
        sb_worker_barrier(w);
    }
    sb_vbd_finish(s, job->vbd, job->dt, begin, end);
    if (fast && !sb_vbd_range_sound(s, begin, end)) sb_worker_raise(&job->unsound);
}

sb_status sb_integrate_vbd(sb_solver* s, double dt) {
    sb_fast_publish(s); /* the state's arrays current */
    struct sb_vbd* v = s->vbd;
    sb_vbd_follow_topology(s, v);
    double relaxation = s->def.vbd_relaxation > 0.0 ? s->def.vbd_relaxation : 1.0;
    sb_vbd_job job = {s, v, dt, sb_vbd_iterations(&s->def), s->def.vbd_chebyshev_rho, relaxation, 0, 0};
    sb_team_run_adaptive(s->team, sb_team_size(s->team), sb_vbd_step, &job);
    v->has_previous = true;
    s->has_displacement = false;
    /* The fast sweep leaves the forces and energies to sb_solver_settle when
     * nothing needs them now (as pbd does): a force pass costs half a sweep.
     * A collapse it met is reported by evaluating them. */
    s->forces_stale = v->fast && !atomic_load(&job.collapsed) && !sb_step_needs_forces(s);
    /* the fast step checked the state on the team: only a failure is looked at again, to name the vertex */
    if (s->forces_stale) return atomic_load(&job.unsound) ? sb_check_state(s) : SB_OK;
    return sb_solver_compute_forces(s);
}

uint32_t sb_vbd_schedule_faults(const sb_solver* s, uint32_t* needs) {
    *needs = 0;
    return s->vbd && s->vbd->fast ? sb_fast_vbd_schedule_faults(s->vbd->fast, s->model, needs) : UINT32_MAX;
}

/* The checkpoint's part (kernels/solver/solver_state.c): the velocities the next
 * first guess compares with, and whether there are any yet. */
static size_t sb_vbd_state_bytes(const sb_solver* s) { return 3 * (size_t)s->model->vertex_count * sizeof(double) + 1; }

void sb_vbd_save(const sb_solver* s, sb_sections_writer* w) {
    uint8_t has = s->vbd->has_previous;
    sb_sections_put(w, &has, 1);
    sb_sections_put(w, s->vbd->previous_v, sb_vbd_state_bytes(s) - 1);
}

void sb_vbd_load(sb_solver* s, sb_cursor* r) {
    uint8_t has;
    sb_cursor_take(r, &has, 1);
    sb_cursor_take(r, s->vbd->previous_v, sb_vbd_state_bytes(s) - 1);
    s->vbd->has_previous = has;
}
