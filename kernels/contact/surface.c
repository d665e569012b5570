/* The colliders against the body's surface: a tool smaller than the
 * mesh's spacing stops at the triangles between the vertices.
 *
 * Design. The vertex pass (kernels/contact/contact.c) answers each
 * vertex's move; a collider that fits between vertices meets none of
 * them. This pass, after it, takes each triangle and each collider that
 * meets the surface (the built-in sphere, capsule and box, a program's
 * own collider with a triangle_point callback: sb_collider_meets_surface):
 * the collider names the material point of the
 * triangle nearest its core, by barycentric weights w — the point its
 * center, segment or edges came nearest in the step, or went through
 * (kernels/contact/colliders/triangle_point.c) — and that point, which
 * moved from Σ w_i x0_i to Σ w_i x1_i, is answered as a vertex is: the
 * collider's own sweep and the same velocity and position answers
 * (restitution, Coulomb friction, the push out), so the point of contact
 * stops, swept: a fast tool does not pass a sheet in a step. A point at a
 * corner (a weight of 1) is the vertex the vertex pass answered.
 *
 * The point's change of velocity Δv and position Δx are spread over the
 * corners as an impulse would be: corner i takes w_i m_i⁻¹ / W of them, W =
 * Σ w_j² m_j⁻¹ (a fixed or held corner, m⁻¹ = 0, none), which moves the
 * point by exactly Δv and Δx (Σ w_i · w_i m_i⁻¹ / W = 1), and gives the body
 * the momentum Σ m_i Δv_i = Δv Σ_free w_i / W, the opposite of what the
 * collider receives: momentum is conserved. Along the normal Δx is the
 * answer's push; along the surface, dt times the change of velocity (the
 * rest of the step at the answered velocity), so a corner is not dragged
 * along the surface by the point's reset. A corrected corner takes d = v dt
 * as its Verlet displacement, as in the vertex pass; every move starts where
 * the step started (the view's `from`, kept where an answer reset d: a
 * corner answered again from x − d could start inside, or past, a thin
 * capsule and be pushed out on its far side). A corner the push
 * carried into the collider (a sheet wrapped round a thin capsule: the
 * normal at the point of contact is not the way out at the corner) is then
 * answered as a vertex, by the same collider.
 *
 * A collider with a footprint (kernels/contact/footprint.c) answers the
 * mean of a patch of vertices about that point instead, spread by the
 * patch's weights the same way, at a corner too (the vertex pass leaves
 * it out). Its touching patches are kept as candidates and answered after
 * the triangles, earliest and deepest first, each tested again: the first
 * pushes out the patches that overlap it.
 *
 * One thread, triangles in a fixed order and each triangle's colliders in
 * order, each answer seen by the next (Gauss-Seidel): the same for any
 * thread count. A broad phase keeps it cheap on a large body: each
 * triangle belongs to the block of 8 vertices of its lowest corner, and
 * each block knows the blocks its triangles' corners lie in (made once,
 * from the topology); the box of a block's moves (the fused vertex pass
 * computes it anyway) joined over those blocks holds every move of its
 * triangles, so a block whose join reaches no such collider's step bounds
 * and ball skips its triangles. The same test on a group first skips the
 * group: a group is the vertex pass's chunk of 256 vertices, whose box it
 * computes first, and knows the groups its triangles reach (a sheet lying
 * on a floor around a small sphere costs a join of a few boxes a group).
 * Where no collider meeting the surface reaches a chunk, the vertex pass
 * makes no block boxes and the group's box stands for its blocks'. A
 * triangle whose move's box lies outside a ball holding the collider
 * through the step (sb_collider_surface_ball) costs the box. Blocks of 8:
 * with 32 (a tenth of a row of the 100k sheet), a sheet on a floor around a
 * sphere had 4 260 triangles' boxes made a step, 178 of which met the
 * sphere's ball (bench/results/contact.md). A tearing solver's corners
 * change blocks as it splits vertices, so there every block's triangles
 * are tested. */
#include "kernels/contact/surface.h"
#include "kernels/contact/contact.h"
#include "kernels/contact/surface_triangles.h"
#include "kernels/contact/footprint.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/state/solver_fast.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* For each unit (a block or a group), the units of the same kind holding
 * the corners of the triangles it owns, itself first (CSR). */
typedef struct sb_surface_reach {
    uint32_t *first, *unit;
} sb_surface_reach;

/* One vertex of the point a collider answers: its weight, its move, its
 * velocity and inverse mass. */
typedef struct sb_patch_vertex {
    uint32_t vertex;
    double weight, from[3], to[3], v[3], inv_mass;
} sb_patch_vertex;

