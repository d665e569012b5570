/* Building the fast kernels' model: color each element kind, lay the
 * elements out color by color (in model order within a color, which keeps
 * the locality of the vertex order), pad each color to whole SIMD blocks and
 * convert the constants to sb_real, folding uniform ones to one value. */
#include "kernels/forces/fast_model.h"
#include "common/error.h"
#include "kernels/runtime/wide.h"
#include "common/edge_map.h"

#include <math.h>
#include <stdlib.h>

static uint32_t sb_round_up(uint32_t n, uint32_t step) { return (n + step - 1) / step * step; }

/* The highest rank an element may have within its color (hinges carried). */
#define SB_MAX_RANK 3

#define SB_NONE UINT32_MAX

/* Elements per block: about 64 blocks (every block color then has some for
 * each thread), at least 256 elements, and at most as many as keep a
 * block's vertex state within SB_BLOCK_CACHE_BYTES, so that it stays in
 * the core's L2 while the block's element colors run over it. A vertex
 * brings its packed positions and forces (2 × 4 reals) and a mesh has about
 * two triangles a vertex (three bonds or hinges: fewer bytes an element),
 * so an element brings 4 reals: at most 16 384 elements in float, 8 192
 * in double. The cap was 2 048 before: a block was then about one row of
 * the 1M sheet's quads, each vertex row fell in two blocks of different
 * block colors, and the triangle pass loaded the positions and forces
 * twice (its L2 misses: bench/results/fused.md, "The blocks of the
 * blocked coloring"). A fixed
 * budget, not the machine's cache size, so that a build's trajectory is
 * the same on every machine. Depends on the element count only, never on
 * the thread count, so the summation order is the same for any. */
#define SB_BLOCK_CACHE_BYTES (256u * 1024u) /* a quarter of a 1 MiB L2 (the 2-core EPYC VM's) */
static uint32_t sb_block_size(uint32_t count) {
    const uint32_t most = SB_BLOCK_CACHE_BYTES / (4u * (uint32_t)sizeof(sb_real));
    uint32_t size = count / 64;
    size = size < 256 ? 256 : size > most ? most : size;
    return sb_round_up(size, SB_WIDTH);
}

/* Block colors: blocks sharing a vertex get different colors. */
static bool sb_color_blocks(uint32_t vertex_count, uint32_t count, uint32_t block_size, int arity,
                            const uint32_t* const* vertices, uint8_t* block_color, uint32_t block_count) {
    sb_colorer colorer;
    if (!sb_colorer_init(&colorer, vertex_count)) return false;
    for (uint32_t b = 0; b < block_count; b++) {
        uint32_t end = (b + 1) * block_size < count ? (b + 1) * block_size : count;
        uint64_t taken = 0;
        for (uint32_t e = b * block_size; e < end; e++)
            for (int a = 0; a < arity; a++) taken |= colorer.used[vertices[a][e]];
        int k = sb_colorer_pick(&colorer, taken);
        block_color[b] = (uint8_t)k;
        for (uint32_t e = b * block_size; k != SB_OVERFLOW_COLOR && e < end; e++)
            for (int a = 0; a < arity; a++) colorer.used[vertices[a][e]] |= UINT64_C(1) << k;
    }
    sb_colorer_free(&colorer);
    return true;
}

/* Lays out block b's elements [first, end) by their local colors from
 * slot *slot on, padding each color to whole SIMD blocks; within a color,
 * by rank (NULL: all 0), highest first, else in model order. */
static void sb_layout_block(sb_element_group* g, uint32_t first, uint32_t end, const uint8_t* color,
                            const uint8_t* rank, uint32_t* slot) {
    uint32_t sizes[SB_MAX_COLORS] = {0}, cursor[SB_MAX_COLORS];
    for (uint32_t e = first; e < end; e++) sizes[color[e - first]]++;
    sb_block* block = &g->blocks[g->block_count++];
    block->first_range = g->range_count;
    block->range_count = 0;
    for (int k = 0; k < SB_MAX_COLORS; k++) {
        if (!sizes[k]) continue;
        g->ranges[g->range_count++] = (sb_color_range){*slot, *slot + sizes[k], k == SB_OVERFLOW_COLOR};
        block->range_count++;
        cursor[k] = *slot;
        *slot = sb_round_up(*slot + sizes[k], SB_WIDTH);
    }
    for (int r = SB_MAX_RANK; r >= 0; r--)
        for (uint32_t e = first; e < end; e++)
            if ((rank ? rank[e] : 0) == r) g->source[cursor[color[e - first]]++] = e;
    for (uint32_t r = block->first_range; r < g->range_count; r++) /* padding copies the color's first */
        for (uint32_t s = g->ranges[r].end; s < sb_round_up(g->ranges[r].end, SB_WIDTH); s++)
            g->source[s] = g->source[g->ranges[r].begin];
}

/* The slot count: every block's colors padded. Colors each block's
 * elements into color (count entries) on the way. */
static uint32_t sb_color_within_blocks(sb_colorer* colorer, uint32_t count, uint32_t block_size, int arity,
                                       const uint32_t* const* vertices, uint8_t* color, uint32_t* ranges) {
    uint32_t slots = 0;
    *ranges = 0;
    for (uint32_t first = 0; first < count; first += block_size) {
        uint32_t end = first + block_size < count ? first + block_size : count;
        sb_colorer_run(colorer, first, end, arity, vertices, color + first);
        uint32_t sizes[SB_MAX_COLORS] = {0};
        for (uint32_t e = first; e < end; e++) sizes[color[e]]++;
        for (int k = 0; k < SB_MAX_COLORS; k++)
            if (sizes[k]) {
                slots += sb_round_up(sizes[k], SB_WIDTH);
                (*ranges)++;
            }
    }
    return slots;
}

