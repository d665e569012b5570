/* Cutting through tetrahedra: local remeshing where a blade's swept
 * surface passes through a body of linear co-rotated tetrahedra
 * (sb_solver_def.cut_through; the triangles' counterpart is
 * kernels/interaction/cut_mesh.c), so that the incision lies where the
 * blade went, not along the mesh's faces.
 *
 * Design. Local remeshing, not virtual nodes (Molino, Bao and Fedkiw
 * 2004), for cut_mesh.c's reason: the pieces' new surfaces are real faces
 * of real tetrahedra that the elasticity, the contact's surface and every
 * output already handle, with no embedding weights in any kernel; the
 * price is new vertices and elements where the blade passes.
 *
 * The remeshing is by edge bisection. Each accepted step the blades'
 * edges are swept against the tetrahedra's unique edges
 * (kernels/interaction/cutting.c, continuous in time: no edge slips past
 * a blade), and each crossing, at fraction f from the edge's first end,
 *  - puts each end that lies within its snap distance of the step's swept
 *    plane on the cut instead of making a sliver: SB_CUT_VOLUME_SNAP
 *    (2.5 %) of the longest rest edge at the vertex. An edge is at least
 *    as long along as its end is from the plane, so a bisection lands at
 *    least 2.5 % of the edge from either end (f in [0.025, 0.975]): no
 *    element made is thinner than that fraction of its parent (a bisection
 *    at f gives two of volume f V and (1 − f) V) and the stable step
 *    shrinks at most by about √0.025; a snapped vertex lies at most 2.5 %
 *    of its longest edge off the blade's surface, 4.3 % of a cell in a
 *    mesh of cubes cut into six (the longest edge the cube's diagonal; the
 *    target is 5 %). A bound by the shortest edge instead would let a long
 *    edge be bisected a hair from its end: on scenes/syringe_body's
 *    irregular tetrahedra (edges 1.7 to 67 mm) that made elements 1e-5 of
 *    a regular one's shape, and the body blew up at the first cut. A new
 *    vertex takes the larger of its ends' snap distances, a split's
 *    copies their vertex's. The test is
 *    the vertex's own distance from the plane, not the meeting point's
 *    from the end along the edge, so that every edge at a vertex judges it
 *    alike: a vertex either is on the cut or is not, and no bisection
 *    lands a sliver's width from a vertex snapped by another edge (a
 *    blade that sweeps no plane, moving along itself, falls back to the
 *    meeting point's distance);
 *  - on an edge with an end already on the cut is that end's own crossing;
 *  - else bisects the edge (u, w): a vertex P at f, on the cut, and each
 *    tetrahedron (u, w, a, b) on the edge becomes (u, P, a, b) and
 *    (P, w, a, b), the same orientation, rest shapes (D_m⁻¹, volume) from
 *    P's interpolated rest position. Every tetrahedron on the edge is
 *    split at the same P, so the mesh stays conforming whatever the order
 *    of the crossings; a tetrahedron the blade's plane fully crosses ends,
 *    after the crossings of its three or four edges, as a tetrahedron and
 *    a prism, or two prisms, each split into tetrahedra whose shared quad
 *    faces are split the same way on both sides (the bisections made them
 *    so: a quad's diagonal is the edge bisected first, not the lowest
 *    index, and it is conforming by construction). P's mass is what the
 *    lumped masses (ρ V / 4 a corner) give the new tetrahedra: ρ V / 4 of
 *    each tetrahedron on the edge, (1 − f) of it taken from u and f from w
 *    (the lever ratio), so with P's position and velocity interpolated at
 *    f the mass, momentum and centre of mass of the three are those of
 *    the two before (to rounding) and the lumping stays consistent; the
 *    forces (for the Verlet re-kick) go with the mass. ρ is each
 *    tetrahedron's own, found at creation from its corners' lumped masses.
 * Then each vertex on the cut whose tetrahedra fall into several groups,
 * joined through faces that are not cut, is split, one vertex per group
 * (the copies take its state, the mass by the groups' rest volumes, and
 * their group's tetrahedra). A face is cut when its three corners are on
 * the cut and the vertices of its two tetrahedra off it are not (a face
 * the blade's surface holds). Last the edges and the boundary faces (the
 * contact's, kernels/contact/surface_triangles.c) are found again.
 *
 * Everything runs on the advancing thread, edges in order, blades in
 * their order: the same cut for any thread count. A tetrahedron's
 * neighbours are found by a scan of the tetrahedra, a cost only of the
 * steps that cut. The quadratic tetrahedra (their middle nodes would need
 * the edge's midpoints moved) and a volume of springs (its model keeps no
 * tetrahedra to split, only their edges) are refused (breakage.c). */
