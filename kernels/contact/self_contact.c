/* Self-contact: the model's triangles against each other — a sheet that
 * folds onto itself, and the bodies of a multi-object model, which are one
 * model to the solver.
 *
 * Design. A correction of the step, like the collider pass
 * (kernels/contact/contact.c), after it: the integrator and the colliders have
 * moved every vertex from x0 to x1; this pass finds the vertex–triangle
 * and edge–edge pairs that crossed during the step or end it closer than
 * the contact thickness h, and moves them apart.
 *
 *   broad phase  a hierarchy of the triangles (kernels/contact/triangle_bvh.c),
 *                refitted around each triangle's move, searched against
 *                itself with normal cones: a flat connected patch is
 *                skipped whole, so a sheet that is nowhere folded costs
 *                the refit and little else. Every vertex and edge belongs
 *                to one triangle (its first), and a pair of triangles tests
 *                only the features they own, so each feature pair is met
 *                once; features sharing a vertex are never paired.
 *   narrow phase kernels/contact/proximity.c: a pair is a candidate when it crossed
 *                in the step (continuous test, within h at the crossing) or
 *                ends it closer than 2h; candidates are kept in search
 *                order.
 *   response     Gauss-Seidel over the candidates, on one thread, in order,
 *                until a pass corrects nothing (at most SB_SELF_PASSES).
 *                A pair is the constraint C = (P − Q)·n − h >= 0, P and Q
 *                the closest points (the vertex and its point on the
 *                triangle, or the points of the two edges) as weighted sums
 *                Σ β_i x_i, n from Q to P: for a pair that crossed, the
 *                triangle's (or the two edges') normal at the end of the
 *                step, on the side it started from; otherwise the direction
 *                (P − Q)/|P − Q|. C < 0 moves each vertex by
 *                β_i w_i Δλ n, Δλ = −C / Σ β_i² w_i (w the inverse mass: a
 *                fixed vertex never moves); a closing relative velocity
 *                along n is removed by the matching impulse (inelastic,
 *                frictionless: Provot's response). A corrected vertex takes
 *                d = v dt as its Verlet displacement, as in the collider
 *                pass.
 *
 * Parallel and deterministic: the refit runs over the hierarchy's cut in
 * parallel; the search is split into tasks (a cut node against itself, two
 * overlapping cut nodes against each other) taken dynamically by the team,
 * each writing its candidates to its own worker's buffer and recording
 * where; the response reads them task by task in the tasks' order, so the
 * result is the same for any thread count. With tearing, a step that
 * broke a bond or split a vertex makes the unique edges, their owners and
 * the hierarchy's corners and connected patches again from the live
 * triangles (sb_self_contact_retopologize: a dead triangle owns and meets
 * nothing); otherwise everything is allocated at creation; a step whose candidates overflow the buffers (more than
 * SB_SELF_CANDIDATES_PER_TRIANGLE per triangle on one worker) drops the
 * rest and counts them in the step's stats. */
#include "kernels/contact/self_contact.h"
#include "kernels/state/solver_data.h"
#include "kernels/state/solver_fast.h"
#include "kernels/contact/triangle_bvh.h"
#include "kernels/contact/proximity.h"
#include "common/edge_map.h"
#include "common/error.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#define SB_SELF_PASSES 16
#define SB_SELF_ROUNDS 4
#define SB_SELF_SLACK 0.05
#define SB_SELF_CANDIDATES_PER_TRIANGLE 16
#define SB_EDGE_PAIR 0x80000000u /* a candidate's kind, in the top bit of its first index */

typedef struct sb_self_candidate {
    uint32_t a, b; /* vertex | triangle, or SB_EDGE_PAIR | edge, edge */
} sb_self_candidate;

typedef struct sb_self_task {
    uint32_t a, b;                 /* cut nodes: a == b searches a against itself */
    uint32_t worker, first, count; /* where its candidates went */
} sb_self_task;

