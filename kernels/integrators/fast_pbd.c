/* The SIMD sweeps of pbd and xpbd: kernels/integrators/pbd.c's step and projections
 * (the formulas are in its design note, which stays the reference) with
 * SB_WIDTH constraints of one color of a block per SIMD block, in sb_real.
 *
 * Layout. Every run of kernels/integrators/pbd.c's bond and triangle groups (one
 * color of one block of their blocked colorings) becomes slots, a multiple
 * of SB_WIDTH, holding the run's constraints in the same order; a SIMD
 * block's unused lanes copy a real constraint and are masked where
 * positions are written (kernels/runtime/wide.h's convention). A serial run (the
 * overflow color), whose constraints may share vertices, has one
 * constraint a SIMD block. Each slot keeps copies of what its projection reads
 * (vertex indices, rest length or rest cosines, compliance α = 1/k, the
 * damping as β = d/k, whether it is alive; a triangle slot also those of
 * the bond each edge carries, not alive where it carries none) and its λ;
 * the copies are made again when breakage or tearing changed the model
 * (the broken-bond and vertex counts say so). The positions being
 * projected are packed x y z w with the inverse mass (0 on fixed and held
 * vertices) in w, so that one 16-byte load per vertex brings everything a
 * projection needs of it, and one store puts it back.
 *
 * Cost. A triangle's six projections (its bonds, then its corners) run on
 * its vertices in registers, loaded and stored once: the bond pass's own
 * loads and stores are gone where triangles carry the bonds (the 100 ×
 * 100 sheet: all of them). Each projection is a chain of dependent
 * operations (an inverse square root and a division for a corner, beside
 * which a reciprocal), so SB_PBD_BLOCKS SIMD blocks of a run are projected
 * together, step by step, giving the processor independent chains to
 * overlap (bonds, short chains, gained nothing from it). Triangles of a run are sorted by the
 * edges that carry bonds (kernels/integrators/pbd.c), and an edge is projected only in
 * the blocks where some lane carries a live bond there. A corner's
 * W = Σ w |∇C|² is taken in closed form, and its lengths from one inverse
 * square root (sb_pbd_wide_corner). A block's vertex indices are read from
 * its slots by the loads and stores themselves (sb_wv_load4w_at), not
 * moved into a vector and out again lane by lane.
 *
 * Precision. The sweeps move each vertex's displacement in the step,
 * Δ = x − x_prev, not its position, and each constraint's edges at the
 * start of the step are taken once a step (x_prev,j − x_prev,i: a float
 * difference of nearby points, exact or rounded to the edge's own
 * precision); an edge is then that plus the displacements' difference.
 * Positions held in float and moved by every projection would be rounded
 * to the coordinates' precision (6e-8 m at 1 m) hundreds of times a step,
 * and v = Δ/dt would carry that over dt (3e-4 m/s at dt = 0.2 ms; the fast
 * Verlet step keeps its displacement for the same reason). Here
 * x = x_prev + Δ is rounded once a step, as in the scalar sweeps.
 *
 * A step is one job of the solver's team: the prediction (per vertex), the
 * start edges, the sweeps (the same order as the scalar sweeps: the bonds'
 * block colors, then the triangles', a block's runs in order on one
 * worker, a triangle's bonds and corners one after another on its
 * positions kept in registers), then v = (x − x_prev)/dt into the state's
 * arrays and the packed copies, fused with the finiteness and runaway
 * check. Lanes of a SIMD block, and blocks of a block color, write
 * disjoint vertices and a block's arithmetic does not depend on which
 * worker runs it: the state is bitwise the same for any thread count.
 *
 * Schedule. The sweeps have no barrier: a unit (one block of a group)
 * waits only for the units it shares vertices with, each to have finished
 * the sweep it must follow: a unit of an earlier phase (block color, in
 * sweep order) this sweep, of a later phase the sweep before. Every pair
 * of units that share a vertex is then ordered as in the scalar sweeps,
 * and units that share none run in any order, so each vertex sees the same
 * projections in the same order for any thread count. A unit's finished
 * sweeps are a counter on its own cache line (sb_worker_post, and
 * sb_worker_wait_at_least, which waits as the team's policy says). Each
 * worker runs its share of each phase's blocks (as a barrier per phase
 * split them), in each phase first the units that another worker's units
 * wait for: the workers meet only where their blocks touch (on the 100 ×
 * 100 sheet, two threads: one block of each, a few waits a sweep), and a
 * worker may run up to a block or so ahead of the other instead of both
 * waiting at every phase. Tearing re-points elements to a split vertex
 * only where they had its origin, so the waits found at creation still
 * cover every pair that shares one. When the team runs the step on one
 * worker (sb_team_run_adaptive, on a busy machine), that worker takes every
 * unit in index order, which is sweep order. A unit's start edges are taken by its
 * worker before its first sweep (they are then in that worker's cache, and
 * no barrier separates them from the sweeps). A step has 2 barriers (after
 * the prediction, before the velocities), where a barrier after each block
 * color made 12 on that sheet (2 + 5 sweeps × 2), and one after each color
 * of the elements about 45. Dropping the barriers alone changed little;
 * what made two threads pay was taking each unit's start edges on the
 * thread that projects it (before, half of them were written on the other
 * core): the bonds-alone step on two threads is then close to twice as
 * fast as on one (bench/results/pbd_peer.md; the barrier traces and the
 * before/after runs are in bench/results/notes/xpbd.md).
 *
 * Forces and energies. A position-based step needs no force: unless
 * something in the next step reads them (an external-force callback, the
 * adaptive stepper's energy balance, breakage, self-contact), the new
 * state's forces and energies are evaluated when first asked for
 * (sb_solver_settle). A collapsed edge (a bond or a corner's edge of
 * squared length under SB_PBD_COLLAPSED2) is flagged by the sweeps; the
 * forces are then evaluated at once, and their pass names the element. */
#include "kernels/integrators/fast_pbd.h"
#include "kernels/integrators/pbd_internal.h"
#include "kernels/integrators/pbd.h"
#include "kernels/interaction/breakage.h"
#include "kernels/runtime/wide.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A group's slots, run by run. */
typedef struct sb_pbd_slots {
    const sb_blocked* runs; /* the group's */
    uint32_t* first;        /* run_count + 1: each run's first slot, a multiple of SB_WIDTH */
    uint32_t total;         /* slots */
    uint32_t* item;         /* the model index each slot copies */
} sb_pbd_slots;

/* The copies of distance constraints' constants (a bond's), and λ, per slot. */
typedef struct sb_pbd_wide_distances {
    sb_real *r0, *alpha, *beta, *alive, *lambda; /* alive 0: broken, or no bond there */
} sb_pbd_wide_distances;

typedef struct sb_pbd_wide_bonds {
    sb_pbd_slots slots;
    uint32_t *i, *j;
    sb_real* edge[3]; /* x_i − x_j at the start of the step */
    sb_pbd_wide_distances d;
    bool damped; /* a bond with damping: the sweeps read the start positions too */
} sb_pbd_wide_bonds;

