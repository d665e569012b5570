/* Position-based dynamics: pbd (Müller et al. 2007) and xpbd, its compliant
 * form (Macklin, Müller and Chentanez 2016).
 *
 * A step of dt:
 *   1. predict: v += dt (g + f_ext/m − drag v) on free vertices, x* = x + dt v
 *      (f_ext the external callback's forces of the last evaluation, at the
 *      start of the step, as the symplectic Euler kick uses them);
 *   2. project, `pbd_iterations` times, Gauss-Seidel in a fixed order:
 *      - every bond with k = bond k + spring k > 0 carries a distance
 *        constraint C = |x_i − x_j| − r0: stretch (C > 0) and compress
 *        (C < 0) in one, so a bond resists both;
 *      - every triangle with an angle constant kθ > 0 carries a direction
 *        constraint per corner, C = cos θ − cos θ0 (the angle term's rest
 *        cosine; gradients as in DESIGN.md): the corner angles, hence the
 *        triangle's shape, are kept;
 *      the bonds no such triangle has on an edge first, then the triangles,
 *      each projecting the bonds on its edges (each bond carried by the
 *      first triangle, in model order, that has it: edge c from vertex c to
 *      c + 1, in edge order) and then its three corners: a triangle's
 *      vertices are loaded and stored once for its six constraints in the
 *      SIMD sweeps (kernels/integrators/fast_pbd.c), as the force path's fused bonds;
 *      - with colliders, after those in each sweep, a contact constraint
 *        (x − p)·n >= 0 per free vertex whose move x_prev → x* touches one
 *        (kernels/contact/contact_pbd.c);
 *      the stretch-bend and dihedral (bend) terms are not projected: they
 *      are couplings, not constraints, and only count in the energies;
 *   3. v = (x − x_prev)/dt, then each contact's velocity answer
 *      (restitution, Coulomb friction; kernels/contact/contact_pbd.c); forces and
 *      energies at the new state through sb_solver_compute_forces, as the
 *      other integrators do.
 *
 * Projection of one constraint with compliance α = 1/k (1/kθ for a corner),
 * α̃ = α/dt², W = Σ w_v |∇_v C|² (w = inverse mass, 0 when fixed, so fixed
 * vertices never move) and, for bonds, the spring damping d as the
 * constraint's damping β = d, γ = α̃ β dt = d/(k dt) (Macklin et al., Eq. 26):
 *   Δλ = (−C − α̃ λ − γ ∇C·(x − x_prev)) / ((1 + γ) W + α̃),
 *   x_v += w_v ∇_v C Δλ.
 * xpbd accumulates λ (per constraint, zero at the start of a step): as the
 * iterations grow it converges to the implicit compliant solution, whose
 * static stretch is the physical one (k Δx = F), whatever the count.
 * pbd forgets λ between iterations (λ = 0 in the formula): each iteration
 * moves a lone constraint by the fraction s = W/(W + α̃) = k dt² W/(1 +
 * k dt² W) ∈ [0, 1) of its error — the stiffness in [0, 1] of Müller's PBD,
 * derived per iteration from the bond's constants — so after n iterations
 * (1 − s)^n of the error is left: pbd gets stiffer with more iterations and
 * with longer steps (the dependence xpbd removes), and rigid (s → 1) when
 * k dt² W ≫ 1.
 *
 * Parallel and deterministic: bonds and triangles each get a blocked
 * coloring (kernels/forces/coloring.h, sb_blocked): cut into blocks of
 * consecutive constraints (model order, which follows the mesh and so
 * space), blocks colored so that those of one block color share no
 * vertex, and within a block the constraints colored so that those of one
 * color share no vertex (the SIMD sweeps' lanes). Each iteration runs the
 * bonds' block colors then the triangles' in order, the blocks of one
 * block color in parallel (the overflow block color's on one thread), a
 * block's constraints color by color on one thread (a triangle's bonds and
 * corners one after another in one work item). A vertex is written by one
 * block per block color and read by no other, so the result is bitwise the
 * same for any thread count, and threads wait at one barrier per block
 * color (2 a group on a sheet) instead of one per color of the elements
 * (7 to 9). Small models (under ~1024 constraints a block color per
 * thread) run on fewer threads than asked. The projection works in double
 * on its own copy of the positions. */