struct sb_self_contact {
    sb_triangle_bvh* bvh;
    uint32_t (*edges)[2];
    uint32_t* tri_edges; /* 3 per triangle: edge (v[e], v[(e + 1) % 3]) */
    uint8_t* owns;       /* per triangle: bit c, it owns vertex v[c]; bit 3 + e, edge e */
    const uint8_t* dead; /* per triangle, tearing's (NULL: none): out of the contact */
    double h;
    sb_real *from4, *x4, *v4; /* start positions; the generic path's packed copies */
    uint8_t* touched;
    uint32_t* touched_list;
    uint32_t touched_count;
    sb_self_task* tasks;
    uint32_t task_count;
    atomic_uint next_task;
    sb_self_candidate** buffers; /* one per worker */
    uint32_t* used;
    uint32_t capacity;
    int workers;
    atomic_uint dropped;
    uint32_t contacts;
    bool settled; /* the last round's passes separated every pair */
};

static sb_self_contact* sb_self(const sb_solver* s) { return s->self; }

/* Unique edges and which live triangle owns each vertex and edge (its
 * first); a dead triangle (sc->dead: tearing's) owns nothing and meets
 * nothing. */
static bool sb_self_features(sb_self_contact* sc, const sb_model* m) {
    uint32_t n = m->triangle_count;
    sb_edge_map map;
    uint8_t* seen = calloc(m->vertex_count, 1);
    if (!seen || !sb_edge_map_init(&map, 3 * (size_t)n)) {
        free(seen);
        return false;
    }
    memset(sc->owns, 0, n);
    uint32_t count = 0;
    for (uint32_t t = 0; t < n; t++)
        for (int e = 0; e < 3 && !(sc->dead && sc->dead[t]); e++) {
            uint32_t a = m->tri_v[e][t], b = m->tri_v[(e + 1) % 3][t];
            bool inserted;
            uint32_t* id = sb_edge_map_upsert(&map, a, b, count, &inserted);
            if (inserted) {
                sc->edges[count][0] = a, sc->edges[count][1] = b;
                count++;
                sc->owns[t] |= (uint8_t)(8u << e);
            }
            sc->tri_edges[3 * (size_t)t + e] = *id;
            if (!seen[a]) {
                seen[a] = 1;
                sc->owns[t] |= (uint8_t)(1u << e);
            }
        }
    sb_edge_map_free(&map);
    free(seen);
    return true;
}

static void sb_self_contact_subscribe(sb_solver* s);

sb_status sb_self_contact_retopologize(sb_solver* s, const uint8_t* triangle_dead, sb_error* err) {
    sb_self_contact* sc = s->self;
    if (!sc) return SB_OK;
    sc->dead = triangle_dead;
    if (!sb_self_features(sc, s->model) || !sb_triangle_bvh_retopologize(sc->bvh, triangle_dead))
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory updating self-contact after a split");
    return SB_OK;
}

sb_status sb_self_contact_prepare(sb_solver* s, sb_error* err) {
    const sb_model* m = s->model;
    if (!(s->def.contact_thickness > 0.0))
        return sb_error_set(err, SB_ERR_INVALID,
                            "self_collision needs a contact thickness > 0 (the distance kept between surfaces)");
    if (m->triangle_count == 0) return SB_OK; /* nothing to collide: the pass is off */
    sb_self_contact* sc = calloc(1, sizeof *sc);
    s->self = sc;
    if (!sc) return sb_error_set(err, SB_ERR_NOMEM, "out of memory for self-contact");
    sc->h = s->def.contact_thickness;
    sc->workers = sb_team_size(s->team);
    double* rest = malloc(3 * (size_t)m->vertex_count * sizeof *rest);
    bool ok = rest != NULL;
    for (uint32_t i = 0; ok && i < m->vertex_count; i++)
        rest[3 * i] = m->rest_x[i], rest[3 * i + 1] = m->rest_y[i], rest[3 * i + 2] = m->rest_z[i];
    ok = ok && (sc->bvh = sb_triangle_bvh_create(m->triangle_count, (const uint32_t* const*)m->tri_v, rest)) != NULL;
    free(rest);
    sc->tri_edges = malloc(3 * (size_t)m->triangle_count * sizeof *sc->tri_edges);
    sc->edges = malloc(3 * (size_t)m->triangle_count * sizeof *sc->edges);
    sc->owns = calloc(m->triangle_count, 1);
    ok = ok && sc->tri_edges && sc->edges && sc->owns && sb_self_features(sc, m);
    /* packed arrays 64-byte aligned, as the fast kernels' loads of them want */
    size_t packed = (4 * (size_t)m->vertex_count * sizeof(sb_real) / 64 + 1) * 64;
    sc->from4 = aligned_alloc(64, packed);
    if (!sb_fused(s)) { /* the generic path's packed copies */
        sc->x4 = aligned_alloc(64, packed);
        sc->v4 = aligned_alloc(64, packed);
        ok = ok && sc->x4 && sc->v4;
        if (ok) memset(sc->x4, 0, packed), memset(sc->v4, 0, packed);
    }
    sc->touched = calloc(m->vertex_count, 1);
    sc->touched_list = malloc(m->vertex_count * sizeof *sc->touched_list);
    uint32_t cuts = sc->bvh ? sc->bvh->cut_count : 0;
    sc->tasks = malloc(((size_t)cuts * (cuts + 1) / 2 + 1) * sizeof *sc->tasks);
    sc->capacity = SB_SELF_CANDIDATES_PER_TRIANGLE * m->triangle_count + 65536;
    sc->buffers = calloc((size_t)sc->workers, sizeof *sc->buffers);
    sc->used = calloc((size_t)sc->workers, sizeof *sc->used);
    ok = ok && sc->from4 && sc->touched && sc->touched_list && sc->tasks && sc->buffers && sc->used;
    for (int w = 0; ok && w < sc->workers; w++)
        ok = (sc->buffers[w] = malloc(sc->capacity * sizeof **sc->buffers)) != NULL;
    if (!ok) return sb_error_set(err, SB_ERR_NOMEM, "out of memory for self-contact");
    sb_self_contact_subscribe(s);
    return SB_OK;
}