typedef struct sb_pbd_wide_triangles {
    sb_pbd_slots slots;
    uint32_t* v[3];
    sb_real* edge[2][3]; /* x_1 − x_0 and x_2 − x_0 at the start of the step */
    sb_real *cos0[3], *alpha, *alive, *lambda[3];
    sb_pbd_wide_distances bonds[3]; /* the bonds carried by edge c (vertices c, c + 1) */
    bool damped;                    /* a carried bond with damping */
} sb_pbd_wide_triangles;

/* How many sweeps a unit has finished in the step, alone on its cache line. */
typedef struct sb_pbd_done {
    _Alignas(64) atomic_uint sweeps;
} sb_pbd_done;

/* The sweeps' schedule ("Schedule" above). A unit is one block of a
 * group: the bonds' blocks are units 0 … nb − 1, the triangles' follow. */
typedef struct sb_pbd_schedule {
    uint32_t units, bond_units;
    uint32_t* phase;             /* units: its block color's place in a sweep */
    uint32_t *need_first, *need; /* unit u waits for units need[need_first[u] … need_first[u + 1]) */
    int width;                   /* the workers the plan is for */
    uint32_t *plan, *plan_first; /* worker i runs units plan[plan_first[i] … plan_first[i + 1]) in turn */
    sb_pbd_done* done;           /* units */
} sb_pbd_schedule;

struct sb_pbd_wide {
    sb_pbd_wide_bonds bonds;
    sb_pbd_wide_triangles triangles;
    sb_real *x4, *x04;         /* packed: displacements Δ in the step (w: inverse mass), positions at the start */
    uint32_t broken, vertices; /* the model's state the copies were made from */
    sb_pbd_schedule schedule;
};

bool sb_pbd_wide_applies(const sb_solver* s) { return s->fast && !s->def.collider_count && !s->def.handle_count; }

static void* sb_pbd_alloc(uint32_t count, size_t size) { return aligned_alloc(64, ((count * size) / 64 + 1) * 64); }

/* Constraints of run r, and of each SIMD block of its slots (one in a serial run). */
static uint32_t sb_pbd_run_count(const sb_blocked* g, uint32_t r) { return g->run_first[r + 1] - g->run_first[r]; }
static uint32_t sb_pbd_per_block(const sb_blocked* g, uint32_t r) { return g->run_serial[r] ? 1 : SB_WIDTH; }

/* Slots of the runs of g: SB_WIDTH constraints a block, one in a serial run's. */
static bool sb_pbd_slots_build(sb_pbd_slots* slots, const sb_blocked* g) {
    slots->runs = g;
    slots->first = malloc((g->run_count + 1) * sizeof *slots->first);
    if (!slots->first) return false;
    slots->first[0] = 0;
    for (uint32_t r = 0; r < g->run_count; r++) {
        uint32_t count = sb_pbd_run_count(g, r), per_block = sb_pbd_per_block(g, r);
        slots->first[r + 1] = slots->first[r] + (count + per_block - 1) / per_block * SB_WIDTH;
    }
    slots->total = slots->first[g->run_count];
    slots->item = sb_pbd_alloc(slots->total, sizeof *slots->item);
    if (!slots->item) return false;
    for (uint32_t r = 0; r < g->run_count; r++) {
        uint32_t count = sb_pbd_run_count(g, r), per_block = sb_pbd_per_block(g, r);
        for (uint32_t s = slots->first[r]; s < slots->first[r + 1]; s++) {
            uint32_t block = (s - slots->first[r]) / SB_WIDTH, lane = (s - slots->first[r]) % SB_WIDTH;
            uint32_t e = block * per_block + (lane < per_block ? lane : 0);
            slots->item[s] = g->order[g->run_first[r] + (e < count ? e : block * per_block)];
        }
    }
    return true;
}

/* Slot s's copies of bond e's constants (none alive for SB_PBD_NO_BOND). */
static void sb_pbd_bond_copy(const sb_pbd_wide_distances* d, uint32_t s, const sb_model* m, uint32_t e) {
    double k = e == SB_PBD_NO_BOND ? 0.0 : m->bond_k[e] + m->spring_k[e];
    bool alive = k > 0; /* a broken bond has no stiffness (kernels/interaction/breakage.c) */
    d->r0[s] = alive ? (sb_real)m->bond_r0[e] : 0;
    d->alpha[s] = (sb_real)(alive ? 1.0 / k : 1.0);
    d->beta[s] = (sb_real)(alive ? m->spring_damping[e] / k : 0.0);
    d->alive[s] = alive;
}

/* The copies of the model's bond constants in every slot. */
static void sb_pbd_bonds_copy(sb_pbd_wide_bonds* b, const sb_model* m) {
    b->damped = false;
    for (uint32_t s = 0; s < b->slots.total; s++) {
        uint32_t e = b->slots.item[s];
        b->i[s] = m->bond_i[e];
        b->j[s] = m->bond_j[e];
        sb_pbd_bond_copy(&b->d, s, m, e);
        b->damped |= b->d.beta[s] != 0;
    }
}

static void sb_pbd_triangles_copy(sb_pbd_wide_triangles* t, const sb_model* m, uint32_t* const edge_bond[3]) {
    t->damped = false;
    for (uint32_t s = 0; s < t->slots.total; s++) {
        uint32_t e = t->slots.item[s];
        bool alive = m->angle_k[e] > 0;
        for (int c = 0; c < 3; c++) {
            t->v[c][s] = m->tri_v[c][e];
            t->cos0[c][s] = (sb_real)m->tri_cos0[c][e];
            sb_pbd_bond_copy(&t->bonds[c], s, m, edge_bond[c][e]);
            t->damped |= t->bonds[c].beta[s] != 0;
        }
        t->alpha[s] = (sb_real)(alive ? 1.0 / m->angle_k[e] : 1.0);
        t->alive[s] = alive;
    }
}

/* The copies again when breakage or tearing changed the model since. */
static void sb_pbd_wide_sync(sb_pbd_wide* w, const sb_solver* s) {
    uint32_t broken = sb_breakage_count(s->breakage), vertices = s->live_vertices;
    if (broken == w->broken && vertices == w->vertices) return;
    sb_pbd_bonds_copy(&w->bonds, s->model);
    sb_pbd_triangles_copy(&w->triangles, s->model, s->pbd->edge_bond);
    w->broken = broken;
    w->vertices = vertices;
}

void sb_pbd_wide_destroy(sb_pbd_wide* w) {
    if (!w) return;
    sb_pbd_wide_bonds* b = &w->bonds;
    sb_pbd_wide_triangles* t = &w->triangles;
    void* arrays[] = {b->slots.first, t->slots.first, b->slots.item, b->i,         b->j,          b->d.r0,
                      b->d.alpha,     b->d.beta,      b->d.alive,    b->d.lambda,  t->slots.item, t->v[0],
                      t->v[1],        t->v[2],        t->cos0[0],    t->cos0[1],   t->cos0[2],    t->alpha,
                      t->alive,       t->lambda[0],   t->lambda[1],  t->lambda[2], w->x4,         w->x04};
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++) free(arrays[a]);
    sb_pbd_schedule* q = &w->schedule;
    void* schedule_arrays[] = {q->phase, q->need_first, q->need, q->plan, q->plan_first, q->done};
    for (size_t a = 0; a < sizeof schedule_arrays / sizeof *schedule_arrays; a++) free(schedule_arrays[a]);
    for (int c = 0; c < 3; c++) {
        sb_pbd_wide_distances* e = &t->bonds[c];
        void* edge_arrays[] = {b->edge[c], t->edge[0][c], t->edge[1][c], e->r0, e->alpha, e->beta, e->alive, e->lambda};
        for (size_t a = 0; a < sizeof edge_arrays / sizeof *edge_arrays; a++) free(edge_arrays[a]);
    }
    free(w);
}

