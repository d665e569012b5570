/* vbd's fast sweep: the per-vertex Newton steps of kernels/integrators/vbd.c (its
 * scalar reference, whose design note holds the method) in sb_real, SIMD
 * with kernels/runtime/wide.h, the lanes being vertices of one color.
 *
 * Layout, built once: the vertices of each color (vbd's order) are cut into
 * blocks of SB_WIDTH lanes. A block holds, per term family, slots of
 * SB_WIDTH entries: slot s of lane l is the lane vertex's s-th element of
 * that family, with everything the vertex's share needs gathered beside it,
 * so that every lane runs the same code:
 *   bond: the other vertex, r0, k = k_bond + k_spring and the damping;
 *   triangle: rotated so that the vertex p comes first, (p, q, r) in the
 *     triangle's own cyclic order, with the rest cosines at p, q, r and the
 *     rest lengths of pq, qr, rp: p is then the apex of corner p, the far
 *     end of corner q's second edge and of corner r's first, whatever its
 *     place in the triangle; and the corners' Gauss-Newton form (λ, p, q:
 *     two square roots and two divisions, once at creation, not per vertex
 *     and sweep);
 *   hinge: relabelled so that p is e0 or o0 (swapping e0 ↔ e1 with o0 ↔ o1
 *     leaves φ unchanged) with a flag for which; its other three vertices
 *     are gathered, p's position is the lane's own (a quarter fewer
 *     gathers, the sweep's main cost with the hinge's arithmetic); its rest
 *     angle as cos φ0, sin φ0, so that φ − φ0 is the atan2 of (cos φ, sin
 *     φ) turned back by φ0, already in (−π, π] (no wrap).
 * Lengths come from sb_w_rsqrt of their squares (1/r and r = r² · 1/r,
 * no square root and division), the hinge's 1/|n|² from sb_w_recip, the
 * 3 × 3 solve's pivots from sb_w_rsqrt: in float these are estimates with
 * a Newton step, within 2 units of the last place (tests/test_wide.c). On
 * the 100 × 100 sheet (1 thread) the hinges take about half of a sweep,
 * the triangles a quarter, the bonds an eighth.
 * A lane with fewer elements than the block's slots is padded with inert
 * entries (every vertex the lane's own, so each counts as collapsed and
 * adds nothing). Elements whose constants are all zero are left out, as
 * they add nothing. One gather per neighbour position instead of a walk
 * through the model's element arrays; measured against the scalar double
 * reference sweep in bench/results/implicit.md.
 *
 * The shares are vbd.c's closed forms, exact forces with positive
 * semi-definite blocks: the bond's block with its sideways stiffness
 * clamped at 0 and the damping's d/dt u uᵀ, each triangle corner's
 * Gauss-Newton λ w wᵀ (kernels/forces/hessian_corners.c's definite stand-in, w the
 * vertex's part), the hinge's Gauss-Newton block k u uᵀ. A
 * collapsed element adds nothing (a collapsed triangle nothing at all,
 * where the reference keeps the corners it met before the collapse) and is
 * flagged: vbd.c then evaluates the forces, which report it.
 *
 * A step packs x, x⁰ and y as x y z w per vertex (w: whether the vertex
 * moves, and its mass), sweeps, and unpacks the vertices that moved (and
 * every vertex into the fast path's packed positions, which the stretch
 * check reads when the forces wait for sb_solver_settle); each worker packs
 * and unpacks its own range. Every update reads and writes the
 * same values whatever the split over the team: the state is bitwise the
 * same for any thread count.
 *
 * Schedule. The sweeps have no barrier per color: a block waits only for
 * the blocks whose vertices its elements read (its needs, found at
 * creation; the relation is symmetric), each to have finished the sweep it
 * must follow: a block of an earlier color this sweep, of a later color
 * the sweep before (kernels/integrators/fast_pbd.c's scheme, its units
 * being these blocks). Each pair of blocks that share an element is then
 * ordered as in the colors' Gauss-Seidel order, and the rest run in any
 * order. A block's finished sweeps are a counter on its own cache line.
 * The colors are vbd.c's, refined by its two-part partition and ordered so
 * that part 1's interface comes first in part 1's sweep and part 0's in the
 * middle of part 0's. In a team of 2 (SB_VBD_PARTS) each worker runs its
 * part's colors whole, so only the interface blocks wait across, and each
 * finds what it waits for done about half a part's sweep earlier: a worker
 * waits only when the other fell that far behind (taken off its core). In
 * larger teams the workers form two groups, one per part (the first half,
 * rounded up, part 0's), each splitting its part's colors as
 * sb_worker_range splits them; each worker runs its seam blocks of a color
 * first (those that another worker's read), then the rest, so that the
 * others find them done in the next color (on the 100 × 100 sheet at 3
 * threads this still meets more seams than the 7 colors did: 82 futex
 * sleeps a step against 48, on 2 oversubscribed cores). Only the needs of another worker's blocks are
 * waited for (a worker's own run in order), and only the blocks that
 * another worker's read post (the needs are split so at creation, for the
 * team's size).
 * Before the partition, each worker ran half of each of the 7 colors and
 * met the other at a seam in every color: on the 100 × 100 sheet at 4
 * sweeps, 2 threads, 31 futex sleeps a step against 9 with it (a loaded
 * machine, bench/results/vbd_sweeps.md). A step has 2 barriers (after the
 * packing, before the unpacking), where one after each color made 29.
 * With Chebyshev acceleration a barrier before and after each sweep's
 * acceleration stays. With Chebyshev acceleration the packed
 * positions of the last two sweeps are kept and each worker accelerates
 * its own range after a sweep (vbd.c). With over-relaxation each lane adds
 * ω times its Newton step (vbd.c). */
#include "kernels/integrators/fast_vbd.h"
#include "kernels/forces/fast_block.h"
#include "kernels/forces/reference_terms.h"

#include <stdlib.h>
#include <string.h>

typedef struct sb_vbd_block {
    uint32_t lanes;                        /* real vertices */
    uint32_t bonds, triangles, hinges;     /* slots of each family */
    size_t bond_at, triangle_at, hinge_at; /* entry of slot 0, lane 0 */
} sb_vbd_block;

typedef struct sb_vbd_bonds {
    uint32_t* other;
    sb_real *r0, *k, *damping;
} sb_vbd_bonds;

typedef struct sb_vbd_triangles {
    uint32_t *q, *r;
    sb_real* cos0[3]; /* at p, q, r */
    sb_real* len0[3]; /* of pq, qr, rp */
    sb_real *k_angle, *k_sb;
    sb_real *lambda, *gn_p, *gn_q; /* the corners' Gauss-Newton form (sb_vbd_corner_k), a constant per triangle */
} sb_vbd_triangles;

typedef struct sb_vbd_hinges {
    uint32_t* v[3];                      /* the other three of e0, e1, o0, o1 in order, p being e0 or o0 */
    sb_real *cos0, *sin0, *k, *opposite; /* cos φ0, sin φ0; opposite: 1 where p is o0 */
} sb_vbd_hinges;

/* How many sweeps a block has finished in the step, alone on its cache line. */
typedef struct sb_vbd_done {
    _Alignas(64) atomic_uint sweeps;
} sb_vbd_done;