void sb_self_contact_destroy(sb_self_contact* sc) {
    if (!sc) return;
    sb_triangle_bvh_destroy(sc->bvh);
    free(sc->edges), free(sc->tri_edges), free(sc->owns);
    free(sc->from4), free(sc->x4), free(sc->v4), free(sc->touched), free(sc->touched_list);
    free(sc->tasks), free(sc->used);
    for (int w = 0; sc->buffers && w < sc->workers; w++) free(sc->buffers[w]);
    free(sc->buffers);
    free(sc);
}

static uint32_t sb_self_contact_count(const sb_self_contact* sc) { return sc ? sc->contacts : 0; }
static uint32_t sb_self_contact_dropped(const sb_self_contact* sc) {
    return sc ? atomic_load_explicit(&sc->dropped, memory_order_relaxed) : 0;
}

/* ---- the search ---- */

/* What a search task sees. */
typedef struct sb_self_search {
    sb_self_contact* sc;
    const sb_model* model;
    const sb_real *x0, *x1;
    sb_self_candidate* out;
    uint32_t* used;
} sb_self_search;

static sb_vec3 sb_at(const sb_real* x4, uint32_t i) {
    const sb_real* p = x4 + 4 * (size_t)i;
    return (sb_vec3){p[0], p[1], p[2]};
}

/* The swept box of vertex v grown by r, as lo x y z, hi x y z. */
static void sb_swept_box(const sb_self_search* q, uint32_t v, double r, double box[6]) {
    const sb_real *p = q->x0 + 4 * (size_t)v, *p1 = q->x1 + 4 * (size_t)v;
    for (int a = 0; a < 3; a++) {
        box[a] = (p[a] < p1[a] ? p[a] : p1[a]) - r;
        box[3 + a] = (p[a] < p1[a] ? p1[a] : p[a]) + r;
    }
}

static bool sb_boxes_meet(const double a[6], const double b[6]) {
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5];
}

/* Vertices v moving from x0 to x1 (packed) over the step. */
static sb_moving_quad sb_quad(const sb_real* x0, const sb_real* x1, const uint32_t v[4]) {
    sb_moving_quad quad;
    for (int k = 0; k < 4; k++) quad.x0[k] = sb_at(x0, v[k]), quad.x1[k] = sb_at(x1, v[k]);
    return quad;
}

/* The squared distance of a pair (vertex 0 and triangle 1 2 3, or edge 0 1
 * and edge 2 3) at the end of the step, with its closest points' triangle
 * weights w or edge parameters s, u. */
static double sb_end_distance2(const sb_moving_quad* q, bool edges, double w[3], double* s, double* u) {
    return edges ? sb_segments_closest(q->x1[0], q->x1[1], q->x1[2], q->x1[3], s, u)
                 : sb_point_triangle_closest(q->x1[0], q->x1[1], q->x1[2], q->x1[3], w);
}

/* Whether the pair, end_distance2 apart at the end of the step, crossed
 * within h during it; w or s, u then give the points that met. */