/* ---- the schedule ------------------------------------------------------------ */

/* The group and block of unit u. */
static const sb_pbd_slots* sb_pbd_unit_slots(const sb_pbd_wide* w, uint32_t u, uint32_t* block) {
    bool bond = u < w->schedule.bond_units;
    *block = bond ? u : u - w->schedule.bond_units;
    return bond ? &w->bonds.slots : &w->triangles.slots;
}

/* Calls visit(v, context) for each vertex of unit u's slots (a vertex as
 * often as slots have it). */
static void sb_pbd_unit_vertices(const sb_pbd_wide* w, uint32_t u, void (*visit)(uint32_t, void*), void* context) {
    uint32_t block;
    const sb_pbd_slots* slots = sb_pbd_unit_slots(w, u, &block);
    const sb_blocked* g = slots->runs;
    bool bond = u < w->schedule.bond_units;
    const uint32_t* ends[3] = {w->bonds.i, w->bonds.j, NULL};
    if (!bond) ends[0] = w->triangles.v[0], ends[1] = w->triangles.v[1], ends[2] = w->triangles.v[2];
    for (uint32_t s = slots->first[g->block_first_run[block]]; s < slots->first[g->block_first_run[block + 1]]; s++)
        for (int a = 0; a < (bond ? 2 : 3); a++) visit(ends[a][s], context);
}

/* The neighbours' pass over a unit's vertices: each vertex's units
 * (vertex_first/vertex_units), counted or listed once per unit. */
typedef struct sb_pbd_neighbours {
    const sb_pbd_schedule* q;
    uint32_t unit, *stamp; /* stamp[v]: 1 + the last unit that counted vertex v */
    uint32_t *vertex_first, *vertex_units;
    uint32_t *mark, count, *out; /* mark[y]: 1 + the last unit that took unit y; out: NULL to count */
} sb_pbd_neighbours;

static void sb_pbd_count_vertex(uint32_t v, void* context) {
    sb_pbd_neighbours* n = context;
    if (n->stamp[v] == n->unit + 1) return;
    n->stamp[v] = n->unit + 1;
    if (n->out)
        n->vertex_units[n->vertex_first[v]++] = n->unit; /* filling: vertex_first ends one list on */
    else
        n->vertex_first[v + 1]++;
}

static void sb_pbd_take_neighbours(uint32_t v, void* context) {
    sb_pbd_neighbours* n = context;
    if (n->stamp[v] == n->unit + 1) return;
    n->stamp[v] = n->unit + 1;
    for (uint32_t e = v ? n->vertex_first[v - 1] : 0; e < n->vertex_first[v]; e++) {
        uint32_t y = n->vertex_units[e];
        /* units of one phase share no vertex, except the overflow color's, run in order on one worker */
        if (n->q->phase[y] == n->q->phase[n->unit] || n->mark[y] == n->unit + 1) continue;
        n->mark[y] = n->unit + 1;
        if (n->out) n->out[n->count] = y;
        n->count++;
    }
}

/* Unit u's worker in a team of `width` (the block color's blocks split as
 * sb_worker_range splits, the overflow color's all on worker 0). */
static int sb_pbd_unit_color(const sb_pbd_wide* w, uint32_t u) {
    uint32_t block;
    const sb_blocked* g = sb_pbd_unit_slots(w, u, &block)->runs;
    int color = 0;
    while (g->color_first_block[color + 1] <= block) color++;
    return color;
}

static int sb_pbd_owner(const sb_pbd_wide* w, uint32_t u, int width) {
    uint32_t block;
    const sb_blocked* g = sb_pbd_unit_slots(w, u, &block)->runs;
    int color = sb_pbd_unit_color(w, u);
    if (color == SB_OVERFLOW_COLOR) return 0;
    uint32_t count = g->color_first_block[color + 1] - g->color_first_block[color],
             at = block - g->color_first_block[color];
    uint32_t share = count / (uint32_t)width, extra = count % (uint32_t)width;
    /* worker i has [i share + min(i, extra), … + share + (i < extra)) */
    int i = 0;
    while (i + 1 < width && (uint32_t)(i + 1) * share + ((uint32_t)(i + 1) < extra ? (uint32_t)(i + 1) : extra) <= at)
        i++;
    return i;
}

/* The schedule of w's units for a team of `width` workers. */
static bool sb_pbd_schedule_build(sb_pbd_wide* w, uint32_t vertex_count, int width) {
    sb_pbd_schedule* q = &w->schedule;
    const sb_blocked* groups[2] = {w->bonds.slots.runs, w->triangles.slots.runs};
    q->bond_units = groups[0]->block_count;
    q->units = q->bond_units + groups[1]->block_count;
    q->width = width;
    uint32_t units = q->units ? q->units : 1;
    q->phase = malloc(units * sizeof *q->phase);
    q->need_first = calloc(units + 1, sizeof *q->need_first);
    q->plan = malloc(units * sizeof *q->plan);
    q->plan_first = calloc((size_t)width + 1, sizeof *q->plan_first);
    q->done = aligned_alloc(_Alignof(sb_pbd_done), units * sizeof *q->done);
    sb_pbd_neighbours n = {.q = q,
                           .stamp = calloc((size_t)vertex_count + 1, sizeof *n.stamp),
                           .vertex_first = calloc((size_t)vertex_count + 2, sizeof *n.vertex_first),
                           .mark = calloc(units, sizeof *n.mark)};
    int* owner = malloc(units * sizeof *owner);
    bool ok = q->phase && q->need_first && q->plan && q->plan_first && q->done && n.stamp && n.vertex_first && n.mark &&
              owner;
    /* phases: the bonds' block colors, then the triangles', in sweep order */
    uint32_t phase = 0, u = 0;
    for (int g = 0; ok && g < 2; g++)
        for (int color = 0; color < SB_MAX_COLORS; color++) {
            uint32_t first = groups[g]->color_first_block[color], end = groups[g]->color_first_block[color + 1];
            for (uint32_t b = first; b < end; b++) q->phase[u++] = phase;
            phase += end > first;
        }
    /* each vertex's units */
    for (n.unit = 0; ok && n.unit < q->units; n.unit++) sb_pbd_unit_vertices(w, n.unit, sb_pbd_count_vertex, &n);
    for (uint32_t v = 0; ok && v < vertex_count; v++) n.vertex_first[v + 1] += n.vertex_first[v];
    ok = ok && (n.vertex_units = malloc((n.vertex_first[vertex_count] + 1) * sizeof *n.vertex_units));
    if (ok) memset(n.stamp, 0, ((size_t)vertex_count + 1) * sizeof *n.stamp);
    n.out = n.vertex_units; /* any non-NULL: fill */
    for (n.unit = 0; ok && n.unit < q->units; n.unit++) sb_pbd_unit_vertices(w, n.unit, sb_pbd_count_vertex, &n);
    /* vertex_first[v] now ends v's list: v's units are [vertex_first[v − 1], vertex_first[v]) */
    /* each unit's neighbours in other phases: counted, then listed */
    for (int pass = 0; ok && pass < 2; pass++) {
        if (ok) memset(n.stamp, 0, ((size_t)vertex_count + 1) * sizeof *n.stamp);
        if (ok) memset(n.mark, 0, units * sizeof *n.mark);
        n.out = pass ? q->need : NULL;
        n.count = 0;
        for (n.unit = 0; n.unit < q->units; n.unit++) {
            sb_pbd_unit_vertices(w, n.unit, sb_pbd_take_neighbours, &n);
            q->need_first[n.unit + 1] = n.count;
        }
        if (!pass) ok = (q->need = malloc((n.count + 1) * sizeof *q->need)) != NULL;
    }
    /* the plan: each worker's units phase by phase, in each phase those
     * that another worker's units wait for (or that wait for them) first,
     * so that the other worker finds them done; the overflow color's, which
     * may share vertices, in order */
    for (uint32_t x = 0; ok && x < q->units; x++) owner[x] = sb_pbd_owner(w, x, width);
    uint32_t at = 0;
    for (int i = 0; ok && i < width; i++) {
        q->plan_first[i] = at;
        for (uint32_t first = 0, end; first < q->units; first = end) {
            for (end = first; end < q->units && q->phase[end] == q->phase[first]; end++) {
            }
            bool serial = first < end && sb_pbd_unit_color(w, first) == SB_OVERFLOW_COLOR;
            for (int shared = 1; shared >= 0; shared--)
                for (uint32_t x = first; x < end; x++) {
                    if (owner[x] != i) continue;
                    bool across = false;
                    for (uint32_t e = q->need_first[x]; e < q->need_first[x + 1]; e++) across |= owner[q->need[e]] != i;
                    if (serial ? shared : across == shared) q->plan[at++] = x;
                }
        }
    }
    if (ok) q->plan_first[width] = at;
    free(n.stamp), free(n.vertex_first), free(n.vertex_units), free(n.mark), free(owner);
    return ok;
}