#include "kernels/interaction/cut_volume.h"
#include "kernels/interaction/cut_mesh.h"
#include "kernels/interaction/cutting.h"
#include "kernels/state/solver_data.h"
#include "common/edge_map.h"
#include "common/geometry.h"
#include "common/union_find.h"
#include "softbond/volume.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SB_NONE UINT32_MAX
/* A vertex this close to the blade's plane (a fraction of its longest
 * rest edge) is put on the cut instead of a new vertex beside it. */
#define SB_CUT_VOLUME_SNAP 0.025
/* Room for new tetrahedra: this many a spare vertex (a bisection adds one
 * a tetrahedron on the edge; a Kuhn mesh's edges have up to 6, refined
 * ones near the cut more). */
#define SB_TETS_PER_VERTEX 12

/* The per-tetrahedron reals: D_m⁻¹ (9), volume, μ, λ, β, and the density. */
enum { SB_TET_REALS = 14 };

static const int sb_edge_ends[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

struct sb_cut_volume {
    sb_model* live;
    uint32_t vertices, vertex_capacity, tet_capacity, face_capacity, refused;
    double* snap; /* per vertex slot, m: SB_CUT_VOLUME_SNAP of its longest rest edge */
    const sb_cutting* cutting;
    double* planes; /* the step's swept planes, 4 numbers each (sb_cutting_planes) */
    uint32_t plane_count;
    uint8_t* on_cut;   /* per vertex slot */
    double* reals;     /* live's tetrahedron reals, SB_TET_REALS arrays of tet_capacity */
    double* density;   /* per tetrahedron slot, kg/m³ (in reals) */
    uint32_t* indices; /* live's tet_v (10 arrays of tet_capacity), then face_v (3 of face_capacity) */
    uint8_t* nodes;    /* live's tet_nodes */
    sb_model edges;    /* bond_count, bond_i, bond_j: the tetrahedra's unique edges */
    uint8_t* skip;     /* per edge slot: 0 */
    /* work space: a vertex's or an edge's tetrahedra, their groups, the groups' volumes */
    uint32_t *star, *parent, *group;
    double* group_volume;
};

/* ---- rest shapes and room --------------------------------------------------------- */

static double sb_sq(double a) { return a * a; }

static void sb_rest_of(const sb_model* m, uint32_t v, double out[3]) {
    out[0] = m->rest_x[v], out[1] = m->rest_y[v], out[2] = m->rest_z[v];
}

/* Tetrahedron t's rest D_m⁻¹ and volume from its corners' rest positions. */
static void sb_rest_shape(sb_model* m, uint32_t t) {
    double p[4][3], dm[9], inv[9] = {0};
    for (int c = 0; c < 4; c++) sb_rest_of(m, m->tet_v[c][t], p[c]);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) dm[3 * r + c] = p[c + 1][r] - p[0][r];
    sb_m3_invert(dm, inv);
    for (int k = 0; k < 9; k++) m->tet_dm_inv[k][t] = inv[k];
    m->tet_volume[t] = sb_tet_volume(p[0], p[1], p[2], p[3]);
}

/* live's tetrahedron and face arrays again, with room for the new ones. */
static bool sb_room(sb_cut_volume* c) {
    sb_model* l = c->live;
    size_t nt = c->tet_capacity, nf = c->face_capacity;
    c->reals = calloc(SB_TET_REALS * nt + 1, sizeof(double));
    c->indices = calloc(SB_TET_NODES * nt + 3 * nf + 1, sizeof(uint32_t));
    c->nodes = calloc(nt + 1, 1);
    if (!c->reals || !c->indices || !c->nodes) return false;
    double** reals[SB_TET_REALS - 1] = {&l->tet_volume, &l->tet_mu, &l->tet_lambda, &l->tet_beta};
    for (int k = 0; k < 9; k++) reals[4 + k] = &l->tet_dm_inv[k];
    for (int a = 0; a < SB_TET_REALS - 1; a++) {
        memcpy(c->reals + a * nt, *reals[a], l->tet_count * sizeof(double));
        *reals[a] = c->reals + a * nt;
    }
    c->density = c->reals + (SB_TET_REALS - 1) * nt;
    for (int k = 0; k < SB_TET_NODES; k++) {
        memcpy(c->indices + k * nt, l->tet_v[k], l->tet_count * sizeof(uint32_t));
        l->tet_v[k] = c->indices + k * nt;
    }
    for (int k = 0; k < 3; k++) {
        uint32_t* faces = c->indices + SB_TET_NODES * nt + k * nf;
        memcpy(faces, l->face_v[k], l->face_count * sizeof(uint32_t));
        l->face_v[k] = faces;
    }
    memcpy(c->nodes, l->tet_nodes, l->tet_count);
    l->tet_nodes = c->nodes;
    return true;
}