#include "kernels/integrators/pbd_internal.h"
#include "kernels/integrators/fast_pbd.h"
#include "kernels/integrators/pbd.h"
#include "kernels/interaction/handle_internal.h"
#include "common/edge_map.h"
#include "common/error.h"
#include "softbond/runtime.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void sb_pbd_group_free(sb_pbd_group* g) {
    sb_blocked_free(&g->runs);
    free(g->lambda);
}

void sb_pbd_destroy(sb_pbd* p) {
    if (!p) return;
    sb_pbd_group_free(&p->bonds);
    sb_pbd_group_free(&p->triangles);
    for (int c = 0; c < 3; c++) free(p->edge_bond[c]);
    free(p->x);
    free(p->x0);
    sb_pbd_contacts_destroy(p->contacts);
    sb_pbd_wide_destroy(p->wide);
    free(p);
}

/* Items per block of the blocked coloring: at least 8 blocks of a group,
 * so that each thread of 2 has some of each block color, and more of at
 * most 4096 items in a large group; blocks of a sheet's rows or more, so
 * that a sweep synchronises threads at few block colors (the 100 × 100
 * sheet: 2, against 7 to 9 colors of its elements). A run's last SIMD
 * block is padded (kernels/integrators/fast_pbd.c): with smaller blocks, 24 on that
 * sheet, the padding was 10 % of the triangles' slots (2 % with 8).
 * Depends on the item count only, never on the thread count: the order of
 * the projections is the same for any. */
#define SB_PBD_MIN_BLOCKS 8
static uint32_t sb_pbd_block_size(uint32_t count) {
    uint32_t size = (count + SB_PBD_MIN_BLOCKS - 1) / SB_PBD_MIN_BLOCKS;
    return size < 512 ? 512 : size > 4096 ? 4096 : size;
}

/* Colors the `count` items whose vertices are ends[a][e] (items[e] their
 * model indices) into g's blocked order. */
static bool sb_pbd_group_build(sb_pbd_group* g, uint32_t vertex_count, uint32_t count, int arity,
                               const uint32_t* const* ends, const uint32_t* items, int lambdas) {
    g->lambda = calloc((size_t)(count ? count : 1) * (size_t)lambdas, sizeof *g->lambda);
    if (!g->lambda || !sb_blocked_build(&g->runs, vertex_count, count, sb_pbd_block_size(count), arity, ends))
        return false;
    for (uint32_t e = 0; e < count; e++) g->runs.order[e] = items[g->runs.order[e]];
    return true;
}

/* Which bonds the triangles carry: a bond of `bonds` (model indices,
 * `count` of them) is carried by edge c of the first triangle (model order)
 * with an angle constant that has its ends, into p->edge_bond; the bonds
 * left over are moved to the front of `bonds`, their count returned. */
static uint32_t sb_pbd_carry_bonds(sb_pbd* p, const sb_model* m, uint32_t* bonds, uint32_t count, bool* ok) {
    size_t nt = m->triangle_count ? m->triangle_count : 1;
    for (int c = 0; c < 3; c++) p->edge_bond[c] = malloc(nt * sizeof *p->edge_bond[c]);
    sb_edge_map map;
    *ok = p->edge_bond[0] && p->edge_bond[1] && p->edge_bond[2] && sb_edge_map_init(&map, count);
    if (!*ok) return 0;
    bool inserted;
    for (uint32_t e = 0; e < count; e++)
        sb_edge_map_upsert(&map, m->bond_i[bonds[e]], m->bond_j[bonds[e]], e, &inserted);
    for (uint32_t t = 0; t < m->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            uint32_t* e = m->angle_k[t] > 0 ? sb_edge_map_find(&map, m->tri_v[c][t], m->tri_v[(c + 1) % 3][t]) : NULL;
            p->edge_bond[c][t] = e && *e != SB_PBD_NO_BOND ? bonds[*e] : SB_PBD_NO_BOND;
            if (e && *e != SB_PBD_NO_BOND) bonds[*e] = SB_PBD_NO_BOND; /* carried by this triangle only */
            if (e) *e = SB_PBD_NO_BOND;
        }
    sb_edge_map_free(&map);
    uint32_t left = 0;
    for (uint32_t e = 0; e < count; e++)
        if (bonds[e] != SB_PBD_NO_BOND) bonds[left++] = bonds[e];
    return left;
}