sb_pbd_wide* sb_pbd_wide_create(const sb_pbd* p, const sb_model* m) {
    sb_pbd_wide* w = calloc(1, sizeof *w);
    if (!w) return NULL;
    sb_pbd_wide_bonds* b = &w->bonds;
    sb_pbd_wide_triangles* t = &w->triangles;
    bool ok = sb_pbd_slots_build(&b->slots, &p->bonds.runs) && sb_pbd_slots_build(&t->slots, &p->triangles.runs);
    uint32_t nb = b->slots.total, nt = t->slots.total;
    uint32_t** indices[5] = {&b->i, &b->j, &t->v[0], &t->v[1], &t->v[2]};
    uint32_t index_counts[5] = {nb, nb, nt, nt, nt};
    sb_real** reals[11] = {&b->d.r0,    &b->d.alpha, &b->d.beta, &b->d.alive, &b->d.lambda, &t->cos0[0],
                           &t->cos0[1], &t->cos0[2], &t->alpha,  &t->alive,   &t->lambda[0]};
    uint32_t real_counts[11] = {nb, nb, nb, nb, nb, nt, nt, nt, nt, nt, nt};
    for (int a = 0; ok && a < 5; a++) ok = (*indices[a] = sb_pbd_alloc(index_counts[a], sizeof(uint32_t))) != NULL;
    for (int a = 0; ok && a < 11; a++) ok = (*reals[a] = sb_pbd_alloc(real_counts[a], sizeof(sb_real))) != NULL;
    ok = ok && (t->lambda[1] = sb_pbd_alloc(nt, sizeof(sb_real))) && (t->lambda[2] = sb_pbd_alloc(nt, sizeof(sb_real)));
    for (int c = 0; ok && c < 3; c++) {
        sb_pbd_wide_distances* e = &t->bonds[c];
        sb_real** edge_reals[8] = {&b->edge[c], &t->edge[0][c], &t->edge[1][c], &e->r0,
                                   &e->alpha,   &e->beta,       &e->alive,      &e->lambda};
        for (int a = 0; ok && a < 8; a++) ok = (*edge_reals[a] = sb_pbd_alloc(a ? nt : nb, sizeof(sb_real))) != NULL;
    }
    ok = ok && (w->x4 = sb_pbd_alloc(4 * m->vertex_count, sizeof(sb_real))) &&
         (w->x04 = sb_pbd_alloc(4 * m->vertex_count, sizeof(sb_real)));
    if (!ok) {
        sb_pbd_wide_destroy(w);
        return NULL;
    }
    sb_pbd_bonds_copy(b, m);
    sb_pbd_triangles_copy(t, m, p->edge_bond);
    w->vertices = m->vertex_count;
    if (!sb_pbd_schedule_build(w, m->vertex_count, p->threads)) {
        sb_pbd_wide_destroy(w);
        return NULL;
    }
    return w;
}

/* ---- the step --------------------------------------------------------------- */

typedef struct sb_pbd_wide_job {
    sb_solver* solver;
    sb_pbd_wide* wide;
    double dt;
    int iterations;
    bool xpbd;
    atomic_int collapsed, bad;
} sb_pbd_wide_job;

/* The constants of one sweep's projections. */
typedef struct sb_pbd_sweep {
    sb_real* x4; /* the displacements */
    sb_wide inv_dt2, inv_dt;
    bool first;      /* the step's first sweep: λ starts at 0 */
    bool accumulate; /* xpbd: λ kept between sweeps */
} sb_pbd_sweep;

/* Edges shorter than this (squared, m²) count as collapsed: the direction
 * is lost; kept far below any rest length so that the force pass, which
 * then runs, names the element. */
#define SB_PBD_COLLAPSED2 1e-30

/* Δλ = (−C − α̃ λ − γ rate) / ((1 + γ) W + α̃), λ += Δλ where kept. */
static inline sb_wide sb_pbd_wide_delta(const sb_pbd_sweep* k, sb_wide C, sb_wide alpha, sb_wide W, sb_wide gamma,
                                        sb_wide rate, sb_real* lambda) {
    sb_wide at = sb_w_mul(alpha, k->inv_dt2), zero = sb_w_set(0);
    sb_wide l = k->first || !k->accumulate ? zero : sb_w_load(lambda);
    sb_wide numerator = sb_w_sub(sb_w_sub(sb_w_sub(zero, C), sb_w_mul(at, l)), sb_w_mul(gamma, rate));
    sb_wide d = sb_w_div(numerator, sb_w_add(sb_w_mul(sb_w_add(sb_w_set(1), gamma), W), at));
    if (k->accumulate) sb_w_store(lambda, sb_w_add(l, d));
    return d;
}

/* The start edges x_i − x_j of a block's lanes. */
static inline sb_wvec3 sb_pbd_edge(sb_real* const edge[3], uint32_t s) {
    return (sb_wvec3){sb_w_load(edge[0] + s), sb_w_load(edge[1] + s), sb_w_load(edge[2] + s)};
}