/* The point a collider answers, Σ weight_j x_j (the weights sum to 1): a
 * triangle's corners, or the patch a collider with a footprint presses
 * (kernels/contact/footprint.c). */
typedef struct sb_patch {
    uint32_t count, *vertex; /* vertex: the footprint's patch, room for it */
    double* weight;
    sb_patch_vertex* at; /* room for 3, or the footprint's patch */
} sb_patch;

/* A triangle whose patch a collider with a footprint touches this step,
 * waiting to be answered in order (sb_press_order). */
typedef struct sb_pressed {
    uint32_t triangle, collider;
    double fraction, depth;
} sb_pressed;

struct sb_surface {
    sb_surface_triangles triangles;
    uint32_t blocks, groups;
    uint32_t *owned_first, *owned; /* CSR: the triangles each block owns, in triangle order */
    sb_surface_reach blocks_reach; /* the blocks each block's triangles reach */
    sb_surface_reach groups_reach; /* the groups each group's triangles reach */
    double* boxes;                 /* 6 a block: the box of its moves this step */
    double* group_boxes;           /* 6 a group: the box of its moves this step */
    uint8_t* fine;                 /* per group: its blocks' boxes were set this step (else its box stands for them) */
    bool by_block;                 /* the topology is fixed: blocks may be skipped */
    const uint8_t* dead;           /* tearing's torn triangles, out of the pass (NULL: none) */
    sb_footprint footprint;        /* where a collider has a footprint */
    sb_patch patch;                /* the pass's own, for the point it answers */
    sb_pressed* pressed;           /* room for a candidate per triangle and collider with a footprint */
    uint32_t pressed_count;
};

bool sb_surface_active(const sb_solver* s) {
    if (s->def.vertex_contact_only || !sb_surface_triangles_exist(s->model)) return false;
    for (uint32_t c = 0; c < s->def.collider_count; c++)
        if (sb_collider_meets_surface(s->def.colliders[c])) return true;
    return false;
}

static uint32_t sb_owner_block(const sb_surface_triangles* tris, uint32_t t) {
    uint32_t a = tris->v[0][t], b = tris->v[1][t], c = tris->v[2][t], low = a < b ? a : b;
    return (low < c ? low : c) / SB_SURFACE_BLOCK;
}

/* first[] from the counts in first[1..blocks] (a prefix sum). */
static void sb_prefix(uint32_t* first, uint32_t blocks) {
    for (uint32_t b = 0; b < blocks; b++) first[b + 1] += first[b];
}

/* The triangles each block owns, in triangle order. */
static bool sb_surface_own(sb_surface* f) {
    uint32_t* at = malloc(((size_t)f->blocks + 1) * sizeof *at);
    if (!at) return false;
    for (uint32_t t = 0; t < f->triangles.count; t++) f->owned_first[sb_owner_block(&f->triangles, t) + 1]++;
    sb_prefix(f->owned_first, f->blocks);
    memcpy(at, f->owned_first, ((size_t)f->blocks + 1) * sizeof *at);
    for (uint32_t t = 0; t < f->triangles.count; t++) f->owned[at[sb_owner_block(&f->triangles, t)]++] = t;
    free(at);
    return true;
}

/* The units of `size` blocks that the triangles of unit u reach (u
 * first, then each other once), into reach[] when it is not NULL; returns
 * how many. `seen` is the last unit that marked each unit. */
static uint32_t sb_surface_reached(const sb_surface* f, uint32_t size, uint32_t u, uint32_t* seen, uint32_t* reach) {
    uint32_t first = u * size, last = first + size < f->blocks ? first + size : f->blocks, count = 1;
    seen[u] = u;
    if (reach) reach[0] = u;
    for (uint32_t k = f->owned_first[first]; k < f->owned_first[last]; k++)
        for (int c = 0; c < 3; c++) {
            uint32_t other = f->triangles.v[c][f->owned[k]] / (SB_SURFACE_BLOCK * size);
            if (seen[other] == u) continue;
            seen[other] = u;
            if (reach) reach[count] = other;
            count++;
        }
    return count;
}

/* The reach of every unit of `size` blocks. */
static bool sb_surface_reach_of(const sb_surface* f, uint32_t size, sb_surface_reach* r) {
    uint32_t units = (f->blocks + size - 1) / size;
    uint32_t* seen = malloc((size_t)units * sizeof *seen);
    r->first = calloc((size_t)units + 1, sizeof *r->first);
    if (!seen || !r->first) {
        free(seen);
        return false;
    }
    for (int pass = 0; pass < 2; pass++) { /* count, then fill */
        for (uint32_t u = 0; u < units; u++) seen[u] = UINT32_MAX;
        for (uint32_t u = 0; u < units; u++) {
            uint32_t count = sb_surface_reached(f, size, u, seen, pass ? r->unit + r->first[u] : NULL);
            if (!pass) r->first[u + 1] = count;
        }
        if (pass) break;
        sb_prefix(r->first, units);
        r->unit = malloc(((size_t)r->first[units] + 1) * sizeof *r->unit);
        if (!r->unit) break;
    }
    free(seen);
    return r->unit != NULL;
}