struct sb_fast_vbd {
    uint32_t vertex_count, color_count, block_count;
    uint32_t* color_block; /* color_count + 1: each color's first block */
    uint8_t* color_part;   /* per color: its part of vbd.c's partition, the worker that runs it in a team of 2 */
    sb_vbd_block* blocks;
    uint32_t *need_first, *need; /* block b reads the vertices of blocks need[need_first[b] … need_first[b + 1]) */
    int width;                   /* the workers the split below is for */
    uint32_t* across;            /* block b's first across[b] needs are of other workers' blocks */
    sb_vbd_done* done;           /* block_count */
    uint32_t* lane;              /* SB_WIDTH per block: the lanes' vertices, padding repeats the first */
    sb_vbd_bonds bonds;
    sb_vbd_triangles triangles;
    sb_vbd_hinges hinges;
    sb_real *x4, *x04, *y4;   /* packed; x04's w: 1 when the vertex moves; y4's w: its mass */
    sb_real *last4, *before4; /* packed, with Chebyshev: the iterates one and two sweeps back; else NULL */
};

/* ---- the layout --------------------------------------------------------- */

typedef struct sb_vbd_counts {
    uint32_t bonds, triangles, hinges;
} sb_vbd_counts;

static double sb_vbd_bond_k(const sb_model* m, uint32_t b) {
    return (m->term_enabled[SB_TERM_BOND] ? m->bond_k[b] : 0.0) +
           (m->term_enabled[SB_TERM_SPRING] ? m->spring_k[b] : 0.0);
}
static double sb_vbd_bond_damping(const sb_model* m, uint32_t b) {
    return m->term_enabled[SB_TERM_SPRING] ? m->spring_damping[b] : 0.0;
}
static double sb_vbd_angle_k(const sb_model* m, uint32_t t) {
    return m->term_enabled[SB_TERM_ANGLE] ? m->angle_k[t] : 0.0;
}
static double sb_vbd_stretch_bend_k(const sb_model* m, uint32_t t) {
    return m->term_enabled[SB_TERM_STRETCH_BEND] ? m->stretch_bend_k[t] : 0.0;
}
static double sb_vbd_hinge_k(const sb_model* m, uint32_t h) {
    return m->term_enabled[SB_TERM_BEND] ? m->hinge_k[h] : 0.0;
}

/* Whether an element adds anything (some constant is not zero). */
static bool sb_vbd_counts_element(const sb_model* m, const sb_element* e) {
    switch (e->kind) {
    case SB_ELEMENT_BOND: return sb_vbd_bond_k(m, e->index) != 0.0 || sb_vbd_bond_damping(m, e->index) != 0.0;
    case SB_ELEMENT_TRIANGLE: return sb_vbd_angle_k(m, e->index) != 0.0 || sb_vbd_stretch_bend_k(m, e->index) != 0.0;
    case SB_ELEMENT_HINGE: return sb_vbd_hinge_k(m, e->index) != 0.0;
    case SB_ELEMENT_TET:
    case SB_ELEMENT_MEMBRANE:
    case SB_ELEMENT_PLATE: return false; /* no fast sweep for them (kernels/solver/solver.c) */
    }
    return false;
}

static sb_vbd_counts sb_vbd_vertex_counts(const sb_model* m, const sb_vertex_elements* at, uint32_t i) {
    sb_vbd_counts n = {0, 0, 0};
    for (uint32_t k = at->start[i]; k < at->start[i + 1]; k++) {
        sb_element e = sb_element_at(m, sb_entry_element(at->entry[k]));
        if (!sb_vbd_counts_element(m, &e)) continue;
        n.bonds += e.kind == SB_ELEMENT_BOND, n.triangles += e.kind == SB_ELEMENT_TRIANGLE;
        n.hinges += e.kind == SB_ELEMENT_HINGE;
    }
    return n;
}

static uint32_t sb_max_u32(uint32_t a, uint32_t b) { return a > b ? a : b; }

/* Blocks and their slots; returns the entries of each family in *total. */
static void sb_vbd_plan(sb_fast_vbd* f, const sb_model* m, const sb_vertex_elements* at, const uint32_t* color_start,
                        const uint32_t* order, sb_vbd_counts* total) {
    *total = (sb_vbd_counts){0, 0, 0};
    uint32_t b = 0;
    for (uint32_t c = 0; c < f->color_count; c++) {
        f->color_block[c] = b;
        for (uint32_t first = color_start[c]; first < color_start[c + 1]; first += SB_WIDTH, b++) {
            sb_vbd_block* block = &f->blocks[b];
            uint32_t lanes = color_start[c + 1] - first < SB_WIDTH ? color_start[c + 1] - first : SB_WIDTH;
            *block = (sb_vbd_block){.lanes = lanes};
            for (uint32_t l = 0; l < SB_WIDTH; l++) {
                uint32_t i = order[first + (l < lanes ? l : 0)];
                f->lane[(size_t)b * SB_WIDTH + l] = i;
                sb_vbd_counts n = sb_vbd_vertex_counts(m, at, i);
                block->bonds = sb_max_u32(block->bonds, n.bonds);
                block->triangles = sb_max_u32(block->triangles, n.triangles);
                block->hinges = sb_max_u32(block->hinges, n.hinges);
            }
            block->bond_at = (size_t)total->bonds * SB_WIDTH;
            block->triangle_at = (size_t)total->triangles * SB_WIDTH;
            block->hinge_at = (size_t)total->hinges * SB_WIDTH;
            total->bonds += block->bonds, total->triangles += block->triangles, total->hinges += block->hinges;
        }
    }
    f->color_block[f->color_count] = b;
}

/* An inert entry of each family at vertex i: collapsed, all constants 0. */
static void sb_vbd_inert_bond(sb_vbd_bonds* e, size_t q, uint32_t i) {
    e->other[q] = i, e->r0[q] = 1, e->k[q] = 0, e->damping[q] = 0;
}
static void sb_vbd_inert_triangle(sb_vbd_triangles* e, size_t q, uint32_t i) {
    e->q[q] = e->r[q] = i;
    for (int c = 0; c < 3; c++) e->cos0[c][q] = 0, e->len0[c][q] = 1;
    e->k_angle[q] = e->k_sb[q] = e->lambda[q] = e->gn_q[q] = 0;
    e->gn_p[q] = 1;
}
static void sb_vbd_inert_hinge(sb_vbd_hinges* e, size_t q, uint32_t i) {
    for (int a = 0; a < 3; a++) e->v[a][q] = i;
    e->sin0[q] = e->k[q] = e->opposite[q] = 0;
    e->cos0[q] = 1;
}

/* Entry q: bond b seen from the vertex at `place`. */
static void sb_vbd_put_bond(sb_vbd_bonds* e, size_t q, const sb_model* m, uint32_t b, int place) {
    e->other[q] = place == 0 ? m->bond_j[b] : m->bond_i[b];
    e->r0[q] = (sb_real)m->bond_r0[b];
    e->k[q] = (sb_real)sb_vbd_bond_k(m, b);
    e->damping[q] = (sb_real)sb_vbd_bond_damping(m, b);
}

/* The Gauss-Newton form of a triangle's corners (kernels/forces/hessian.h's
 * definite stand-in): λ, the positive eigenvalue of [[kθ, ksb], [ksb, 0]],
 * and its unit eigenvector (p, q); (1, 0) when ksb is 0. A constant of the
 * triangle: computed once here (in double), not per vertex and sweep. */
static void sb_vbd_corner_form(double ka, double ksb, double* lambda, double* p, double* q) {
    *lambda = 0.5 * (ka + sqrt(ka * ka + 4.0 * ksb * ksb));
    double a = ksb != 0.0 ? ksb : 1.0, b = ksb != 0.0 ? *lambda - ka : 0.0, norm = sqrt(a * a + b * b);
    *p = a / norm, *q = b / norm;
}

