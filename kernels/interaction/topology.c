/* Tearing: the surface splits where its bonds broke, as
 * production cloth tearing does, by vertex duplication.
 *
 * Design. The model stays immutable: the topology is solver state, held in
 * breakage's working copy (kernels/interaction/breakage.c), whose element index arrays
 * are the solver's own and whose vertex arrays have spare slots reserved at
 * creation (sb_solver_def.max_splits). A spare slot is dormant until used:
 * fixed, mass 0, at rest on vertex 0, in no element; every pass runs over
 * it and nothing moves it or counts it (no kinetic or gravity energy, no
 * contact, no force). So no array is ever reallocated and no loop bound
 * changes: a split writes a few slots.
 *
 * The fans of a vertex v: its triangles, joined when they share an edge
 * (v, x) that is whole (no bond, or an unbroken one). A dead triangle
 * (one on a broken bond's edge) joins fans through its whole edges too, so
 * that a fused bond (kernels/forces/fast_corners.c: a bond carried by a
 * triangle's edge, dead or not) always sits in the fan its edge belongs
 * to; a piece with no live triangle stays with v. When v has two or more
 * fans with a live triangle, fans 1.. get new vertices: position,
 * velocity, displacement and rest position copied, the mass shared by the
 * fans' rest areas (each copy its fan's share, v what the copies leave, so
 * that the masses sum to v's to rounding: the position and momentum of
 * what was v are kept), the forces the Verlet re-kick subtracts shared the
 * same way. An unbroken bond (v, x) goes with
 * the fan of the triangles on its edge (all in one fan, the edge being
 * whole), a live hinge with the fan of its wing at v, and the rest
 * (broken bonds, dead hinges) stays with v. A vertex held by a hard handle
 * keeps its hold; its copies are free (the handle holds vertex numbers).
 *
 * Which vertices are looked at: those of a triangle that died and the ends
 * of a bond that broke, queued once each, first in first out. A step makes
 * at most max_splits_per_step new vertices; a vertex that would pass the
 * cap waits at the head of the queue for the next step (the first vertex
 * of a step always goes). Everything runs on the advancing thread in queue
 * order, and the queue's order is bond order: the same splits for any
 * thread count.
 *
 * The stars (the elements at each vertex, per kind) are CSR ranges of
 * (element, corner) entries. A split reorders v's range fan by fan,
 * stably, and gives fan f's sub-range to its new vertex: a star only ever
 * splits, so no allocation and no rebuild.
 *
 * Why the fast model's coloring stays valid without recoloring: a new
 * vertex w appears only in elements that had v there before, in place of
 * v. Two elements sharing w afterwards shared v before, and elements that
 * shared v may now share nothing. So every conflict after a split was a
 * conflict before: the element colors within a block (SIMD lanes), the
 * block colors (threads), the fused bonds (carried by their triangle's
 * slot, whose vertices they follow) and pbd's constraint colors all stay
 * valid. Each re-pointed element has one slot (padding lanes copy an
 * element's vertices but are masked out of every scatter), which is all a
 * split writes in the fast model; its masses are per vertex. */
#include "kernels/interaction/topology.h"
#include "kernels/state/solver_data.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"
#include "common/union_find.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SB_NONE UINT32_MAX

/* The elements of one kind at each vertex: entries 3t + c (corner c of
 * triangle t), 2b + e (end e of bond b) or 4h + a (hinge h's e0, e1, o0,
 * o1), a contiguous range of `entry` per vertex. */
typedef struct sb_star {
    uint32_t *start, *count, *entry;
} sb_star;

enum { SB_STAR_TRIANGLES, SB_STAR_BONDS, SB_STAR_HINGES, SB_STARS };
static const uint32_t sb_arity[SB_STARS] = {3, 2, 4};

struct sb_topology {
    sb_model* live;
    const uint8_t *broken, *triangle_dead, *hinge_dead;
    uint32_t count, capacity, per_step, refused;
    uint32_t* origin;
    sb_star stars[SB_STARS];
    uint32_t *queue, head, queued; /* circular, capacity entries */
    uint8_t* pending;
    /* work space of the largest star */
    uint32_t *parent, *fan[SB_STARS], *scratch;
    double* area;
};