static void sb_surface_reach_free(sb_surface_reach* r) {
    free(r->first);
    free(r->unit);
}

/* The largest footprint of the solver's colliders (0: none), and how many
 * have one. */
static double sb_largest_footprint(const sb_solver* s, uint32_t* count) {
    double largest = 0.0;
    *count = 0;
    for (uint32_t c = 0; c < s->def.collider_count; c++) {
        double footprint = sb_collider_footprint(s->def.colliders[c]);
        largest = fmax(largest, footprint);
        *count += footprint > 0.0;
    }
    return largest;
}

/* A footprint needs the surface's neighbours to stay and a corner of every
 * triangle within it. */
static sb_status sb_check_footprints(const sb_solver* s, const sb_surface* f, sb_error* err) {
    double longest = -1.0;
    for (uint32_t c = 0; c < s->def.collider_count; c++) {
        const sb_collider* collider = s->def.colliders[c];
        double footprint = sb_collider_footprint(collider);
        if (footprint == 0.0) continue;
        if (s->def.max_splits > 0)
            return sb_error_set(err, SB_ERR_INVALID,
                                "collider '%s': a footprint (%g m) cannot be used with tearing (max_splits %d): the "
                                "surface's neighbours change as it tears",
                                collider->name, footprint, (int)s->def.max_splits);
        if (longest < 0.0) longest = sb_footprint_longest_edge(s->model, &f->triangles);
        if (footprint < longest)
            return sb_error_set(err, SB_ERR_INVALID,
                                "collider '%s': footprint %g m is shorter than the longest edge of the body's surface "
                                "at rest (%g m); it must be 0 or at least that",
                                collider->name, footprint, longest);
    }
    return SB_OK;
}

/* The patch's room: 3 corners, or the largest footprint's patch; the
 * candidates' room. */
static bool sb_surface_patch_room(sb_surface* f, const sb_solver* s) {
    uint32_t pressing;
    double largest = sb_largest_footprint(s, &pressing);
    if (largest > 0.0 && !sb_footprint_make(s->model, &f->triangles, largest, &f->footprint)) return false;
    size_t room = f->footprint.room > 3 ? f->footprint.room : 3;
    f->patch.at = malloc(room * sizeof *f->patch.at);
    f->patch.vertex = malloc(room * sizeof *f->patch.vertex);
    f->patch.weight = malloc(room * sizeof *f->patch.weight);
    if (pressing && !(f->pressed = malloc(((size_t)f->triangles.count * pressing + 1) * sizeof *f->pressed)))
        return false;
    return f->patch.at && f->patch.vertex && f->patch.weight;
}

sb_status sb_surface_create(const sb_solver* s, sb_surface** out, sb_error* err) {
    const sb_model* m = s->model;
    sb_surface* f = *out = calloc(1, sizeof *f);
    if (!f) return sb_error_set(err, SB_ERR_NOMEM, "out of memory for the surface contact");
    sb_status status = sb_surface_triangles_make(m, &f->triangles, err);
    if (status == SB_OK) status = sb_check_footprints(s, f, err);
    if (status != SB_OK) {
        sb_surface_destroy(f);
        *out = NULL;
        return status;
    }
    f->blocks = (m->vertex_count + SB_SURFACE_BLOCK - 1) / SB_SURFACE_BLOCK;
    f->groups = (f->blocks + SB_SURFACE_GROUP - 1) / SB_SURFACE_GROUP;
    f->by_block = s->def.max_splits <= 0;
    f->owned_first = calloc((size_t)f->blocks + 1, sizeof *f->owned_first);
    f->owned = malloc(((size_t)f->triangles.count + 1) * sizeof *f->owned);
    f->boxes = malloc(6 * ((size_t)f->blocks + 1) * sizeof *f->boxes);
    f->group_boxes = malloc(6 * ((size_t)f->groups + 1) * sizeof *f->group_boxes);
    f->fine = calloc((size_t)f->groups + 1, sizeof *f->fine);
    if (f->owned_first && f->owned && f->boxes && f->group_boxes && f->fine && sb_surface_own(f) &&
        sb_surface_patch_room(f, s) && sb_surface_reach_of(f, 1, &f->blocks_reach) &&
        sb_surface_reach_of(f, SB_SURFACE_GROUP, &f->groups_reach))
        return SB_OK;
    sb_surface_destroy(f);
    *out = NULL;
    return sb_error_set(err, SB_ERR_NOMEM, "out of memory for the surface contact");
}