static bool sb_crossed(const sb_moving_quad* q, bool edges, double h, double end_distance2, double w[3], double* s,
                       double* u) {
    double t;
    if (!sb_quad_may_cross(q, sqrt(end_distance2), h)) return false;
    return edges ? sb_edge_edge_crossing(q, h, &t, s, u) : sb_vertex_triangle_crossing(q, h, &t, w);
}

static void sb_keep(const sb_self_search* q, uint32_t a, uint32_t b) {
    if (*q->used < q->sc->capacity)
        q->out[(*q->used)++] = (sb_self_candidate){a, b};
    else
        atomic_fetch_add_explicit(&q->sc->dropped, 1, memory_order_relaxed);
}

/* Whether the pair (vertices v: vertex and triangle, or edge and edge)
 * crossed in the step or ends it within 2h. */
static bool sb_near(const sb_self_search* q, const uint32_t v[4], bool edges) {
    double h = q->sc->h, w[3], s, u;
    sb_moving_quad quad = sb_quad(q->x0, q->x1, v);
    double d2 = sb_end_distance2(&quad, edges, w, &s, &u);
    return d2 < 4.0 * h * h || sb_crossed(&quad, edges, h, d2, w, &s, &u);
}

static void sb_union(const double a[6], const double b[6], double out[6]) {
    for (int k = 0; k < 3; k++) {
        out[k] = a[k] < b[k] ? a[k] : b[k];
        out[3 + k] = a[3 + k] > b[3 + k] ? a[3 + k] : b[3 + k];
    }
}

/* Vertex against triangle t, given their swept boxes. */
static void sb_vertex_against(const sb_self_search* q, uint32_t vertex, const double vertex_box[6], uint32_t t,
                              const double tri_box[6]) {
    const sb_model* m = q->model;
    uint32_t v[4] = {vertex, m->tri_v[0][t], m->tri_v[1][t], m->tri_v[2][t]};
    if (vertex == v[1] || vertex == v[2] || vertex == v[3]) return;
    if (sb_boxes_meet(vertex_box, tri_box) && sb_near(q, v, false)) sb_keep(q, vertex, t);
}

/* Edge e against edge f, given their swept boxes. */
static void sb_edge_against(const sb_self_search* q, uint32_t e, const double box_e[6], uint32_t f,
                            const double box_f[6]) {
    const uint32_t *a = q->sc->edges[e], *b = q->sc->edges[f];
    if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) return;
    uint32_t v[4] = {a[0], a[1], b[0], b[1]};
    if (sb_boxes_meet(box_e, box_f) && sb_near(q, v, true)) sb_keep(q, SB_EDGE_PAIR | e, f);
}

/* A leaf's triangles with the swept boxes (grown by h) of their corners,
 * their edges (edge e from corner e to corner e + 1, as tri_edges) and
 * themselves, made once per leaf visit. */
typedef struct sb_leaf_boxes {
    uint32_t count, triangle[SB_BVH_LEAF];
    double corner[SB_BVH_LEAF][3][6], edge[SB_BVH_LEAF][3][6], box[SB_BVH_LEAF][6];
} sb_leaf_boxes;

static void sb_leaf_boxes_of(const sb_self_search* q, const sb_bvh_node* leaf, sb_leaf_boxes* out) {
    const sb_triangle_bvh* bvh = q->sc->bvh;
    out->count = leaf->count;
    for (uint32_t k = 0; k < leaf->count; k++) {
        out->triangle[k] = bvh->order[leaf->first + k];
        for (int c = 0; c < 3; c++)
            sb_swept_box(q, bvh->corners.corner[c][leaf->first + k], q->sc->h, out->corner[k][c]);
        for (int e = 0; e < 3; e++) sb_union(out->corner[k][e], out->corner[k][(e + 1) % 3], out->edge[k][e]);
        sb_union(out->edge[k][0], out->corner[k][2], out->box[k]);
    }
}

