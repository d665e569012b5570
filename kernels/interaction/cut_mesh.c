/* Cutting through triangles: local remeshing where a blade's edge crosses
 * the surface (sb_solver_def.cut_through), so that the incision lies where
 * the blade went, not along the mesh's edges.
 *
 * Design. Local remeshing, not virtual nodes (Molino, Bao and Fedkiw
 * 2004): a virtual node duplicates each cut element whole and embeds the
 * cut in it, so the pieces' surfaces would still be the old triangles (the
 * incision only a drawn line inside them) and every kernel would need the
 * embedding's weights; remeshing makes the incision's edges real mesh
 * edges that every kernel already handles, at the cost of new vertices
 * and elements. It runs on the working copy (kernels/interaction/
 * breakage.c), whose element arrays get room reserved at creation for
 * the new bonds and triangles (the counts grow, no array is ever
 * reallocated; the reference kernels read the counts each evaluation).
 *
 * Each accepted step, the blades' edges are swept against the bonds
 * (kernels/interaction/cutting.c, continuous in time) and each crossing,
 * where along the bond the edge met it (fraction f from its first end),
 *  - on a bond with an end already on the cut, past its middle, puts the
 *    other end on the cut: the blade's path holds two points of the bond,
 *    so it runs along it (refining there, as the tissue moves the blade
 *    across it again and again, would make ever shorter edges); nearer, it
 *    is no crossing;
 *  - within SB_CUT_SNAP of the mean bond length of an end puts that end on
 *    the cut (no sliver);
 *  - else refines the bond: a vertex P on it at f, on the cut, its
 *    position, velocity and displacement interpolated at f. The bond
 *    becomes its first part and a new bond its second, each with its
 *    constants and a share f or 1 − f of its rest length. Each triangle
 *    (a, b, x) on the bond becomes (a, P, x) and a new (P, b, x), in the
 *    same orientation, with the rest lengths of its edges interpolated (P x
 *    by Stewart's theorem from the triangle's own rest lengths, so the rest
 *    state is the old one's, cut) and the rest cosines from them; a new
 *    bond P x takes the refined bond's constants. A hinge across the bond
 *    now runs across its first part; a hinge whose wing was the triangle
 *    takes P for the wing's far vertex (P lies in the triangle's plane at
 *    rest: the rest dihedrals hold). The new inner edges get no hinge.
 * The stable step. An explicit step is stable while ω dt < 2, ω² about a
 * vertex's stiffness over its mass; the cut must not raise that anywhere
 * or the sheet runs away at its own step (a new vertex with a lever share
 * of its ends' mass but four full bonds did, at the first cut). So:
 *  - the ratio limit is the largest bond stiffness over mass of a free
 *    vertex of the model (its step is stable for it);
 *  - P takes the mass its bonds need at that ratio, from its ends in the
 *    lever ratio, (1 − f) from the first and f from the second (mass,
 *    momentum and centre of mass of the three those of the two before, to
 *    rounding; the forces, for the Verlet re-kick, go with the mass), as
 *    far as each end can spare it and stay at the limit itself (a tenth of
 *    its mass at least; half of a fixed one's); where they cannot, P's new
 *    bonds are softer in proportion;
 *  - a far corner x gains the bond P x but no mass: the bond is no stiffer
 *    than x can take at the limit;
 *  - the angle and stretch-bend constants of (a, P, x) and (P, b, x) are
 *    g² and (1 − g)² of the old (g: P's fraction from a; such a term's
 *    stiffness goes as its constant over its shorter edge squared), a
 *    hinge whose wing's far vertex became P takes g² (or (1 − g)²: P is
 *    that much lower over its edge) and a hinge across the bond f²: a
 *    sliver is soft, never stiff (these terms' energy only drops; a new
 *    bond P x adds a little where its triangle is strained);
 *  - a vertex on a bond between two fixed vertices is fixed (the pin holds
 *    the edge);
 *  - a split vertex's copies share its mass by the stiffness of the bonds
 *    each takes (by their fans' areas a sliver fan's copy was light on
 *    full bonds), so each keeps its ratio.
 * Then every edge whose two ends are on the cut (the cut is where the
 * blade went, so such an edge lies along it) is cut: an inner edge's bond
 * gets a twin, each with half the constants (the pair pulls as the bond
 * did), one for the triangle on each side, and the hinge across it loses
 * its constant. Last, each vertex on the cut whose triangles fall into
 * several fans (joined through edges that are not cut) is split, one
 * vertex per fan, as tearing splits (kernels/interaction/topology.c): the
 * copies take the vertex's state, the mass by their bonds' stiffness (above),
 * and its bonds, triangles and hinges go with their fans.
 *
 * Everything runs on the advancing thread in bond order, blades in their
 * order: the same cut for any thread count. The element lists it needs
 * (the triangles and bonds at a vertex) are found by a scan of the
 * elements at each refinement and split, a cost only of the steps that
 * cut (fine for the sheets a trainer cuts; a large mesh would want stars).
 * The fast kernels' element layout (colors, blocks, padded slots) is
 * built at creation from the elements there are, so after a step that
 * cut, the fast model is built again from the working copy
 * (sb_fast_rebuild; a cost only of the steps that cut), and implicit
 * Euler builds its matrix anew when the element count changed
 * (kernels/integrators/implicit_euler.c); pbd, xpbd and vbd keep
 * structures of their own built for the first elements and are refused
 * at creation. */