/* Which edges of model triangle t carry a bond: bit c for edge c. */
static unsigned sb_pbd_carried(const sb_pbd* p, uint32_t t) {
    unsigned mask = 0;
    for (int c = 0; c < 3; c++) mask |= (unsigned)(p->edge_bond[c][t] != SB_PBD_NO_BOND) << c;
    return mask;
}

/* Sorts the triangles of each run by the edges that carry a bond (a
 * stable counting sort), so that the SIMD sweeps' blocks mostly hold
 * triangles that carry bonds on the same edges and project only those.
 * The triangles of a run (unless serial) share no vertex: their order does
 * not change the result. */
static bool sb_pbd_sort_by_carried(sb_pbd* p) {
    sb_blocked* g = &p->triangles.runs;
    uint32_t* sorted = malloc((g->count ? g->count : 1) * sizeof *sorted);
    if (!sorted) return false;
    for (uint32_t r = 0; r < g->run_count; r++) {
        uint32_t cursor[9] = {0}, first = g->run_first[r], end = g->run_first[r + 1];
        if (g->run_serial[r]) continue;
        for (uint32_t e = first; e < end; e++) cursor[sb_pbd_carried(p, g->order[e]) + 1]++;
        cursor[0] = first;
        for (int mask = 1; mask <= 8; mask++) cursor[mask] += cursor[mask - 1];
        for (uint32_t e = first; e < end; e++) sorted[cursor[sb_pbd_carried(p, g->order[e])]++] = g->order[e];
        memcpy(g->order + first, sorted + first, (end - first) * sizeof *sorted);
    }
    free(sorted);
    return true;
}

/* The bonds with a stiffness and a free end (those no triangle carries in
 * the bond group); the triangles with an angle constant. */
static bool sb_pbd_build(sb_pbd* p, const sb_model* m) {
    size_t nb = m->bond_count ? m->bond_count : 1, nt = m->triangle_count ? m->triangle_count : 1;
    uint32_t *bi = malloc(nb * sizeof *bi), *bj = malloc(nb * sizeof *bj), *bid = malloc(nb * sizeof *bid);
    uint32_t *tv[3], *tid = malloc(nt * sizeof *tid);
    for (int c = 0; c < 3; c++) tv[c] = malloc(nt * sizeof *tv[c]);
    bool ok = bi && bj && bid && tid && tv[0] && tv[1] && tv[2];
    uint32_t bonds = 0, triangles = 0;
    for (uint32_t b = 0; ok && b < m->bond_count; b++) {
        bool free_end = m->inv_mass[m->bond_i[b]] > 0 || m->inv_mass[m->bond_j[b]] > 0;
        if (m->bond_k[b] + m->spring_k[b] > 0 && free_end) bid[bonds++] = b;
    }
    if (ok) bonds = sb_pbd_carry_bonds(p, m, bid, bonds, &ok);
    for (uint32_t e = 0; ok && e < bonds; e++) {
        bi[e] = m->bond_i[bid[e]];
        bj[e] = m->bond_j[bid[e]];
    }
    for (uint32_t t = 0; ok && t < m->triangle_count; t++) {
        if (!(m->angle_k[t] > 0)) continue;
        for (int c = 0; c < 3; c++) tv[c][triangles] = m->tri_v[c][t];
        tid[triangles++] = t;
    }
    const uint32_t* bond_ends[2] = {bi, bj};
    const uint32_t* tri_ends[3] = {tv[0], tv[1], tv[2]};
    ok = ok && sb_pbd_group_build(&p->bonds, m->vertex_count, bonds, 2, bond_ends, bid, 1) &&
         sb_pbd_group_build(&p->triangles, m->vertex_count, triangles, 3, tri_ends, tid, 6) &&
         sb_pbd_sort_by_carried(p);
    free(bi), free(bj), free(bid), free(tid);
    for (int c = 0; c < 3; c++) free(tv[c]);
    return ok;
}

/* A sweep has a barrier per block color: with fewer than this many
 * constraints a block color per thread the barriers cost more than the
 * work (with a barrier per element color on the 900-vertex default scene,
 * ~400 constraints a color, a step took about twice as long on 2 threads
 * as on 1: bench/results/notes/xpbd.md). The team never changes the
 * result. */