/* The features two triangles own, against each other. */
static void sb_triangle_pair(const sb_self_search* q, const sb_leaf_boxes* a, uint32_t i, const sb_leaf_boxes* b,
                             uint32_t j) {
    if (!sb_boxes_meet(a->box[i], b->box[j])) return;
    const sb_model* m = q->model;
    const sb_self_contact* sc = q->sc;
    uint32_t ta = a->triangle[i], tb = b->triangle[j];
    if (sc->dead && (sc->dead[ta] || sc->dead[tb])) return;
    for (int c = 0; c < 3; c++) {
        if (sc->owns[ta] >> c & 1) sb_vertex_against(q, m->tri_v[c][ta], a->corner[i][c], tb, b->box[j]);
        if (sc->owns[tb] >> c & 1) sb_vertex_against(q, m->tri_v[c][tb], b->corner[j][c], ta, a->box[i]);
    }
    for (int e = 0; e < 3; e++) {
        if (!(sc->owns[ta] >> (3 + e) & 1)) continue;
        for (int f = 0; f < 3; f++)
            if (sc->owns[tb] >> (3 + f) & 1)
                sb_edge_against(q, sc->tri_edges[3 * (size_t)ta + e], a->edge[i][e], sc->tri_edges[3 * (size_t)tb + f],
                                b->edge[j][f]);
    }
}

static void sb_search_pair(const sb_self_search* q, uint32_t a, uint32_t b);

static void sb_search_self(const sb_self_search* q, uint32_t node) {
    const sb_triangle_bvh* bvh = q->sc->bvh;
    if (sb_triangle_bvh_flat(bvh, node)) return;
    const sb_bvh_node* n = &bvh->nodes[node];
    if (n->leaf) {
        sb_leaf_boxes boxes;
        sb_leaf_boxes_of(q, n, &boxes);
        for (uint32_t i = 0; i < boxes.count; i++)
            for (uint32_t j = i + 1; j < boxes.count; j++) sb_triangle_pair(q, &boxes, i, &boxes, j);
        return;
    }
    sb_search_self(q, node + 1);
    sb_search_self(q, sb_bvh_right(bvh, node));
    sb_search_pair(q, node + 1, sb_bvh_right(bvh, node));
}

static void sb_search_pair(const sb_self_search* q, uint32_t a, uint32_t b) {
    const sb_triangle_bvh* bvh = q->sc->bvh;
    if (!sb_bvh_overlap(bvh, a, b)) return;
    const sb_bvh_node *na = &bvh->nodes[a], *nb = &bvh->nodes[b];
    if (na->leaf && nb->leaf) {
        sb_leaf_boxes boxes_a, boxes_b;
        sb_leaf_boxes_of(q, na, &boxes_a);
        sb_leaf_boxes_of(q, nb, &boxes_b);
        for (uint32_t i = 0; i < boxes_a.count; i++)
            for (uint32_t j = 0; j < boxes_b.count; j++) sb_triangle_pair(q, &boxes_a, i, &boxes_b, j);
    } else if (nb->leaf || (!na->leaf && na->count >= nb->count)) {
        sb_search_pair(q, a + 1, b);
        sb_search_pair(q, sb_bvh_right(bvh, a), b);
    } else {
        sb_search_pair(q, a, b + 1);
        sb_search_pair(q, a, sb_bvh_right(bvh, b));
    }
}

/* The tasks of this step, in a fixed order (worker 0, after the refit). */
static void sb_plan_tasks(sb_self_contact* sc) {
    const sb_triangle_bvh* bvh = sc->bvh;
    sc->task_count = 0;
    for (uint32_t i = 0; i < bvh->cut_count; i++) {
        uint32_t a = bvh->cut[i];
        if (!bvh->culled[a]) sc->tasks[sc->task_count++] = (sb_self_task){.a = a, .b = a};
        for (uint32_t j = i + 1; j < bvh->cut_count; j++) {
            uint32_t b = bvh->cut[j];
            if (!bvh->culled[sb_triangle_bvh_common(bvh, a, b)] && sb_bvh_overlap(bvh, a, b))
                sc->tasks[sc->task_count++] = (sb_self_task){.a = a, .b = b};
        }
    }
    atomic_store_explicit(&sc->next_task, 0, memory_order_relaxed);
    atomic_store_explicit(&sc->dropped, 0, memory_order_relaxed);
}

static void sb_run_tasks(const sb_worker* w, sb_solver* s, const sb_real* x1) {
    sb_self_contact* sc = sb_self(s);
    sb_self_search q = {sc, s->model, sc->from4, x1, sc->buffers[w->index], &sc->used[w->index]};
    sc->used[w->index] = 0;
    for (;;) {
        uint32_t k = atomic_fetch_add_explicit(&sc->next_task, 1, memory_order_relaxed);
        if (k >= sc->task_count) break;
        sb_self_task* task = &sc->tasks[k];
        task->worker = (uint32_t)w->index;
        task->first = *q.used;
        if (task->a == task->b)
            sb_search_self(&q, task->a);
        else
            sb_search_pair(&q, task->a, task->b);
        task->count = *q.used - task->first;
    }
}