#include "kernels/interaction/cut_mesh.h"
#include "kernels/state/solver_data.h"
#include "common/union_find.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SB_NONE UINT32_MAX
/* A crossing this close to a bond's end (a fraction of the model's mean
 * bond rest length) puts the end on the cut instead of a new vertex: the
 * cut at most 2 % of a bond off the blade's line, and no sliver. */
#define SB_CUT_SNAP 0.02

struct sb_cut_mesh {
    sb_model* live;
    uint32_t vertices, vertex_capacity; /* in use, reserved (live->vertex_count) */
    uint32_t bond_capacity, triangle_capacity, refused;
    double snap;            /* m: SB_CUT_SNAP of the model's mean bond rest length */
    double ratio_limit;     /* 1/s²: the largest bond stiffness over mass of a free model vertex */
    uint8_t *on_cut, *skip; /* per vertex: on the cut; per bond: cut, or severed */
    uint32_t* side;         /* per bond: for a cut one, the triangle it belongs to */
    double* block;          /* the element arrays with room */
    uint32_t* index_block;
    /* work space: a vertex's triangles and their fans */
    uint32_t *star, *fan, *parent;
};

static double sb_sq(double a) { return a * a; }

/* Bond e's stiffness (its harmonic and spring constants), N/m. */
static double sb_bond_stiffness(const sb_model* m, uint32_t e) { return m->bond_k[e] + m->spring_k[e]; }

/* The bonds' stiffness at vertex v, N/m. */
static double sb_vertex_stiffness(const sb_model* m, uint32_t v) {
    double sum = 0.0;
    for (uint32_t e = 0; e < m->bond_count; e++)
        if (m->bond_i[e] == v || m->bond_j[e] == v) sum += sb_bond_stiffness(m, e);
    return sum;
}

/* The largest stiffness over mass of a free vertex: the model's stable
 * step is about 2 / √ of it (a lattice's fastest mode), so the cut keeps
 * every vertex it makes or lightens at or below it. */
static double sb_ratio_limit(const sb_model* m) {
    double *stiffness = calloc((size_t)m->vertex_count + 1, sizeof *stiffness), limit = 0.0;
    if (!stiffness) return 0.0;
    for (uint32_t e = 0; e < m->bond_count; e++) {
        stiffness[m->bond_i[e]] += sb_bond_stiffness(m, e);
        stiffness[m->bond_j[e]] += sb_bond_stiffness(m, e);
    }
    for (uint32_t v = 0; v < m->vertex_count; v++)
        if (m->inv_mass[v] > 0.0) limit = fmax(limit, stiffness[v] * m->inv_mass[v]);
    free(stiffness);
    return limit;
}

/* live's bond and triangle arrays again, with room for the new ones. */
static bool sb_room(sb_cut_mesh* c) {
    sb_model* l = c->live;
    size_t nb = c->bond_capacity, nt = c->triangle_capacity;
    c->block = calloc(8 * nb + 8 * nt + 1, sizeof(double));
    c->index_block = calloc(2 * nb + 3 * nt + 1, sizeof(uint32_t));
    if (!c->block || !c->index_block) return false;
    double** reals[16] = {&l->bond_r0,
                          &l->bond_k,
                          &l->spring_k,
                          &l->spring_damping,
                          &l->bond_break_min,
                          &l->bond_break_max,
                          &l->tri_cos0[0],
                          &l->tri_cos0[1],
                          &l->tri_cos0[2],
                          &l->tri_len0[0],
                          &l->tri_len0[1],
                          &l->tri_len0[2],
                          &l->angle_k,
                          &l->stretch_bend_k,
                          NULL,
                          NULL};
    double* next = c->block;
    for (int a = 0; a < 14; a++) {
        size_t count = a < 6 ? l->bond_count : l->triangle_count, room = a < 6 ? nb : nt;
        memcpy(next, *reals[a], count * sizeof(double));
        *reals[a] = next;
        next += room;
    }
    for (size_t e = l->bond_count; e < nb; e++) l->bond_break_max[e] = INFINITY;
    uint32_t** index[5] = {&l->bond_i, &l->bond_j, &l->tri_v[0], &l->tri_v[1], &l->tri_v[2]};
    uint32_t* at = c->index_block;
    for (int a = 0; a < 5; a++) {
        size_t count = a < 2 ? l->bond_count : l->triangle_count;
        memcpy(at, *index[a], count * sizeof *at);
        *index[a] = at;
        at += a < 2 ? nb : nt;
    }
    return true;
}