static uint32_t sb_element_count(const sb_model* m, int kind) {
    return kind == SB_STAR_TRIANGLES ? m->triangle_count : kind == SB_STAR_BONDS ? m->bond_count : m->hinge_count;
}

/* Where an entry's vertex index is, in the working copy. */
static uint32_t* sb_slot(const sb_model* m, int kind, uint32_t e) {
    if (kind == SB_STAR_TRIANGLES) return &m->tri_v[e % 3][e / 3];
    if (kind == SB_STAR_BONDS) return e % 2 ? &m->bond_j[e / 2] : &m->bond_i[e / 2];
    uint32_t* roles[4] = {m->hinge_e0, m->hinge_e1, m->hinge_o0, m->hinge_o1};
    return &roles[e % 4][e / 4];
}

static bool sb_star_build(sb_star* star, const sb_model* m, int kind, uint32_t capacity) {
    size_t entries = (size_t)sb_element_count(m, kind) * sb_arity[kind];
    star->start = calloc((size_t)capacity + 1, sizeof *star->start);
    star->count = calloc((size_t)capacity + 1, sizeof *star->count);
    star->entry = malloc((entries + 1) * sizeof *star->entry);
    if (!star->start || !star->count || !star->entry) return false;
    for (uint32_t e = 0; e < entries; e++) star->count[*sb_slot(m, kind, e)]++;
    for (uint32_t v = 1; v < capacity; v++) star->start[v] = star->start[v - 1] + star->count[v - 1];
    memset(star->count, 0, (size_t)capacity * sizeof *star->count);
    for (uint32_t e = 0; e < entries; e++) {
        uint32_t v = *sb_slot(m, kind, e);
        star->entry[star->start[v] + star->count[v]++] = e;
    }
    return true;
}

static bool sb_work_space(sb_topology* t) {
    uint32_t degree = 0;
    for (int k = 0; k < SB_STARS; k++)
        for (uint32_t v = 0; v < t->capacity; v++)
            degree = t->stars[k].count[v] > degree ? t->stars[k].count[v] : degree;
    size_t d = (size_t)degree + 1;
    t->parent = malloc(d * sizeof *t->parent);
    t->scratch = malloc(d * sizeof *t->scratch);
    t->area = malloc(d * sizeof *t->area);
    bool ok = t->parent && t->scratch && t->area;
    for (int k = 0; k < SB_STARS; k++) ok = (t->fan[k] = malloc(d * sizeof *t->fan[k])) != NULL && ok;
    return ok;
}

sb_topology* sb_topology_create(sb_model* live, uint32_t model_vertices, uint32_t per_step, const uint8_t* broken,
                                const uint8_t* triangle_dead, const uint8_t* hinge_dead, bool* ok) {
    sb_topology* t = calloc(1, sizeof *t);
    if (!t) {
        *ok = false;
        return NULL;
    }
    *t = (sb_topology){.live = live,
                       .broken = broken,
                       .triangle_dead = triangle_dead,
                       .hinge_dead = hinge_dead,
                       .count = model_vertices,
                       .capacity = live->vertex_count,
                       .per_step = per_step};
    size_t cap = (size_t)t->capacity + 1;
    t->origin = malloc(cap * sizeof *t->origin);
    t->queue = malloc(cap * sizeof *t->queue);
    t->pending = calloc(cap, 1);
    bool good = t->origin && t->queue && t->pending;
    for (int k = 0; good && k < SB_STARS; k++) good = sb_star_build(&t->stars[k], live, k, t->capacity);
    good = good && sb_work_space(t);
    if (!good) {
        sb_topology_destroy(t);
        *ok = false;
        return NULL;
    }
    for (uint32_t v = 0; v < t->capacity; v++) t->origin[v] = v < model_vertices ? v : SB_NONE;
    return t;
}

void sb_topology_destroy(sb_topology* t) {
    if (!t) return;
    for (int k = 0; k < SB_STARS; k++) {
        free(t->stars[k].start);
        free(t->stars[k].count);
        free(t->stars[k].entry);
        free(t->fan[k]);
    }
    void* arrays[] = {t->origin, t->queue, t->pending, t->parent, t->scratch, t->area};
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++) free(arrays[a]);
    free(t);
}