/* The distance constraints of a block's lanes at slot s of d on the edges
 * n = x_i − x_j (turned into n̂: 0 for a collapsed edge, marked in
 * *collapsed), W = w_i + w_j, `moved` the edges' change in the step (read
 * when damped): Δλ, 0 where not alive. */
static inline sb_wide sb_pbd_wide_distance(const sb_pbd_wide_distances* d, const sb_pbd_sweep* k, uint32_t s,
                                           sb_wvec3* n, sb_wvec3 moved, sb_wide W, bool damped, sb_wmask* collapsed) {
    sb_wide r2 = sb_wv_dot(*n, *n), tiny = sb_w_set((sb_real)SB_PBD_COLLAPSED2);
    *collapsed = sb_w_less(r2, tiny);
    sb_wide inv_r = sb_w_rsqrt(sb_w_max(r2, tiny));
    *n = sb_wv_scale(*n, inv_r);
    sb_wide gamma = sb_w_set(0), rate = sb_w_set(0);
    if (damped) {
        gamma = sb_w_mul(sb_w_load(d->beta + s), k->inv_dt);
        rate = sb_wv_dot(*n, moved);
    }
    sb_wide C = sb_w_sub(sb_w_mul(r2, inv_r), sb_w_load(d->r0 + s));
    sb_wide delta = sb_pbd_wide_delta(k, C, sb_w_load(d->alpha + s), W, gamma, rate, d->lambda + s);
    return sb_w_mul(delta, sb_w_load(d->alive + s));
}

/* The bonds of the block at slot s, `count` of them real. Returns whether one collapsed. */
static inline bool sb_pbd_wide_bond_block(const sb_pbd_wide_bonds* b, const sb_pbd_sweep* k, uint32_t s, int count,
                                          bool damped) {
    sb_windex ii = sb_w_index(b->i + s), jj = sb_w_index(b->j + s);
    sb_wide wi, wj;
    sb_wvec3 xi = sb_wv_load4w(k->x4, ii, &wi), xj = sb_wv_load4w(k->x4, jj, &wj);
    sb_wvec3 moved = sb_wv_sub(xi, xj); /* Δ_i − Δ_j */
    sb_wvec3 n = sb_wv_add(sb_pbd_edge(b->edge, s), moved);
    sb_wmask collapsed;
    sb_wide d = sb_pbd_wide_distance(&b->d, k, s, &n, moved, sb_w_add(wi, wj), damped, &collapsed);
    sb_wv_store4w(k->x4, ii, sb_wv_add(xi, sb_wv_scale(n, sb_w_mul(wi, d))), wi, count);
    sb_wv_store4w(k->x4, jj, sb_wv_sub(xj, sb_wv_scale(n, sb_w_mul(wj, d))), wj, count);
    return sb_w_any(collapsed, count);
}

/* Corner at p[q] of the triangle (p[q], p[q+1], p[q+2]) of a block, on the
 * positions in registers: C = â·b̂ − cos θ0 (a, b the edges to p[q+1],
 * p[q+2]), with ∇_{q+1} C = (b̂ − c â)/|a| = b/(|a||b|) − c a/|a|²,
 * ∇_{q+2} C = a/(|a||b|) − c b/|b|², ∇_q C = −(the two), whose squares sum
 * to W = (1 − c²)(w_{q+1}/|a|² + w_{q+2}/|b|² + w_q (1/|a|² + 1/|b|² −
 * 2c/(|a||b|))) (c = cos θ; the same W as kernels/integrators/pbd.c's sum of the
 * three, in closed form). One inverse square root of |a|²|b|² gives
 * 1/(|a||b|), and its reciprocal (an estimate and a Newton step, ~1 ulp,
 * beside the inverse square root rather than its square after it)
 * 1/|a|² = |b|²/(|a|²|b|²) and 1/|b|²: the gradients come from a and b
 * unnormalised.
 *
 * The projections of a triangle's corners follow one another, each on the
 * positions the one before moved, so the step's time is that chain's length
 * (the blocks projected together overlap only a few). What does not need
 * the inverse square root is taken from the dot products beside it: W =
 * sin² · M/(|a|²|b|²), with sin² = |a × b|²/(|a|²|b|²) = (|a|²|b|² −
 * (a·b)²)/(|a|²|b|²) and M = (w_{q+1} + w_q)|b|² + (w_{q+2} + w_q)|a|² −
 * 2 w_q a·b (the bracket above times |a|²|b|²); the numerator's cos θ0 − α̃ λ
 * before it too; and the inverse masses arrive multiplied by the
 * triangle's aliveness (`wl`, 0 for a dead corner, whose W is then 0 and
 * Δλ finite). Returns the collapsed lanes (an edge, or the product, under
 * SB_PBD_COLLAPSED2). */
static inline sb_wmask sb_pbd_wide_corner(const sb_pbd_sweep* k, sb_wvec3 p[3], const sb_wide wl[3], int q,
                                          sb_wide cos0, sb_wide at, sb_real* lambda) {
    int q1 = (q + 1) % 3, q2 = (q + 2) % 3;
    sb_wvec3 a = sb_wv_sub(p[q1], p[q]), b = sb_wv_sub(p[q2], p[q]);
    sb_wide A2 = sb_wv_dot(a, a), B2 = sb_wv_dot(b, b), D = sb_wv_dot(a, b), AB2 = sb_w_mul(A2, B2);
    sb_wide tiny = sb_w_set((sb_real)SB_PBD_COLLAPSED2), zero = sb_w_set(0);
    sb_wmask collapsed = sb_w_less(sb_w_min(A2, B2), tiny) | sb_w_less(AB2, tiny);
    /* beside the inverse square root */
    sb_wide cross2 = sb_w_sub(AB2, sb_w_mul(D, D)); /* |a × b|² */
    sb_wide wq2 = sb_w_add(wl[q], wl[q]);
    sb_wide M = sb_w_sub(sb_w_add(sb_w_mul(sb_w_add(wl[q1], wl[q]), B2), sb_w_mul(sb_w_add(wl[q2], wl[q]), A2)),
                         sb_w_mul(wq2, D));
    sb_wide l = k->first || !k->accumulate ? zero : sb_w_load(lambda);
    sb_wide target = sb_w_sub(cos0, sb_w_mul(at, l)); /* Δλ = (cos θ0 − α̃ λ − c)/(W + α̃) */
    sb_wide clamped = sb_w_max(AB2, tiny);
    sb_wide iab = sb_w_rsqrt(clamped), iab2 = sb_w_recip(clamped); /* 1/(|a||b|), its square */
    sb_wide cosine = sb_w_mul(D, iab);
    sb_wide sin2 = sb_w_mul(cross2, iab2), S = sb_w_mul(M, iab2);
    sb_wide d = sb_w_div(sb_w_sub(target, cosine), sb_w_add(sb_w_mul(sin2, S), at));
    if (k->accumulate) sb_w_store(lambda, sb_w_add(l, d));
    sb_wide ia2 = sb_w_mul(iab2, B2), ib2 = sb_w_mul(iab2, A2);
    sb_wvec3 g1 = sb_wv_sub(sb_wv_scale(b, iab), sb_wv_scale(a, sb_w_mul(cosine, ia2))); /* ∇C */
    sb_wvec3 g2 = sb_wv_sub(sb_wv_scale(a, iab), sb_wv_scale(b, sb_w_mul(cosine, ib2)));
    p[q1] = sb_wv_add(p[q1], sb_wv_scale(g1, sb_w_mul(wl[q1], d)));
    p[q2] = sb_wv_add(p[q2], sb_wv_scale(g2, sb_w_mul(wl[q2], d)));
    p[q] = sb_wv_sub(p[q], sb_wv_scale(sb_wv_add(g1, g2), sb_w_mul(wl[q], d)));
    return collapsed;
}