void sb_surface_destroy(sb_surface* f) {
    if (!f) return;
    sb_surface_triangles_free(&f->triangles);
    free(f->owned_first);
    free(f->owned);
    sb_surface_reach_free(&f->blocks_reach);
    sb_surface_reach_free(&f->groups_reach);
    sb_footprint_free(&f->footprint);
    free(f->pressed);
    free(f->patch.at);
    free(f->patch.vertex);
    free(f->patch.weight);
    free(f->boxes);
    free(f->group_boxes);
    free(f->fine);
    free(f);
}

void sb_surface_set_dead(sb_surface* f, const uint8_t* dead) { f->dead = dead; }

static void sb_box_set(double* box, const double lo[3], const double hi[3]) {
    for (int k = 0; k < 3; k++) box[k] = lo[k], box[3 + k] = hi[k];
}

void sb_surface_set_box(sb_surface* f, uint32_t block, const double lo[3], const double hi[3]) {
    sb_box_set(f->boxes + 6 * (size_t)block, lo, hi);
}

void sb_surface_set_group_box(sb_surface* f, uint32_t group, const double lo[3], const double hi[3], bool fine) {
    sb_box_set(f->group_boxes + 6 * (size_t)group, lo, hi);
    f->fine[group] = fine;
}

/* Block b's box: its own when its group's were set, else its group's,
 * which holds it. */
static const double* sb_block_box(const sb_surface* f, uint32_t b) {
    uint32_t g = b / SB_SURFACE_GROUP;
    return f->fine[g] ? f->boxes + 6 * (size_t)b : f->group_boxes + 6 * (size_t)g;
}

/* box ∪= other (plain comparisons: fmin would be a call per value) */
static void sb_box_join(double* box, const double* other) {
    for (int k = 0; k < 3; k++) {
        box[k] = other[k] < box[k] ? other[k] : box[k];
        box[3 + k] = other[3 + k] > box[3 + k] ? other[3 + k] : box[3 + k];
    }
}

static void sb_box_empty(double* box) {
    for (int k = 0; k < 3; k++) box[k] = INFINITY, box[3 + k] = -INFINITY;
}

/* Whether the view's `from` holds vertex i's start this step (the view's note). */
static bool sb_view_holds_from(const sb_surface_view* view, uint32_t i) {
    return !view->kept || view->kept[i] == view->stamp;
}

/* Axis k of vertex i's start this step. */
static double sb_view_from(const sb_surface_view* view, uint32_t i, int k) {
    size_t at = view->stride * i;
    if (sb_view_holds_from(view, i)) return view->from[3 * (size_t)i + k];
    return (double)view->x[k][at] - (double)view->d[k][at];
}

/* Keeps vertex i's start `from` before the pass moves it. */
static void sb_view_keep_from(const sb_surface_view* view, uint32_t i, const double from[3]) {
    if (sb_view_holds_from(view, i)) return;
    memcpy(view->from + 3 * (size_t)i, from, 3 * sizeof *from);
    view->kept[i] = view->stamp;
}

/* Every block's and group's box from the view (the passes that do not set
 * them). */
static void sb_surface_make_boxes(sb_surface* f, const sb_solver* s, const sb_surface_view* view) {
    uint32_t n = s->model->vertex_count;
    for (uint32_t g = 0; g < f->groups; g++) sb_box_empty(f->group_boxes + 6 * (size_t)g), f->fine[g] = 1;
    for (uint32_t b = 0; b < f->blocks; b++) {
        double* box = f->boxes + 6 * (size_t)b;
        sb_box_empty(box);
        for (uint32_t i = b * SB_SURFACE_BLOCK; i < n && i < (b + 1) * SB_SURFACE_BLOCK; i++)
            for (int k = 0; k < 3; k++) {
                size_t at = view->stride * i;
                double x = view->x[k][at], from = sb_view_from(view, i, k);
                box[k] = fmin(box[k], fmin(x, from));
                box[3 + k] = fmax(box[3 + k], fmax(x, from));
            }
        sb_box_join(f->group_boxes + 6 * (size_t)(b / SB_SURFACE_GROUP), box);
    }
}

/* The balls that hold the colliders meeting the surface through the step,
 * grown by the contact thickness and the collider's footprint: a triangle
 * whose box lies outside a collider's ball cannot touch it. (The point a
 * footprint's patch answers is a mean of vertices within the footprint of
 * the triangle at rest: near it, unless the body is stretched beyond it.) */