sb_cut_mesh* sb_cut_mesh_create(sb_model* live, uint32_t model_vertices, bool* ok) {
    sb_cut_mesh* c = calloc(1, sizeof *c);
    *ok = c != NULL;
    if (!c) return NULL;
    uint32_t spare = live->vertex_count - model_vertices;
    *c = (sb_cut_mesh){.live = live,
                       .vertices = model_vertices,
                       .vertex_capacity = live->vertex_count,
                       .bond_capacity = live->bond_count + 4 * spare,
                       .triangle_capacity = live->triangle_count + 2 * spare};
    size_t nv = c->vertex_capacity + 1, nb = c->bond_capacity + 1;
    c->on_cut = calloc(nv, 1);
    c->skip = calloc(nb, 1);
    c->side = malloc(nb * sizeof *c->side);
    c->star = malloc(((size_t)c->triangle_capacity + 1) * sizeof *c->star);
    c->fan = malloc(((size_t)c->triangle_capacity + 1) * sizeof *c->fan);
    c->parent = malloc(((size_t)c->triangle_capacity + 1) * sizeof *c->parent);
    *ok = c->on_cut && c->skip && c->side && c->star && c->fan && c->parent && sb_room(c);
    if (!*ok) {
        sb_cut_mesh_destroy(c);
        return NULL;
    }
    for (size_t e = 0; e < nb; e++) c->side[e] = SB_NONE;
    double sum = 0.0;
    for (uint32_t e = 0; e < live->bond_count; e++) sum += live->bond_r0[e];
    c->snap = live->bond_count ? SB_CUT_SNAP * sum / live->bond_count : 0.0;
    c->ratio_limit = sb_ratio_limit(live);
    return c;
}

void sb_cut_mesh_destroy(sb_cut_mesh* c) {
    if (!c) return;
    void* arrays[] = {c->on_cut, c->skip, c->side, c->block, c->index_block, c->star, c->fan, c->parent};
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++) free(arrays[a]);
    free(c);
}

uint32_t sb_cut_mesh_vertex_count(const sb_cut_mesh* c) { return c->vertices; }
uint32_t sb_cut_mesh_refused(const sb_cut_mesh* c) { return c->refused; }
const uint8_t* sb_cut_mesh_skip(const sb_cut_mesh* c) { return c->skip; }

/* ---- vertices ------------------------------------------------------------------ */

/* Vertex i's mass where the solver keeps it; `held` by a hard handle keeps
 * inverse mass 0 where the integrators move it. */
static void sb_set_mass(sb_solver* s, sb_model* m, uint32_t i, double mass, bool held) {
    m->mass[i] = mass;
    m->inv_mass[i] = m->fixed[i] || !(mass > 0.0) ? 0.0 : 1.0 / mass;
    if (s->pinned_inv_mass) s->pinned_inv_mass[i] = held ? 0.0 : m->inv_mass[i];
}

/* The per-vertex arrays a new vertex's values are written into: the
 * model's rest and initial velocity, the state, the Verlet displacement and
 * compensation. */
enum { SB_VERTEX_ARRAYS = 15 };
static void sb_vertex_arrays(sb_solver* s, double* rest[6], sb_real* state[12]) {
    sb_model* m = (sb_model*)s->model;
    double* r[6] = {m->rest_x, m->rest_y, m->rest_z, m->vel_x, m->vel_y, m->vel_z};
    sb_state* st = &s->state;
    sb_real* q[12] = {st->x,     st->y,     st->z,     st->vx,     st->vy,     st->vz,
                      s->disp_x, s->disp_y, s->disp_z, s->carry_x, s->carry_y, s->carry_z};
    memcpy(rest, r, sizeof r);
    memcpy(state, q, sizeof q);
}

/* Vertex w gets (1 − f) of u's values plus f of v's (f = 0: a copy of u). */
void sb_blend_vertex(sb_solver* s, uint32_t u, uint32_t v, double f, uint32_t w) {
    double* rest[6];
    sb_real* state[12];
    sb_vertex_arrays(s, rest, state);
    for (int a = 0; a < 6; a++) rest[a][w] = (1.0 - f) * rest[a][u] + f * rest[a][v];
    for (int a = 0; a < 12; a++) state[a][w] = (sb_real)((1.0 - f) * state[a][u] + f * state[a][v]);
    for (int a = 0; s->fast && a < 3; a++) /* the fast path's compensation lives packed only */
        s->carry4[4 * (size_t)w + a] =
            (sb_real)((1.0 - f) * s->carry4[4 * (size_t)u + a] + f * s->carry4[4 * (size_t)v + a]);
    uint8_t* fixed = ((sb_model*)s->model)->fixed;
    fixed[w] = fixed[u] && fixed[v]; /* a copy of a fixed vertex, or a vertex on a bond between two, is fixed */
}