/* Colors and lays out `count` elements; subset (or NULL for the identity)
 * maps them to the model's element numbers, which source[] then holds;
 * rank (or NULL) orders them within a color (sb_layout_block). */
static bool sb_group_build(sb_element_group* g, uint32_t vertex_count, uint32_t count, int arity,
                           const uint32_t* const* vertices, const uint32_t* subset, const uint8_t* rank) {
    *g = (sb_element_group){0};
    if (count == 0) return true;
    uint32_t block_size = sb_block_size(count), block_count = (count + block_size - 1) / block_size;
    uint8_t *color = malloc(count), *block_color = malloc(block_count);
    sb_colorer colorer;
    bool ok = color && block_color && sb_colorer_init(&colorer, vertex_count);
    if (ok) {
        uint32_t ranges;
        g->capacity = sb_color_within_blocks(&colorer, count, block_size, arity, vertices, color, &ranges) + SB_WIDTH;
        sb_colorer_free(&colorer);
        g->ranges = malloc(ranges * sizeof *g->ranges);
        g->blocks = malloc(block_count * sizeof *g->blocks);
        g->source = malloc(g->capacity * sizeof *g->source);
        ok = g->ranges && g->blocks && g->source &&
             sb_color_blocks(vertex_count, count, block_size, arity, vertices, block_color, block_count);
    }
    uint32_t slot = 0;
    for (int k = 0; ok && k < SB_MAX_COLORS; k++) {
        g->color_first_block[k] = g->block_count;
        for (uint32_t b = 0; b < block_count; b++) {
            if (block_color[b] != k) continue;
            uint32_t first = b * block_size, end = first + block_size < count ? first + block_size : count;
            sb_layout_block(g, first, end, color + first, rank, &slot);
        }
        if (g->block_count > g->color_first_block[k]) g->block_colors = (uint32_t)k + 1;
    }
    g->color_first_block[SB_MAX_COLORS] = g->block_count;
    for (uint32_t s = slot; ok && s < g->capacity; s++) g->source[s] = g->source[0];
    for (uint32_t s = 0; ok && subset && s < g->capacity; s++) g->source[s] = subset[g->source[s]];
    g->count = count;
    free(color);
    free(block_color);
    return ok;
}

static uint32_t* sb_gather_index(const uint32_t* in, const sb_element_group* g, bool* ok) {
    uint32_t* out = malloc((g->capacity ? g->capacity : 1) * sizeof *out);
    if (!out) *ok = false;
    for (uint32_t s = 0; out && s < g->capacity; s++) out[s] = in[g->source[s]];
    return out;
}

static sb_real* sb_gather_real(const double* in, const sb_element_group* g, bool* ok) {
    sb_real* out = malloc((g->capacity ? g->capacity : 1) * sizeof *out);
    if (!out) *ok = false;
    for (uint32_t s = 0; out && s < g->capacity; s++) out[s] = (sb_real)in[g->source[s]];
    return out;
}

/* Folds a uniform constant to one value when `fold` (not for a breakable
 * model's bond group and hinges, whose elements' constants are zeroed one
 * by one as they break: then the values are kept per slot and the uniform
 * value beside them). The
 * uniformity is that of `in` (count values); the slots take their values
 * from `slots_from`, indexed like the group's source. */
static sb_fast_constant sb_constant_from(const double* in, uint32_t count, const double* slots_from,
                                         const sb_element_group* g, bool fold, bool* ok) {
    bool uniform = true;
    for (uint32_t e = 1; e < count && uniform; e++) uniform = in[e] == in[0];
    sb_real value = uniform && count ? (sb_real)in[0] : 0;
    return (sb_fast_constant){uniform && fold ? NULL : sb_gather_real(slots_from, g, ok), value};
}

static sb_fast_constant sb_gather_constant(const double* in, uint32_t count, const sb_element_group* g, bool fold,
                                           bool* ok) {
    return sb_constant_from(in, count, in, g, fold, ok);
}

static bool sb_all_zero(const double* values, uint32_t count) {
    for (uint32_t e = 0; e < count; e++)
        if (values[e] != 0.0) return false;
    return true;
}

/* The bonds left to the bond kernel: all of them, or those no triangle owns. */
static bool sb_fast_bonds(sb_fast_model* f, const sb_model* m, const int64_t* owner) {
    uint32_t count = 0;
    uint32_t* subset = malloc((m->bond_count ? m->bond_count : 1) * sizeof *subset);
    uint32_t* ends_i = malloc((m->bond_count ? m->bond_count : 1) * sizeof *ends_i);
    uint32_t* ends_j = malloc((m->bond_count ? m->bond_count : 1) * sizeof *ends_j);
    bool ok = subset && ends_i && ends_j;
    for (uint32_t b = 0; ok && b < m->bond_count; b++)
        if (!owner || owner[b] < 0) {
            subset[count] = b;
            ends_i[count] = m->bond_i[b];
            ends_j[count++] = m->bond_j[b];
        }
    const uint32_t* ends[2] = {ends_i, ends_j};
    ok = ok && sb_group_build(&f->bonds, m->vertex_count, count, 2, ends, subset, NULL);
    free(subset);
    free(ends_i);
    free(ends_j);
    if (!ok) return false;
    f->bond_i = sb_gather_index(m->bond_i, &f->bonds, &ok);
    f->bond_j = sb_gather_index(m->bond_j, &f->bonds, &ok);
    f->bond_r0 = sb_gather_real(m->bond_r0, &f->bonds, &ok);
    f->bond_k = sb_gather_constant(m->bond_k, m->bond_count, &f->bonds, !m->breakable, &ok);
    f->spring_k = sb_gather_constant(m->spring_k, m->bond_count, &f->bonds, !m->breakable, &ok);
    f->spring_damping = sb_gather_constant(m->spring_damping, m->bond_count, &f->bonds, !m->breakable, &ok);
    f->has_bond = m->term_enabled[SB_TERM_BOND];
    f->has_spring = m->term_enabled[SB_TERM_SPRING];
    f->has_damping = sb_constant_on(f->spring_damping) && !sb_all_zero(m->spring_damping, m->bond_count);
    return ok;
}