/* ---- the response ---- */

/* One candidate as a constraint: its vertices, their weights β, the
 * normal n and C = Σ β_i x_i · n − h. False when it needs nothing. */
typedef struct sb_self_constraint {
    uint32_t v[4];
    double beta[4], n[3], C;
} sb_self_constraint;

static double sb_sign(double x) { return x < 0.0 ? -1.0 : 1.0; }

static bool sb_constraint(const sb_self_contact* sc, const sb_self_candidate* c, const sb_real* x1,
                          sb_self_constraint* k) {
    bool edges = (c->a & SB_EDGE_PAIR) != 0;
    if (edges) {
        const uint32_t *a = sc->edges[c->a & ~SB_EDGE_PAIR], *b = sc->edges[c->b];
        k->v[0] = a[0], k->v[1] = a[1], k->v[2] = b[0], k->v[3] = b[1];
    } else {
        k->v[0] = c->a;
        for (int j = 0; j < 3; j++) k->v[1 + j] = sc->bvh->tri_v[j][c->b];
    }
    sb_moving_quad q = sb_quad(sc->from4, x1, k->v);
    double h = sc->h, w[3], s, u;
    double d2 = sb_end_distance2(&q, edges, w, &s, &u);
    /* a crossing found replaces the closest points by the points that met */
    bool crossed = sb_crossed(&q, edges, h, d2, w, &s, &u);
    if (edges)
        k->beta[0] = 1.0 - s, k->beta[1] = s, k->beta[2] = -(1.0 - u), k->beta[3] = -u;
    else
        k->beta[0] = 1.0, k->beta[1] = -w[0], k->beta[2] = -w[1], k->beta[3] = -w[2];
    if (!crossed && d2 >= h * h) return false;
    sb_vec3 gap = {0, 0, 0};
    for (int j = 0; j < 4; j++) gap = sb_v3_add(gap, sb_v3_scale(q.x1[j], k->beta[j]));
    double distance = sqrt(sb_v3_dot(gap, gap));
    sb_vec3 n;
    if (crossed || !(distance > 0.0)) {
        /* the plane's normal at the end, on the side the pair started from:
         * (P − Q)·m has the sign of the coplanarity cubic's value for two
         * edges, the opposite for a vertex and a triangle */
        double c4[4];
        sb_coplanarity_cubic(&q, c4);
        sb_vec3 m3 = edges ? sb_v3_cross(sb_v3_sub(q.x1[1], q.x1[0]), sb_v3_sub(q.x1[3], q.x1[2]))
                           : sb_v3_cross(sb_v3_sub(q.x1[2], q.x1[1]), sb_v3_sub(q.x1[3], q.x1[1]));
        double length = sb_v3_length(m3);
        if (!(length > 0.0) || c4[3] == 0.0) return false;
        n = sb_v3_scale(m3, (edges ? sb_sign(c4[3]) : -sb_sign(c4[3])) / length);
    } else {
        n = sb_v3_scale(gap, 1.0 / distance);
    }
    k->n[0] = n.x, k->n[1] = n.y, k->n[2] = n.z;
    k->C = sb_v3_dot(gap, n) - h;
    /* a pair projected to h may read a hair closer after rounding to
     * sb_real: within SB_SELF_SLACK of h it counts as separated */
    return k->C < -SB_SELF_SLACK * h;
}

static void sb_touch(sb_self_contact* sc, uint32_t i) {
    if (sc->touched[i]) return;
    sc->touched[i] = 1;
    sc->touched_list[sc->touched_count++] = i;
}

/* Puts a pair's free vertices back where they started the step, at rest. */
static void sb_freeze(sb_self_contact* sc, const sb_model* m, const sb_self_constraint* k, sb_real* x1, sb_real* v) {
    for (int j = 0; j < 4; j++) {
        uint32_t i = k->v[j];
        if (m->inv_mass[i] == 0.0) continue;
        for (int a = 0; a < 3; a++) {
            x1[4 * (size_t)i + a] = sc->from4[4 * (size_t)i + a];
            v[4 * (size_t)i + a] = 0;
        }
        sb_touch(sc, i);
    }
}