/* Moves `share` of vertex u's mass (and the same part of its force before the
 * step's end, for the re-kick) to w, a new vertex (free: no handle holds it). */
void sb_give_mass(sb_solver* s, uint32_t u, uint32_t w, double share, double* before) {
    sb_model* m = (sb_model*)s->model;
    double mass = m->mass[u], part = mass > 0.0 ? share / mass : 0.0;
    bool held = s->pinned_inv_mass && s->pinned_inv_mass[u] == 0.0 && !m->fixed[u];
    for (int a = 0; a < 3; a++) {
        double moved = part * before[3 * (size_t)u + a];
        before[3 * (size_t)w + a] += moved;
        before[3 * (size_t)u + a] -= moved;
    }
    sb_set_mass(s, m, w, m->mass[w] + share, false);
    sb_set_mass(s, m, u, mass - share, held);
}

/* A new vertex slot, or SB_NONE when none is left. */
static uint32_t sb_new_vertex(sb_cut_mesh* c, double* before) {
    if (c->vertices == c->vertex_capacity) {
        c->refused++;
        return SB_NONE;
    }
    uint32_t w = c->vertices++;
    for (int a = 0; a < 3; a++) before[3 * (size_t)w + a] = 0.0;
    return w;
}

/* ---- elements -------------------------------------------------------------------- */

/* The corner of triangle t at vertex v, or −1. */
static int sb_corner(const sb_model* m, uint32_t t, uint32_t v) {
    for (int k = 0; k < 3; k++)
        if (m->tri_v[k][t] == v) return k;
    return -1;
}

/* The triangles on edge (i, j), at most two found: returns the count. */
static int sb_edge_triangles(const sb_model* m, uint32_t i, uint32_t j, uint32_t out[2]) {
    int count = 0;
    for (uint32_t t = 0; t < m->triangle_count && count < 2; t++)
        if (sb_corner(m, t, i) >= 0 && sb_corner(m, t, j) >= 0) out[count++] = t;
    return count;
}

/* Triangle t's rest cosines from its rest lengths (law of cosines). */
static void sb_rest_cosines(sb_model* m, uint32_t t) {
    for (int k = 0; k < 3; k++) {
        double next = m->tri_len0[k][t], prev = m->tri_len0[(k + 2) % 3][t], across = m->tri_len0[(k + 1) % 3][t];
        m->tri_cos0[k][t] = (sb_sq(next) + sb_sq(prev) - sb_sq(across)) / (2.0 * next * prev);
    }
}

/* A new bond (i, j) with bond `like`'s constants, scaled by `scale`, rest length r0. */
static uint32_t sb_add_bond(sb_cut_mesh* c, uint32_t i, uint32_t j, uint32_t like, double scale, double r0) {
    sb_model* m = c->live;
    uint32_t e = m->bond_count++;
    m->bond_i[e] = i, m->bond_j[e] = j, m->bond_r0[e] = r0;
    m->bond_k[e] = scale * m->bond_k[like];
    m->spring_k[e] = scale * m->spring_k[like];
    m->spring_damping[e] = scale * m->spring_damping[like];
    m->bond_break_min[e] = 0.0, m->bond_break_max[e] = INFINITY;
    c->side[e] = SB_NONE;
    c->skip[e] = 0;
    return e;
}

/* Hinge h's vertex `from` becomes `to` when it is one of roles [first, last). */
static void sb_hinge_swap(sb_model* m, uint32_t h, int first, int last, uint32_t from, uint32_t to) {
    uint32_t* roles[4] = {m->hinge_e0, m->hinge_e1, m->hinge_o0, m->hinge_o1};
    for (int r = first; r < last; r++)
        if (roles[r][h] == from) roles[r][h] = to;
}

static bool sb_hinge_edge(const sb_model* m, uint32_t h, uint32_t a, uint32_t b) {
    return (m->hinge_e0[h] == a && m->hinge_e1[h] == b) || (m->hinge_e0[h] == b && m->hinge_e1[h] == a);
}

/* The hinges after triangle (a, b, x) became (a, P, x) and (P, b, x), P at
 * g from a: a wing's far vertex b (a) becomes P, g (1 − g) as high over
 * the hinge's edge, and the hinge's constant takes the square of that (its
 * stiffness against P's motion goes as the constant over the height squared). */
static void sb_refine_hinges(sb_model* m, uint32_t a, uint32_t b, uint32_t x, uint32_t p, double g) {
    for (uint32_t h = 0; h < m->hinge_count; h++) {
        bool on_ax = sb_hinge_edge(m, h, a, x), on_bx = sb_hinge_edge(m, h, b, x);
        if (!on_ax && !on_bx) continue;
        uint32_t far = on_ax ? b : a;
        if (m->hinge_o0[h] != far && m->hinge_o1[h] != far) continue;
        sb_hinge_swap(m, h, 2, 4, far, p);
        m->hinge_k[h] *= sb_sq(on_ax ? g : 1.0 - g);
    }
}