/* Each tetrahedron's density from its corners' lumped masses: a corner's
 * mass over a quarter of the rest volume around it, averaged. */
static bool sb_densities(sb_cut_volume* c) {
    const sb_model* m = c->live;
    double* around = calloc((size_t)c->vertices + 1, sizeof *around);
    if (!around) return false;
    for (uint32_t t = 0; t < m->tet_count; t++)
        for (int k = 0; k < 4; k++) around[m->tet_v[k][t]] += 0.25 * m->tet_volume[t];
    for (uint32_t t = 0; t < m->tet_count; t++) {
        double sum = 0.0;
        for (int k = 0; k < 4; k++) sum += m->mass[m->tet_v[k][t]] / around[m->tet_v[k][t]];
        c->density[t] = 0.25 * sum;
    }
    free(around);
    return true;
}

/* Each model vertex's snap distance: SB_CUT_VOLUME_SNAP of its longest rest edge. */
static void sb_snap_distances(sb_cut_volume* c) {
    const sb_model* m = c->live;
    for (uint32_t v = 0; v < c->vertex_capacity; v++) c->snap[v] = 0.0; /* in no tetrahedron, or a spare slot */
    for (uint32_t t = 0; t < m->tet_count; t++)
        for (int e = 0; e < 6; e++) {
            uint32_t u = m->tet_v[sb_edge_ends[e][0]][t], w = m->tet_v[sb_edge_ends[e][1]][t];
            double a[3], b[3];
            sb_rest_of(m, u, a);
            sb_rest_of(m, w, b);
            double snap = SB_CUT_VOLUME_SNAP * sqrt(sb_sq(b[0] - a[0]) + sb_sq(b[1] - a[1]) + sb_sq(b[2] - a[2]));
            c->snap[u] = fmax(c->snap[u], snap);
            c->snap[w] = fmax(c->snap[w], snap);
        }
}

/* The tetrahedra's unique edges again, in order of first appearance. */
static void sb_edges_find(sb_cut_volume* c) {
    const sb_model* m = c->live;
    sb_edge_map map;
    c->edges.bond_count = 0;
    if (!sb_edge_map_init(&map, 6 * (size_t)m->tet_count + 1)) {
        c->refused++; /* no edges: the blades cut nothing until the next step's */
        return;
    }
    uint32_t* ends[2] = {c->edges.bond_i, c->edges.bond_j};
    for (uint32_t t = 0; t < m->tet_count; t++)
        for (int e = 0; e < 6; e++) {
            uint32_t a = m->tet_v[sb_edge_ends[e][0]][t], b = m->tet_v[sb_edge_ends[e][1]][t];
            bool inserted;
            sb_edge_map_upsert(&map, a, b, c->edges.bond_count, &inserted);
            if (!inserted) continue;
            ends[0][c->edges.bond_count] = a;
            ends[1][c->edges.bond_count++] = b;
        }
    sb_edge_map_free(&map);
}