typedef struct sb_surface_balls {
    uint64_t meets; /* a bit per collider that meets the surface */
    double center[SB_MAX_COLLIDERS][3], radius2[SB_MAX_COLLIDERS], footprint[SB_MAX_COLLIDERS];
} sb_surface_balls;

static void sb_surface_balls_of(const sb_solver* s, sb_surface_balls* balls) {
    balls->meets = 0;
    for (uint32_t c = 0; c < s->def.collider_count; c++) {
        if (!sb_collider_meets_surface(s->def.colliders[c])) continue;
        double radius;
        sb_collider_surface_ball(s->def.colliders[c], balls->center[c], &radius);
        balls->footprint[c] = sb_collider_footprint(s->def.colliders[c]);
        radius += s->def.contact_thickness + balls->footprint[c];
        balls->radius2[c] = radius * radius;
        balls->meets |= (uint64_t)1 << c;
    }
}

/* Whether the box [lo, hi] reaches into collider c's ball. */
static bool sb_box_meets_ball(const sb_surface_balls* balls, uint32_t c, const double lo[3], const double hi[3]) {
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double x = balls->center[c][k], out = x < lo[k] ? lo[k] - x : x > hi[k] ? x - hi[k] : 0.0;
        d2 += out * out;
    }
    return d2 <= balls->radius2[c];
}

/* Whether the box reaches a collider meeting the surface: its bounds and
 * its ball (a block of a sheet lying inside a large sphere's bounds but
 * far from its ball, as a floor around the sphere, skips its triangles). */
static bool sb_box_reaches(const sb_solver* s, const double box[6], const sb_surface_balls* balls) {
    for (uint32_t c = 0; c < s->def.collider_count; c++) {
        double lo[3], hi[3];
        for (int k = 0; k < 3; k++) lo[k] = box[k] - balls->footprint[c], hi[k] = box[3 + k] + balls->footprint[c];
        if ((balls->meets >> c & 1) && sb_box_meets_ball(balls, c, box, box + 3) && sb_contact_reaches(s, c, lo, hi))
            return true;
    }
    return false;
}

/* Whether the join of the boxes of the units unit u's triangles reach
 * (groups, or blocks) reaches a collider meeting the surface. */
static bool sb_unit_reaches(const sb_surface* f, bool groups, const sb_solver* s, uint32_t u,
                            const sb_surface_balls* balls) {
    const sb_surface_reach* r = groups ? &f->groups_reach : &f->blocks_reach;
    double box[6];
    sb_box_empty(box);
    for (uint32_t k = r->first[u]; k < r->first[u + 1]; k++)
        sb_box_join(box, groups ? f->group_boxes + 6 * (size_t)r->unit[k] : sb_block_box(f, r->unit[k]));
    return sb_box_reaches(s, box, balls);
}

sb_surface_view sb_surface_view_packed(sb_solver* s, double* from, uint32_t* kept, uint32_t stamp) {
    sb_surface_view view = {.stride = 4, .from = from, .kept = kept, .stamp = stamp};
    for (int k = 0; k < 3; k++) {
        view.x[k] = s->positions4 + k;
        view.v[k] = s->velocities4 + k;
        view.d[k] = s->displacements4 + k;
        view.f[k] = s->forces4 + k;
    }
    return view;
}

sb_surface_view sb_surface_view_state(sb_solver* s, double* from) {
    sb_state* st = &s->state;
    return (sb_surface_view){.x = {st->x, st->y, st->z},
                             .v = {st->vx, st->vy, st->vz},
                             .d = {s->disp_x, s->disp_y, s->disp_z},
                             .f = {NULL, NULL, NULL},
                             .stride = 1,
                             .from = from};
}

/* A triangle's corners at the start and the end of the step, their
 * velocities and inverse masses. */
typedef struct sb_corners {
    uint32_t vertex[3];
    double from[3][3], to[3][3], v[3][3], inv_mass[3];
} sb_corners;

static void sb_read_corners(const sb_solver* s, const sb_surface* f, const sb_surface_view* view, uint32_t t,
                            sb_corners* c) {
    const double* inv_mass = sb_inv_mass(s);
    for (int j = 0; j < 3; j++) {
        uint32_t i = c->vertex[j] = f->triangles.v[j][t];
        size_t at = view->stride * i;
        for (int k = 0; k < 3; k++) {
            c->to[j][k] = view->x[k][at];
            c->v[j][k] = view->v[k][at];
            c->from[j][k] = sb_view_from(view, i, k);
        }
        c->inv_mass[j] = inv_mass[i];
    }
}