/* Projects one violated constraint and removes its closing velocity;
 * false when no vertex can move. */
static bool sb_project(sb_self_contact* sc, const sb_model* m, const sb_self_constraint* k, sb_real* x1, sb_real* v) {
    double W = 0.0, closing = 0.0;
    for (int j = 0; j < 4; j++) {
        W += k->beta[j] * k->beta[j] * m->inv_mass[k->v[j]];
        const sb_real* vj = v + 4 * (size_t)k->v[j];
        closing += k->beta[j] * (vj[0] * k->n[0] + vj[1] * k->n[1] + vj[2] * k->n[2]);
    }
    if (!(W > 0.0)) return false;
    double dl = -k->C / W, dj = closing < 0.0 ? -closing / W : 0.0;
    for (int j = 0; j < 4; j++) {
        double scale = k->beta[j] * m->inv_mass[k->v[j]];
        if (scale == 0.0) continue;
        sb_real *xj = x1 + 4 * (size_t)k->v[j], *vj = v + 4 * (size_t)k->v[j];
        for (int a = 0; a < 3; a++) {
            xj[a] = (sb_real)(xj[a] + scale * dl * k->n[a]);
            vj[a] = (sb_real)(vj[a] + scale * dj * k->n[a]);
        }
        sb_touch(sc, k->v[j]);
    }
    return true;
}

/* One pass over the candidates, task by task, in order; returns the pairs
 * it corrected. With `freeze`, a violated pair is not projected but its
 * free vertices are put back where they started the step, at rest. */
static uint32_t sb_self_pass(sb_solver* s, sb_real* x1, sb_real* v, bool freeze) {
    sb_self_contact* sc = sb_self(s);
    uint32_t corrected = 0;
    for (uint32_t k = 0; k < sc->task_count; k++) {
        const sb_self_task* task = &sc->tasks[k];
        const sb_self_candidate* c = sc->buffers[task->worker] + task->first;
        for (uint32_t j = 0; j < task->count; j++) {
            sb_self_constraint constraint;
            if (!sb_constraint(sc, &c[j], x1, &constraint)) continue;
            if (freeze)
                sb_freeze(sc, s->model, &constraint, x1, v);
            else if (sb_project(sc, s->model, &constraint, x1, v))
                corrected++;
        }
    }
    return corrected;
}

/* Gauss-Seidel passes until one corrects nothing (worker 0); false when
 * SB_SELF_PASSES did not get there. */
static bool sb_resolve(sb_solver* s, sb_real* x1, sb_real* v, bool first_round) {
    sb_self_contact* sc = sb_self(s);
    for (int pass = 0; pass < SB_SELF_PASSES; pass++) {
        uint32_t corrected = sb_self_pass(s, x1, v, false);
        if (pass == 0 && first_round) sc->contacts = corrected;
        if (corrected == 0) return true;
    }
    return false;
}

/* Refit, plan, search, resolve: every worker of the job; worker 0 resolves.
 * Pairs the passes cannot separate (a vertex jammed between two layers
 * closer than twice the thickness) are a rigid impact zone in Bridson et
 * al.'s sense, given the simplest rigid motion: their vertices go back to
 * where they started the step (where nothing crossed) and stop; then the
 * search runs again around the new positions, for at most SB_SELF_ROUNDS
 * rounds. */
static void sb_self_contact_run(const sb_worker* w, sb_solver* s, sb_real* x1, sb_real* v) {
    sb_self_contact* sc = sb_self(s);
    sb_triangle_bvh* bvh = sc->bvh;
    if (w->index == 0) sc->touched_count = 0, sc->contacts = 0;
    for (int round = 0; round < SB_SELF_ROUNDS; round++) {
        int64_t begin, end;
        sb_worker_range(w, bvh->cut_count, &begin, &end);
        for (int64_t k = begin; k < end; k++) sb_triangle_bvh_refit_subtree(bvh, bvh->cut[k], sc->from4, x1, sc->h);
        sb_worker_barrier(w);
        if (w->index == 0) {
            sb_triangle_bvh_refit_top(bvh);
            sb_plan_tasks(sc);
        }
        sb_worker_barrier(w);
        sb_run_tasks(w, s, x1);
        sb_worker_barrier(w);
        if (w->index == 0) {
            sc->settled = sb_resolve(s, x1, v, round == 0);
            if (!sc->settled) sb_self_pass(s, x1, v, true);
        }
        sb_worker_barrier(w);
        if (sc->settled) break;
    }
}