/* Triangle t rotated to start at its corner `place`. */
static void sb_vbd_put_triangle(sb_vbd_triangles* e, size_t q, const sb_model* m, uint32_t t, int place) {
    e->q[q] = m->tri_v[(place + 1) % 3][t];
    e->r[q] = m->tri_v[(place + 2) % 3][t];
    for (int c = 0; c < 3; c++) {
        e->cos0[c][q] = (sb_real)m->tri_cos0[(place + c) % 3][t];
        e->len0[c][q] = (sb_real)m->tri_len0[(place + c) % 3][t];
    }
    e->k_angle[q] = (sb_real)sb_vbd_angle_k(m, t);
    e->k_sb[q] = (sb_real)sb_vbd_stretch_bend_k(m, t);
    double lambda, p, pq;
    sb_vbd_corner_form(sb_vbd_angle_k(m, t), sb_vbd_stretch_bend_k(m, t), &lambda, &p, &pq);
    e->lambda[q] = (sb_real)lambda, e->gn_p[q] = (sb_real)p, e->gn_q[q] = (sb_real)pq;
}

/* Hinge h relabelled so that the vertex at `place` is e0 or o0. */
static void sb_vbd_put_hinge(sb_vbd_hinges* e, size_t q, const sb_model* m, uint32_t h, int place) {
    uint32_t v[4] = {m->hinge_e0[h], m->hinge_e1[h], m->hinge_o0[h], m->hinge_o1[h]};
    bool swap = place == 1 || place == 3;
    for (int a = 0, at = 0; a < 4; a++)
        if (a != (place >= 2 ? 2 : 0)) e->v[at++][q] = v[swap ? a ^ 1 : a];
    e->cos0[q] = (sb_real)cos(m->hinge_phi0[h]), e->sin0[q] = (sb_real)sin(m->hinge_phi0[h]);
    e->k[q] = (sb_real)sb_vbd_hinge_k(m, h);
    e->opposite[q] = place >= 2 ? 1 : 0;
}

/* Fills block b's entries: each lane's elements, then inert padding. */
static void sb_vbd_fill_block(sb_fast_vbd* f, const sb_model* m, const sb_vertex_elements* at, uint32_t b) {
    const sb_vbd_block* block = &f->blocks[b];
    for (uint32_t l = 0; l < SB_WIDTH; l++) {
        uint32_t i = f->lane[(size_t)b * SB_WIDTH + l];
        sb_vbd_counts n = {0, 0, 0};
        for (uint32_t k = at->start[i]; l < block->lanes && k < at->start[i + 1]; k++) {
            sb_element e = sb_element_at(m, sb_entry_element(at->entry[k]));
            int place = sb_entry_place(at->entry[k]);
            if (!sb_vbd_counts_element(m, &e)) continue;
            if (e.kind == SB_ELEMENT_BOND)
                sb_vbd_put_bond(&f->bonds, block->bond_at + (size_t)n.bonds++ * SB_WIDTH + l, m, e.index, place);
            if (e.kind == SB_ELEMENT_TRIANGLE)
                sb_vbd_put_triangle(&f->triangles, block->triangle_at + (size_t)n.triangles++ * SB_WIDTH + l, m,
                                    e.index, place);
            if (e.kind == SB_ELEMENT_HINGE)
                sb_vbd_put_hinge(&f->hinges, block->hinge_at + (size_t)n.hinges++ * SB_WIDTH + l, m, e.index, place);
        }
        for (uint32_t s = n.bonds; s < block->bonds; s++)
            sb_vbd_inert_bond(&f->bonds, block->bond_at + (size_t)s * SB_WIDTH + l, i);
        for (uint32_t s = n.triangles; s < block->triangles; s++)
            sb_vbd_inert_triangle(&f->triangles, block->triangle_at + (size_t)s * SB_WIDTH + l, i);
        for (uint32_t s = n.hinges; s < block->hinges; s++)
            sb_vbd_inert_hinge(&f->hinges, block->hinge_at + (size_t)s * SB_WIDTH + l, i);
    }
}

/* ---- the schedule ------------------------------------------------------ */

/* Calls visit(v, context) for each vertex that block b's elements read
 * besides the lanes' own (a vertex as often as entries have it). */
static void sb_vbd_block_reads(const sb_fast_vbd* f, uint32_t b, void (*visit)(uint32_t, void*), void* context) {
    const sb_vbd_block* block = &f->blocks[b];
    for (uint32_t l = 0; l < block->lanes; l++) {
        for (uint32_t s = 0; s < block->bonds; s++)
            visit(f->bonds.other[block->bond_at + (size_t)s * SB_WIDTH + l], context);
        for (uint32_t s = 0; s < block->triangles; s++) {
            size_t q = block->triangle_at + (size_t)s * SB_WIDTH + l;
            visit(f->triangles.q[q], context), visit(f->triangles.r[q], context);
        }
        for (uint32_t s = 0; s < block->hinges; s++)
            for (int a = 0; a < 3; a++) visit(f->hinges.v[a][block->hinge_at + (size_t)s * SB_WIDTH + l], context);
    }
}

/* The needs pass over one block's reads: each other block (of another
 * color: a color's vertices share no element) counted or listed once. */
typedef struct sb_vbd_needs {
    const uint32_t* block_of; /* per vertex: its block, UINT32_MAX for a vertex in none (fixed) */
    uint32_t block, *mark;    /* mark[y]: 1 + the last block that took block y */
    uint32_t count, *out;     /* out: NULL to count */
} sb_vbd_needs;

static void sb_vbd_take_need(uint32_t v, void* context) {
    sb_vbd_needs* n = context;
    uint32_t y = n->block_of[v];
    if (y == UINT32_MAX || y == n->block || n->mark[y] == n->block + 1) return;
    n->mark[y] = n->block + 1;
    if (n->out) n->out[n->count] = y;
    n->count++;
}

/* The workers of a team of `width` (2 or more) that run part p's colors:
 * the first half (rounded up) part 0's, the others part 1's; *group is
 * the view of worker `index` within them (index -1 when it is not one). */
static void sb_vbd_part_group(int width, int part, int index, sb_worker* group) {
    int zero = (width + 1) / 2, first = part ? zero : 0, count = part ? width - zero : zero;
    bool member = index >= first && index < first + count;
    *group = (sb_worker){NULL, member ? index - first : -1, count};
}

/* Color c's blocks [*begin, *end) that worker `index` of a team of `width`
 * runs: all of them alone; else its share (sb_worker_range) of the colors
 * of its part's group, nothing of the other part's. In a team of 2 each
 * worker runs one part's colors whole. */
static void sb_vbd_color_range(const sb_fast_vbd* f, uint32_t c, int index, int width, int64_t* begin, int64_t* end) {
    int64_t count = f->color_block[c + 1] - f->color_block[c];
    *begin = 0, *end = count;
    if (width == 1) return;
    sb_worker group;
    sb_vbd_part_group(width, f->color_part[c], index, &group);
    if (group.index < 0)
        *end = 0;
    else
        sb_worker_range(&group, count, begin, end);
}

/* Block b's worker in a team of `width` (sb_vbd_color_range). */
static int sb_vbd_owner(const sb_fast_vbd* f, uint32_t b, int width) {
    uint32_t c = 0;
    while (f->color_block[c + 1] <= b) c++;
    for (int i = 0; i < width; i++) {
        int64_t begin, end;
        sb_vbd_color_range(f, c, i, width, &begin, &end);
        if (b - f->color_block[c] >= begin && b - f->color_block[c] < end) return i;
    }
    return 0;
}