void sb_topology_queue(sb_topology* t, uint32_t v) {
    if (t->pending[v]) return;
    t->pending[v] = 1;
    t->queue[(t->head + t->queued++) % t->capacity] = v;
}

uint32_t sb_topology_vertex_count(const sb_topology* t) { return t->count; }
uint32_t sb_topology_origin(const sb_topology* t, uint32_t v) { return t->origin[v]; }
uint32_t sb_topology_refused(const sb_topology* t) { return t->refused; }

/* Triangle entry e's vertex `which` (0 or 1) after the corner's. */
static uint32_t sb_other(const sb_topology* t, uint32_t e, int which) {
    return t->live->tri_v[(e % 3 + 1 + which) % 3][e / 3];
}

static bool sb_has(const sb_topology* t, uint32_t e, uint32_t x) {
    return sb_other(t, e, 0) == x || sb_other(t, e, 1) == x;
}

/* Whether the edge (v, x) is whole: no bond on it, or an unbroken one. */
static bool sb_edge_whole(const sb_topology* t, uint32_t v, uint32_t x) {
    const sb_star* s = &t->stars[SB_STAR_BONDS];
    bool found = false;
    for (uint32_t q = s->start[v]; q < s->start[v] + s->count[v]; q++) {
        uint32_t e = s->entry[q], b = e / 2;
        if ((e % 2 ? t->live->bond_i[b] : t->live->bond_j[b]) != x) continue;
        if (!t->broken[b]) return true;
        found = true;
    }
    return !found;
}

/* Labels v's triangle entries with their fans: 0, 1, ... in the order of
 * their first live triangle; a piece without one gets 0. Returns the fans
 * with a live triangle. */
static uint32_t sb_label_fans(sb_topology* t, uint32_t v) {
    const sb_star* s = &t->stars[SB_STAR_TRIANGLES];
    const uint32_t* entry = s->entry + s->start[v];
    uint32_t d = s->count[v], *parent = t->parent, *fan = t->fan[SB_STAR_TRIANGLES], fans = 0;
    for (uint32_t i = 0; i < d; i++) parent[i] = i;
    for (uint32_t i = 0; i < d; i++)
        for (int a = 0; a < 2; a++) {
            uint32_t x = sb_other(t, entry[i], a);
            if (!sb_edge_whole(t, v, x)) continue;
            for (uint32_t j = i + 1; j < d; j++)
                if (sb_has(t, entry[j], x)) sb_join(parent, i, j);
        }
    for (uint32_t i = 0; i < d; i++) t->scratch[i] = SB_NONE; /* a root's fan */
    for (uint32_t i = 0; i < d; i++) {
        uint32_t root = sb_find(parent, i);
        if (!t->triangle_dead[entry[i] / 3] && t->scratch[root] == SB_NONE) t->scratch[root] = fans++;
    }
    for (uint32_t i = 0; i < d; i++) {
        uint32_t f = t->scratch[sb_find(parent, i)];
        fan[i] = f == SB_NONE ? 0 : f;
    }
    return fans;
}

bool sb_topology_splits(sb_topology* t) {
    for (uint32_t q = 0; q < t->queued; q++)
        if (sb_label_fans(t, t->queue[(t->head + q) % t->capacity]) >= 2) return true;
    return false;
}

/* The fan of v's first triangle that has both x and (y or z) besides v, or 0. */
static uint32_t sb_fan_with(const sb_topology* t, uint32_t v, uint32_t x, uint32_t y, uint32_t z) {
    const sb_star* s = &t->stars[SB_STAR_TRIANGLES];
    for (uint32_t i = 0; i < s->count[v]; i++) {
        uint32_t e = s->entry[s->start[v] + i];
        if (sb_has(t, e, x) && (y == SB_NONE || sb_has(t, e, y) || sb_has(t, e, z)))
            return t->fan[SB_STAR_TRIANGLES][i];
    }
    return 0;
}