/* Which triangle edge owns each bond: owner[b] = 3 t + c for edge c of
 * triangle t, −1 for none. */
static int64_t* sb_bond_owners(const sb_model* m, bool* ok) {
    if (m->triangle_count == 0 || m->bond_count == 0) return NULL;
    int64_t* owner = malloc(m->bond_count * sizeof *owner);
    sb_edge_map map;
    if (!owner || !sb_edge_map_init(&map, m->bond_count)) {
        free(owner);
        *ok = false;
        return NULL;
    }
    bool inserted;
    for (uint32_t b = 0; b < m->bond_count; b++) {
        sb_edge_map_upsert(&map, m->bond_i[b], m->bond_j[b], b, &inserted);
        owner[b] = -1;
    }
    for (uint32_t t = 0; t < m->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            uint32_t* b = sb_edge_map_find(&map, m->tri_v[c][t], m->tri_v[(c + 1) % 3][t]);
            if (b && owner[*b] < 0) owner[*b] = 3 * (int64_t)t + c;
        }
    sb_edge_map_free(&map);
    return owner;
}

/* Per triangle edge (3 arrays of triangle_count, edge c's at c · nt): the
 * owned bond's rest length and constants, 0 where the edge owns none. */
typedef struct sb_edge_values {
    double *r0, *bond_k, *spring_k, *damping;
    uint8_t* owned; /* per triangle, bit c */
} sb_edge_values;

static bool sb_edge_values_fill(sb_edge_values* e, const sb_model* m, const int64_t* owner) {
    size_t nt = m->triangle_count;
    double** arrays[4] = {&e->r0, &e->bond_k, &e->spring_k, &e->damping};
    bool ok = (e->owned = calloc(nt, 1)) != NULL;
    for (int a = 0; a < 4; a++) ok = (*arrays[a] = calloc(3 * nt, sizeof(double))) != NULL && ok;
    for (uint32_t b = 0; ok && b < m->bond_count; b++) {
        if (owner[b] < 0) continue;
        int c = (int)(owner[b] % 3);
        size_t t = (size_t)(owner[b] / 3), at = c * nt + t;
        e->owned[t] |= (uint8_t)(1u << c);
        e->r0[at] = m->bond_r0[b];
        e->bond_k[at] = m->bond_k[b];
        e->spring_k[at] = m->spring_k[b];
        e->damping[at] = m->spring_damping[b];
    }
    return ok;
}

static void sb_edge_values_free(sb_edge_values* e) {
    free(e->r0);
    free(e->bond_k);
    free(e->spring_k);
    free(e->damping);
    free(e->owned);
}

/* Whether every owned bond of edge c has the triangle's own rest length
 * there (in sb_real), so that the kernel can reuse tri_len0[c]. */
static bool sb_edge_rest_shared(const sb_model* m, const sb_edge_values* e, int c) {
    for (uint32_t t = 0; t < m->triangle_count; t++)
        if ((e->owned[t] >> c & 1u) && (sb_real)e->r0[c * (size_t)m->triangle_count + t] != (sb_real)m->tri_len0[c][t])
            return false;
    return true;
}

/* The fused bonds' flags, rest lengths and constants per triangle slot. */
static bool sb_fast_fused_edges(sb_fast_model* f, const sb_model* m, const int64_t* owner) {
    size_t nt = m->triangle_count;
    sb_edge_values e = {0};
    bool ok = sb_edge_values_fill(&e, m, owner);
    for (uint32_t s = 0; ok && s < f->triangles.capacity; s++) f->tri_owned[s] |= e.owned[f->triangles.source[s]];
    for (int c = 0; ok && c < 3; c++) {
        size_t at = c * nt;
        if (!sb_edge_rest_shared(m, &e, c)) f->tri_edge_r0[c] = sb_gather_real(e.r0 + at, &f->triangles, &ok);
        f->tri_edge_bond_k[c] = sb_constant_from(m->bond_k, m->bond_count, e.bond_k + at, &f->triangles, true, &ok);
        f->tri_edge_spring_k[c] =
            sb_constant_from(m->spring_k, m->bond_count, e.spring_k + at, &f->triangles, true, &ok);
        f->tri_edge_damping[c] =
            sb_constant_from(m->spring_damping, m->bond_count, e.damping + at, &f->triangles, true, &ok);
    }
    for (size_t k = 0; ok && k < 3 * nt; k++) f->fused_damping |= e.damping[k] != 0.0;
    sb_edge_values_free(&e);
    f->fused_bonds = ok;
    return ok;
}

/* Which triangle edge carries each hinge (sb_fast_model.fused_hinges):
 * carried[3 t + c] is the hinge on edge c of triangle t, whose opposite
 * vertex is one of the hinge's wing tips, or SB_NONE. Of a hinge's two
 * wings the one carrying fewer so far takes it. NULL when some hinge has
 * no wing among the triangles (or shares its edge with another hinge):
 * then the hinge pass computes them all. */