/* Each block's needs of other workers' blocks (in a team of f->width)
 * moved to the front of its list, and counted. */
static void sb_vbd_split_needs(sb_fast_vbd* f) {
    for (uint32_t b = 0; b < f->block_count; b++) {
        int mine = sb_vbd_owner(f, b, f->width);
        uint32_t front = f->need_first[b];
        for (uint32_t e = f->need_first[b]; e < f->need_first[b + 1]; e++)
            if (sb_vbd_owner(f, f->need[e], f->width) != mine) {
                uint32_t y = f->need[e];
                f->need[e] = f->need[front], f->need[front++] = y;
            }
        f->across[b] = front - f->need_first[b];
    }
}

/* Each block's needs (the blocks whose vertices it reads, which read its
 * own in turn) and the blocks' done counters. */
static bool sb_vbd_schedule_build(sb_fast_vbd* f) {
    uint32_t blocks = f->block_count ? f->block_count : 1;
    uint32_t* block_of = malloc(((size_t)f->vertex_count + 1) * sizeof *block_of);
    sb_vbd_needs n = {.block_of = block_of, .mark = calloc(blocks, sizeof *n.mark)};
    f->need_first = calloc((size_t)blocks + 1, sizeof *f->need_first);
    f->done = aligned_alloc(_Alignof(sb_vbd_done), blocks * sizeof *f->done);
    f->across = malloc(blocks * sizeof *f->across);
    bool ok = block_of && n.mark && f->need_first && f->done && f->across;
    for (uint32_t i = 0; ok && i < f->vertex_count; i++) block_of[i] = UINT32_MAX;
    for (uint32_t b = 0; ok && b < f->block_count; b++)
        for (uint32_t l = 0; l < f->blocks[b].lanes; l++) block_of[f->lane[(size_t)b * SB_WIDTH + l]] = b;
    for (int pass = 0; ok && pass < 2; pass++) {
        memset(n.mark, 0, blocks * sizeof *n.mark);
        n.out = pass ? f->need : NULL;
        n.count = 0;
        for (n.block = 0; n.block < f->block_count; n.block++) {
            sb_vbd_block_reads(f, n.block, sb_vbd_take_need, &n);
            f->need_first[n.block + 1] = n.count;
        }
        if (!pass) ok = (f->need = malloc(((size_t)n.count + 1) * sizeof *f->need)) != NULL;
    }
    if (ok) sb_vbd_split_needs(f);
    free(block_of), free(n.mark);
    return ok;
}

/* Whether block y is among block b's needs. */
static bool sb_vbd_needs_block(const sb_fast_vbd* f, uint32_t b, uint32_t y) {
    for (uint32_t e = f->need_first[b]; e < f->need_first[b + 1]; e++)
        if (f->need[e] == y) return true;
    return false;
}

uint32_t sb_fast_vbd_schedule_faults(const sb_fast_vbd* f, const sb_model* m, uint32_t* needs) {
    uint32_t* block_of = malloc(((size_t)m->vertex_count + 1) * sizeof *block_of);
    if (!block_of) return UINT32_MAX;
    for (uint32_t i = 0; i < m->vertex_count; i++) block_of[i] = UINT32_MAX;
    for (uint32_t b = 0; b < f->block_count; b++)
        for (uint32_t l = 0; l < f->blocks[b].lanes; l++) block_of[f->lane[(size_t)b * SB_WIDTH + l]] = b;
    uint32_t faults = 0;
    for (uint64_t id = 0; id < sb_element_count(m); id++) {
        sb_element e = sb_element_at(m, id);
        if (!sb_vbd_counts_element(m, &e)) continue;
        for (int a = 0; a < e.count; a++)
            for (int c = 0; c < e.count; c++) {
                uint32_t x = block_of[e.vertex[a]], y = block_of[e.vertex[c]];
                if (a == c || x == UINT32_MAX || y == UINT32_MAX) continue;
                faults += x == y || !sb_vbd_needs_block(f, x, y); /* one color's vertices share no element */
            }
    }
    *needs = f->need_first[f->block_count];
    free(block_of);
    return faults;
}

static void* sb_vbd_alloc(size_t count, size_t size) { return aligned_alloc(64, ((count * size) / 64 + 1) * 64); }

static bool sb_vbd_alloc_entries(sb_fast_vbd* f, sb_vbd_counts total) {
    size_t nb = (size_t)total.bonds * SB_WIDTH, nt = (size_t)total.triangles * SB_WIDTH;
    size_t nh = (size_t)total.hinges * SB_WIDTH;
    bool ok = (f->bonds.other = sb_vbd_alloc(nb, sizeof(uint32_t))) != NULL;
    ok &= (f->bonds.r0 = sb_vbd_alloc(nb, sizeof(sb_real))) != NULL;
    ok &= (f->bonds.k = sb_vbd_alloc(nb, sizeof(sb_real))) != NULL;
    ok &= (f->bonds.damping = sb_vbd_alloc(nb, sizeof(sb_real))) != NULL;
    ok &= (f->triangles.q = sb_vbd_alloc(nt, sizeof(uint32_t))) != NULL;
    ok &= (f->triangles.r = sb_vbd_alloc(nt, sizeof(uint32_t))) != NULL;
    for (int c = 0; c < 3; c++) {
        ok &= (f->triangles.cos0[c] = sb_vbd_alloc(nt, sizeof(sb_real))) != NULL;
        ok &= (f->triangles.len0[c] = sb_vbd_alloc(nt, sizeof(sb_real))) != NULL;
    }
    ok &= (f->triangles.k_angle = sb_vbd_alloc(nt, sizeof(sb_real))) != NULL;
    ok &= (f->triangles.k_sb = sb_vbd_alloc(nt, sizeof(sb_real))) != NULL;
    ok &= (f->triangles.lambda = sb_vbd_alloc(nt, sizeof(sb_real))) != NULL;
    ok &= (f->triangles.gn_p = sb_vbd_alloc(nt, sizeof(sb_real))) != NULL;
    ok &= (f->triangles.gn_q = sb_vbd_alloc(nt, sizeof(sb_real))) != NULL;
    for (int a = 0; a < 3; a++) ok &= (f->hinges.v[a] = sb_vbd_alloc(nh, sizeof(uint32_t))) != NULL;
    ok &= (f->hinges.cos0 = sb_vbd_alloc(nh, sizeof(sb_real))) != NULL;
    ok &= (f->hinges.sin0 = sb_vbd_alloc(nh, sizeof(sb_real))) != NULL;
    ok &= (f->hinges.k = sb_vbd_alloc(nh, sizeof(sb_real))) != NULL;
    ok &= (f->hinges.opposite = sb_vbd_alloc(nh, sizeof(sb_real))) != NULL;
    return ok;
}

void sb_fast_vbd_destroy(sb_fast_vbd* f) {
    if (!f) return;
    free(f->color_block), free(f->color_part), free(f->blocks), free(f->lane), free(f->need_first), free(f->need),
        free(f->done);
    free(f->across);
    free(f->bonds.other), free(f->bonds.r0), free(f->bonds.k), free(f->bonds.damping);
    free(f->triangles.q), free(f->triangles.r), free(f->triangles.k_angle), free(f->triangles.k_sb);
    free(f->triangles.lambda), free(f->triangles.gn_p), free(f->triangles.gn_q);
    for (int c = 0; c < 3; c++) free(f->triangles.cos0[c]), free(f->triangles.len0[c]);
    for (int a = 0; a < 3; a++) free(f->hinges.v[a]);
    free(f->hinges.cos0), free(f->hinges.sin0), free(f->hinges.k), free(f->hinges.opposite);
    free(f->x4), free(f->x04), free(f->y4), free(f->last4), free(f->before4);
    free(f);
}