/* An unbroken bond goes with the triangles on its edge; a broken one stays. */
static void sb_label_bonds(sb_topology* t, uint32_t v) {
    const sb_star* s = &t->stars[SB_STAR_BONDS];
    for (uint32_t i = 0; i < s->count[v]; i++) {
        uint32_t e = s->entry[s->start[v] + i], b = e / 2;
        uint32_t x = e % 2 ? t->live->bond_i[b] : t->live->bond_j[b];
        t->fan[SB_STAR_BONDS][i] = t->broken[b] ? 0 : sb_fan_with(t, v, x, SB_NONE, SB_NONE);
    }
}

/* A live hinge goes with its wing at v; a dead one stays. */
static void sb_label_hinges(sb_topology* t, uint32_t v) {
    const sb_star* s = &t->stars[SB_STAR_HINGES];
    const sb_model* m = t->live;
    for (uint32_t i = 0; i < s->count[v]; i++) {
        uint32_t e = s->entry[s->start[v] + i], h = e / 4, a = e % 4;
        uint32_t ids[4] = {m->hinge_e0[h], m->hinge_e1[h], m->hinge_o0[h], m->hinge_o1[h]};
        uint32_t fan =
            a < 2 ? sb_fan_with(t, v, ids[1 - a], ids[2], ids[3]) : sb_fan_with(t, v, ids[0], ids[1], ids[1]);
        t->fan[SB_STAR_HINGES][i] = t->hinge_dead[h] ? 0 : fan;
    }
}

/* Reorders v's entries of one kind fan by fan, stably, and gives fan f's
 * range to v (f = 0) or to vertex first + f − 1. */
static void sb_star_partition(sb_topology* t, int kind, uint32_t v, uint32_t fans, uint32_t first) {
    sb_star* s = &t->stars[kind];
    uint32_t begin = s->start[v], d = s->count[v], *entry = s->entry + begin, cursor = 0;
    for (uint32_t f = 0; f < fans; f++) {
        uint32_t from = cursor, owner = f ? first + f - 1 : v;
        for (uint32_t i = 0; i < d; i++)
            if (t->fan[kind][i] == f) t->scratch[cursor++] = entry[i];
        s->start[owner] = begin + from;
        s->count[owner] = cursor - from;
    }
    memcpy(entry, t->scratch, d * sizeof *entry);
}

/* Vertex w's elements (its star's range) point at w, in the working copy
 * and in their fast slots. */
static void sb_repoint(sb_solver* s, sb_topology* t, uint32_t w) {
    for (int kind = 0; kind < SB_STARS; kind++) {
        const sb_star* star = &t->stars[kind];
        for (uint32_t q = star->start[w]; q < star->start[w] + star->count[w]; q++) {
            uint32_t e = star->entry[q];
            *sb_slot(t->live, kind, e) = w;
            if (!s->fast) continue;
            if (kind == SB_STAR_TRIANGLES) sb_fast_move_corner(s->fast, e / 3, (int)(e % 3), w);
            if (kind == SB_STAR_BONDS) sb_fast_move_bond_end(s->fast, e / 2, (int)(e % 2), w);
            if (kind == SB_STAR_HINGES) sb_fast_move_hinge_vertex(s->fast, e / 4, (int)(e % 4), w);
        }
    }
}