static uint32_t* sb_hinge_carriers(const sb_model* m, bool* ok) {
    if (!m->hinge_count || !m->triangle_count || !m->term_enabled[SB_TERM_BEND]) return NULL;
    size_t nt = m->triangle_count, nh = m->hinge_count;
    uint32_t *carried = malloc(3 * nt * sizeof *carried), (*wings)[2] = malloc(nh * sizeof *wings);
    uint8_t* load = calloc(nt, 1);
    sb_edge_map map = {0};
    bool fusable = carried && wings && load && sb_edge_map_init(&map, nh), inserted;
    *ok = fusable;
    for (uint32_t h = 0; fusable && h < nh; h++) {
        sb_edge_map_upsert(&map, m->hinge_e0[h], m->hinge_e1[h], h, &inserted);
        fusable = inserted;
        wings[h][0] = wings[h][1] = SB_NONE;
    }
    for (uint32_t e = 0; fusable && e < 3 * nt; e++) {
        uint32_t t = e / 3, c = e % 3, opposite = m->tri_v[(c + 2) % 3][t];
        uint32_t* h = sb_edge_map_find(&map, m->tri_v[c][t], m->tri_v[(c + 1) % 3][t]);
        carried[e] = SB_NONE;
        if (h && (opposite == m->hinge_o0[*h] || opposite == m->hinge_o1[*h])) wings[*h][wings[*h][0] != SB_NONE] = e;
    }
    for (uint32_t h = 0; fusable && h < nh; h++) {
        uint32_t e = wings[h][0];
        if (wings[h][1] != SB_NONE && load[wings[h][1] / 3] < load[e / 3]) e = wings[h][1];
        fusable = e != SB_NONE;
        if (fusable) {
            carried[e] = h;
            load[e / 3]++;
        }
    }
    sb_edge_map_free(&map);
    free(wings);
    free(load);
    if (fusable) return carried;
    free(carried);
    return NULL;
}

/* Per triangle, what its hinge slots carry (sb_fast_model.tri_hinge_*),
 * by triangle; the edges' field also ranks the triangles (hinges carried). */
typedef struct sb_carried_values {
    uint8_t *edges, *count;
    uint32_t* other[3];
    double *phi0[3], *k[3];
} sb_carried_values;

/* Hinge h on edge c of triangle t, in the triangle's order: o1 and the
 * sign of φ (flipped once by reversing the edge, once by swapping wings). */
static uint32_t sb_carried_other(const sb_model* m, uint32_t h, uint32_t t, int c, double* sign) {
    bool own_o0 = m->tri_v[(c + 2) % 3][t] == m->hinge_o0[h];
    *sign = (m->tri_v[c][t] == m->hinge_e0[h]) == own_o0 ? 1.0 : -1.0;
    return own_o0 ? m->hinge_o1[h] : m->hinge_o0[h];
}

static bool sb_carried_fill(sb_carried_values* v, const sb_model* m, const uint32_t* carried) {
    size_t nt = m->triangle_count;
    bool ok = (v->edges = calloc(nt, 1)) != NULL && (v->count = calloc(nt, 1)) != NULL;
    for (int j = 0; j < 3; j++) {
        ok = (v->other[j] = malloc(nt * sizeof *v->other[j])) != NULL && ok;
        ok = (v->phi0[j] = calloc(nt, sizeof(double))) != NULL && ok;
        ok = (v->k[j] = calloc(nt, sizeof(double))) != NULL && ok;
    }
    for (uint32_t t = 0; ok && t < nt; t++) {
        int j = 0;
        for (int c = 0; c < 3; c++) {
            uint32_t h = carried[3 * (size_t)t + c];
            if (h == SB_NONE) continue;
            double sign;
            v->other[j][t] = sb_carried_other(m, h, t, c, &sign);
            v->phi0[j][t] = sign * m->hinge_phi0[h];
            v->k[j][t] = m->hinge_k[h];
            v->edges[t] |= (uint8_t)((c + 1) << 2 * j++);
        }
        v->count[t] = (uint8_t)j;
        for (; j < 3; j++) v->other[j][t] = m->tri_v[2][t]; /* any vertex of the slot's: its k is 0 */
    }
    return ok;
}

static void sb_carried_free(sb_carried_values* v) {
    free(v->edges);
    free(v->count);
    for (int j = 0; j < 3; j++) {
        free(v->other[j]);
        free(v->phi0[j]);
        free(v->k[j]);
    }
}

/* The carried hinges' fields, other vertices, rest angles and constants
 * per triangle slot. */
static bool sb_fast_carried_hinges(sb_fast_model* f, const sb_model* m, const sb_carried_values* v) {
    bool ok = (f->tri_hinge_edges = malloc(f->triangles.capacity + SB_WIDTH)) != NULL;
    for (uint32_t s = 0; ok && s < f->triangles.capacity + SB_WIDTH; s++)
        f->tri_hinge_edges[s] = s < f->triangles.capacity ? v->edges[f->triangles.source[s]] : 0;
    for (int j = 0; ok && j < 3; j++) {
        f->tri_hinge_other[j] = sb_gather_index(v->other[j], &f->triangles, &ok);
        f->tri_hinge_phi0[j] = sb_gather_real(v->phi0[j], &f->triangles, &ok);
        f->tri_hinge_k[j] = sb_constant_from(m->hinge_k, m->hinge_count, v->k[j], &f->triangles, !m->breakable, &ok);
    }
    f->fused_hinges = ok;
    return ok;
}

/* The triangle group: colored by the corners, and with fused hinges by
 * the hinges' other vertices too (so that a block's scatters stay apart
 * from other blocks' of its color, and a color's lanes from each other). */