/* How much mass vertex v can give a new vertex and stay at or below the
 * ratio limit (a tenth of its mass at least); half of a fixed or held
 * vertex's (it does not move: no step limit). */
static double sb_spare_mass(const sb_solver* s, const sb_cut_mesh* c, uint32_t v) {
    const sb_model* m = c->live;
    if (sb_inv_mass(s)[v] == 0.0) return 0.5 * m->mass[v];
    return fmax(m->mass[v] - sb_vertex_stiffness(m, v) / c->ratio_limit, 0.1 * m->mass[v]);
}

/* How much stiffness vertex v can take on and stay at or below the ratio
 * limit, N/m (no limit for a fixed or held vertex). */
static double sb_spare_stiffness(const sb_solver* s, const sb_cut_mesh* c, uint32_t v) {
    const sb_model* m = c->live;
    if (sb_inv_mass(s)[v] == 0.0) return INFINITY;
    return fmax(0.0, c->ratio_limit * m->mass[v] - sb_vertex_stiffness(m, v));
}

/* Triangle t, with the bond (u, w) on its edge, split at P (fraction f from
 * u); the new bond P x takes `bond`'s constants times `scale`, less where x
 * cannot take them on (x gains a bond, not mass). */
static void sb_refine_triangle(sb_solver* s, sb_cut_mesh* c, uint32_t t, uint32_t u, uint32_t w, double f, uint32_t p,
                               uint32_t bond, double scale) {
    sb_model* m = c->live;
    int cu = sb_corner(m, t, u), cw = sb_corner(m, t, w);
    /* (a, b, x) in t's order: the edge runs a → b at corner ca */
    int ca = (cu + 1) % 3 == cw ? cu : cw, cb = (ca + 1) % 3, cx = (ca + 2) % 3;
    uint32_t a = m->tri_v[ca][t], b = m->tri_v[cb][t], x = m->tri_v[cx][t];
    double g = a == u ? f : 1.0 - f; /* P's fraction from a */
    double ab = m->tri_len0[ca][t], bx = m->tri_len0[cb][t], xa = m->tri_len0[cx][t];
    double px = sqrt(fmax(0.0, (1.0 - g) * sb_sq(xa) + g * sb_sq(bx) - g * (1.0 - g) * sb_sq(ab)));
    uint32_t n = m->triangle_count++;
    for (int k = 0; k < 3; k++) m->tri_v[k][n] = m->tri_v[k][t];
    m->tri_v[cb][t] = p; /* t: (a, P, x) */
    m->tri_v[ca][n] = p; /* n: (P, b, x) */
    m->tri_len0[ca][t] = g * ab, m->tri_len0[cb][t] = px;
    m->tri_len0[ca][n] = (1.0 - g) * ab, m->tri_len0[cb][n] = bx, m->tri_len0[cx][n] = px;
    /* the angle terms' stiffness goes as the constant over the shorter edge
     * squared: the constants by the square of the part, a sliver stays soft */
    m->angle_k[n] = sb_sq(1.0 - g) * m->angle_k[t], m->angle_k[t] *= sb_sq(g);
    m->stretch_bend_k[n] = sb_sq(1.0 - g) * m->stretch_bend_k[t], m->stretch_bend_k[t] *= sb_sq(g);
    sb_rest_cosines(m, t);
    sb_rest_cosines(m, n);
    sb_refine_hinges(m, a, b, x, p, g);
    double stiffness = sb_bond_stiffness(m, bond);
    sb_add_bond(c, p, x, bond, stiffness > 0.0 ? fmin(scale, sb_spare_stiffness(s, c, x) / stiffness) : scale, px);
}

/* Refines bond e at fraction f: a vertex on it, the cut's. */
static void sb_refine(sb_solver* s, sb_cut_mesh* c, uint32_t e, double f, double* before) {
    sb_model* m = c->live;
    uint32_t u = m->bond_i[e], w = m->bond_j[e], p = sb_new_vertex(c, before);
    if (p == SB_NONE) return;
    sb_blend_vertex(s, u, w, f, p);
    uint32_t sides[2], wings = (uint32_t)sb_edge_triangles(m, u, w, sides);
    /* P's bonds: the bond's two parts and one to each triangle's far corner */
    double stiffness = (2.0 + wings) * sb_bond_stiffness(m, e), need = stiffness / c->ratio_limit;
    double share = fmin(need, fmin(sb_spare_mass(s, c, u) / (1.0 - f), sb_spare_mass(s, c, w) / f));
    double scale = share < need ? share / need : 1.0; /* P's bonds softer where its ends cannot spare the mass */
    sb_give_mass(s, u, p, (1.0 - f) * share, before);
    sb_give_mass(s, w, p, f * share, before);
    c->on_cut[p] = 1;
    uint32_t triangles = m->triangle_count;
    for (uint32_t t = 0; t < triangles; t++)
        if (sb_corner(m, t, u) >= 0 && sb_corner(m, t, w) >= 0) sb_refine_triangle(s, c, t, u, w, f, p, e, scale);
    for (uint32_t h = 0; h < m->hinge_count; h++)
        if (sb_hinge_edge(m, h, u, w)) {
            sb_hinge_swap(m, h, 0, 2, w, p);
            m->hinge_k[h] *= sb_sq(f); /* across the bond's first part, f as long */
        }
    double r0 = m->bond_r0[e];
    sb_add_bond(c, p, w, e, scale, (1.0 - f) * r0);
    m->bond_j[e] = p;
    m->bond_r0[e] = f * r0;
    m->bond_k[e] *= scale, m->spring_k[e] *= scale, m->spring_damping[e] *= scale;
}