/* The box around triangle t's corners' moves, read from the view (most
 * triangles a pass looks at end here: their corners are not read whole). */
static void sb_triangle_box(const sb_surface* f, const sb_surface_view* view, uint32_t t, double lo[3], double hi[3]) {
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int j = 0; j < 3; j++) {
        uint32_t i = f->triangles.v[j][t];
        size_t at = view->stride * i;
        for (int k = 0; k < 3; k++) {
            double b = view->x[k][at], a = sb_view_from(view, i, k);
            lo[k] = a < lo[k] ? a : lo[k], lo[k] = b < lo[k] ? b : lo[k];
            hi[k] = a > hi[k] ? a : hi[k], hi[k] = b > hi[k] ? b : hi[k];
        }
    }
}

/* The point of the triangle with corners c at weights w that collider
 * `index` answers: the corners at those weights (a corner at weight 0 left
 * out), or the patch its footprint presses; then the vertices' states
 * from the view. */
static void sb_patch_of(const sb_solver* s, sb_surface* f, const sb_surface_view* view, const sb_corners* c,
                        const double w[3], uint32_t index, sb_patch* p) {
    double footprint = sb_collider_footprint(s->def.colliders[index]);
    p->count = 0;
    if (footprint > 0.0) {
        p->count = sb_footprint_patch(&f->footprint, s->model, c->vertex, w, footprint, p->vertex, p->weight);
        for (uint32_t j = 0; j < p->count; j++)
            p->at[j] = (sb_patch_vertex){.vertex = p->vertex[j], .weight = p->weight[j]};
    } else
        for (int j = 0; j < 3; j++)
            if (w[j] != 0.0) p->at[p->count++] = (sb_patch_vertex){.vertex = c->vertex[j], .weight = w[j]};
    const double* inv_mass = sb_inv_mass(s);
    for (uint32_t j = 0; j < p->count; j++) {
        sb_patch_vertex* pv = &p->at[j];
        size_t at = view->stride * pv->vertex;
        for (int k = 0; k < 3; k++) {
            pv->to[k] = view->x[k][at];
            pv->v[k] = view->v[k][at];
            pv->from[k] = sb_view_from(view, pv->vertex, k);
        }
        pv->inv_mass = inv_mass[pv->vertex];
    }
}

/* Σ weight_j from_j and Σ weight_j to_j */
static void sb_patch_move(const sb_patch* p, double from[3], double to[3]) {
    for (int k = 0; k < 3; k++) {
        from[k] = p->at[0].weight * p->at[0].from[k];
        to[k] = p->at[0].weight * p->at[0].to[k];
        for (uint32_t j = 1; j < p->count; j++) {
            from[k] += p->at[j].weight * p->at[j].from[k];
            to[k] += p->at[j].weight * p->at[j].to[k];
        }
    }
}

/* Σ weight_j v_j */
static void sb_patch_velocity(const sb_patch* p, double v[3]) {
    for (int k = 0; k < 3; k++) {
        v[k] = p->at[0].weight * p->at[0].v[k];
        for (uint32_t j = 1; j < p->count; j++) v[k] += p->at[j].weight * p->at[j].v[k];
    }
}

/* A vertex's new state: the share `share` of the point's Δx and Δv. */
static void sb_move_vertex(const sb_solver* s, const sb_surface_view* view, const sb_patch_vertex* pv, double share,
                           const double dx[3], const double dv[3], double dt) {
    size_t at = view->stride * pv->vertex;
    sb_view_keep_from(view, pv->vertex, pv->from);
    for (int k = 0; k < 3; k++) {
        double v = pv->v[k] + share * dv[k];
        view->x[k][at] = (sb_real)(pv->to[k] + share * dx[k]);
        view->v[k][at] = (sb_real)v;
        view->d[k][at] = (sb_real)(v * dt);
        if (view->f[k]) view->f[k][at] = sb_fast_initial_force(s, pv->vertex, k, v);
    }
}

/* A corner the spread carried into the collider (a sheet wrapped round a
 * capsule: the push along the normal at the point of contact is not the
 * way out at the corner) is answered as the vertex pass answers a vertex. */
static void sb_answer_corner(const sb_solver* s, const sb_surface_view* view, uint32_t i, uint32_t index, double dt) {
    size_t at = view->stride * i;
    double x[3], v[3], from[3], impulse[3], point[3];
    for (int k = 0; k < 3; k++) {
        x[k] = view->x[k][at], v[k] = view->v[k][at];
        from[k] = sb_view_from(view, i, k);
    }
    if (sb_contact_vertex(s, i, (uint64_t)1 << index, from, x, v, impulse, point) < 0) return;
    sb_view_keep_from(view, i, from);
    for (int k = 0; k < 3; k++) {
        view->x[k][at] = (sb_real)x[k];
        view->v[k][at] = (sb_real)v[k];
        view->d[k][at] = (sb_real)(v[k] * dt);
        if (view->f[k]) view->f[k][at] = sb_fast_initial_force(s, i, k, v[k]);
    }
    sb_contact_record(s, 0, (int)index, impulse);
    sb_contact_record_torque(s, 0, (int)index, point, impulse);
}