sb_fast_vbd* sb_fast_vbd_create(const sb_model* m, const sb_vertex_elements* at, const uint32_t* color_start,
                                uint32_t color_count, const uint8_t* color_part, const uint32_t* order, bool chebyshev,
                                int width) {
    sb_fast_vbd* f = calloc(1, sizeof *f);
    if (!f) return NULL;
    f->width = width > 1 ? width : 1;
    f->vertex_count = m->vertex_count;
    f->color_count = color_count;
    for (uint32_t c = 0; c < color_count; c++)
        f->block_count += (color_start[c + 1] - color_start[c] + SB_WIDTH - 1) / SB_WIDTH;
    size_t packed = 4 * (size_t)m->vertex_count;
    f->color_block = malloc(((size_t)color_count + 1) * sizeof *f->color_block);
    f->color_part = malloc((size_t)color_count + 1);
    if (f->color_part) memcpy(f->color_part, color_part, color_count);
    f->blocks = malloc(((size_t)f->block_count + 1) * sizeof *f->blocks);
    f->lane = sb_vbd_alloc(((size_t)f->block_count + 1) * SB_WIDTH, sizeof *f->lane);
    f->x4 = sb_vbd_alloc(packed, sizeof(sb_real));
    f->x04 = sb_vbd_alloc(packed, sizeof(sb_real));
    f->y4 = sb_vbd_alloc(packed, sizeof(sb_real));
    if (chebyshev) f->last4 = sb_vbd_alloc(packed, sizeof(sb_real)), f->before4 = sb_vbd_alloc(packed, sizeof(sb_real));
    sb_vbd_counts total;
    bool ok = f->color_block && f->color_part && f->blocks && f->lane && f->x4 && f->x04 && f->y4 &&
              (!chebyshev || (f->last4 && f->before4));
    if (ok) sb_vbd_plan(f, m, at, color_start, order, &total);
    if (!ok || !sb_vbd_alloc_entries(f, total)) {
        sb_fast_vbd_destroy(f);
        return NULL;
    }
    for (uint32_t b = 0; b < f->block_count; b++) sb_vbd_fill_block(f, m, at, b);
    if (!sb_vbd_schedule_build(f)) {
        sb_fast_vbd_destroy(f);
        return NULL;
    }
    for (uint32_t i = 0; i < m->vertex_count; i++) f->y4[4 * (size_t)i + 3] = (sb_real)m->mass[i];
    return f;
}

/* ---- the sweep ---------------------------------------------------------- */

/* A symmetric 3 × 3 matrix per lane. */
typedef struct sb_wsym3 {
    sb_wide xx, xy, xz, yy, yz, zz;
} sb_wsym3;

static inline sb_wide sb_w_madd(sb_wide a, sb_wide b, sb_wide c) { return sb_w_add(sb_w_mul(a, b), c); }

/* h += s u uᵀ */
static inline void sb_ws_outer(sb_wsym3* h, sb_wvec3 u, sb_wide s) {
    sb_wvec3 su = sb_wv_scale(u, s);
    h->xx = sb_w_madd(su.x, u.x, h->xx), h->xy = sb_w_madd(su.x, u.y, h->xy), h->xz = sb_w_madd(su.x, u.z, h->xz);
    h->yy = sb_w_madd(su.y, u.y, h->yy), h->yz = sb_w_madd(su.y, u.z, h->yz), h->zz = sb_w_madd(su.z, u.z, h->zz);
}

/* h += s (u vᵀ + v uᵀ) */
static inline void sb_ws_outer2(sb_wsym3* h, sb_wvec3 u, sb_wvec3 v, sb_wide s) {
    sb_wvec3 su = sb_wv_scale(u, s), sv = sb_wv_scale(v, s);
    h->xx = sb_w_madd(su.x, v.x, sb_w_madd(sv.x, u.x, h->xx));
    h->xy = sb_w_madd(su.x, v.y, sb_w_madd(sv.x, u.y, h->xy));
    h->xz = sb_w_madd(su.x, v.z, sb_w_madd(sv.x, u.z, h->xz));
    h->yy = sb_w_madd(su.y, v.y, sb_w_madd(sv.y, u.y, h->yy));
    h->yz = sb_w_madd(su.y, v.z, sb_w_madd(sv.y, u.z, h->yz));
    h->zz = sb_w_madd(su.z, v.z, sb_w_madd(sv.z, u.z, h->zz));
}

/* h += s I */
static inline void sb_ws_diagonal(sb_wsym3* h, sb_wide s) {
    h->xx = sb_w_add(h->xx, s), h->yy = sb_w_add(h->yy, s), h->zz = sb_w_add(h->zz, s);
}

static inline sb_wvec3 sb_wv_madd(sb_wvec3 a, sb_wide s, sb_wvec3 c) {
    return (sb_wvec3){sb_w_madd(a.x, s, c.x), sb_w_madd(a.y, s, c.y), sb_w_madd(a.z, s, c.z)};
}

/* 1 where a >= b, else 0 (a NaN counts as >=, as the reference's !(a < b) would not: positions are finite). */
static inline sb_wide sb_w_at_least(sb_wide a, sb_wide b) { return sb_w_pick_greater(b, a, sb_w_set(0), sb_w_set(1)); }

/* a where the flag is 1, b where it is 0 */
static inline sb_wvec3 sb_wv_pick(sb_wide flag, sb_wvec3 a, sb_wvec3 b) {
    sb_wide half = sb_w_set((sb_real)0.5);
    return (sb_wvec3){sb_w_pick_greater(flag, half, a.x, b.x), sb_w_pick_greater(flag, half, a.y, b.y),
                      sb_w_pick_greater(flag, half, a.z, b.z)};
}

/* What every share reads of the lanes' vertices, and what they sum. */
typedef struct sb_vbd_lanes {
    const sb_fast_vbd* f;
    sb_wide inv_dt;
    sb_wvec3 x, moved; /* the position, and x − x⁰ */
    sb_wvec3 force;
    sb_wsym3 h;
    sb_wide lost; /* > 0 where a real element (some constant not 0) collapsed */
} sb_vbd_lanes;

/* Counts an element with constants of sizes `weight` that collapsed (alive 0). */
static inline void sb_vbd_lose(sb_vbd_lanes* l, sb_wide alive, sb_wide weight) {
    l->lost = sb_w_madd(sb_w_sub(sb_w_set(1), alive), sb_w_abs(weight), l->lost);
}

/* A bond's force k (r − r0) u plus the damping's d u (u · v_rel) and its
 * block (k (1 − σ) + d/dt) u uᵀ + k σ I, σ = max(0, 1 − r0/r)
 * (kernels/forces/hessian_edges.c's definite block, vbd.c's damping). */