static void sb_self_contact_save_packed(sb_solver* s, size_t begin, size_t end) {
    if (s->self) memcpy(s->self->from4 + begin, s->positions4 + begin, (end - begin) * sizeof(sb_real));
}

static void sb_self_contact_packed(const sb_worker* w, sb_solver* s, double dt) {
    sb_self_contact* sc = sb_self(s);
    if (!sc) return;
    sb_self_contact_run(w, s, s->positions4, s->velocities4);
    if (w->index == 0)
        for (uint32_t k = 0; k < sc->touched_count; k++) {
            uint32_t i = sc->touched_list[k];
            sc->touched[i] = 0;
            const sb_real* v = s->velocities4 + 4 * (size_t)i;
            for (int a = 0; a < 3; a++) {
                s->displacements4[4 * (size_t)i + a] = (sb_real)(v[a] * dt);
                s->forces4[4 * (size_t)i + a] = sb_fast_initial_force(s, i, a, v[a]);
            }
        }
    sb_worker_barrier(w);
}

static void sb_pack(sb_real* out, const sb_real* a, const sb_real* b, const sb_real* c, uint32_t n) {
    for (uint32_t i = 0; i < n; i++)
        out[4 * (size_t)i] = a[i], out[4 * (size_t)i + 1] = b[i], out[4 * (size_t)i + 2] = c[i];
}

static void sb_self_contact_save_state(sb_solver* s) {
    if (s->self) sb_pack(s->self->from4, s->state.x, s->state.y, s->state.z, s->state.vertex_count);
}

static void sb_self_state_job(void* context, const sb_worker* w) {
    sb_solver* s = context;
    sb_self_contact_run(w, s, s->self->x4, s->self->v4);
}

static uint32_t sb_self_contact_state_pass(sb_solver* s, double dt) {
    sb_self_contact* sc = sb_self(s);
    if (!sc) return 0;
    sb_state* st = &s->state;
    sb_pack(sc->x4, st->x, st->y, st->z, st->vertex_count);
    sb_pack(sc->v4, st->vx, st->vy, st->vz, st->vertex_count);
    sb_team_run(s->team, sb_team_size(s->team), sb_self_state_job, s);
    sb_real* xs[3] = {st->x, st->y, st->z};
    sb_real* vs[3] = {st->vx, st->vy, st->vz};
    sb_real* ds[3] = {s->disp_x, s->disp_y, s->disp_z};
    for (uint32_t k = 0; k < sc->touched_count; k++) {
        uint32_t i = sc->touched_list[k];
        sc->touched[i] = 0;
        for (int a = 0; a < 3; a++) {
            xs[a][i] = sc->x4[4 * (size_t)i + a];
            vs[a][i] = sc->v4[4 * (size_t)i + a];
            ds[a][i] = (sb_real)(sc->v4[4 * (size_t)i + a] * dt);
        }
    }
    return sc->contacts;
}

/* The stats of the step just taken. */
static void sb_self_contact_collect(sb_solver* s) {
    s->stats.self_contacts += sb_self_contact_count(s->self);
    s->stats.self_dropped += sb_self_contact_dropped(s->self);
}

/* The begin stage: the positions the moves start from, where the correct
 * stage will run (the fused step keeps them in its drift: before_drift). */
static void sb_self_contact_begin(sb_solver* s, double t0, double dt) {
    (void)t0, (void)dt;
    if (!sb_fused(s)) sb_self_contact_save_state(s);
}

/* The correct stage, after the colliders'; whether a vertex moved. */
static bool sb_self_contact_correct(sb_solver* s, double dt) {
    uint32_t contacts = sb_self_contact_state_pass(s, dt);
    sb_self_contact_collect(s);
    return contacts > 0;
}

static void sb_self_contact_subscribe(sb_solver* s) {
    sb_add_feature(s, (sb_feature){.name = "self-contact",
                                   .begin = sb_self_contact_begin,
                                   .correct = sb_self_contact_correct,
                                   .collect = sb_self_contact_collect});
    s->hooks.before_drift = sb_self_contact_save_packed;
    s->hooks.after_drift = sb_self_contact_packed;
}