#define SB_PBD_ITEMS_PER_THREAD 1024

static int sb_pbd_team(const sb_pbd* p, int requested) {
    const sb_blocked *b = &p->bonds.runs, *t = &p->triangles.runs;
    uint32_t colors = sb_blocked_colors(b) + sb_blocked_colors(t);
    uint32_t per_color = colors ? (b->count + t->count) / colors : 0;
    uint32_t blocks_per_color = colors ? (b->block_count + t->block_count) / colors : 0;
    int team = (int)(per_color / SB_PBD_ITEMS_PER_THREAD);
    if (team > (int)blocks_per_color) team = (int)blocks_per_color; /* a block is one thread's */
    return team < 1 ? 1 : team > requested ? requested : team;
}

sb_status sb_pbd_prepare(sb_solver* s) {
    sb_pbd* p = calloc(1, sizeof *p);
    size_t n3 = 3 * (size_t)s->model->vertex_count + 1;
    if (p) {
        p->x = malloc(n3 * sizeof *p->x);
        p->x0 = malloc(n3 * sizeof *p->x0);
    }
    bool built = p && p->x && p->x0 && sb_pbd_build(p, s->model) && sb_pbd_contacts_create(s, &p->contacts);
    if (built) p->threads = sb_pbd_team(p, sb_team_size(s->team)); /* the SIMD sweeps' schedule is for it */
    if (built && sb_pbd_wide_applies(s)) built = (p->wide = sb_pbd_wide_create(p, s->model)) != NULL;
    if (!built) {
        sb_pbd_destroy(p);
        return sb_error_set(&s->error, SB_ERR_NOMEM, "out of memory preparing the position-based solver");
    }
    s->pbd = p;
    return SB_OK;
}

/* The constants of one step's projections. */
typedef struct sb_pbd_step {
    const sb_model* m;
    const double* inv_mass;     /* the model's, 0 where a hard handle holds (kernels/interaction/handle.c) */
    uint32_t* const* edge_bond; /* sb_pbd's */
    double *x, *x0;
    double inv_dt2, dt;
    bool xpbd;
} sb_pbd_step;

/* Δλ for a constraint of value C, compliance alpha (α̃ = alpha/dt²), W, the
 * damping γ and the constraint's rate term ∇C·(x − x_prev); updates λ. */
static double sb_pbd_delta(const sb_pbd_step* k, double C, double alpha, double W, double gamma, double rate,
                           double* lambda) {
    double at = alpha * k->inv_dt2, l = k->xpbd ? *lambda : 0.0;
    double denominator = (1.0 + gamma) * W + at;
    if (!(denominator > 0)) return 0.0;
    double d = (-C - at * l - gamma * rate) / denominator;
    if (k->xpbd) *lambda = l + d;
    return d;
}

/* The distance constraint of bond b on vertices i and j (its own ends, or
 * the ends of the triangle edge that carries it). */
static void sb_pbd_distance(const sb_pbd_step* k, uint32_t b, uint32_t i, uint32_t j, double* lambda) {
    const sb_model* m = k->m;
    double *xi = k->x + 3 * (size_t)i, *xj = k->x + 3 * (size_t)j;
    double n[3] = {xi[0] - xj[0], xi[1] - xj[1], xi[2] - xj[2]};
    double r = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(r > 0)) return; /* coincident ends: no direction; the force pass reports it */
    double stiffness = m->bond_k[b] + m->spring_k[b], wi = k->inv_mass[i], wj = k->inv_mass[j];
    if (!(stiffness > 0)) return; /* broken (kernels/interaction/breakage.c) */
    double rate = 0.0;
    for (int c = 0; c < 3; c++) {
        n[c] /= r;
        rate += n[c] * ((xi[c] - k->x0[3 * (size_t)i + c]) - (xj[c] - k->x0[3 * (size_t)j + c]));
    }
    double gamma = m->spring_damping[b] / (stiffness * k->dt);
    double d = sb_pbd_delta(k, r - m->bond_r0[b], 1.0 / stiffness, wi + wj, gamma, rate, lambda);
    for (int c = 0; c < 3; c++) {
        xi[c] += wi * d * n[c];
        xj[c] -= wj * d * n[c];
    }
}

static void sb_pbd_bond(const sb_pbd_step* k, uint32_t b, double* lambda) {
    sb_pbd_distance(k, b, k->m->bond_i[b], k->m->bond_j[b], lambda);
}