/* The boundary faces again (outward), as far as there is room. */
static void sb_faces_find(sb_cut_volume* c) {
    sb_model* m = c->live;
    sb_tet_mesh corners = {.vertex_count = c->vertices, .tet_count = m->tet_count};
    corners.positions = malloc((3 * (size_t)c->vertices + 1) * sizeof(double));
    corners.tets = malloc((4 * (size_t)m->tet_count + 1) * sizeof(uint32_t));
    sb_mesh surface = {0};
    sb_error err;
    bool ok = corners.positions && corners.tets;
    for (uint32_t v = 0; ok && v < c->vertices; v++) sb_rest_of(m, v, corners.positions + 3 * (size_t)v);
    for (uint32_t t = 0; ok && t < m->tet_count; t++)
        for (int k = 0; k < 4; k++) corners.tets[4 * (size_t)t + k] = m->tet_v[k][t];
    if (ok && sb_tet_mesh_surface(&corners, &surface, &err) == SB_OK) {
        m->face_count = surface.triangle_count < c->face_capacity ? surface.triangle_count : c->face_capacity;
        c->refused += surface.triangle_count - m->face_count;
        for (uint32_t f = 0; f < m->face_count; f++)
            for (int k = 0; k < 3; k++) m->face_v[k][f] = surface.triangles[3 * (size_t)f + k];
    } else {
        c->refused++; /* out of memory: the faces stay as they were */
    }
    sb_mesh_free(&surface);
    sb_tet_mesh_free(&corners);
}

const char* sb_cut_volume_missing(const sb_model* m) {
    if (m->tet_count == 0)
        return m->face_count > 0 ? "tetrahedra in the model (a volume of springs keeps only their edges: use "
                                   "tissue.model: corotated)"
                                 : "a model with triangles or tetrahedra";
    for (uint32_t t = 0; t < m->tet_count; t++)
        if (m->tet_nodes[t] != 4) return "linear tetrahedra (tissue.model: corotated, not corotated_quadratic)";
    if (m->triangle_count > 0 || m->membrane_count > 0) return "a model of tetrahedra alone (no triangles beside them)";
    return NULL;
}

sb_cut_volume* sb_cut_volume_create(sb_model* live, uint32_t model_vertices, const sb_cutting* cutting, bool* ok) {
    sb_cut_volume* c = calloc(1, sizeof *c);
    *ok = c != NULL;
    if (!c) return NULL;
    uint32_t spare = live->vertex_count - model_vertices;
    c->live = live;
    c->cutting = cutting;
    c->planes = malloc((4 * (size_t)sb_cutting_count(cutting) + 1) * sizeof *c->planes);
    c->vertices = model_vertices;
    c->vertex_capacity = live->vertex_count;
    c->tet_capacity = live->tet_count + SB_TETS_PER_VERTEX * spare;
    c->face_capacity = 4 * c->tet_capacity;
    size_t nv = c->vertex_capacity + 1, nt = c->tet_capacity + 1, ne = 6 * (size_t)c->tet_capacity + 1;
    c->on_cut = calloc(nv, 1);
    c->snap = malloc(nv * sizeof *c->snap);
    c->skip = calloc(ne, 1);
    c->edges.bond_i = malloc(ne * sizeof(uint32_t));
    c->edges.bond_j = malloc(ne * sizeof(uint32_t));
    c->star = malloc(nt * sizeof *c->star);
    c->parent = malloc(nt * sizeof *c->parent);
    c->group = malloc(nt * sizeof *c->group);
    c->group_volume = malloc(nt * sizeof *c->group_volume);
    *ok = c->planes && c->on_cut && c->snap && c->skip && c->edges.bond_i && c->edges.bond_j && c->star && c->parent &&
          c->group && c->group_volume && sb_room(c) && sb_densities(c);
    if (!*ok) {
        sb_cut_volume_destroy(c);
        return NULL;
    }
    sb_snap_distances(c);
    sb_edges_find(c);
    *ok = c->refused == 0;
    if (!*ok) {
        sb_cut_volume_destroy(c);
        return NULL;
    }
    return c;
}

void sb_cut_volume_destroy(sb_cut_volume* c) {
    if (!c) return;
    void* arrays[] = {c->planes, c->snap,  c->on_cut, c->skip,    c->edges.bond_i, c->edges.bond_j, c->star,
                      c->parent, c->group, c->reals,  c->indices, c->nodes,        c->group_volume};
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++) free(arrays[a]);
    free(c);
}

const sb_model* sb_cut_volume_edges(const sb_cut_volume* c) { return &c->edges; }
const uint8_t* sb_cut_volume_skip(const sb_cut_volume* c) { return c->skip; }
uint32_t sb_cut_volume_vertex_count(const sb_cut_volume* c) { return c->vertices; }
uint32_t sb_cut_volume_refused(const sb_cut_volume* c) { return c->refused; }
uint32_t sb_cut_volume_capacity(const sb_cut_volume* c) { return c->tet_capacity; }
uint32_t sb_cut_volume_face_capacity(const sb_cut_volume* c) { return c->face_capacity; }