static inline void sb_vbd_bond_share(sb_vbd_lanes* l, size_t at) {
    const sb_vbd_bonds* e = &l->f->bonds;
    sb_windex other = sb_w_index(e->other + at);
    sb_wvec3 xq = sb_wv_load4(l->f->x4, other), x0q = sb_wv_load4(l->f->x04, other);
    sb_wvec3 delta = sb_wv_sub(xq, l->x);
    sb_wide r2 = sb_wv_dot(delta, delta), r0 = sb_w_load(e->r0 + at);
    sb_wide shortest = sb_w_mul(sb_w_set((sb_real)SB_COLLAPSE_RATIO), r0);
    sb_wide alive = sb_w_at_least(r2, sb_w_mul(shortest, shortest));
    sb_wide inv_r = sb_w_pick_greater(alive, sb_w_set(0), sb_w_rsqrt(r2), sb_w_set(0)), r = sb_w_mul(r2, inv_r);
    sb_wide k = sb_w_load(e->k + at), d = sb_w_load(e->damping + at);
    sb_vbd_lose(l, alive, sb_w_add(k, d));
    k = sb_w_mul(k, alive), d = sb_w_mul(d, alive);
    sb_wvec3 u = sb_wv_scale(delta, inv_r);
    sb_wvec3 relative = sb_wv_scale(sb_wv_sub(sb_wv_sub(xq, x0q), l->moved), l->inv_dt);
    sb_wide along = sb_w_madd(k, sb_w_sub(r, r0), sb_w_mul(d, sb_wv_dot(u, relative)));
    sb_wide sideways = sb_w_max(sb_w_sub(sb_w_set(1), sb_w_mul(r0, inv_r)), sb_w_set(0));
    l->force = sb_wv_madd(u, along, l->force);
    sb_ws_outer(&l->h, u, sb_w_madd(k, sb_w_sub(sb_w_set(1), sideways), sb_w_mul(d, l->inv_dt)));
    sb_ws_diagonal(&l->h, sb_w_mul(k, sideways));
}

/* An edge of a triangle: unit vector, 1/length, length − rest. */
typedef struct sb_wedge {
    sb_wvec3 unit;
    sb_wide inverse, strain;
} sb_wedge;

static inline sb_wedge sb_vbd_edge(sb_wvec3 from, sb_wvec3 to, sb_wide rest, sb_wide* alive) {
    sb_wvec3 d = sb_wv_sub(to, from);
    sb_wide squared = sb_wv_dot(d, d), shortest = sb_w_mul(sb_w_set((sb_real)SB_COLLAPSE_RATIO), rest);
    sb_wide ok = sb_w_at_least(squared, sb_w_mul(shortest, shortest));
    *alive = sb_w_mul(*alive, ok);
    sb_wide inverse = sb_w_pick_greater(ok, sb_w_set(0), sb_w_rsqrt(squared), sb_w_set(0));
    return (sb_wedge){sb_wv_scale(d, inverse), inverse, sb_w_sub(sb_w_mul(squared, inverse), rest)};
}

static inline sb_wedge sb_wedge_reversed(sb_wedge e) { return (sb_wedge){sb_wv_neg(e.unit), e.inverse, e.strain}; }

/* The corner's scalars: c = â·b̂, g = kθ (c − c0) + ksb S, h = ksb (c − c0). */
typedef struct sb_wcorner {
    sb_wide c, g, h;
} sb_wcorner;

static inline sb_wcorner sb_vbd_corner(sb_wedge a, sb_wedge b, sb_wide cos0, sb_wide ka, sb_wide ksb) {
    sb_wide c = sb_wv_dot(a.unit, b.unit), dc = sb_w_sub(c, cos0), s = sb_w_add(a.strain, b.strain);
    return (sb_wcorner){c, sb_w_madd(ka, dc, sb_w_mul(ksb, s)), sb_w_mul(ksb, dc)};
}

/* A triangle's constants and the Gauss-Newton form of its corners
 * (sb_vbd_corner_form): λ, the positive eigenvalue of [[kθ, ksb], [ksb, 0]],
 * with its unit eigenvector (p, q). */
typedef struct sb_wcorner_k {
    sb_wide ka, ksb, lambda, p, q;
} sb_wcorner_k;

/* p at the far end of a corner's edge a (b its other edge): F_p = −(g ∇_a c
 * + h â), ∇_a c = (b̂ − c â)/A, and the block λ w wᵀ, w = p ∇_a c + q â. */
static inline void sb_vbd_corner_end(sb_vbd_lanes* l, sb_wedge a, sb_wedge b, sb_wide cos0, const sb_wcorner_k* k) {
    sb_wcorner q = sb_vbd_corner(a, b, cos0, k->ka, k->ksb);
    sb_wvec3 grad = sb_wv_scale(sb_wv_sub(b.unit, sb_wv_scale(a.unit, q.c)), a.inverse);
    l->force = sb_wv_sub(l->force, sb_wv_add(sb_wv_scale(grad, q.g), sb_wv_scale(a.unit, q.h)));
    sb_ws_outer(&l->h, sb_wv_add(sb_wv_scale(grad, k->p), sb_wv_scale(a.unit, k->q)), k->lambda);
}

/* p at the apex (edges a, b leave it): F_p = g w + h s with w = ∇_a c +
 * ∇_b c, s = â + b̂, and the block λ (p w + q s)(p w + q s)ᵀ. */
static inline void sb_vbd_corner_apex(sb_vbd_lanes* l, sb_wedge a, sb_wedge b, sb_wide cos0, const sb_wcorner_k* k) {
    sb_wcorner q = sb_vbd_corner(a, b, cos0, k->ka, k->ksb);
    sb_wvec3 w = sb_wv_add(sb_wv_scale(sb_wv_sub(b.unit, sb_wv_scale(a.unit, q.c)), a.inverse),
                           sb_wv_scale(sb_wv_sub(a.unit, sb_wv_scale(b.unit, q.c)), b.inverse));
    sb_wvec3 s = sb_wv_add(a.unit, b.unit);
    l->force = sb_wv_add(l->force, sb_wv_add(sb_wv_scale(w, q.g), sb_wv_scale(s, q.h)));
    sb_ws_outer(&l->h, sb_wv_add(sb_wv_scale(w, k->p), sb_wv_scale(s, k->q)), k->lambda);
}

/* A triangle (p, q, r): corner p with p at its apex, corner q (edges
 * q→r, q→p) with p at the end of its second edge, corner r (edges r→p,
 * r→q) with p at the end of its first. A collapsed triangle adds nothing. */
static inline void sb_vbd_triangle_share(sb_vbd_lanes* l, size_t at) {
    const sb_vbd_triangles* e = &l->f->triangles;
    sb_wvec3 xq = sb_wv_load4(l->f->x4, sb_w_index(e->q + at)), xr = sb_wv_load4(l->f->x4, sb_w_index(e->r + at));
    sb_wide alive = sb_w_set(1);
    sb_wedge pq = sb_vbd_edge(l->x, xq, sb_w_load(e->len0[0] + at), &alive);
    sb_wedge qr = sb_vbd_edge(xq, xr, sb_w_load(e->len0[1] + at), &alive);
    sb_wedge rp = sb_vbd_edge(xr, l->x, sb_w_load(e->len0[2] + at), &alive);
    sb_wide ka = sb_w_load(e->k_angle + at), ksb = sb_w_load(e->k_sb + at);
    sb_vbd_lose(l, alive, sb_w_add(sb_w_abs(ka), sb_w_abs(ksb)));
    sb_wcorner_k k = {sb_w_mul(ka, alive), sb_w_mul(ksb, alive), sb_w_mul(sb_w_load(e->lambda + at), alive),
                      sb_w_load(e->gn_p + at), sb_w_load(e->gn_q + at)};
    sb_vbd_corner_apex(l, pq, sb_wedge_reversed(rp), sb_w_load(e->cos0[0] + at), &k);
    sb_vbd_corner_end(l, sb_wedge_reversed(pq), qr, sb_w_load(e->cos0[1] + at), &k);
    sb_vbd_corner_end(l, rp, sb_wedge_reversed(qr), sb_w_load(e->cos0[2] + at), &k);
}