/* Triangle blocks projected together. A triangle's six projections are a
 * chain of dependent operations, each tens of operations long; a few
 * independent SIMD blocks of a run, their steps interleaved, give the
 * processor that many chains to overlap (a third less time for the
 * corners step at three blocks, little more at four; bonds, whose chain is
 * short, gained nothing: bench/results/notes/xpbd.md). Inlined
 * with the count a constant, so that the loops over the blocks unroll. */
#define SB_PBD_BLOCKS 3
#define SB_PBD_INLINE static inline __attribute__((always_inline))

/* A block of triangles in registers: vertex indices, inverse masses, the
 * positions relative to the start of vertex 0 (its displacement, the
 * others' start edges plus theirs), and the start edges (edge[0] = 0):
 * a vertex's displacement is p − edge. */
typedef struct sb_pbd_triangle_regs {
    const uint32_t* v[3];
    sb_wide w[3];
    sb_wvec3 p[3], edge[3];
    sb_wmask collapsed;
} sb_pbd_triangle_regs;

SB_PBD_INLINE void sb_pbd_triangle_load(const sb_pbd_wide_triangles* t, const sb_pbd_sweep* k, uint32_t s,
                                        sb_pbd_triangle_regs* r) {
    for (int c = 0; c < 3; c++) {
        r->v[c] = t->v[c] + s;
        r->p[c] = sb_wv_load4w_at(k->x4, r->v[c], &r->w[c]);
        r->edge[c] = c ? sb_pbd_edge(t->edge[c - 1], s) : (sb_wvec3){sb_w_set(0), sb_w_set(0), sb_w_set(0)};
        if (c) r->p[c] = sb_wv_add(r->p[c], r->edge[c]);
    }
    r->collapsed = 0;
}

/* The bond carried by edge c (vertices c, c + 1) of a block's triangles. */
SB_PBD_INLINE void sb_pbd_triangle_edge(const sb_pbd_wide_triangles* t, const sb_pbd_sweep* k, uint32_t s,
                                        sb_pbd_triangle_regs* r, int c, bool damped) {
    int c1 = (c + 1) % 3;
    sb_wvec3 n = sb_wv_sub(r->p[c], r->p[c1]), moved = n;
    if (damped) moved = sb_wv_sub(n, sb_wv_sub(r->edge[c], r->edge[c1]));
    sb_wmask flat;
    sb_wide d = sb_pbd_wide_distance(&t->bonds[c], k, s, &n, moved, sb_w_add(r->w[c], r->w[c1]), damped, &flat);
    r->collapsed |= flat;
    r->p[c] = sb_wv_add(r->p[c], sb_wv_scale(n, sb_w_mul(r->w[c], d)));
    r->p[c1] = sb_wv_sub(r->p[c1], sb_wv_scale(n, sb_w_mul(r->w[c1], d)));
}

/* Whether a live bond is on some lane of `blocks` blocks from slot s. */
SB_PBD_INLINE bool sb_pbd_carries(const sb_pbd_wide_distances* d, uint32_t s, int blocks) {
    sb_wmask live = 0;
    for (int h = 0; h < blocks; h++) live |= sb_w_less(sb_w_set(0), sb_w_load(d->alive + s + (uint32_t)h * SB_WIDTH));
    return sb_w_any(live, SB_WIDTH);
}

/* The triangles of `blocks` blocks from slot s: the bonds their edges
 * carry, then their three corners, in turn on the positions kept in
 * registers; then each vertex's move added once. */
SB_PBD_INLINE bool sb_pbd_wide_triangle_blocks(const sb_pbd_wide_triangles* t, const sb_pbd_sweep* k, uint32_t s,
                                               const int lanes[], int blocks, bool damped) {
    sb_pbd_triangle_regs r[SB_PBD_BLOCKS];
    for (int h = 0; h < blocks; h++) sb_pbd_triangle_load(t, k, s + (uint32_t)h * SB_WIDTH, &r[h]);
        /* Unrolled, so that p[c] names registers: as a loop the positions went
         * through the stack (a few % slower: bench/results/notes/xpbd.md). */
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++) {
        if (!sb_pbd_carries(&t->bonds[c], s, blocks)) continue;
        for (int h = 0; h < blocks; h++) sb_pbd_triangle_edge(t, k, s + (uint32_t)h * SB_WIDTH, &r[h], c, damped);
    }
    sb_wide wl[SB_PBD_BLOCKS][3], at[SB_PBD_BLOCKS];
    for (int h = 0; h < blocks; h++) {
        sb_wide alive = sb_w_load(t->alive + s + (uint32_t)h * SB_WIDTH);
        for (int c = 0; c < 3; c++) wl[h][c] = sb_w_mul(r[h].w[c], alive);
        at[h] = sb_w_mul(sb_w_load(t->alpha + s + (uint32_t)h * SB_WIDTH), k->inv_dt2);
    }
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++)
        for (int h = 0; h < blocks; h++) {
            uint32_t slot = s + (uint32_t)h * SB_WIDTH;
            r[h].collapsed |=
                sb_pbd_wide_corner(k, r[h].p, wl[h], c, sb_w_load(t->cos0[c] + slot), at[h], t->lambda[c] + slot);
        }
    bool any = false;
    for (int h = 0; h < blocks; h++) {
        for (int c = 0; c < 3; c++) {
            sb_wvec3 moved = c ? sb_wv_sub(r[h].p[c], r[h].edge[c]) : r[h].p[c];
            sb_wv_store4w_at(k->x4, r[h].v[c], moved, r[h].w[c], lanes[h]);
        }
        any |= sb_w_any(r[h].collapsed, lanes[h]);
    }
    return any;
}

/* Real lanes of the block at slot s of run r. */
static int sb_pbd_block_lanes(const sb_pbd_slots* slots, uint32_t r, uint32_t s) {
    if (slots->runs->run_serial[r]) return 1;
    uint32_t left = sb_pbd_run_count(slots->runs, r) - (s - slots->first[r]);
    return left < SB_WIDTH ? (int)left : SB_WIDTH;
}

/* The projections of `blocks` SIMD blocks of a run: the group, the sweep, the
 * first block's slot, each block's real lanes; returns whether an edge
 * collapsed. */
typedef bool (*sb_pbd_block_fn)(const void* group, const sb_pbd_sweep* k, uint32_t s, const int lanes[], int blocks);

static bool sb_pbd_undamped_bonds(const void* group, const sb_pbd_sweep* k, uint32_t s, const int lanes[], int blocks) {
    (void)blocks; /* one */
    return sb_pbd_wide_bond_block(group, k, s, lanes[0], false);
}

static bool sb_pbd_damped_bonds(const void* group, const sb_pbd_sweep* k, uint32_t s, const int lanes[], int blocks) {
    (void)blocks; /* one */
    return sb_pbd_wide_bond_block(group, k, s, lanes[0], true);
}