static bool sb_fast_triangles(sb_fast_model* f, const sb_model* m, const uint32_t* carried) {
    sb_carried_values values = {0};
    bool ok = !carried || sb_carried_fill(&values, m, carried);
    const uint32_t* ids[6] = {m->tri_v[0], m->tri_v[1], m->tri_v[2], values.other[0], values.other[1], values.other[2]};
    ok = ok &&
         sb_group_build(&f->triangles, m->vertex_count, m->triangle_count, carried ? 6 : 3, ids, NULL, values.count);
    ok = ok && (!carried || sb_fast_carried_hinges(f, m, &values));
    sb_carried_free(&values);
    if (!ok) return false;
    for (int c = 0; c < 3; c++) {
        f->tri_v[c] = sb_gather_index(m->tri_v[c], &f->triangles, &ok);
        f->tri_cos0[c] = sb_gather_real(m->tri_cos0[c], &f->triangles, &ok);
        f->tri_len0[c] = sb_gather_real(m->tri_len0[c], &f->triangles, &ok);
    }
    /* every slot live, no bond owned yet; the padding past the slots none */
    f->tri_owned = calloc((size_t)f->triangles.capacity + SB_WIDTH, 1);
    ok = ok && f->tri_owned;
    for (uint32_t s = 0; ok && s < f->triangles.capacity; s++) f->tri_owned[s] = 1u << SB_TRIANGLE_LIVE;
    f->mortal_triangles = m->breakable;
    f->angle_k = sb_gather_constant(m->angle_k, m->triangle_count, &f->triangles, true, &ok);
    f->stretch_bend_k = sb_gather_constant(m->stretch_bend_k, m->triangle_count, &f->triangles, true, &ok);
    f->has_corners = m->term_enabled[SB_TERM_ANGLE] || m->term_enabled[SB_TERM_STRETCH_BEND];
    return ok;
}

static bool sb_fast_hinges(sb_fast_model* f, const sb_model* m) {
    const uint32_t* ids[4] = {m->hinge_e0, m->hinge_e1, m->hinge_o0, m->hinge_o1};
    if (!sb_group_build(&f->hinges, m->vertex_count, m->hinge_count, 4, ids, NULL, NULL)) return false;
    bool ok = true;
    for (int a = 0; a < 4; a++) f->hinge_v[a] = sb_gather_index(ids[a], &f->hinges, &ok);
    f->hinge_phi0 = sb_gather_real(m->hinge_phi0, &f->hinges, &ok);
    f->hinge_k = sb_gather_constant(m->hinge_k, m->hinge_count, &f->hinges, !m->breakable, &ok);
    f->has_hinges = m->term_enabled[SB_TERM_BEND];
    return ok;
}

static double* sb_gather_double(const double* in, const sb_element_group* g, bool* ok) {
    double* out = malloc((g->capacity ? g->capacity : 1) * sizeof *out);
    if (!out) *ok = false;
    for (uint32_t s = 0; out && s < g->capacity; s++) out[s] = in[g->source[s]];
    return out;
}

static bool sb_fast_tet_group(sb_fast_model* f, const sb_model* m) {
    const uint32_t* ids[SB_TET_NODES];
    for (int a = 0; a < SB_TET_NODES; a++) ids[a] = m->tet_v[a];
    if (!sb_group_build(&f->tets, m->vertex_count, m->tet_count, SB_TET_NODES, ids, NULL, NULL)) return false;
    bool ok = true;
    for (int a = 0; a < SB_TET_NODES; a++) f->tet_v[a] = sb_gather_index(ids[a], &f->tets, &ok);
    f->tet_nodes = malloc(f->tets.capacity ? f->tets.capacity : 1);
    if (!f->tet_nodes) ok = false;
    for (uint32_t s = 0; f->tet_nodes && s < f->tets.capacity; s++) f->tet_nodes[s] = m->tet_nodes[f->tets.source[s]];
    for (int k = 0; k < 9; k++) f->tet_dm_inv[k] = sb_gather_double(m->tet_dm_inv[k], &f->tets, &ok);
    f->tet_volume = sb_gather_double(m->tet_volume, &f->tets, &ok);
    f->tet_mu = sb_gather_double(m->tet_mu, &f->tets, &ok);
    f->tet_lambda = sb_gather_double(m->tet_lambda, &f->tets, &ok);
    f->tet_beta = sb_gather_double(m->tet_beta, &f->tets, &ok);
    for (int k = 0; k < 9; k++) f->tet_lane_dm_inv[k] = sb_gather_real(m->tet_dm_inv[k], &f->tets, &ok);
    f->tet_lane_volume = sb_gather_real(m->tet_volume, &f->tets, &ok);
    f->tet_lane_mu = sb_gather_real(m->tet_mu, &f->tets, &ok);
    f->tet_lane_lambda = sb_gather_real(m->tet_lambda, &f->tets, &ok);
    f->tet_lane_beta = sb_gather_real(m->tet_beta, &f->tets, &ok);
    f->tet_damped = m->tet_damped;
    f->has_tets = m->tet_count > 0 && m->term_enabled[SB_TERM_COROTATED];
    return ok;
}

/* The vertices of each membrane's plate, by place (a place past a plate's
 * count repeats its membrane's corner 0, as a linear tetrahedron's). */
static uint32_t* sb_plate_ids(const sb_model* m, int place, bool* ok) {
    uint32_t* ids = malloc((m->membrane_count ? m->membrane_count : 1) * sizeof *ids);
    if (!ids) *ok = false;
    for (uint32_t t = 0; ids && t < m->membrane_count; t++)
        ids[t] =
            place < m->plate_nodes[t] ? m->plate_v[SB_PLATE_NODES * (size_t)t + (size_t)place] : m->membrane_v[0][t];
    return ids;
}