/* ---- crossings ------------------------------------------------------------------- */

/* The corner of tetrahedron t at vertex v, or −1. */
static int sb_corner(const sb_model* m, uint32_t t, uint32_t v) {
    for (int k = 0; k < 4; k++)
        if (m->tet_v[k][t] == v) return k;
    return -1;
}

/* The tetrahedra on edge (u, w) into c->star; returns their count. */
static uint32_t sb_edge_tets(sb_cut_volume* c, uint32_t u, uint32_t w) {
    const sb_model* m = c->live;
    uint32_t d = 0;
    for (uint32_t t = 0; t < m->tet_count; t++)
        if (sb_corner(m, t, u) >= 0 && sb_corner(m, t, w) >= 0) c->star[d++] = t;
    return d;
}

/* Tetrahedron n: a copy of t. */
static void sb_copy_tet(sb_cut_volume* c, uint32_t t, uint32_t n) {
    sb_model* m = c->live;
    for (int k = 0; k < SB_TET_NODES; k++) m->tet_v[k][n] = m->tet_v[k][t];
    m->tet_nodes[n] = m->tet_nodes[t];
    for (int a = 0; a < SB_TET_REALS; a++)
        c->reals[a * (size_t)c->tet_capacity + n] = c->reals[a * (size_t)c->tet_capacity + t];
}

/* Corner `from` of tetrahedron t becomes `to` (a linear one's middles repeat corner 0). */
static void sb_tet_swap(sb_model* m, uint32_t t, uint32_t from, uint32_t to) {
    m->tet_v[sb_corner(m, t, from)][t] = to;
    for (int k = 4; k < SB_TET_NODES; k++) m->tet_v[k][t] = m->tet_v[0][t];
    sb_rest_shape(m, t);
}

/* Bisects edge (u, w) at fraction f: a vertex P there, on the cut; the
 * edge's d tetrahedra (in c->star) each split in two. */
static void sb_bisect(sb_solver* s, sb_cut_volume* c, uint32_t u, uint32_t w, double f, uint32_t d, double* before) {
    sb_model* m = c->live;
    uint32_t p = c->vertices++;
    for (int a = 0; a < 3; a++) before[3 * (size_t)p + a] = 0.0;
    m->mass[p] = 0.0;
    sb_blend_vertex(s, u, w, f, p);
    double share = 0.0;
    for (uint32_t i = 0; i < d; i++) share += 0.25 * c->density[c->star[i]] * m->tet_volume[c->star[i]];
    share = fmin(share, fmin(0.5 * m->mass[u] / (1.0 - f), 0.5 * m->mass[w] / f)); /* a fixed end keeps most */
    sb_give_mass(s, u, p, (1.0 - f) * share, before);
    sb_give_mass(s, w, p, f * share, before);
    c->on_cut[p] = 1;
    c->snap[p] = fmax(c->snap[u], c->snap[w]);
    for (uint32_t i = 0; i < d; i++) {
        uint32_t t = c->star[i], n = m->tet_count++;
        sb_copy_tet(c, t, n);
        sb_tet_swap(m, t, w, p); /* (u, P, a, b) */
        sb_tet_swap(m, n, u, p); /* (P, w, a, b) */
    }
}

static double sb_rest_distance(const sb_model* m, uint32_t u, uint32_t w) {
    double a[3], b[3];
    sb_rest_of(m, u, a);
    sb_rest_of(m, w, b);
    return sqrt(sb_sq(b[0] - a[0]) + sb_sq(b[1] - a[1]) + sb_sq(b[2] - a[2]));
}

void sb_cut_volume_sweeps(sb_cut_volume* c, double t0, double t1) {
    c->plane_count = sb_cutting_planes(c->cutting, t0, t1, c->planes);
}

/* Vertex v's distance from the nearest of the step's swept planes (now). */
static double sb_sweep_distance(const sb_solver* s, const sb_cut_volume* c, uint32_t v) {
    double nearest = INFINITY, x[3] = {s->state.x[v], s->state.y[v], s->state.z[v]};
    for (uint32_t k = 0; k < c->plane_count; k++) {
        const double* n = c->planes + 4 * (size_t)k;
        nearest = fmin(nearest, fabs(n[0] * x[0] + n[1] * x[1] + n[2] * x[2] + n[3]));
    }
    return nearest;
}