static double sb_rest_area(const sb_model* m, uint32_t tri) {
    double p[3][3];
    for (int c = 0; c < 3; c++) {
        uint32_t i = m->tri_v[c][tri];
        p[c][0] = m->rest_x[i], p[c][1] = m->rest_y[i], p[c][2] = m->rest_z[i];
    }
    double a[3], b[3];
    for (int k = 0; k < 3; k++) a[k] = p[1][k] - p[0][k], b[k] = p[2][k] - p[0][k];
    double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* Each fan's share of v's mass (t->area): its live triangles' rest areas
 * over all fans' (equal shares when they have none). */
static void sb_fan_shares(sb_topology* t, uint32_t v, uint32_t fans) {
    const sb_star* s = &t->stars[SB_STAR_TRIANGLES];
    double total = 0.0;
    for (uint32_t f = 0; f < fans; f++) t->area[f] = 0.0;
    for (uint32_t i = 0; i < s->count[v]; i++) {
        uint32_t tri = s->entry[s->start[v] + i] / 3;
        if (t->triangle_dead[tri]) continue;
        double a = sb_rest_area(t->live, tri);
        t->area[t->fan[SB_STAR_TRIANGLES][i]] += a;
        total += a;
    }
    for (uint32_t f = 0; f < fans; f++) t->area[f] = total > 0.0 ? t->area[f] / total : 1.0 / fans;
}

/* w becomes a copy of v: rest, initial velocity, fixed flag, and the
 * solver's state (both the arrays and the packed working state). */
static void sb_copy_vertex(sb_solver* s, sb_model* m, uint32_t v, uint32_t w) {
    double* rest[6] = {m->rest_x, m->rest_y, m->rest_z, m->vel_x, m->vel_y, m->vel_z};
    for (int a = 0; a < 6; a++) rest[a][w] = rest[a][v];
    m->fixed[w] = m->fixed[v];
    sb_state* st = &s->state;
    sb_real* soa[15] = {st->x,  st->y,     st->z,     st->vx,    st->vy,     st->vz,     st->fx,    st->fy,
                        st->fz, s->disp_x, s->disp_y, s->disp_z, s->carry_x, s->carry_y, s->carry_z};
    for (int a = 0; a < 15; a++) soa[a][w] = soa[a][v];
    if (!s->fast) return;
    sb_real* packed[5] = {s->positions4, s->velocities4, s->displacements4, s->forces4, s->carry4};
    for (int a = 0; a < 5; a++) memcpy(packed[a] + 4 * (size_t)w, packed[a] + 4 * (size_t)v, 4 * sizeof(sb_real));
}

/* Vertex i's mass everywhere the solver keeps it; `held` by a hard handle
 * keeps inverse mass 0 where the integrators move it. */
static void sb_set_mass(sb_solver* s, sb_model* m, uint32_t i, double mass, bool held) {
    m->mass[i] = mass;
    m->inv_mass[i] = m->fixed[i] || !(mass > 0.0) ? 0.0 : 1.0 / mass;
    double moving = held ? 0.0 : m->inv_mass[i];
    if (s->pinned_inv_mass) s->pinned_inv_mass[i] = moving;
    if (!s->fast) return;
    s->fast->mass[i] = (sb_real)mass;
    s->fast->inv_mass[i] = (sb_real)moving;
}

/* Splits v, one vertex per fan; false when it has to wait for the next
 * step (the cap of this one reached). */
static bool sb_split_vertex(sb_solver* s, sb_topology* t, uint32_t v, uint32_t* made, double* before) {
    uint32_t fans = sb_label_fans(t, v), copies = fans - 1;
    if (fans < 2) return true;
    if (*made > 0 && *made + copies > t->per_step) return false;
    if (t->count + copies > t->capacity) {
        t->refused += copies;
        return true;
    }
    sb_label_bonds(t, v);
    sb_label_hinges(t, v);
    uint32_t first = t->count;
    for (int kind = 0; kind < SB_STARS; kind++) sb_star_partition(t, kind, v, fans, first);
    sb_fan_shares(t, v, fans);
    sb_model* m = t->live;
    double mass = m->mass[v], force[3] = {before[3 * (size_t)v], before[3 * (size_t)v + 1], before[3 * (size_t)v + 2]};
    bool held = s->pinned_inv_mass && s->pinned_inv_mass[v] == 0.0 && !m->fixed[v];
    double rest = mass, rest_force[3] = {force[0], force[1], force[2]};
    for (uint32_t f = fans - 1; f > 0; f--) { /* the copies' shares; v keeps what they leave */
        uint32_t w = first + f - 1;
        t->origin[w] = t->origin[v];
        sb_copy_vertex(s, m, v, w);
        sb_repoint(s, t, w);
        sb_set_mass(s, m, w, mass * t->area[f], false);
        rest -= m->mass[w];
        for (int a = 0; a < 3; a++) rest_force[a] -= before[3 * (size_t)w + a] = force[a] * t->area[f];
    }
    sb_set_mass(s, m, v, rest, held);
    for (int a = 0; a < 3; a++) before[3 * (size_t)v + a] = rest_force[a];
    t->count += copies;
    *made += copies;
    return true;
}

uint32_t sb_topology_split(sb_solver* s, sb_topology* t, double* before) {
    uint32_t made = 0;
    while (t->queued > 0) {
        uint32_t v = t->queue[t->head];
        if (!sb_split_vertex(s, t, v, &made, before)) break;
        t->pending[v] = 0;
        t->head = (t->head + 1) % t->capacity;
        t->queued--;
    }
    return made;
}

/* ---- the saved state (kernels/solver/solver_state.c) ---------------------------- */

/* Everything a split changes that a later step reads, as byte ranges: the
 * topology's counts, queue, origins and stars, and the working copy's
 * vertex arrays and element indices. The same list writes and reads. */
static int sb_topology_ranges(sb_topology* t, sb_range* out) {
    sb_model* m = t->live;
    size_t cap = t->capacity, nb = m->bond_count, nt = m->triangle_count, nh = m->hinge_count;
    sb_range list[] = {{&t->count, 4},        {&t->refused, 4},      {&t->head, 4},          {&t->queued, 4},
                       {t->origin, 4 * cap},  {t->queue, 4 * cap},   {t->pending, cap},      {m->rest_x, 8 * cap},
                       {m->rest_y, 8 * cap},  {m->rest_z, 8 * cap},  {m->vel_x, 8 * cap},    {m->vel_y, 8 * cap},
                       {m->vel_z, 8 * cap},   {m->mass, 8 * cap},    {m->inv_mass, 8 * cap}, {m->fixed, cap},
                       {m->bond_i, 4 * nb},   {m->bond_j, 4 * nb},   {m->tri_v[0], 4 * nt},  {m->tri_v[1], 4 * nt},
                       {m->tri_v[2], 4 * nt}, {m->hinge_e0, 4 * nh}, {m->hinge_e1, 4 * nh},  {m->hinge_o0, 4 * nh},
                       {m->hinge_o1, 4 * nh}};
    int n = (int)(sizeof list / sizeof *list);
    memcpy(out, list, sizeof list);
    for (int k = 0; k < SB_STARS; k++) {
        size_t entries = (size_t)sb_element_count(m, k) * sb_arity[k];
        out[n++] = (sb_range){t->stars[k].start, 4 * (cap + 1)};
        out[n++] = (sb_range){t->stars[k].count, 4 * (cap + 1)};
        out[n++] = (sb_range){t->stars[k].entry, 4 * entries};
    }
    return n;
}

enum { SB_TOPOLOGY_RANGES = 25 + 3 * SB_STARS };

void sb_topology_save(const sb_topology* t, sb_sections_writer* w) {
    sb_range ranges[SB_TOPOLOGY_RANGES];
    sb_ranges_put(w, ranges, sb_topology_ranges((sb_topology*)t, ranges)); /* reads only */
}

void sb_topology_load(sb_solver* s, sb_topology* t, sb_cursor* r) {
    sb_range ranges[SB_TOPOLOGY_RANGES];
    sb_ranges_take(r, ranges, sb_topology_ranges(t, ranges));
    const sb_model* m = t->live;
    for (uint32_t v = 0; v < t->capacity; v++) /* the handles pin theirs again after */
        sb_set_mass(s, t->live, v, m->mass[v], false);
    if (!s->fast) return;
    for (uint32_t e = 0; e < m->triangle_count; e++)
        for (int c = 0; c < 3; c++) sb_fast_move_corner(s->fast, e, c, m->tri_v[c][e]);
    for (uint32_t e = 0; e < m->bond_count; e++) {
        sb_fast_move_bond_end(s->fast, e, 0, m->bond_i[e]);
        sb_fast_move_bond_end(s->fast, e, 1, m->bond_j[e]);
    }
    uint32_t* roles[4] = {m->hinge_e0, m->hinge_e1, m->hinge_o0, m->hinge_o1};
    for (uint32_t e = 0; e < m->hinge_count; e++)
        for (int a = 0; a < 4; a++) sb_fast_move_hinge_vertex(s->fast, e, a, roles[a][e]);
}