static bool sb_fast_membrane_group(sb_fast_model* f, const sb_model* m) {
    bool plates = m->plate_count > 0 && m->term_enabled[SB_TERM_BEND], ok = true;
    const uint32_t* ids[SB_PLATE_NODES] = {m->membrane_v[0], m->membrane_v[1], m->membrane_v[2]};
    uint32_t* stencil[SB_PLATE_NODES] = {NULL};
    for (int a = 0; plates && a < SB_PLATE_NODES; a++) ids[a] = stencil[a] = sb_plate_ids(m, a, &ok);
    ok = ok && sb_group_build(&f->membranes, m->vertex_count, m->membrane_count, plates ? SB_PLATE_NODES : 3, ids, NULL,
                              NULL);
    for (int a = 0; a < SB_PLATE_NODES; a++) free(stencil[a]);
    if (!ok) return false;
    f->plate_model = plates ? m : NULL;
    for (int a = 0; a < 3; a++) f->membrane_v[a] = sb_gather_index(m->membrane_v[a], &f->membranes, &ok);
    for (int k = 0; k < 4; k++) f->membrane_dm_inv[k] = sb_gather_double(m->membrane_dm_inv[k], &f->membranes, &ok);
    f->membrane_volume = sb_gather_double(m->membrane_volume, &f->membranes, &ok);
    f->membrane_mu = sb_gather_double(m->membrane_mu, &f->membranes, &ok);
    f->membrane_lambda = sb_gather_double(m->membrane_lambda, &f->membranes, &ok);
    f->membrane_beta = sb_gather_double(m->membrane_beta, &f->membranes, &ok);
    for (int k = 0; k < 4; k++) f->membrane_lane_dm_inv[k] = sb_gather_real(m->membrane_dm_inv[k], &f->membranes, &ok);
    f->membrane_lane_volume = sb_gather_real(m->membrane_volume, &f->membranes, &ok);
    f->membrane_lane_mu = sb_gather_real(m->membrane_mu, &f->membranes, &ok);
    f->membrane_lane_lambda = sb_gather_real(m->membrane_lambda, &f->membranes, &ok);
    f->membrane_lane_beta = sb_gather_real(m->membrane_beta, &f->membranes, &ok);
    f->membrane_damped = m->membrane_damped;
    f->has_membranes = m->membrane_count > 0 && (m->term_enabled[SB_TERM_MEMBRANE] || plates);
    return ok;
}

/* slot_of[source[s]] = s for the real slots of every color of a group. */
static uint32_t* sb_slot_map(const sb_element_group* g, uint32_t model_count, bool* ok) {
    uint32_t* slot_of = malloc((model_count ? model_count : 1) * sizeof *slot_of);
    if (!slot_of) *ok = false;
    for (uint32_t r = 0; slot_of && r < g->range_count; r++)
        for (uint32_t s = g->ranges[r].begin; s < g->ranges[r].end; s++) slot_of[g->source[s]] = s;
    return slot_of;
}

/* Where each fused hinge sits (sb_fast_model.hinge_fused_at). */
static bool sb_fused_places(sb_fast_model* f, const sb_model* m, const uint32_t* carried) {
    f->hinge_fused_at = malloc(m->hinge_count * sizeof *f->hinge_fused_at);
    for (uint32_t t = 0; f->hinge_fused_at && t < m->triangle_count; t++)
        for (int c = 0, j = 0; c < 3; c++) {
            uint32_t h = carried[3 * (size_t)t + c];
            if (h == SB_NONE) continue;
            double sign;
            uint32_t other = sb_carried_other(m, h, t, c, &sign);
            f->hinge_fused_at[h] = 2 * (3 * f->triangle_slot[t] + j++) + (other == m->hinge_o1[h]);
        }
    return f->hinge_fused_at != NULL;
}

/* Where each model element sits, for breakage (kernels/interaction/breakage.c). */
static bool sb_fast_places(sb_fast_model* f, const sb_model* m, const int64_t* owner, const uint32_t* carried) {
    bool ok = true;
    uint32_t* bond_slot = sb_slot_map(&f->bonds, m->bond_count, &ok);
    f->triangle_slot = sb_slot_map(&f->triangles, m->triangle_count, &ok);
    f->hinge_slot = sb_slot_map(&f->hinges, m->hinge_count, &ok);
    if (ok && carried) ok = sb_fused_places(f, m, carried);
    f->bond_place = malloc((m->bond_count ? m->bond_count : 1) * sizeof *f->bond_place);
    ok = ok && f->bond_place;
    for (uint32_t b = 0; ok && b < m->bond_count; b++) {
        bool fused = owner && owner[b] >= 0;
        f->bond_place[b] = fused ? -1 - (3 * (int64_t)f->triangle_slot[owner[b] / 3] + owner[b] % 3) : bond_slot[b];
    }
    free(bond_slot);
    return ok;
}

/* Fused bonds whose limits relative to their rest lengths lie within this
 * of each other share one value: one material's break strain, the break
 * length and the rest length rounded apart. */
#define SB_RATIO_SPREAD 1e-9

/* The fused bonds' limits relative to their rest lengths (ratio2 per
 * bond: (max / r0)² or (min / r0)²) times `margin`, per fused edge
 * (sb_fast_model.tri_edge_max_ratio2): one value, the loosest (the
 * lowest max, or with `low` the highest min), when they all lie within
 * SB_RATIO_SPREAD; else per slot, 0 where an edge owns no bond (masked). */