/* Whether the ends of edge (u, w), met at f, are near the cut: within the
 * snap distance of a swept plane (or, for a blade that sweeps none, the
 * meeting point within it of the end). */
static void sb_near_ends(const sb_solver* s, const sb_cut_volume* c, uint32_t u, uint32_t w, double f, bool near[2]) {
    if (c->plane_count) {
        near[0] = sb_sweep_distance(s, c, u) < c->snap[u];
        near[1] = sb_sweep_distance(s, c, w) < c->snap[w];
    } else {
        double length = sb_rest_distance(c->live, u, w);
        near[0] = f * length < c->snap[u];
        near[1] = (1.0 - f) * length < c->snap[w];
    }
}

void sb_cut_volume_cross(sb_solver* s, sb_cut_volume* c, uint32_t edge, double f, double* before) {
    sb_model* m = c->live;
    uint32_t u = c->edges.bond_i[edge], w = c->edges.bond_j[edge];
    uint32_t d = sb_edge_tets(c, u, w);
    if (d == 0) return; /* bisected already this step (by another blade) */
    bool near[2];
    sb_near_ends(s, c, u, w, f, near);
    if (near[0] || near[1]) {
        c->on_cut[u] |= near[0];
        c->on_cut[w] |= near[1];
    } else if (!c->on_cut[u] && !c->on_cut[w]) { /* else the crossing is that end's own */
        if (c->vertices < c->vertex_capacity && m->tet_count + d <= c->tet_capacity)
            sb_bisect(s, c, u, w, f, d, before);
        else
            c->refused++;
    }
}

/* ---- splits -------------------------------------------------------------------------- */

/* Whether the face that tetrahedra t and n share (its corners v, x, y) is
 * cut: its corners on the cut, the two tetrahedra's other vertices off it. */
static bool sb_face_cut(const sb_cut_volume* c, uint32_t t, uint32_t n, const uint32_t face[3]) {
    const sb_model* m = c->live;
    for (int k = 0; k < 3; k++)
        if (!c->on_cut[face[k]]) return false;
    uint32_t tets[2] = {t, n};
    for (int side = 0; side < 2; side++)
        for (int k = 0; k < 4; k++) {
            uint32_t x = m->tet_v[k][tets[side]];
            if (x != face[0] && x != face[1] && x != face[2] && c->on_cut[x]) return false;
        }
    return true;
}

/* Whether tetrahedra t and n, both at v, share a face at v that is not cut. */
static bool sb_joined(const sb_cut_volume* c, uint32_t v, uint32_t t, uint32_t n) {
    const sb_model* m = c->live;
    uint32_t face[3] = {v, SB_NONE, SB_NONE};
    int shared = 1;
    for (int k = 0; k < 4; k++) {
        uint32_t x = m->tet_v[k][t];
        if (x != v && sb_corner(m, n, x) >= 0) {
            if (shared == 3) return false; /* the same four corners: not a mesh */
            face[shared++] = x;
        }
    }
    return shared == 3 && !sb_face_cut(c, t, n, face);
}

/* v's tetrahedra into c->star (*degree of them) and their groups into
 * c->group (0, 1, … in the order of their first tetrahedron), joined
 * through faces not cut. Returns the groups. */
static uint32_t sb_groups(sb_cut_volume* c, uint32_t v, uint32_t* degree) {
    const sb_model* m = c->live;
    uint32_t d = 0, groups = 0;
    for (uint32_t t = 0; t < m->tet_count; t++)
        if (sb_corner(m, t, v) >= 0) c->parent[d] = d, c->star[d++] = t;
    for (uint32_t i = 0; i < d; i++)
        for (uint32_t j = i + 1; j < d; j++)
            if (sb_joined(c, v, c->star[i], c->star[j])) {
                uint32_t a = sb_find(c->parent, i), b = sb_find(c->parent, j);
                c->parent[a > b ? a : b] = a > b ? b : a;
            }
    for (uint32_t i = 0; i < d; i++) c->group[i] = SB_NONE;
    for (uint32_t i = 0; i < d; i++) {
        uint32_t root = sb_find(c->parent, i);
        if (c->group[root] == SB_NONE) c->group[root] = groups++;
        c->group[i] = c->group[root];
    }
    *degree = d;
    return groups;
}