static bool sb_pbd_undamped_triangles(const void* group, const sb_pbd_sweep* k, uint32_t s, const int lanes[],
                                      int blocks) {
    return blocks == SB_PBD_BLOCKS ? sb_pbd_wide_triangle_blocks(group, k, s, lanes, SB_PBD_BLOCKS, false)
                                   : sb_pbd_wide_triangle_blocks(group, k, s, lanes, 1, false);
}

static bool sb_pbd_damped_triangles(const void* group, const sb_pbd_sweep* k, uint32_t s, const int lanes[],
                                    int blocks) {
    return blocks == SB_PBD_BLOCKS ? sb_pbd_wide_triangle_blocks(group, k, s, lanes, SB_PBD_BLOCKS, true)
                                   : sb_pbd_wide_triangle_blocks(group, k, s, lanes, 1, true);
}

/* Run r's slots, `together` SIMD blocks at a time (1 or SB_PBD_BLOCKS),
 * one in a serial run, whose blocks may share vertices. */
static bool sb_pbd_run(const sb_pbd_slots* slots, uint32_t r, const void* group, sb_pbd_block_fn project,
                       uint32_t together, const sb_pbd_sweep* k) {
    bool collapsed = false;
    uint32_t end = slots->first[r + 1], step = slots->runs->run_serial[r] ? 1 : together;
    for (uint32_t s = slots->first[r], blocks; s < end; s += blocks * SB_WIDTH) {
        blocks = s + step * SB_WIDTH <= end ? step : 1;
        int lanes[SB_PBD_BLOCKS] = {sb_pbd_block_lanes(slots, r, s)};
        for (uint32_t h = 1; h < blocks; h++) lanes[h] = sb_pbd_block_lanes(slots, r, s + h * SB_WIDTH);
        collapsed |= project(group, k, s, lanes, (int)blocks);
    }
    return collapsed;
}

/* Unit u's runs in order (a block of bonds, one SIMD block at a time, or
 * of triangles, SB_PBD_BLOCKS at a time). */
static bool sb_pbd_unit(const sb_pbd_wide* wide, uint32_t u, const sb_pbd_sweep* k) {
    uint32_t block;
    const sb_pbd_slots* slots = sb_pbd_unit_slots(wide, u, &block);
    bool bond = u < wide->schedule.bond_units;
    const void* group = bond ? (const void*)&wide->bonds : (const void*)&wide->triangles;
    sb_pbd_block_fn project = bond ? (wide->bonds.damped ? sb_pbd_damped_bonds : sb_pbd_undamped_bonds)
                                   : (wide->triangles.damped ? sb_pbd_damped_triangles : sb_pbd_undamped_triangles);
    bool collapsed = false;
    for (uint32_t r = slots->runs->block_first_run[block]; r < slots->runs->block_first_run[block + 1]; r++)
        collapsed |= sb_pbd_run(slots, r, group, project, bond ? 1 : SB_PBD_BLOCKS, k);
    return collapsed;
}

/* This worker's turns [begin, end) and the unit of turn e: its plan's, or,
 * when the job runs on one worker (sb_team_run_adaptive chose the caller
 * alone, whatever width the plan is for), every unit in index order, which
 * is sweep order: each unit then finds the units it waits for done. */
static uint32_t sb_pbd_turns_begin(const sb_pbd_schedule* q, const sb_worker* w) {
    return w->width == 1 ? 0 : q->plan_first[w->index];
}
static uint32_t sb_pbd_turns_end(const sb_pbd_schedule* q, const sb_worker* w) {
    return w->width == 1 ? q->units : q->plan_first[w->index + 1];
}
static uint32_t sb_pbd_turn(const sb_pbd_schedule* q, const sb_worker* w, uint32_t e) {
    return w->width == 1 ? e : q->plan[e];
}

/* Sweep `sweep` (0, 1, …) of this worker's units in its plan's order, each
 * once the units it waits for have finished the sweeps it must follow:
 * those of earlier phases this sweep, those of later phases the sweep
 * before. */
static bool sb_pbd_sweep_units(const sb_worker* w, sb_pbd_schedule* q, const sb_pbd_wide* wide, const sb_pbd_sweep* k,
                               unsigned sweep) {
    bool collapsed = false;
    for (uint32_t e = sb_pbd_turns_begin(q, w); e < sb_pbd_turns_end(q, w); e++) {
        uint32_t u = sb_pbd_turn(q, w, e);
        for (uint32_t n = q->need_first[u]; n < q->need_first[u + 1]; n++) {
            uint32_t y = q->need[n];
            sb_worker_wait_at_least(w, &q->done[y].sweeps, sweep + (q->phase[y] < q->phase[u]));
        }
        collapsed |= sb_pbd_unit(wide, u, k);
        sb_worker_post(w, &q->done[u].sweeps, sweep + 1);
    }
    return collapsed;
}

/* This worker's vertices [begin, end). */
static void sb_pbd_vertex_share(const sb_worker* w, const sb_solver* s, int64_t* begin, int64_t* end) {
    sb_worker_range(w, s->state.vertex_count, begin, end);
}

/* Δ = dt v after v += dt (g + f_ext/m − drag v) on free vertices (in
 * double, as the scalar step), packed with the inverse mass; x_prev packed. */
static void sb_pbd_wide_predict(const sb_worker* w, const sb_pbd_wide_job* job) {
    const sb_solver* s = job->solver;
    const sb_state* st = &s->state;
    const double *inv_mass = sb_inv_mass(s), dt = job->dt;
    const sb_real* x[3] = {st->x, st->y, st->z};
    const sb_real* v[3] = {st->vx, st->vy, st->vz};
    int64_t begin, end;
    sb_pbd_vertex_share(w, s, &begin, &end);
    for (int64_t i = begin; i < end; i++) {
        sb_real *x4 = job->wide->x4 + 4 * i, *x04 = job->wide->x04 + 4 * i;
        for (int c = 0; c < 3; c++) {
            double vc = sb_pbd_predicted_velocity(s, (uint32_t)i, c, v[c][i], dt);
            x04[c] = x[c][i];
            x4[c] = (sb_real)(dt * vc);
        }
        x4[3] = (sb_real)inv_mass[i];
        x04[3] = 0;
    }
}

/* x = x_prev + Δ, v = Δ/dt into the state's arrays and the packed copies
 * on free vertices; raises bad for a value not finite or a vertex that ran
 * away (sb_check_state then names it). */
static void sb_pbd_wide_finish(const sb_worker* w, sb_pbd_wide_job* job) {
    sb_solver* s = job->solver;
    sb_state* st = &s->state;
    sb_real* x[3] = {st->x, st->y, st->z};
    sb_real* v[3] = {st->vx, st->vy, st->vz};
    const double inv_dt = 1.0 / job->dt;
    int64_t begin, end;
    sb_pbd_vertex_share(w, s, &begin, &end);
    int bad = 0;
    for (int64_t i = begin; i < end; i++) {
        if (s->model->fixed[i]) continue; /* inverse mass 0: never moved */
        const sb_real *x4 = job->wide->x4 + 4 * i, *x04 = job->wide->x04 + 4 * i;
        for (int c = 0; c < 3; c++) {
            sb_real xc = (sb_real)((double)x04[c] + x4[c]), vc = (sb_real)(x4[c] * inv_dt);
            x[c][i] = s->positions4[4 * i + c] = xc;
            v[c][i] = s->velocities4[4 * i + c] = vc;
            bad |= !(fabs(xc - s->center[c]) <= s->runaway) | !isfinite(vc);
        }
    }
    if (bad) sb_worker_raise(&job->bad);
}