static void sb_fused_ratios(sb_fast_model* f, const sb_model* m, const double* ratio2, double margin, bool low,
                            sb_fast_constant out[3], bool* ok) {
    double least = INFINITY, most = -INFINITY;
    for (uint32_t b = 0; b < m->bond_count; b++)
        if (f->bond_place[b] < 0) least = fmin(least, ratio2[b]), most = fmax(most, ratio2[b]);
    if (least == most || most <= least * (1.0 + SB_RATIO_SPREAD)) {
        for (int c = 0; c < 3; c++) out[c] = (sb_fast_constant){NULL, (sb_real)((low ? most : least) * margin)};
        return;
    }
    for (int c = 0; c < 3 && *ok; c++)
        *ok = (out[c].values = calloc((size_t)f->triangles.capacity + 1, sizeof(sb_real))) != NULL;
    for (uint32_t b = 0; *ok && b < m->bond_count; b++) {
        int64_t place = f->bond_place[b];
        if (place < 0) out[(-1 - place) % 3].values[(-1 - place) / 3] = (sb_real)(ratio2[b] * margin);
    }
}

/* The margins of the limits (sb_fast_model.bond_near_max2), for a model
 * with a finite limit on some bond. */
static bool sb_fast_limits(sb_fast_model* f, const sb_model* m) {
    bool limited = false, any_min = false, ok = true;
    for (uint32_t b = 0; b < m->bond_count; b++) {
        limited |= isfinite(m->bond_break_max[b]) || m->bond_break_min[b] > 0.0;
        any_min |= m->bond_break_min[b] > 0.0;
    }
    if (!limited) return true;
    f->limits_measured = f->has_bond || f->has_spring || f->bonds.count == 0;
    size_t slots = (size_t)f->bonds.capacity + 1;
    ok = (f->bond_near_max2 = malloc(slots * sizeof *f->bond_near_max2)) != NULL;
    ok = ok && (!any_min || (f->bond_near_min2 = calloc(slots, sizeof *f->bond_near_min2)) != NULL);
    for (size_t s = 0; ok && s < slots; s++) f->bond_near_max2[s] = (sb_real)INFINITY;
    double* ratio2 = ok ? malloc(2 * ((size_t)m->bond_count + 1) * sizeof *ratio2) : NULL;
    ok = ok && ratio2;
    for (uint32_t b = 0; ok && b < m->bond_count; b++) {
        double lo = m->bond_break_min[b], hi = m->bond_break_max[b], r0 = m->bond_r0[b];
        int64_t place = f->bond_place[b];
        ratio2[b] = hi * hi / (r0 * r0);
        ratio2[m->bond_count + b] = lo * lo / (r0 * r0);
        f->fused_limits |= place < 0 && (isfinite(hi) || lo > 0.0);
        if (place < 0) continue;
        f->bond_near_max2[place] = (sb_real)(hi * hi * (1.0 - SB_LIMIT_MARGIN));
        if (any_min) f->bond_near_min2[place] = (sb_real)(lo * lo * (1.0 + SB_LIMIT_MARGIN));
    }
    if (ok && f->fused_limits) {
        sb_fused_ratios(f, m, ratio2, 1.0 - SB_LIMIT_MARGIN, false, f->tri_edge_max_ratio2, &ok);
        sb_fused_ratios(f, m, ratio2 + m->bond_count, 1.0 + SB_LIMIT_MARGIN, true, f->tri_edge_min_ratio2, &ok);
    }
    free(ratio2);
    return ok;
}

/* A margin (or each of a per-slot one's slots) times factor. */
static void sb_scale_margin(sb_real* values, size_t count, double factor) {
    for (size_t s = 0; values && s < count; s++) values[s] = (sb_real)(values[s] * factor);
}
static void sb_scale_constant(sb_fast_constant* c, size_t slots, double factor) {
    c->uniform = (sb_real)(c->uniform * factor);
    sb_scale_margin(c->values, slots, factor);
}

void sb_fast_widen_limits(sb_fast_model* f, double factor) {
    if (!f->bond_near_max2) return;
    double wider = factor * factor;
    size_t bonds = (size_t)f->bonds.capacity + 1, triangles = (size_t)f->triangles.capacity + 1;
    sb_scale_margin(f->bond_near_max2, bonds, wider); /* a broken bond's +inf and 0 stay */
    sb_scale_margin(f->bond_near_min2, bonds, 1.0 / wider);
    for (int c = 0; f->fused_limits && c < 3; c++) {
        sb_scale_constant(&f->tri_edge_max_ratio2[c], triangles, wider);
        sb_scale_constant(&f->tri_edge_min_ratio2[c], triangles, 1.0 / wider);
    }
}

/* A fused bond goes with its edge's bit (its margins with it); one of the
 * bond group with its slot's constants and margins. */
void sb_fast_break_bond(sb_fast_model* f, uint32_t bond) {
    int64_t place = f->bond_place[bond];
    if (place < 0) {
        uint32_t slot = (uint32_t)((-1 - place) / 3);
        int c = (int)((-1 - place) % 3);
        f->tri_owned[slot] &= (uint8_t) ~(1u << c);
        return;
    }
    if (f->bond_near_max2) f->bond_near_max2[place] = (sb_real)INFINITY; /* never near again */
    if (f->bond_near_min2) f->bond_near_min2[place] = 0;
    f->bond_k.values[place] = f->spring_k.values[place] = f->spring_damping.values[place] = 0;
    f->bond_r0[place] = 0;
}

void sb_fast_drop_triangle(sb_fast_model* f, uint32_t triangle) {
    f->tri_owned[f->triangle_slot[triangle]] &= (uint8_t) ~(1u << SB_TRIANGLE_LIVE);
}

void sb_fast_drop_hinge(sb_fast_model* f, uint32_t hinge) {
    f->hinge_k.values[f->hinge_slot[hinge]] = 0;
    if (!f->fused_hinges) return;
    uint32_t at = f->hinge_fused_at[hinge] / 2;
    f->tri_hinge_k[at % 3].values[at / 3] = 0;
}