/* A hinge with p at e0 (opposite 0) or o0 (1): F_p = k (φ − φ0) u_p and the
 * Gauss-Newton block k u_p u_pᵀ, u_p = α n0/|n0|² + β n1/|n1|² with
 * (α, β) = ((o0 − e1)·ê, (o1 − e1)·ê) at e0 and (|e|, 0) at o0
 * (kernels/forces/reference_hinges.c). A collapsed hinge adds nothing. */
static inline void sb_vbd_hinge_share(sb_vbd_lanes* l, size_t at) {
    const sb_vbd_hinges* e = &l->f->hinges;
    sb_wvec3 g[3];
    for (int a = 0; a < 3; a++) g[a] = sb_wv_load4(l->f->x4, sb_w_index(e->v[a] + at));
    sb_wide opposite = sb_w_load(e->opposite + at), edge_end = sb_w_sub(sb_w_set(1), opposite);
    /* e0, e1, o0, o1: (p, g0, g1, g2) at e0, (g0, g1, p, g2) at o0 */
    sb_wvec3 p[4] = {sb_wv_pick(opposite, g[0], l->x), sb_wv_pick(opposite, g[1], g[0]),
                     sb_wv_pick(opposite, l->x, g[1]), g[2]};
    sb_wvec3 edge = sb_wv_sub(p[1], p[0]);
    sb_wvec3 n0 = sb_wv_cross(sb_wv_sub(p[2], p[0]), sb_wv_sub(p[2], p[1]));
    sb_wvec3 n1 = sb_wv_cross(sb_wv_sub(p[3], p[1]), sb_wv_sub(p[3], p[0]));
    sb_wide edge_sq = sb_wv_dot(edge, edge), n0_sq = sb_wv_dot(n0, n0), n1_sq = sb_wv_dot(n1, n1);
    /* the smallest normal number keeps a zero-length edge (limit 0) caught, as in kernels/forces/fast_hinges.c */
    sb_wide limit = sb_w_madd(sb_w_set((sb_real)(SB_MIN_WING_RATIO * SB_MIN_WING_RATIO)), sb_w_mul(edge_sq, edge_sq),
                              sb_w_set(SB_REAL_MIN));
    sb_wide alive = sb_w_mul(sb_w_pick_greater(n0_sq, limit, sb_w_set(1), sb_w_set(0)),
                             sb_w_pick_greater(n1_sq, limit, sb_w_set(1), sb_w_set(0)));
    sb_wide inv_length = sb_w_pick_greater(alive, sb_w_set(0), sb_w_rsqrt(edge_sq), sb_w_set(0));
    sb_wide length = sb_w_mul(edge_sq, inv_length);
    sb_wide sine = sb_w_mul(sb_wv_dot(sb_wv_cross(n0, n1), edge), inv_length);
    /* φ − φ0 as the angle of (cos φ, sin φ) turned back by φ0: atan2 gives it in (−π, π] */
    sb_wide cosine = sb_wv_dot(n0, n1), c0 = sb_w_load(e->cos0 + at), s0 = sb_w_load(e->sin0 + at);
    sb_wide delta =
        sb_w_atan2(sb_w_sub(sb_w_mul(sine, c0), sb_w_mul(cosine, s0)), sb_w_madd(cosine, c0, sb_w_mul(sine, s0)));
    sb_wvec3 unit = sb_wv_scale(edge, inv_length);
    sb_wide alpha = sb_w_madd(opposite, length, sb_w_mul(edge_end, sb_wv_dot(sb_wv_sub(p[2], p[1]), unit)));
    sb_wide beta = sb_w_mul(edge_end, sb_wv_dot(sb_wv_sub(p[3], p[1]), unit));
    sb_wide w0 = sb_w_pick_greater(alive, sb_w_set(0), sb_w_mul(alpha, sb_w_recip(n0_sq)), sb_w_set(0));
    sb_wide w1 = sb_w_pick_greater(alive, sb_w_set(0), sb_w_mul(beta, sb_w_recip(n1_sq)), sb_w_set(0));
    sb_wvec3 u = sb_wv_add(sb_wv_scale(n0, w0), sb_wv_scale(n1, w1));
    sb_wide k = sb_w_load(e->k + at);
    sb_vbd_lose(l, alive, k);
    l->force = sb_wv_madd(u, sb_w_mul(k, delta), l->force);
    sb_ws_outer(&l->h, u, k);
}

/* Solves h d = r by Cholesky per lane; d = 0 where h is not positive definite. */
static inline sb_wvec3 sb_ws_solve(const sb_wsym3* h, sb_wvec3 r) {
    sb_wide zero = sb_w_set(0), one = sb_w_set(1);
    /* the pivots' inverse square roots (i = 1/l): multiplications, not divisions */
    sb_wide i00 = sb_w_rsqrt(h->xx);
    sb_wide l10 = sb_w_mul(h->xy, i00), l20 = sb_w_mul(h->xz, i00);
    sb_wide t11 = sb_w_sub(h->yy, sb_w_mul(l10, l10)), i11 = sb_w_rsqrt(t11);
    sb_wide l21 = sb_w_mul(sb_w_sub(h->yz, sb_w_mul(l20, l10)), i11);
    sb_wide t22 = sb_w_sub(sb_w_sub(h->zz, sb_w_mul(l20, l20)), sb_w_mul(l21, l21)), i22 = sb_w_rsqrt(t22);
    sb_wide z0 = sb_w_mul(r.x, i00), z1 = sb_w_mul(sb_w_sub(r.y, sb_w_mul(l10, z0)), i11);
    sb_wide z2 = sb_w_mul(sb_w_sub(sb_w_sub(r.z, sb_w_mul(l20, z0)), sb_w_mul(l21, z1)), i22);
    sb_wide d2 = sb_w_mul(z2, i22), d1 = sb_w_mul(sb_w_sub(z1, sb_w_mul(l21, d2)), i11);
    sb_wide d0 = sb_w_mul(sb_w_sub(sb_w_sub(z0, sb_w_mul(l10, d1)), sb_w_mul(l20, d2)), i00);
    /* comparisons with NaN are false: a lane that took a root of a negative is not definite */
    sb_wide definite = sb_w_pick_greater(
        h->xx, zero, sb_w_pick_greater(t11, zero, sb_w_pick_greater(t22, zero, one, zero), zero), zero);
    return (sb_wvec3){sb_w_pick_greater(definite, zero, d0, zero), sb_w_pick_greater(definite, zero, d1, zero),
                      sb_w_pick_greater(definite, zero, d2, zero)};
}

typedef struct sb_vbd_rates {
    sb_wide inv_dt, inv_dt2, drag_per_dt, relaxation;
} sb_vbd_rates;

/* One Newton step on each lane's vertex (vbd.c's sb_vbd_vertex); whether
 * an element of a lane collapsed. */