/* Corner at vertex v[0] of the triangle (v[0], v[1], v[2]): C = â·b̂ − cos θ0. */
static void sb_pbd_corner(const sb_pbd_step* k, const uint32_t v[3], double cos0, double kt, double* lambda) {
    double *p0 = k->x + 3 * (size_t)v[0], *p1 = k->x + 3 * (size_t)v[1], *p2 = k->x + 3 * (size_t)v[2];
    double a[3], b[3], A = 0, B = 0;
    for (int c = 0; c < 3; c++) {
        a[c] = p1[c] - p0[c];
        b[c] = p2[c] - p0[c];
        A += a[c] * a[c];
        B += b[c] * b[c];
    }
    A = sqrt(A), B = sqrt(B);
    if (!(A > 0 && B > 0)) return; /* a collapsed edge: the force pass reports it */
    double cosine = 0, g1[3], g2[3], g0[3];
    for (int c = 0; c < 3; c++) cosine += (a[c] / A) * (b[c] / B);
    double w[3] = {k->inv_mass[v[0]], k->inv_mass[v[1]], k->inv_mass[v[2]]}, W = 0;
    for (int c = 0; c < 3; c++) {
        g1[c] = (b[c] / B - cosine * a[c] / A) / A;
        g2[c] = (a[c] / A - cosine * b[c] / B) / B;
        g0[c] = -g1[c] - g2[c];
    }
    const double* grads[3] = {g0, g1, g2};
    for (int q = 0; q < 3; q++)
        W += w[q] * (grads[q][0] * grads[q][0] + grads[q][1] * grads[q][1] + grads[q][2] * grads[q][2]);
    double d = sb_pbd_delta(k, cosine - cos0, 1.0 / kt, W, 0.0, 0.0, lambda);
    double* points[3] = {p0, p1, p2};
    for (int q = 0; q < 3; q++)
        for (int c = 0; c < 3; c++) points[q][c] += w[q] * d * grads[q][c];
}

/* The bonds a triangle carries, on its edges in order, then its three
 * corners: λ holds the corners' three, then the edges'. */
static void sb_pbd_triangle(const sb_pbd_step* k, uint32_t t, double* lambda) {
    const sb_model* m = k->m;
    for (int c = 0; c < 3; c++)
        if (k->edge_bond[c][t] != SB_PBD_NO_BOND)
            sb_pbd_distance(k, k->edge_bond[c][t], m->tri_v[c][t], m->tri_v[(c + 1) % 3][t], lambda + 3 + c);
    if (!(m->angle_k[t] > 0)) return; /* on a broken bond's edge (kernels/interaction/breakage.c) */
    for (int c = 0; c < 3; c++) {
        uint32_t v[3] = {m->tri_v[c][t], m->tri_v[(c + 1) % 3][t], m->tri_v[(c + 2) % 3][t]};
        sb_pbd_corner(k, v, m->tri_cos0[c][t], m->angle_k[t], lambda + c);
    }
}

typedef void (*sb_pbd_project_fn)(const sb_pbd_step*, uint32_t, double*);

/* This worker's blocks [begin, end) of block color k of g: its share, all
 * of the overflow color's (whose blocks may share vertices) on worker 0. */
void sb_pbd_block_share(const sb_worker* w, const sb_blocked* g, int k, uint32_t* begin, uint32_t* end) {
    int64_t first = 0, last = g->color_first_block[k + 1] - g->color_first_block[k];
    if (k != SB_OVERFLOW_COLOR)
        sb_worker_range(w, last, &first, &last);
    else if (w->index != 0)
        first = last;
    *begin = g->color_first_block[k] + (uint32_t)first;
    *end = g->color_first_block[k] + (uint32_t)last;
}

/* All block colors of a group in order, a barrier after each, a block's
 * items in run order; called by every worker of the job. */
static void sb_pbd_group_pass(const sb_worker* w, const sb_pbd_step* k, sb_pbd_group* g, sb_pbd_project_fn project,
                              int lambdas) {
    const sb_blocked* b = &g->runs;
    for (int color = 0; color < SB_MAX_COLORS; color++) {
        if (b->color_first_block[color] == b->color_first_block[color + 1]) continue;
        uint32_t begin, end;
        sb_pbd_block_share(w, b, color, &begin, &end);
        for (uint32_t e = b->run_first[b->block_first_run[begin]]; e < b->run_first[b->block_first_run[end]]; e++)
            project(k, b->order[e], g->lambda + (size_t)lambdas * e);
        sb_worker_barrier(w);
    }
}