void sb_fast_move_corner(sb_fast_model* f, uint32_t triangle, int corner, uint32_t vertex) {
    f->tri_v[corner][f->triangle_slot[triangle]] = vertex;
}

void sb_fast_move_bond_end(sb_fast_model* f, uint32_t bond, int end, uint32_t vertex) {
    int64_t place = f->bond_place[bond];
    if (place >= 0) (end ? f->bond_j : f->bond_i)[place] = vertex;
}

/* A fused hinge's other vertex moves with it; its edge and own wing tip
 * are its triangle's corners, which move with theirs. */
void sb_fast_move_hinge_vertex(sb_fast_model* f, uint32_t hinge, int role, uint32_t vertex) {
    f->hinge_v[role][f->hinge_slot[hinge]] = vertex;
    if (!f->fused_hinges) return;
    uint32_t at = f->hinge_fused_at[hinge];
    if (role == 2 + (int)(at % 2)) f->tri_hinge_other[at / 2 % 3][at / 6] = vertex;
}

static bool sb_fast_vertices(sb_fast_model* f, const sb_model* m) {
    f->vertex_count = m->vertex_count;
    size_t n = (size_t)m->vertex_count + 1;
    f->mass = calloc(n, sizeof *f->mass);
    f->inv_mass = calloc(n, sizeof *f->inv_mass);
    if (!f->mass || !f->inv_mass) return false;
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        f->mass[i] = (sb_real)m->mass[i];
        f->inv_mass[i] = (sb_real)m->inv_mass[i];
    }
    return true;
}

sb_fast_model* sb_fast_model_create(const sb_model* m, sb_error* err) {
    sb_fast_model* f = calloc(1, sizeof *f);
    bool ok = f != NULL;
    int64_t* owner = ok ? sb_bond_owners(m, &ok) : NULL;
    uint32_t* carried = ok ? sb_hinge_carriers(m, &ok) : NULL;
    ok = ok && sb_fast_vertices(f, m) && sb_fast_bonds(f, m, owner) && sb_fast_triangles(f, m, carried) &&
         (!owner || sb_fast_fused_edges(f, m, owner)) && sb_fast_hinges(f, m) && sb_fast_tet_group(f, m) &&
         sb_fast_membrane_group(f, m) &&
         (!m->breakable || (sb_fast_places(f, m, owner, carried) && sb_fast_limits(f, m)));
    free(owner);
    free(carried);
    if (!ok) {
        sb_fast_model_destroy(f);
        sb_error_set(err, SB_ERR_NOMEM, "out of memory preparing the fast kernels for %u vertices", m->vertex_count);
        return NULL;
    }
    return f;
}

void sb_fast_model_destroy(sb_fast_model* f) {
    if (!f) return;
    sb_element_group* groups[5] = {&f->bonds, &f->triangles, &f->hinges, &f->tets, &f->membranes};
    for (int g = 0; g < 5; g++) {
        free(groups[g]->ranges);
        free(groups[g]->blocks);
    }
    void* arrays[] = {f->mass,
                      f->inv_mass,
                      f->bonds.source,
                      f->bond_i,
                      f->bond_j,
                      f->bond_r0,
                      f->bond_k.values,
                      f->spring_k.values,
                      f->spring_damping.values,
                      f->triangles.source,
                      f->angle_k.values,
                      f->stretch_bend_k.values,
                      f->hinges.source,
                      f->hinge_phi0,
                      f->hinge_k.values,
                      f->bond_place,
                      f->triangle_slot,
                      f->hinge_slot,
                      f->bond_near_max2,
                      f->bond_near_min2,
                      f->tri_owned,
                      f->tri_hinge_edges,
                      f->hinge_fused_at,
                      f->tets.source,
                      f->tet_volume,
                      f->tet_mu,
                      f->tet_lambda,
                      f->membranes.source,
                      f->membrane_volume,
                      f->membrane_mu,
                      f->membrane_lambda,
                      f->membrane_beta,
                      f->tet_beta,
                      f->tet_nodes,
                      f->tet_lane_volume,
                      f->tet_lane_mu,
                      f->tet_lane_lambda,
                      f->tet_lane_beta,
                      f->membrane_lane_volume,
                      f->membrane_lane_mu,
                      f->membrane_lane_lambda,
                      f->membrane_lane_beta};
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++) free(arrays[a]);
    for (int c = 0; c < 3; c++) {
        free(f->tri_v[c]);
        free(f->tri_cos0[c]);
        free(f->tri_len0[c]);
        free(f->tri_edge_r0[c]);
        free(f->tri_edge_bond_k[c].values);
        free(f->tri_edge_spring_k[c].values);
        free(f->tri_edge_damping[c].values);
        free(f->tri_edge_max_ratio2[c].values);
        free(f->tri_edge_min_ratio2[c].values);
        free(f->tri_hinge_other[c]);
        free(f->tri_hinge_phi0[c]);
        free(f->tri_hinge_k[c].values);
    }
    for (int a = 0; a < 4; a++) free(f->hinge_v[a]);
    for (int a = 0; a < SB_TET_NODES; a++) free(f->tet_v[a]);
    for (int k = 0; k < 9; k++) {
        free(f->tet_dm_inv[k]);
        free(f->tet_lane_dm_inv[k]);
    }
    for (int a = 0; a < 3; a++) free(f->membrane_v[a]);
    for (int k = 0; k < 4; k++) {
        free(f->membrane_dm_inv[k]);
        free(f->membrane_lane_dm_inv[k]);
    }
    free(f);
}