/* Splits v into one vertex per group (first, first + 1, … for groups 1, …),
 * the mass by the groups' rest volumes. */
static void sb_split(sb_solver* s, sb_cut_volume* c, uint32_t v, uint32_t groups, uint32_t d, double* before) {
    sb_model* m = c->live;
    if (c->vertices + groups - 1 > c->vertex_capacity) {
        c->refused += groups - 1;
        return;
    }
    uint32_t first = c->vertices;
    c->vertices += groups - 1;
    double total = 0.0, mass = m->mass[v];
    for (uint32_t g = 0; g < groups; g++) c->group_volume[g] = 0.0;
    for (uint32_t i = 0; i < d; i++) {
        c->group_volume[c->group[i]] += m->tet_volume[c->star[i]];
        total += m->tet_volume[c->star[i]];
    }
    for (uint32_t g = 1; g < groups; g++) {
        uint32_t w = first + g - 1;
        sb_blend_vertex(s, v, v, 0.0, w);
        for (int a = 0; a < 3; a++) before[3 * (size_t)w + a] = 0.0;
        m->mass[w] = 0.0;
        sb_give_mass(s, v, w, mass * c->group_volume[g] / total, before);
        c->on_cut[w] = 1;
        c->snap[w] = c->snap[v];
    }
    for (uint32_t i = 0; i < d; i++)
        if (c->group[i]) {
            uint32_t t = c->star[i];
            m->tet_v[sb_corner(m, t, v)][t] = first + c->group[i] - 1;
            for (int k = 4; k < SB_TET_NODES; k++) m->tet_v[k][t] = m->tet_v[0][t];
        }
}

void sb_cut_volume_separate(sb_solver* s, sb_cut_volume* c, double* before) {
    uint32_t vertices = c->vertices;
    for (uint32_t v = 0; v < vertices; v++) {
        if (!c->on_cut[v]) continue;
        uint32_t d, groups = sb_groups(c, v, &d);
        if (groups > 1) sb_split(s, c, v, groups, d, before);
    }
    sb_edges_find(c);
    sb_faces_find(c);
}

/* ---- the saved state ---------------------------------------------------------------- */

enum { SB_CUT_VOLUME_RANGES = 18 };

static int sb_cut_volume_ranges(sb_cut_volume* c, sb_range* out) {
    sb_model* m = c->live;
    size_t nv = c->vertex_capacity, nt = c->tet_capacity, nf = c->face_capacity;
    sb_range list[SB_CUT_VOLUME_RANGES] = {{&c->vertices, 4},
                                           {&c->refused, 4},
                                           {&m->tet_count, 4},
                                           {&m->face_count, 4},
                                           {c->on_cut, nv},
                                           {c->snap, 8 * nv},
                                           {m->rest_x, 8 * nv},
                                           {m->rest_y, 8 * nv},
                                           {m->rest_z, 8 * nv},
                                           {m->vel_x, 8 * nv},
                                           {m->vel_y, 8 * nv},
                                           {m->vel_z, 8 * nv},
                                           {m->mass, 8 * nv},
                                           {m->inv_mass, 8 * nv},
                                           {m->fixed, nv},
                                           {c->reals, 8 * SB_TET_REALS * nt},
                                           {c->indices, 4 * (SB_TET_NODES * nt + 3 * nf)},
                                           {c->nodes, nt}};
    memcpy(out, list, sizeof list);
    return SB_CUT_VOLUME_RANGES;
}

void sb_cut_volume_save(const sb_cut_volume* c, sb_sections_writer* w) {
    sb_range ranges[SB_CUT_VOLUME_RANGES];
    sb_ranges_put(w, ranges, sb_cut_volume_ranges((sb_cut_volume*)c, ranges)); /* reads only */
}

void sb_cut_volume_load(sb_solver* s, sb_cut_volume* c, sb_cursor* r) {
    sb_range ranges[SB_CUT_VOLUME_RANGES];
    sb_ranges_take(r, ranges, sb_cut_volume_ranges(c, ranges));
    const sb_model* m = c->live;
    for (uint32_t v = 0; v < c->vertex_capacity; v++) /* the handles pin theirs again after */
        if (s->pinned_inv_mass) s->pinned_inv_mass[v] = m->inv_mass[v];
    sb_edges_find(c);
}