/* Whether the cut's new elements fit: a refinement takes one vertex, at
 * most 2 + triangles-on-the-bond bonds and that many triangles. */
static bool sb_fits(const sb_cut_mesh* c) {
    const sb_model* m = c->live;
    return m->bond_count + 4 <= c->bond_capacity && m->triangle_count + 2 <= c->triangle_capacity;
}

void sb_cut_mesh_cross(sb_solver* s, sb_cut_mesh* c, uint32_t bond, double f, double* before) {
    sb_model* m = c->live;
    bool edge = false;
    for (uint32_t t = 0; t < m->triangle_count && !edge; t++)
        edge = sb_corner(m, t, m->bond_i[bond]) >= 0 && sb_corner(m, t, m->bond_j[bond]) >= 0;
    if (!edge) { /* a bond on no triangle's edge (a spring across cells) is severed */
        m->bond_k[bond] = m->spring_k[bond] = m->spring_damping[bond] = m->bond_r0[bond] = 0.0;
        c->skip[bond] = 1;
    } else if (c->on_cut[m->bond_i[bond]] || c->on_cut[m->bond_j[bond]]) {
        /* the blade met the bond at one of its ends and at a second point past
         * its middle: it runs along it, and the far end is on the cut (nearer,
         * it is the end's own crossing: an end snapped onto the cut lies a
         * little off the blade's line, which meets its bonds near it) */
        uint32_t far = c->on_cut[m->bond_i[bond]] ? m->bond_j[bond] : m->bond_i[bond];
        double from_cut = (far == m->bond_j[bond] ? f : 1.0 - f) * m->bond_r0[bond];
        if (from_cut >= 0.5 * m->bond_r0[bond]) c->on_cut[far] = 1;
    } else if (f * m->bond_r0[bond] < c->snap || (1.0 - f) * m->bond_r0[bond] < c->snap)
        c->on_cut[f < 0.5 ? m->bond_i[bond] : m->bond_j[bond]] = 1;
    else if (sb_fits(c))
        sb_refine(s, c, bond, f, before);
    else
        c->refused++;
}

/* ---- cut edges and splits ------------------------------------------------------------ */

/* Bond e's edge, its two ends on the cut, is cut: an inner one gets a twin
 * for its second triangle, each with half the constants; the hinges across
 * it lose theirs. */
static void sb_cut_edge(sb_cut_mesh* c, uint32_t e) {
    sb_model* m = c->live;
    uint32_t sides[2], i = m->bond_i[e], j = m->bond_j[e];
    int count = sb_edge_triangles(m, i, j, sides);
    if (count == 0) return;
    c->skip[e] = 1;
    c->side[e] = sides[0];
    if (count == 2) {
        uint32_t twin = sb_add_bond(c, i, j, e, 0.5, m->bond_r0[e]);
        c->skip[twin] = 1;
        c->side[twin] = sides[1];
        m->bond_k[e] *= 0.5, m->spring_k[e] *= 0.5, m->spring_damping[e] *= 0.5;
    }
    for (uint32_t h = 0; h < m->hinge_count; h++)
        if (sb_hinge_edge(m, h, i, j)) m->hinge_k[h] = 0.0;
}

/* Whether the edge (i, j) is the longest (at rest) of a triangle whose
 * three corners are on the cut: a sliver the cut runs along, the cut then
 * along its two other edges (the sliver stays with the side across this one). */
static bool sb_sliver_base(const sb_cut_mesh* c, uint32_t i, uint32_t j) {
    const sb_model* m = c->live;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        int ci = sb_corner(m, t, i), cj = sb_corner(m, t, j);
        if (ci < 0 || cj < 0) continue;
        int first = (ci + 1) % 3 == cj ? ci : cj; /* the edge's corner: its rest length is tri_len0[first] */
        if (!c->on_cut[m->tri_v[(first + 2) % 3][t]]) continue;
        double edge = m->tri_len0[first][t];
        if (edge >= m->tri_len0[(first + 1) % 3][t] && edge >= m->tri_len0[(first + 2) % 3][t]) return true;
    }
    return false;
}