static bool sb_vbd_block_update(const sb_fast_vbd* f, uint32_t b, const sb_vbd_rates* rates) {
    const sb_vbd_block* block = &f->blocks[b];
    sb_windex id = sb_w_index(f->lane + (size_t)b * SB_WIDTH);
    sb_wide moves, mass;
    sb_wvec3 x = sb_wv_load4(f->x4, id), x0 = sb_wv_load4w(f->x04, id, &moves), y = sb_wv_load4w(f->y4, id, &mass);
    sb_wide inertia = sb_w_mul(mass, rates->inv_dt2), drag = sb_w_mul(mass, rates->drag_per_dt);
    sb_vbd_lanes l = {.f = f, .inv_dt = rates->inv_dt, .x = x, .moved = sb_wv_sub(x, x0), .lost = sb_w_set(0)};
    l.force = sb_wv_neg(sb_wv_add(sb_wv_scale(sb_wv_sub(x, y), inertia), sb_wv_scale(l.moved, drag)));
    sb_wide zero = sb_w_set(0), diagonal = sb_w_add(inertia, drag);
    l.h = (sb_wsym3){diagonal, zero, zero, diagonal, zero, diagonal};
    for (uint32_t s = 0; s < block->bonds; s++) sb_vbd_bond_share(&l, block->bond_at + (size_t)s * SB_WIDTH);
    for (uint32_t s = 0; s < block->triangles; s++)
        sb_vbd_triangle_share(&l, block->triangle_at + (size_t)s * SB_WIDTH);
    for (uint32_t s = 0; s < block->hinges; s++) sb_vbd_hinge_share(&l, block->hinge_at + (size_t)s * SB_WIDTH);
    /* ω times the Newton step; held vertices (moves 0) wait */
    sb_wvec3 step = sb_wv_scale(sb_ws_solve(&l.h, l.force), sb_w_mul(moves, rates->relaxation));
    sb_wv_add4(f->x4, id, step, (int)block->lanes);
    return sb_w_any(sb_w_less(sb_w_set(0), l.lost), (int)block->lanes);
}

/* xyz of vertices [begin, end) from 3n interleaved doubles into p4. */
static void sb_vbd_pack(sb_real* p4, const double* x, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; i++)
        for (int c = 0; c < 3; c++) p4[4 * i + c] = (sb_real)x[3 * i + c];
}

/* Chebyshev's step after sweep `sweep` on vertices [begin, end) (vbd.c's
 * sb_vbd_accelerate in sb_real); returns the weight for the next. */
static double sb_vbd_accelerate4(sb_fast_vbd* f, double rho, int sweep, double weight, int64_t begin, int64_t end) {
    weight = sb_vbd_chebyshev_weight(rho, sweep, weight);
    const sb_real omega = (sb_real)weight;
    for (size_t q = 4 * (size_t)begin; q < 4 * (size_t)end; q++) {
        if (sweep >= SB_VBD_CHEBYSHEV_FIRST) f->x4[q] = omega * (f->x4[q] - f->before4[q]) + f->before4[q];
        f->before4[q] = f->last4[q];
        f->last4[q] = f->x4[q];
    }
    return weight;
}

/* Block b's Newton steps of sweep `sweep` (0, 1, …), once the blocks it
 * reads have finished the sweeps it must follow: those of earlier colors
 * (lower block numbers) this sweep, those of later colors the sweep
 * before; they wait for it in turn. Whether an element collapsed. */
static bool sb_vbd_block_in_turn(sb_fast_vbd* f, uint32_t b, unsigned sweep, const sb_vbd_rates* rates,
                                 const sb_worker* w) {
    /* a worker's own blocks run in sweep and color order: only the others' need a wait, and only a
     * block some other worker's block reads (one with needs across: the relation is symmetric) posts */
    uint32_t needs = w->width == 1 ? 0 : w->width == f->width ? f->across[b] : f->need_first[b + 1] - f->need_first[b];
    for (uint32_t e = f->need_first[b]; e < f->need_first[b] + needs; e++)
        sb_worker_wait_at_least(w, &f->done[f->need[e]].sweeps, sweep + (f->need[e] < b));
    bool collapsed = sb_vbd_block_update(f, b, rates);
    if (needs) sb_worker_post(w, &f->done[b].sweeps, sweep + 1);
    return collapsed;
}

/* This worker's blocks [begin, end) of color c in sweep `sweep`, in block
 * order. In a team whose part groups split each color (more than
 * SB_VBD_PARTS workers, the waits planned for it), first the blocks that
 * other workers' blocks read (along the seams between shares), then the
 * rest, so that the others find them done in the next color. */
static bool sb_vbd_color_share(sb_fast_vbd* f, uint32_t c, int64_t begin, int64_t end, unsigned sweep,
                               const sb_vbd_rates* rates, const sb_worker* w) {
    bool collapsed = false, seams = w->width == f->width && w->width > SB_VBD_PARTS;
    for (int seam = seams; seam >= 0; seam--)
        for (int64_t k = begin; k < end; k++) {
            uint32_t b = f->color_block[c] + (uint32_t)k;
            if (!seams || (f->across[b] > 0) == (seam == 1)) collapsed |= sb_vbd_block_in_turn(f, b, sweep, rates, w);
        }
    return collapsed;
}

void sb_fast_vbd_run(sb_fast_vbd* f, const sb_fast_vbd_step* st, const sb_worker* w) {
    int64_t begin, end;
    sb_worker_range(w, f->vertex_count, &begin, &end);
    sb_vbd_pack(f->x4, st->x, begin, end);
    sb_vbd_pack(f->x04, st->x0, begin, end);
    sb_vbd_pack(f->y4, st->y, begin, end);
    for (int64_t i = begin; i < end; i++) f->x04[4 * i + 3] = st->inv_mass[i] > 0.0 ? 1 : 0;
    if (st->chebyshev_rho > 0.0)
        for (size_t q = 4 * (size_t)begin; q < 4 * (size_t)end; q++) f->last4[q] = f->x4[q];
    const int64_t first = begin, past = end;
    sb_worker_range(w, f->block_count, &begin, &end);
    for (int64_t b = begin; b < end; b++) atomic_store_explicit(&f->done[b].sweeps, 0, memory_order_relaxed);
    sb_worker_barrier(w); /* publishes the packing and the zeros */
    const sb_vbd_rates rates = {sb_w_set((sb_real)(1.0 / st->dt)), sb_w_set((sb_real)(1.0 / (st->dt * st->dt))),
                                sb_w_set((sb_real)(st->drag / st->dt)), sb_w_set((sb_real)st->relaxation)};
    bool collapsed = false;
    double weight = 1.0;
    for (int it = 0; it < st->sweeps; it++) {
        for (uint32_t c = 0; c < f->color_count; c++) {
            sb_vbd_color_range(f, c, w->index, w->width, &begin, &end);
            collapsed |= sb_vbd_color_share(f, c, begin, end, (unsigned)it, &rates, w);
        }
        /* every block's sweep done before the acceleration, or before the unpacking */
        if (st->chebyshev_rho > 0.0 || it + 1 == st->sweeps) sb_worker_barrier(w);
        /* the last sweep's acceleration is of the worker's own range, which it unpacks: no barrier */
        if (st->chebyshev_rho > 0.0) {
            weight = sb_vbd_accelerate4(f, st->chebyshev_rho, it + 1, weight, first, past);
            if (it + 1 < st->sweeps) sb_worker_barrier(w);
        }
    }
    if (collapsed) sb_worker_raise(st->collapsed);
    /* the worker's own range, as packed: the vertices that move (inv_mass > 0, all in some lane) */
    for (int64_t i = first; i < past; i++) {
        for (int c = 0; c < 3; c++) st->positions4[4 * i + c] = f->x4[4 * i + c];
        if (st->inv_mass[i] > 0.0)
            for (int c = 0; c < 3; c++) st->x[3 * i + c] = f->x4[4 * i + c];
    }
}