/* out[c][s] = x_prev of b[s] − x_prev of a[s] for the slots [begin, end)
 * (multiples of SB_WIDTH). */
static void sb_pbd_start_edges(const sb_real* x04, const uint32_t* a, const uint32_t* b, sb_real* const out[3],
                               uint32_t begin, uint32_t end) {
    for (uint32_t s = begin; s < end; s += SB_WIDTH) {
        sb_wvec3 e = sb_wv_sub(sb_wv_load4(x04, sb_w_index(b + s)), sb_wv_load4(x04, sb_w_index(a + s)));
        sb_w_store(out[0] + s, e.x);
        sb_w_store(out[1] + s, e.y);
        sb_w_store(out[2] + s, e.z);
    }
}

/* The start edges of this worker's units' slots: each unit's by the worker
 * that projects it, so that they are in its cache, and no barrier is
 * needed between them and the sweeps. */
static void sb_pbd_unit_edges(const sb_worker* w, sb_pbd_wide* wide) {
    const sb_pbd_schedule* q = &wide->schedule;
    sb_pbd_wide_bonds* b = &wide->bonds;
    sb_pbd_wide_triangles* t = &wide->triangles;
    for (uint32_t e = sb_pbd_turns_begin(q, w); e < sb_pbd_turns_end(q, w); e++) {
        uint32_t u = sb_pbd_turn(q, w, e), block;
        const sb_pbd_slots* slots = sb_pbd_unit_slots(wide, u, &block);
        uint32_t begin = slots->first[slots->runs->block_first_run[block]];
        uint32_t end = slots->first[slots->runs->block_first_run[block + 1]];
        if (u < q->bond_units)
            sb_pbd_start_edges(wide->x04, b->j, b->i, b->edge, begin, end);
        else
            for (int c = 1; c < 3; c++) sb_pbd_start_edges(wide->x04, t->v[0], t->v[c], t->edge[c - 1], begin, end);
    }
}

static void sb_pbd_wide_sweeps(void* context, const sb_worker* w) {
    sb_pbd_wide_job* job = context;
    sb_pbd_wide* wide = job->wide;
    sb_pbd_wide_predict(w, job);
    sb_worker_barrier(w);
    sb_pbd_unit_edges(w, wide);
    sb_pbd_sweep k = {wide->x4, sb_w_set((sb_real)(1.0 / (job->dt * job->dt))), sb_w_set((sb_real)(1.0 / job->dt)),
                      true, job->xpbd};
    bool collapsed = false;
    for (int it = 0; it < job->iterations; it++, k.first = false)
        collapsed |= sb_pbd_sweep_units(w, &wide->schedule, wide, &k, (unsigned)it);
    if (collapsed) sb_worker_raise(&job->collapsed);
    sb_worker_barrier(w);
    sb_pbd_wide_finish(w, job);
}

uint32_t sb_pbd_wide_barriers(const sb_solver* s) {
    (void)s;
    return 2;
}

/* Marks unit u's vertices in a byte array (sb_pbd_wide_schedule_faults). */
static void sb_pbd_mark_vertex(uint32_t v, void* context) { ((uint8_t*)context)[v] = 1; }

typedef struct sb_pbd_overlap {
    const uint8_t* marked;
    bool shared;
} sb_pbd_overlap;

static void sb_pbd_check_vertex(uint32_t v, void* context) {
    sb_pbd_overlap* o = context;
    o->shared |= o->marked[v] != 0;
}

uint32_t sb_pbd_wide_schedule_faults(const sb_solver* s, uint32_t* across) {
    const sb_pbd_wide* w = s->pbd->wide;
    const sb_pbd_schedule* q = &w->schedule;
    uint32_t faults = 0, *planned = calloc(q->units + 1, sizeof *planned);
    uint8_t* marked = malloc(s->model->vertex_count + 1);
    if (!planned || !marked) {
        free(planned), free(marked);
        return UINT32_MAX;
    }
    *across = 0;
    for (uint32_t u = 0; u < q->units; u++) {
        memset(marked, 0, s->model->vertex_count + 1);
        sb_pbd_unit_vertices(w, u, sb_pbd_mark_vertex, marked);
        for (uint32_t y = 0; y < q->units; y++) {
            if (y == u || q->phase[y] == q->phase[u]) continue;
            sb_pbd_overlap o = {marked, false};
            sb_pbd_unit_vertices(w, y, sb_pbd_check_vertex, &o);
            bool listed = false;
            for (uint32_t e = q->need_first[u]; e < q->need_first[u + 1]; e++) listed |= q->need[e] == y;
            faults += o.shared != listed;
        }
    }
    for (int i = 0; i < q->width; i++)
        for (uint32_t e = q->plan_first[i]; e < q->plan_first[i + 1]; e++) {
            uint32_t u = q->plan[e];
            planned[u]++;
            /* phases in sweep order, the overflow color's units in order */
            faults += e > q->plan_first[i] && q->phase[q->plan[e - 1]] > q->phase[u];
            faults += e > q->plan_first[i] && q->phase[q->plan[e - 1]] == q->phase[u] &&
                      sb_pbd_unit_color(w, u) == SB_OVERFLOW_COLOR && q->plan[e - 1] > u;
            for (int j = 0; j < q->width; j++)
                for (uint32_t f = q->plan_first[j]; j != i && f < q->plan_first[j + 1]; f++)
                    for (uint32_t n = q->need_first[u]; n < q->need_first[u + 1]; n++)
                        *across += q->need[n] == q->plan[f];
        }
    for (uint32_t u = 0; u < q->units; u++) faults += planned[u] != 1;
    free(planned), free(marked);
    return faults;
}

sb_status sb_pbd_wide_step(sb_solver* s, double dt) {
    sb_pbd* p = s->pbd;
    sb_pbd_wide_sync(p->wide, s);
    sb_pbd_wide_job job = {.solver = s,
                           .wide = p->wide,
                           .dt = dt,
                           .iterations = sb_pbd_iterations(&s->def),
                           .xpbd = s->def.integrator == SB_INTEGRATOR_XPBD};
    sb_pbd_schedule* q = &p->wide->schedule;
    for (uint32_t u = 0; u < q->units; u++) atomic_store_explicit(&q->done[u].sweeps, 0, memory_order_relaxed);
    sb_team_run_adaptive(s->team, q->width, sb_pbd_wide_sweeps, &job); /* the job's start publishes the zeros */
    s->published = true; /* the state's arrays and the packed positions and velocities hold the new state */
    s->has_displacement = false;
    if (atomic_load(&job.bad)) return sb_check_state(s);
    if (!atomic_load(&job.collapsed) && !sb_step_needs_forces(s)) {
        s->forces_stale = true;
        return SB_OK;
    }
    return sb_solver_compute_forces(s);
}