/* The point's move: along the normal, where the answer puts it; along the
 * surface, the rest of the step at the change of velocity, dt Δv. */
static void sb_point_move(const sb_contact* contact, const double answered[3], const double to[3], const double dv[3],
                          double dt, double dx[3]) {
    double push = 0.0, slip = 0.0;
    for (int k = 0; k < 3; k++) {
        push += (answered[k] - to[k]) * contact->normal[k];
        slip += dv[k] * contact->normal[k];
    }
    for (int k = 0; k < 3; k++) dx[k] = push * contact->normal[k] + dt * (dv[k] - slip * contact->normal[k]);
}

/* The contact of the triangle's point that collider `index` answers,
 * into the pass's patch, q and contact; whether it touches. A collider with
 * a footprint answers its patch's point, at a corner too: the vertex pass
 * leaves it out. */
static bool sb_surface_contact(const sb_solver* s, sb_surface* f, const sb_surface_view* view, const sb_corners* c,
                               uint32_t index, sb_contact_query* q, sb_contact* contact) {
    const sb_collider* collider = s->def.colliders[index];
    double w[3];
    if (!sb_collider_triangle_point(collider, c->from, c->to, w)) return false;
    if (sb_collider_footprint(collider) == 0.0 && (w[0] >= 1.0 || w[1] >= 1.0 || w[2] >= 1.0))
        return false; /* a vertex: the vertex pass's */
    sb_patch* p = &f->patch;
    sb_patch_of(s, f, view, c, w, index, p);
    double largest = 0.0, free_weight = 0.0;
    uint32_t nearest = 0;
    for (uint32_t j = 0; j < p->count; j++) {
        if (p->at[j].inv_mass > 0.0) free_weight += p->at[j].weight;
        if (p->at[j].weight > largest) largest = p->at[j].weight, nearest = j;
    }
    if (!(free_weight > 0.0)) return false; /* held */
    *q = (sb_contact_query){.vertex = p->at[nearest].vertex,
                            .t0 = s->time - s->step.dt,
                            .t1 = s->time,
                            .thickness = s->def.contact_thickness};
    sb_patch_move(p, q->from, q->to);
    return collider->collide(collider->user, q, contact);
}

/* The answer of the contact of the pass's patch (sb_surface_contact): the
 * point's change of velocity and position spread over the patch. */
static void sb_surface_apply(const sb_solver* s, sb_surface* f, const sb_surface_view* view, const sb_corners* c,
                             uint32_t index, const sb_contact_query* q, const sb_contact* contact, double dt) {
    const sb_patch* p = &f->patch;
    double v[3], before[3], x[3], dx[3], dv[3], W = 0.0, taken = 0.0, impulse[3];
    sb_patch_velocity(p, v);
    for (uint32_t j = 0; j < p->count; j++) W += p->at[j].weight * p->at[j].weight * p->at[j].inv_mass;
    memcpy(before, v, sizeof v);
    sb_contact_velocity(contact, v);
    sb_contact_position(contact, s->step.dt, q->from, q->to, v, x);
    for (int k = 0; k < 3; k++) dv[k] = v[k] - before[k];
    sb_point_move(contact, x, q->to, dv, dt, dx);
    for (uint32_t j = 0; j < p->count; j++) {
        double share = p->at[j].weight * p->at[j].inv_mass / W;
        if (share > 0.0) sb_move_vertex(s, view, &p->at[j], share, dx, dv, dt);
        if (p->at[j].inv_mass > 0.0) taken += p->at[j].weight;
    }
    for (int k = 0; k < 3; k++) impulse[k] = dv[k] * taken / W;
    sb_contact_record(s, 0, (int)index, impulse);
    sb_contact_record_torque(s, 0, (int)index, contact->point, impulse);
    if (sb_collider_footprint(s->def.colliders[index]) > 0.0) return; /* a patch: no corner is answered alone */
    for (int j = 0; j < 3; j++)
        if (c->inv_mass[j] > 0.0) sb_answer_corner(s, view, c->vertex[j], index, dt);
}