static void sb_cut_edges(sb_cut_mesh* c) {
    sb_model* m = c->live;
    uint32_t bonds = m->bond_count;
    for (uint32_t e = 0; e < bonds; e++) {
        uint32_t i = m->bond_i[e], j = m->bond_j[e];
        if (!c->skip[e] && c->on_cut[i] && c->on_cut[j] && m->bond_count + 1 <= c->bond_capacity &&
            !sb_sliver_base(c, i, j))
            sb_cut_edge(c, e);
    }
}

/* Whether the edge (v, x) is cut: a bond on it is. */
static bool sb_edge_cut(const sb_cut_mesh* c, uint32_t v, uint32_t x) {
    const sb_model* m = c->live;
    for (uint32_t e = 0; e < m->bond_count; e++)
        if (((m->bond_i[e] == v && m->bond_j[e] == x) || (m->bond_i[e] == x && m->bond_j[e] == v)) && c->skip[e] &&
            c->side[e] != SB_NONE)
            return true;
    return false;
}

/* v's triangles into c->star (*degree of them) and their fans into c->fan
 * (0, 1, … in the order of their first triangle), joined through edges not
 * cut. Returns the fans. */
static uint32_t sb_fans(sb_cut_mesh* c, uint32_t v, uint32_t* degree) {
    const sb_model* m = c->live;
    uint32_t d = 0, fans = 0;
    for (uint32_t t = 0; t < m->triangle_count; t++)
        if (sb_corner(m, t, v) >= 0) c->parent[d] = d, c->star[d++] = t;
    for (uint32_t i = 0; i < d; i++)
        for (int k = 0; k < 3; k++) {
            uint32_t x = m->tri_v[k][c->star[i]];
            if (x == v || sb_edge_cut(c, v, x)) continue;
            for (uint32_t j = i + 1; j < d; j++)
                if (sb_corner(m, c->star[j], x) >= 0) {
                    uint32_t a = sb_find(c->parent, i), b = sb_find(c->parent, j);
                    c->parent[a > b ? a : b] = a > b ? b : a;
                }
        }
    for (uint32_t i = 0; i < d; i++) c->fan[i] = SB_NONE;
    for (uint32_t i = 0; i < d; i++) {
        uint32_t root = sb_find(c->parent, i);
        if (c->fan[root] == SB_NONE) c->fan[root] = fans++;
        c->fan[i] = c->fan[root];
    }
    *degree = d;
    return d ? fans : 0;
}

/* The fan of v's first triangle that has x and y besides v (y = SB_NONE: x alone), or 0. */
static uint32_t sb_fan_with(const sb_cut_mesh* c, uint32_t x, uint32_t y, uint32_t d) {
    for (uint32_t i = 0; i < d; i++)
        if (sb_corner(c->live, c->star[i], x) >= 0 && (y == SB_NONE || sb_corner(c->live, c->star[i], y) >= 0))
            return c->fan[i];
    return 0;
}

static uint32_t sb_fan_of(const sb_cut_mesh* c, uint32_t t, uint32_t d) {
    for (uint32_t i = 0; i < d; i++)
        if (c->star[i] == t) return c->fan[i];
    return 0;
}

/* The fan of v's bond e (v one of its ends). */
static uint32_t sb_bond_fan(const sb_cut_mesh* c, uint32_t e, uint32_t v, uint32_t d) {
    const sb_model* m = c->live;
    uint32_t x = m->bond_i[e] == v ? m->bond_j[e] : m->bond_i[e];
    return c->side[e] != SB_NONE ? sb_fan_of(c, c->side[e], d) : sb_fan_with(c, x, SB_NONE, d);
}

/* Splits v into one vertex per fan (first, first + 1, … for fans 1, …).
 * Each copy's mass is v's in proportion to the stiffness of the bonds it
 * takes, so each keeps v's stiffness over mass (a fan's rest area would
 * leave a sliver fan's copy light on full bonds: a step too long for it). */