/* The projection sweeps of one step, as a job of the team. */
typedef struct sb_pbd_job {
    const sb_solver* solver;
    const sb_pbd_step* step;
    sb_pbd* pbd;
    int iterations;
} sb_pbd_job;

static void sb_pbd_sweeps(void* context, const sb_worker* w) {
    const sb_pbd_job* job = context;
    sb_pbd_contacts* contacts = job->pbd->contacts;
    const sb_pbd_step* k = job->step;
    if (contacts) sb_pbd_contacts_find(job->solver, contacts, w, k->x0, k->x, false);
    for (int it = 0; it < job->iterations; it++) {
        sb_pbd_group_pass(w, k, &job->pbd->bonds, sb_pbd_bond, 1);
        sb_pbd_group_pass(w, k, &job->pbd->triangles, sb_pbd_triangle, 6);
        if (!contacts) continue;
        if (it == job->iterations - 1) sb_pbd_contacts_find(job->solver, contacts, w, k->x0, k->x, true);
        sb_pbd_contacts_project(contacts, w, k->x);
    }
}

/* Predicts x* into p->x (and keeps x in p->x0) from the state. */
static void sb_pbd_predict(sb_solver* s, double dt) {
    sb_state* st = &s->state;
    sb_pbd* p = s->pbd;
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        sb_real* v[3] = {&st->vx[i], &st->vy[i], &st->vz[i]};
        const sb_real* x[3] = {&st->x[i], &st->y[i], &st->z[i]};
        for (int c = 0; c < 3; c++) {
            size_t q = 3 * (size_t)i + c;
            double vc = sb_pbd_predicted_velocity(s, i, c, *v[c], dt);
            p->x0[q] = *x[c];
            p->x[q] = *x[c] + dt * vc;
        }
    }
}

/* v = (x − x_prev)/dt and the new positions into the state. */
static void sb_pbd_finish(sb_solver* s, double dt) {
    sb_state* st = &s->state;
    const sb_pbd* p = s->pbd;
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        sb_real* x[3] = {&st->x[i], &st->y[i], &st->z[i]};
        sb_real* v[3] = {&st->vx[i], &st->vy[i], &st->vz[i]};
        for (int c = 0; c < 3; c++) {
            size_t q = 3 * (size_t)i + c;
            if (s->model->fixed[i]) continue; /* inverse mass 0: never moved */
            *v[c] = (sb_real)((p->x[q] - p->x0[q]) / dt);
            *x[c] = (sb_real)p->x[q];
        }
    }
}

int sb_pbd_iterations(const sb_solver_def* def) { return def->pbd_iterations > 0 ? def->pbd_iterations : 10; }

sb_status sb_integrate_pbd(sb_solver* s, double dt) {
    sb_fast_publish(s); /* the state's arrays current */
    sb_pbd* p = s->pbd;
    if (p->wide) return sb_pbd_wide_step(s, dt);
    sb_pbd_predict(s, dt);
    if (s->pinned_inv_mass) sb_handles_place_predicted(s, p->x);
    sb_pbd_step k = {s->model, sb_inv_mass(s),  p->edge_bond, p->x,
                     p->x0,    1.0 / (dt * dt), dt,           s->def.integrator == SB_INTEGRATOR_XPBD};
    uint32_t bonds = p->bonds.runs.count, triangles = p->triangles.runs.count;
    memset(p->bonds.lambda, 0, (bonds ? bonds : 1) * sizeof(double));
    memset(p->triangles.lambda, 0, 6 * (size_t)(triangles ? triangles : 1) * sizeof(double));
    sb_pbd_job job = {s, &k, p, sb_pbd_iterations(&s->def)};
    sb_team_run(s->team, p->threads, sb_pbd_sweeps, &job);
    sb_pbd_finish(s, dt);
    if (p->contacts) s->stats.contacts += sb_pbd_contacts_answer(s, p->contacts, p->x0, p->x, dt);
    s->has_displacement = false;
    return sb_solver_compute_forces(s);
}