/* The triangle against collider `index`: whether its point of contact was answered. */
static bool sb_surface_answer(const sb_solver* s, sb_surface* f, const sb_surface_view* view, const sb_corners* c,
                              uint32_t index, double dt) {
    sb_contact_query q;
    sb_contact contact;
    if (!sb_surface_contact(s, f, view, c, index, &q, &contact)) return false;
    sb_surface_apply(s, f, view, c, index, &q, &contact, dt);
    return true;
}

/* Triangle t's patch against collider `index` with a footprint: a
 * candidate when it touches. */
static void sb_surface_candidate(const sb_solver* s, sb_surface* f, const sb_surface_view* view, const sb_corners* c,
                                 uint32_t t, uint32_t index) {
    sb_contact_query q;
    sb_contact contact;
    if (!sb_surface_contact(s, f, view, c, index, &q, &contact)) return;
    f->pressed[f->pressed_count++] =
        (sb_pressed){.triangle = t, .collider = index, .fraction = contact.fraction, .depth = contact.depth};
}

/* By collider, then the earliest contact, then the deepest, then the triangle. */
static int sb_press_order(const void* a, const void* b) {
    const sb_pressed *x = a, *y = b;
    if (x->collider != y->collider) return x->collider < y->collider ? -1 : 1;
    if (x->fraction != y->fraction) return x->fraction < y->fraction ? -1 : 1;
    if (x->depth != y->depth) return x->depth > y->depth ? -1 : 1;
    return x->triangle < y->triangle ? -1 : x->triangle > y->triangle;
}

/* The candidates of the colliders with a footprint, in order, each
 * answered when it still touches: the first pushes its patch out, and the
 * patches of its neighbours, which overlap it, mostly with it. Answering
 * them in the triangles' order instead pushed each out in turn from wherever
 * the last left it, and the force a tool felt jumped from tick to tick. */
static uint32_t sb_surface_press(const sb_solver* s, sb_surface* f, const sb_surface_view* view, double dt) {
    uint32_t contacts = 0;
    if (f->pressed_count == 0) return 0; /* pressed is NULL without a footprint */
    qsort(f->pressed, f->pressed_count, sizeof *f->pressed, sb_press_order);
    for (uint32_t k = 0; k < f->pressed_count; k++) {
        sb_corners corners;
        sb_read_corners(s, f, view, f->pressed[k].triangle, &corners);
        contacts += sb_surface_answer(s, f, view, &corners, f->pressed[k].collider, dt);
    }
    f->pressed_count = 0;
    return contacts;
}

/* Triangle t against the colliders that meet the surface; returns the contacts. */
static uint32_t sb_surface_triangle(const sb_solver* s, sb_surface* f, const sb_surface_view* view, uint32_t t,
                                    const sb_surface_balls* balls, double dt) {
    sb_corners corners;
    double lo[3], hi[3];
    uint32_t contacts = 0;
    bool read = false;
    sb_triangle_box(f, view, t, lo, hi);
    for (uint32_t c = 0; c < s->def.collider_count; c++) {
        if (!(balls->meets >> c & 1) || !sb_box_meets_ball(balls, c, lo, hi)) continue;
        if (!read) sb_read_corners(s, f, view, t, &corners), read = true;
        if (balls->footprint[c] > 0.0) {
            sb_surface_candidate(s, f, view, &corners, t, c);
            continue;
        }
        if (!sb_surface_answer(s, f, view, &corners, c, dt)) continue;
        contacts++;
        sb_read_corners(s, f, view, t, &corners); /* the next collider sees the answer */
    }
    return contacts;
}

uint32_t sb_surface_pass(const sb_solver* s, sb_surface* f, const sb_surface_view* view, bool boxes_set, double dt) {
    sb_surface_balls balls;
    sb_surface_balls_of(s, &balls);
    if (f->by_block && !boxes_set) sb_surface_make_boxes(f, s, view);
    uint32_t contacts = 0;
    for (uint32_t g = 0; g < f->groups; g++) {
        if (f->by_block && !sb_unit_reaches(f, true, s, g, &balls)) continue;
        uint32_t last = (g + 1) * SB_SURFACE_GROUP < f->blocks ? (g + 1) * SB_SURFACE_GROUP : f->blocks;
        for (uint32_t b = g * SB_SURFACE_GROUP; b < last; b++) {
            if (f->by_block && !sb_unit_reaches(f, false, s, b, &balls)) continue;
            for (uint32_t k = f->owned_first[b]; k < f->owned_first[b + 1]; k++)
                if (!(f->dead && f->dead[f->owned[k]]))
                    contacts += sb_surface_triangle(s, f, view, f->owned[k], &balls, dt);
        }
    }
    return contacts + sb_surface_press(s, f, view, dt);
}