static void sb_split(sb_solver* s, sb_cut_mesh* c, uint32_t v, uint32_t fans, uint32_t d, double* before) {
    sb_model* m = c->live;
    if (c->vertices + fans - 1 > c->vertex_capacity) {
        c->refused += fans - 1;
        return;
    }
    uint32_t first = c->vertices;
    c->vertices += fans - 1;
    double stiffness[64] = {0}, total = 0.0;
    for (uint32_t e = 0; e < m->bond_count; e++)
        if (m->bond_i[e] == v || m->bond_j[e] == v) {
            uint32_t f = sb_bond_fan(c, e, v, d);
            stiffness[f < 64 ? f : 63] += sb_bond_stiffness(m, e);
            total += sb_bond_stiffness(m, e);
        }
    double mass = m->mass[v];
    for (uint32_t f = 1; f < fans; f++) {
        uint32_t w = first + f - 1;
        sb_blend_vertex(s, v, v, 0.0, w);
        for (int a = 0; a < 3; a++) before[3 * (size_t)w + a] = 0.0;
        m->mass[w] = 0.0;
        sb_give_mass(s, v, w, total > 0.0 ? mass * stiffness[f < 64 ? f : 63] / total : mass / fans, before);
        c->on_cut[w] = 1;
    }
    for (uint32_t e = 0; e < m->bond_count; e++) { /* bonds first: they look at the triangles' fans */
        int end = m->bond_i[e] == v ? 0 : m->bond_j[e] == v ? 1 : -1;
        if (end < 0) continue;
        uint32_t f = sb_bond_fan(c, e, v, d);
        if (f) *(end ? &m->bond_j[e] : &m->bond_i[e]) = first + f - 1;
    }
    for (uint32_t h = 0; h < m->hinge_count; h++) {
        uint32_t ids[4] = {m->hinge_e0[h], m->hinge_e1[h], m->hinge_o0[h], m->hinge_o1[h]}, f = 0;
        for (int r = 0; r < 4; r++) {
            if (ids[r] != v) continue;
            f = r < 2 ? sb_fan_with(c, ids[1 - r], ids[2], d) : sb_fan_with(c, ids[0], ids[1], d);
            if (f) sb_hinge_swap(m, h, r, r + 1, v, first + f - 1);
        }
    }
    for (uint32_t i = 0; i < d; i++)
        if (c->fan[i]) m->tri_v[sb_corner(m, c->star[i], v)][c->star[i]] = first + c->fan[i] - 1;
}

void sb_cut_mesh_separate(sb_solver* s, sb_cut_mesh* c, double* before) {
    sb_cut_edges(c);
    uint32_t vertices = c->vertices;
    for (uint32_t v = 0; v < vertices; v++) {
        if (!c->on_cut[v]) continue;
        uint32_t d, fans = sb_fans(c, v, &d);
        if (fans > 1) sb_split(s, c, v, fans, d, before);
    }
}

/* ---- the saved state ---------------------------------------------------------------- */

enum { SB_CUT_RANGES = 38 };

static int sb_cut_ranges(sb_cut_mesh* c, sb_range* out) {
    sb_model* m = c->live;
    size_t nv = c->vertex_capacity, nb = c->bond_capacity, nt = c->triangle_capacity, nh = m->hinge_count;
    sb_range list[SB_CUT_RANGES] = {{&c->vertices, 4},
                                    {&c->refused, 4},
                                    {&m->bond_count, 4},
                                    {&m->triangle_count, 4},
                                    {c->on_cut, nv},
                                    {c->skip, nb},
                                    {c->side, 4 * nb},
                                    {m->rest_x, 8 * nv},
                                    {m->rest_y, 8 * nv},
                                    {m->rest_z, 8 * nv},
                                    {m->vel_x, 8 * nv},
                                    {m->vel_y, 8 * nv},
                                    {m->vel_z, 8 * nv},
                                    {m->mass, 8 * nv},
                                    {m->inv_mass, 8 * nv},
                                    {m->fixed, nv},
                                    {m->bond_i, 4 * nb},
                                    {m->bond_j, 4 * nb},
                                    {m->bond_r0, 8 * nb},
                                    {m->bond_k, 8 * nb},
                                    {m->spring_k, 8 * nb},
                                    {m->spring_damping, 8 * nb},
                                    {m->tri_v[0], 4 * nt},
                                    {m->tri_v[1], 4 * nt},
                                    {m->tri_v[2], 4 * nt},
                                    {m->tri_cos0[0], 8 * nt},
                                    {m->tri_cos0[1], 8 * nt},
                                    {m->tri_cos0[2], 8 * nt},
                                    {m->tri_len0[0], 8 * nt},
                                    {m->tri_len0[1], 8 * nt},
                                    {m->tri_len0[2], 8 * nt},
                                    {m->angle_k, 8 * nt},
                                    {m->stretch_bend_k, 8 * nt},
                                    {m->hinge_k, 8 * nh},
                                    {m->hinge_e0, 4 * nh},
                                    {m->hinge_e1, 4 * nh},
                                    {m->hinge_o0, 4 * nh},
                                    {m->hinge_o1, 4 * nh}};
    memcpy(out, list, sizeof list);
    return SB_CUT_RANGES;
}

void sb_cut_mesh_save(const sb_cut_mesh* c, sb_sections_writer* w) {
    sb_range ranges[SB_CUT_RANGES];
    sb_ranges_put(w, ranges, sb_cut_ranges((sb_cut_mesh*)c, ranges)); /* reads only */
}

void sb_cut_mesh_load(sb_solver* s, sb_cut_mesh* c, sb_cursor* r) {
    sb_range ranges[SB_CUT_RANGES];
    sb_ranges_take(r, ranges, sb_cut_ranges(c, ranges));
    const sb_model* m = c->live;
    for (uint32_t v = 0; v < c->vertex_capacity; v++) /* the handles pin theirs again after */
        if (s->pinned_inv_mass) s->pinned_inv_mass[v] = m->inv_mass[v];
}
