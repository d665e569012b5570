/* Breakage: bonds that break past their limits, as in the Spring Systems
 * library (GMSprAddSpringDetailed's l_min and l_max), and the first step of
 * tearing.
 *
 * Design. The model stays immutable: what breaks is the solver's state. A
 * solver of a breakable model (one with a finite limit on some bond) keeps
 * a working copy of the model (`live`): the same vertex, index and rest
 * arrays, but its own copies of the per-element constants (bond and spring
 * stiffness, damping and rest length; the triangles' angle and
 * stretch-bend constants and rest lengths; the hinges' constants). Every
 * kernel of that solver reads the copy: the scalar reference, implicit
 * Euler, pbd and xpbd through solver->model, the fast kernels through the
 * fast model, which is per solver too and was built from the copy. There
 * the bond group's and the hinges' constants are kept per slot, so each
 * element's can be zeroed in place; a triangle and the bonds fused into it
 * (kernels/forces/fast_corners.c) keep the plain model's folded constants
 * and go by the bits of the triangle slot's byte (its live bit, a bond's
 * edge bit): the fused kernel runs as before, with no branch per element
 * and no stream a plain model's step does not read. A model without
 * limits gets none of this: the same fast model, the same step.
 *
 * Cracks. A break limit with a crack-tip rule, not an energy release
 * criterion: the model's limits (l_min, l_max) are the material's strength
 * and need no new constant per bond, where an energy criterion would need
 * a toughness per bond and the energy at a tip, which a lattice of one
 * bond per cell resolves no better than the strain. A tip rule gives what
 * the lattice misses: at a crack tip the stress is singular (it grows as
 * 1/sqrt(r) towards it), and a cell of the lattice averages it away. So:
 *  - while nothing is broken, the one most overstrained bond past its limit
 *    (l²/max² or min²/l², the lowest limited index on a tie) starts the
 *    crack, at most one a step;
 *  - a vertex a break reached (the bond's ends and the vertices of the
 *    triangles it killed) is a tip, and holds its crack: a plane through
 *    the broken bond's rest midpoint, square to the pull that opened the
 *    crack (the direction at rest of the bond that started it, handed on
 *    from tip to tip). A bond at a tip breaks past its tip strength
 *    (SB_TIP_STRENGTH = 0.8 of the way from its rest length to its limit)
 *    when the crack runs across it: the plane cuts it in its middle half
 *    (SB_TIP_CUT: a bond of the next row of a jittered mesh, which the
 *    plane may just clip at an end, is not the crack's), and it is within
 *    60 degrees of the pull (it carries it). The crack so
 *    runs straight across the pull, mode I, one bond a step at each tip at
 *    most as fast as the sheet's stress moves;
 *  - anywhere else a bond breaks on its own only 25 % past its limit
 *    (SB_CRACK_MARGIN);
 *  - an interior bond whose triangles are all dead (a ligament: the
 *    diagonal left between two broken bonds of a cell) has no material
 *    left to stand for and breaks with the last of them; a border bond
 *    stays (a crack along the border's row would otherwise crumble it).
 * The tips are those before the pass, the breaks are made in bond order,
 * the callbacks after them in bond order: the same for any thread count.
 * sb_solver_def.shatter keeps the brittle rule: every bond past a limit
 * breaks at once.
 *
 * After each accepted step (each accepted adaptive sub-step) one pass over
 * the bonds with a finite limit compares their squared end lengths (in
 * double, from the current positions) with the squared limits, branch-free
 * (it vectorizes); only when one is past does the serial pass pick those
 * that break away from the tips (the tips' bonds, few, are looked at
 * after every step). The fused Verlet step skips the first pass:
 * its force kernels have every bond's squared length in hand already and
 * compare it with the limits' margins (kernels/forces/fast_model.h,
 * SB_LIMIT_MARGIN, far above sb_real's rounding), so the pass runs only
 * after a step that met a bond near a limit (measured at 100k vertices: a
 * quiet step of a breakable sheet went from 1.5x the unbreakable one's
 * time to 1.1-1.3x; with its constants folded and one limit ratio per
 * material it reads no more than the unbreakable one's,
 * bench/results/tearing.md). Once a crack runs (not
 * shattering), the margins the kernels compare with are the limits past
 * by SB_CRACK_MARGIN, the only ones a bond away from the tips breaks at:
 * the bonds around a running crack sit past their plain limits at every
 * step, and the serial pass would otherwise look at every limited bond at
 * every step of the crack. A broken bond's limits become −1 and +inf,
 * so it never matches again. For each it zeroes the bond's constants and
 * rest length (no collapse or blow-up check for it any more) and, the
 * first step of tearing, those of every triangle that has the bond's edge
 * and every hinge whose edge or wings have it (a hinge across a dead
 * triangle has no face to bend); then calls the callback on the advancing
 * thread. The forces and energies are then corrected, so that the next
 * step never feels a broken bond: as each bond, triangle and hinge loses
 * its constants its forces and energies at the step's end state are taken
 * (the scalar reference's, on a one-element view of the working copy, in
 * double, the positions and velocities gathered at its vertices only) and,
 * after the pass, subtracted from the forces at those vertices (the fused
 * step's packed ones, unpublished, or the state's and the packed) and from
 * the term energies, and those vertices' velocities re-kicked: the cost of
 * the broken elements, with no pass over the vertices (the kinetic energy
 * is summed again only where the step summed it, else left to
 * sb_solver_settle). A step that splits a vertex (each copy takes the
 * forces of its own elements) or removes an element whose edge collapsed
 * evaluates everything again instead; whether a queued vertex splits is
 * asked of its star first (sb_topology_splits). Bond order and one thread: the same
 * bonds break at the same step for any thread count.
 *
 * Tearing (kernels/interaction/topology.c) starts from here: a dying triangle's
 * vertices and a broken bond's ends are queued, and after the breaks the
 * queued vertices whose triangles came apart are split (at most
 * max_splits_per_step new vertices a step). For that the working copy also
 * has its own element indices and vertex arrays, the latter with the spare
 * slots the splits fill (sb_solver_def.max_splits), so that every kernel
 * and every per-vertex buffer of the solver, all sized from the copy, has
 * room for them from the start. The forces and energies are evaluated
 * again after a split as after a break. */
#include "kernels/interaction/breakage.h"
#include "kernels/state/solver_data.h"
#include "kernels/state/solver_fast.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/vertex_state.h"
#include "kernels/interaction/topology.h"
#include "kernels/interaction/cutting.h"
#include "kernels/interaction/cut_mesh.h"
#include "kernels/interaction/cut_volume.h"
#include "kernels/contact/contact.h"
#include "kernels/contact/self_contact.h"
#include "softbond/reference.h"
#include "common/edge_map.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The crack rule's constants (the design note): a bond off the cracks
 * breaks on its own when it is longer than (1 + margin) times its break_max
 * (or shorter than break_min over it); a bond at a crack tip breaks at the
 * tip strength, that fraction of the way from its rest length to its
 * limit, when the crack runs across it and it is within 60 degrees of the
 * crack's pull (|cos| at least 0.5). */
#define SB_CRACK_MARGIN 0.25
#define SB_TIP_STRENGTH 0.8
#define SB_TIP_ALIGNED 0.5
#define SB_TIP_CUT 0.25
#define SB_NONE UINT32_MAX

/* A break's crack: the plane through bond `at`'s rest midpoint square to
 * bond `pull`'s rest direction (the pull that opened the crack). */
typedef struct sb_crack_cause {
    uint32_t at, pull;
} sb_crack_cause;

/* The elements (triangles or hinges) on each bond's edge, by bond: CSR. */
typedef struct sb_incidence {
    uint32_t *start, *element;
} sb_incidence;

struct sb_breakage {
    sb_model live;     /* the model the solver's kernels read */
    double* constants; /* one block: live's own constant arrays */
    uint32_t limited_count;
    uint32_t* limited;                       /* the bonds with a finite limit, in bond order */
    double *min2, *max2;                     /* their squared limits; −1 and +inf once broken */
    uint8_t* broken;                         /* per bond */
    double *tip_min2, *tip_max2;             /* their squared limits at a crack tip */
    sb_crack_cause* crack;                   /* per model vertex: the break that last reached it; at SB_NONE: none */
    uint32_t* chosen_pull;                   /* per limited bond: its pull when chosen */
    uint32_t *tips, tip_count;               /* the model vertices with a crack bond, in the order they got one */
    uint32_t *vertex_start, *vertex_limited; /* the limited bonds (their k) at each model vertex: CSR */
    uint32_t* chosen;                        /* per limited bond: the serial pass's breaks */
    uint8_t* picked;                         /* per limited bond: in chosen */
    uint32_t *fresh, fresh_count;            /* the bonds broken in this accept stage, for the callback */
    /* the forces' correction (the design note): positions and velocities in
     * double, the removed elements' forces and energies, 3 per vertex slot */
    double *x3, *v3, *removed_forces;
    uint32_t *touched, touched_count; /* the vertex slots x3, v3 and removed_forces hold, in the order met */
    uint8_t* touched_mark;            /* per vertex slot: in touched */
    bool packed;                      /* the correction reads and writes the packed state only (unpublished) */
    sb_energies removed;
    enum { SB_CORRECTION_OFF, SB_CORRECTION_ARMED, SB_CORRECTION_ON, SB_CORRECTION_FAILED } correction;
    uint32_t model_vertices;
    uint8_t *triangle_dead, *hinge_dead; /* on a broken bond's edge */
    double* forces;                      /* 3n: the forces before a break */
    uint32_t broken_count;
    sb_incidence triangles, hinges;
    uint32_t* triangle_bonds; /* 3 per triangle: the bonds on its edges, UINT32_MAX for none */
    /* tearing: NULL without it */
    sb_topology* topology;
    sb_cutting* cutting;       /* the blades; NULL without */
    sb_cut_mesh* cut;          /* cutting through triangles (sb_solver_def.cut_through); NULL without */
    sb_cut_volume* volume_cut; /* cutting through tetrahedra; NULL without */
    uint32_t *met, met_count;  /* the step's crossings with cut: bonds, and where along each (met_at) */
    double* met_at;
    uint32_t model_bonds, model_triangles;
    double* vertex_block;  /* live's vertex arrays, spare slots included */
    uint8_t* fixed;        /* live's */
    uint32_t* index_block; /* live's element indices */
};

/* The bonds on an element's edges: a triangle's three; a hinge's edge and
 * its two wings' other four. Returns the count found. */
static int sb_element_bonds(const sb_model* m, const sb_edge_map* map, bool hinge, uint32_t e, uint32_t out[5]) {
    uint32_t ends[5][2];
    int edges = hinge ? 5 : 3, count = 0;
    if (hinge) {
        uint32_t e0 = m->hinge_e0[e], e1 = m->hinge_e1[e], o0 = m->hinge_o0[e], o1 = m->hinge_o1[e];
        uint32_t list[5][2] = {{e0, e1}, {e0, o0}, {e1, o0}, {e0, o1}, {e1, o1}};
        memcpy(ends, list, sizeof ends);
    } else
        for (int c = 0; c < 3; c++) {
            ends[c][0] = m->tri_v[c][e];
            ends[c][1] = m->tri_v[(c + 1) % 3][e];
        }
    for (int k = 0; k < edges; k++) {
        const uint32_t* bond = sb_edge_map_find(map, ends[k][0], ends[k][1]);
        if (bond) out[count++] = *bond;
    }
    return count;
}

static bool sb_incidence_build(sb_incidence* in, const sb_model* m, const sb_edge_map* map, bool hinge) {
    uint32_t count = hinge ? m->hinge_count : m->triangle_count, bonds[5];
    in->start = calloc((size_t)m->bond_count + 1, sizeof *in->start);
    uint32_t* cursor = malloc(((size_t)m->bond_count + 1) * sizeof *cursor);
    bool ok = in->start && cursor;
    for (uint32_t e = 0; ok && e < count; e++)
        for (int k = sb_element_bonds(m, map, hinge, e, bonds) - 1; k >= 0; k--) in->start[bonds[k] + 1]++;
    for (uint32_t b = 0; ok && b < m->bond_count; b++) in->start[b + 1] += in->start[b];
    in->element = ok ? malloc(((size_t)in->start[m->bond_count] + 1) * sizeof *in->element) : NULL;
    ok = ok && in->element;
    if (ok) memcpy(cursor, in->start, ((size_t)m->bond_count + 1) * sizeof *cursor);
    for (uint32_t e = 0; ok && e < count; e++)
        for (int k = 0, n = sb_element_bonds(m, map, hinge, e, bonds); k < n; k++) in->element[cursor[bonds[k]]++] = e;
    free(cursor);
    return ok;
}

/* live's constant arrays: copies of the model's, in one block. */
static bool sb_live_constants(sb_breakage* b, const sb_model* m) {
    size_t nb = m->bond_count, nt = m->triangle_count, nh = m->hinge_count;
    b->live = *m;
    b->constants = malloc((4 * nb + 5 * nt + nh + 1) * sizeof(double));
    if (!b->constants) return false;
    double* next = b->constants;
    struct {
        double** field;
        const double* from;
        size_t count;
    } arrays[] = {{&b->live.bond_r0, m->bond_r0, nb},         {&b->live.bond_k, m->bond_k, nb},
                  {&b->live.spring_k, m->spring_k, nb},       {&b->live.spring_damping, m->spring_damping, nb},
                  {&b->live.angle_k, m->angle_k, nt},         {&b->live.stretch_bend_k, m->stretch_bend_k, nt},
                  {&b->live.tri_len0[0], m->tri_len0[0], nt}, {&b->live.tri_len0[1], m->tri_len0[1], nt},
                  {&b->live.tri_len0[2], m->tri_len0[2], nt}, {&b->live.hinge_k, m->hinge_k, nh}};
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++) {
        memcpy(next, arrays[a].from, arrays[a].count * sizeof(double));
        *arrays[a].field = next;
        next += arrays[a].count;
    }
    return true;
}

static bool sb_limits(sb_breakage* b, const sb_model* m) {
    for (uint32_t e = 0; e < m->bond_count; e++)
        b->limited_count += m->bond_break_min[e] > 0.0 || isfinite(m->bond_break_max[e]);
    size_t n = b->limited_count ? b->limited_count : 1;
    b->limited = malloc(n * sizeof *b->limited);
    b->min2 = malloc(n * sizeof *b->min2);
    b->max2 = malloc(n * sizeof *b->max2);
    b->broken = calloc(m->bond_count ? m->bond_count : 1, 1);
    b->fresh = malloc(((size_t)m->bond_count + 1) * sizeof *b->fresh);
    b->tip_min2 = malloc(n * sizeof *b->tip_min2);
    b->tip_max2 = malloc(n * sizeof *b->tip_max2);
    b->crack = malloc(((size_t)m->vertex_count + 1) * sizeof *b->crack);
    b->chosen_pull = malloc(n * sizeof *b->chosen_pull);
    b->tips = malloc(((size_t)m->vertex_count + 1) * sizeof *b->tips);
    b->vertex_start = calloc((size_t)m->vertex_count + 2, sizeof *b->vertex_start);
    b->vertex_limited = malloc(2 * n * sizeof *b->vertex_limited);
    b->chosen = malloc(n * sizeof *b->chosen);
    b->picked = calloc(n, 1);
    b->model_vertices = m->vertex_count;
    b->triangle_dead = calloc((size_t)m->triangle_count + 1, 1);
    b->hinge_dead = calloc((size_t)m->hinge_count + 1, 1);
    void* arrays[] = {b->limited,    b->min2,           b->max2,         b->broken,     b->tip_min2, b->tip_max2,
                      b->crack,      b->tips,           b->vertex_start, b->chosen,     b->picked,   b->triangle_dead,
                      b->hinge_dead, b->vertex_limited, b->fresh,        b->chosen_pull};
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++)
        if (!arrays[a]) return false;
    for (uint32_t v = 0; v < m->vertex_count; v++) b->crack[v].at = b->crack[v].pull = SB_NONE;
    for (uint32_t e = 0, k = 0; e < m->bond_count; e++) {
        double lo = m->bond_break_min[e], hi = m->bond_break_max[e], r0 = m->bond_r0[e];
        if (!(lo > 0.0 || isfinite(hi))) continue;
        double tip_lo = lo > 0.0 ? r0 - SB_TIP_STRENGTH * (r0 - lo) : 0.0;
        double tip_hi = isfinite(hi) ? r0 + SB_TIP_STRENGTH * (hi - r0) : INFINITY;
        b->limited[k] = e;
        b->min2[k] = lo * lo;
        b->max2[k] = hi * hi;
        b->tip_min2[k] = tip_lo * tip_lo;
        b->tip_max2[k++] = tip_hi * tip_hi;
        b->vertex_start[m->bond_i[e] + 2]++;
        b->vertex_start[m->bond_j[e] + 2]++;
    }
    for (uint32_t v = 0; v < m->vertex_count; v++) b->vertex_start[v + 2] += b->vertex_start[v + 1];
    for (uint32_t k = 0; k < b->limited_count; k++) { /* start[v + 1] is v's cursor */
        b->vertex_limited[b->vertex_start[m->bond_i[b->limited[k]] + 1]++] = k;
        b->vertex_limited[b->vertex_start[m->bond_j[b->limited[k]] + 1]++] = k;
    }
    return true;
}

static bool sb_incidences(sb_breakage* b, const sb_model* m) {
    sb_edge_map map;
    if (!sb_edge_map_init(&map, m->bond_count)) return false;
    bool inserted;
    for (uint32_t e = 0; e < m->bond_count; e++) sb_edge_map_upsert(&map, m->bond_i[e], m->bond_j[e], e, &inserted);
    bool ok = sb_incidence_build(&b->triangles, m, &map, false) && sb_incidence_build(&b->hinges, m, &map, true);
    b->triangle_bonds = malloc((3 * (size_t)m->triangle_count + 1) * sizeof *b->triangle_bonds);
    ok = ok && b->triangle_bonds;
    for (uint32_t t = 0; ok && t < m->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            const uint32_t* bond = sb_edge_map_find(&map, m->tri_v[c][t], m->tri_v[(c + 1) % 3][t]);
            b->triangle_bonds[3 * (size_t)t + c] = bond ? *bond : UINT32_MAX;
        }
    sb_edge_map_free(&map);
    return ok;
}

/* The spare vertex slots: def's max_splits, or by default one for every
 * 32 bonds that can break (limited, or every bond with blades; at least
 * 256) but no more than the vertices on them; none when max_splits < 0 or
 * the model has no triangles. */
static uint32_t sb_spare_vertices(const sb_breakage* b, const sb_model* m, const sb_solver_def* def) {
    bool volume = def->cut_through && m->tet_count > 0; /* cutting through tetrahedra: their edges, every vertex */
    uint32_t breakable = volume ? 6 * m->tet_count : def->blade_count ? m->bond_count : b->limited_count;
    if (def->max_splits < 0 || (m->triangle_count == 0 && !volume) || breakable == 0) return 0;
    uint32_t room = UINT32_MAX / 8 - m->vertex_count;
    if (def->max_splits > 0) return (uint32_t)def->max_splits < room ? (uint32_t)def->max_splits : room;
    uint8_t* seen = volume ? NULL : calloc(m->vertex_count, 1);
    uint32_t on = volume ? m->vertex_count : 0;
    for (uint32_t k = 0; seen && k < breakable; k++) {
        uint32_t bond = def->blade_count ? k : b->limited[k], ends[2] = {m->bond_i[bond], m->bond_j[bond]};
        for (int e = 0; e < 2; e++) {
            on += !seen[ends[e]];
            seen[ends[e]] = 1;
        }
    }
    free(seen);
    uint32_t spare = breakable / 32 < 256 ? 256 : breakable / 32;
    spare = spare < on ? spare : on;
    return spare < room ? spare : room;
}

/* live's own vertex arrays (the spare slots dormant: fixed, no mass, at
 * vertex 0's rest, in no element) and element indices. */
static bool sb_live_topology(sb_breakage* b, const sb_model* m, uint32_t spare) {
    size_t n = m->vertex_count, cap = n + spare, nb = m->bond_count, nt = m->triangle_count, nh = m->hinge_count;
    b->vertex_block = malloc(8 * cap * sizeof *b->vertex_block);
    b->fixed = malloc(cap);
    b->index_block = malloc((2 * nb + 3 * nt + 4 * nh + 1) * sizeof *b->index_block);
    if (!b->vertex_block || !b->fixed || !b->index_block) return false;
    sb_model* live = &b->live;
    double** vertex[8] = {&live->rest_x, &live->rest_y, &live->rest_z, &live->vel_x,
                          &live->vel_y,  &live->vel_z,  &live->mass,   &live->inv_mass};
    const double* from[8] = {m->rest_x, m->rest_y, m->rest_z, m->vel_x, m->vel_y, m->vel_z, m->mass, m->inv_mass};
    for (int a = 0; a < 8; a++) {
        *vertex[a] = b->vertex_block + a * cap;
        memcpy(*vertex[a], from[a], n * sizeof(double));
        for (size_t i = n; i < cap; i++) (*vertex[a])[i] = a < 3 ? from[a][0] : 0.0;
    }
    memcpy(b->fixed, m->fixed, n);
    memset(b->fixed + n, 1, spare);
    live->fixed = b->fixed;
    live->vertex_count = (uint32_t)cap;
    uint32_t** index[9] = {&live->bond_i,   &live->bond_j,   &live->tri_v[0], &live->tri_v[1], &live->tri_v[2],
                           &live->hinge_e0, &live->hinge_e1, &live->hinge_o0, &live->hinge_o1};
    const size_t counts[9] = {nb, nb, nt, nt, nt, nh, nh, nh, nh};
    uint32_t* next = b->index_block;
    for (int a = 0; a < 9; a++) {
        memcpy(next, *index[a], counts[a] * sizeof *next);
        *index[a] = next;
        next += counts[a];
    }
    return true;
}

/* Tearing, when the model can tear and def allows it. */
static bool sb_tearing_prepare(sb_breakage* b, const sb_model* m, const sb_solver_def* def) {
    uint32_t spare = sb_spare_vertices(b, m, def);
    if (spare == 0) return true;
    if (!sb_live_topology(b, m, spare)) return false;
    free(b->forces); /* room for the spare vertices too */
    b->forces = malloc(3 * (size_t)b->live.vertex_count * sizeof *b->forces);
    bool ok = b->forces != NULL;
    uint32_t per_step = def->max_splits_per_step > 0 ? (uint32_t)def->max_splits_per_step : SB_DEFAULT_SPLITS_PER_STEP;
    if (ok && def->cut_through) {
        if (m->tet_count) /* cutting through tetrahedra (kernels/interaction/cut_volume.c) */
            b->volume_cut = sb_cut_volume_create(&b->live, m->vertex_count, b->cutting, &ok);
        else
            b->cut = sb_cut_mesh_create(&b->live, m->vertex_count, &ok);
        /* the crossings of one step: each blade's, at most the model's bonds, or 6 a tetrahedron slot */
        size_t edges =
            (size_t)b->live.bond_count + (b->volume_cut ? 6 * (size_t)sb_cut_volume_capacity(b->volume_cut) : 0);
        size_t room = edges * sb_cutting_count(b->cutting) + 1;
        b->met = ok ? malloc(room * sizeof *b->met) : NULL;
        b->met_at = ok ? malloc(room * sizeof *b->met_at) : NULL;
        return ok && b->met && b->met_at;
    }
    if (ok)
        b->topology =
            sb_topology_create(&b->live, m->vertex_count, per_step, b->broken, b->triangle_dead, b->hinge_dead, &ok);
    return ok;
}

/* The correction's arrays, for every vertex slot of the working copy. */
static bool sb_correction_prepare(sb_breakage* b) {
    size_t n = 3 * (size_t)b->live.vertex_count + 1;
    b->x3 = malloc(n * sizeof *b->x3);
    b->v3 = malloc(n * sizeof *b->v3);
    b->removed_forces = malloc(n * sizeof *b->removed_forces);
    b->touched = malloc(n / 3 * sizeof *b->touched + sizeof *b->touched);
    b->touched_mark = calloc(n / 3 + 1, 1);
    return b->x3 && b->v3 && b->removed_forces && b->touched && b->touched_mark;
}

/* What cutting through triangles needs (sb_solver_def.cut_through). */
static sb_status sb_cut_through_check(const sb_model* m, const sb_solver_def* def, sb_error* err) {
    const char* missing = def->blade_count == 0                            ? "blades"
                          : m->triangle_count == 0                         ? sb_cut_volume_missing(m)
                          : m->breakable                                   ? "a model without break limits"
                          : def->integrator > SB_INTEGRATOR_IMPLICIT_EULER ? "an explicit integrator or implicit Euler"
                          : def->collider_count > 0 || def->self_collision ? "no contact"
                          : def->max_splits < 0                            ? "max_splits >= 0"
                                                                           : NULL;
    if (missing)
        return sb_error_set(
            err, SB_ERR_INVALID,
            "cut_through (cutting through triangles and tetrahedra) needs %s; it is not built for the rest yet",
            missing);
    return SB_OK;
}

sb_status sb_breakage_create(const sb_model* m, const sb_solver_def* def, sb_breakage** out, sb_error* err) {
    *out = NULL;
    if (def->cut_through) {
        sb_status status = sb_cut_through_check(m, def, err);
        if (status != SB_OK) return status;
    }
    if (!m->breakable && def->blade_count == 0) return SB_OK;
    sb_breakage* b = calloc(1, sizeof *b);
    sb_status status =
        b && def->blade_count ? sb_cutting_create(def->blades, def->blade_count, &b->cutting, err) : SB_OK;
    if (status != SB_OK) {
        free(b);
        return status;
    }
    if (b) b->forces = malloc((3 * (size_t)m->vertex_count + 1) * sizeof *b->forces);
    if (!b || !b->forces || !sb_live_constants(b, m) || !sb_limits(b, m) || !sb_incidences(b, m) ||
        !sb_tearing_prepare(b, m, def) || !sb_correction_prepare(b) ||
        (b->cutting && !sb_cutting_room(b->cutting, b->live.vertex_count))) {
        sb_breakage_destroy(b);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory preparing %u bonds for breakage", m->bond_count);
    }
    b->live.breakable = true; /* with blades too: per-slot constants in the fast model, zeroed as bonds go */
    b->model_bonds = m->bond_count;
    b->model_triangles = m->triangle_count;
    *out = b;
    return SB_OK;
}

void sb_breakage_destroy(sb_breakage* b) {
    if (!b) return;
    sb_topology_destroy(b->topology);
    sb_cutting_destroy(b->cutting);
    sb_cut_mesh_destroy(b->cut);
    sb_cut_volume_destroy(b->volume_cut);
    free(b->met);
    free(b->met_at);
    void* arrays[] = {b->forces,
                      b->constants,
                      b->limited,
                      b->min2,
                      b->max2,
                      b->broken,
                      b->triangles.start,
                      b->triangles.element,
                      b->hinges.start,
                      b->hinges.element,
                      b->triangle_dead,
                      b->hinge_dead,
                      b->vertex_block,
                      b->fixed,
                      b->index_block,
                      b->tip_min2,
                      b->tip_max2,
                      b->crack,
                      b->chosen_pull,
                      b->tips,
                      b->vertex_start,
                      b->vertex_limited,
                      b->chosen,
                      b->picked,
                      b->triangle_bonds,
                      b->fresh,
                      b->x3,
                      b->v3,
                      b->removed_forces,
                      b->touched,
                      b->touched_mark};
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++) free(arrays[a]);
    free(b);
}

const sb_model* sb_breakage_model(const sb_breakage* b) { return &b->live; }
uint32_t sb_breakage_count(const sb_breakage* b) { return b ? b->broken_count : 0; }
bool sb_breakage_broken(const sb_breakage* b, uint32_t bond) { return b && bond < b->model_bonds && b->broken[bond]; }
const sb_topology* sb_breakage_topology(const sb_breakage* b) { return b ? b->topology : NULL; }
sb_cut_mesh* sb_breakage_cut_mesh(const sb_breakage* b) { return b ? b->cut : NULL; }
sb_cut_volume* sb_breakage_cut_volume(const sb_breakage* b) { return b ? b->volume_cut : NULL; }
sb_topology* sb_breakage_topology_to_load(sb_breakage* b) { return b ? b->topology : NULL; }
bool sb_breakage_triangle_dead(const sb_breakage* b, uint32_t triangle) {
    return b && triangle < b->model_triangles && b->triangle_dead[triangle];
}

/* Limited bond k's squared length at the packed positions p, in double. */
static inline double sb_length2(const sb_breakage* b, const sb_real* p, uint32_t k) {
    const sb_real *pi = p + 4 * (size_t)b->live.bond_i[b->limited[k]],
                  *pj = p + 4 * (size_t)b->live.bond_j[b->limited[k]];
    double dx = (double)pj[0] - pi[0], dy = (double)pj[1] - pi[1], dz = (double)pj[2] - pi[2];
    return dx * dx + dy * dy + dz * dz;
}

static inline bool sb_past(const sb_breakage* b, const sb_real* p, uint32_t k) {
    double l2 = sb_length2(b, p, k);
    return (l2 < b->min2[k]) | (l2 > b->max2[k]);
}

/* The branch-free pass: whether any limited bond is past a limit. */
static bool sb_any_past(const sb_breakage* b, const sb_real* p) {
    int any = 0;
    for (uint32_t k = 0; k < b->limited_count; k++) any |= sb_past(b, p, k);
    return any != 0;
}

/* The position of bond in the limited list (in bond order), or UINT32_MAX. */
static uint32_t sb_limited_index(const sb_breakage* b, uint32_t bond) {
    uint32_t lo = 0, hi = b->limited_count;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (b->limited[mid] < bond)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < b->limited_count && b->limited[lo] == bond ? lo : UINT32_MAX;
}

/* The model vertex v is (a copy of). */
static uint32_t sb_breakage_origin(const sb_breakage* b, uint32_t v) {
    return b->topology ? sb_topology_origin(b->topology, v) : v;
}

/* Vertex v (of the working copy) joins the cracks, reached by the break of `cause`. */
static void sb_crack_reach(sb_breakage* b, uint32_t v, sb_crack_cause cause) {
    uint32_t u = sb_breakage_origin(b, v);
    if (b->crack[u].at == SB_NONE) b->tips[b->tip_count++] = u;
    b->crack[u] = cause;
}

enum { SB_REMOVE_BOND, SB_REMOVE_TRIANGLE, SB_REMOVE_HINGE };

/* Element e of one kind of the working copy, as a model of its own. */
static sb_model sb_single(const sb_model* m, int kind, uint32_t e) {
    sb_model one = *m;
    one.bond_count = one.triangle_count = one.hinge_count = one.tet_count = 0;
    if (kind == SB_REMOVE_BOND) {
        one.bond_count = 1;
        one.bond_i += e, one.bond_j += e, one.bond_r0 += e, one.bond_k += e, one.spring_k += e;
        one.spring_damping += e;
    } else if (kind == SB_REMOVE_TRIANGLE) {
        one.triangle_count = 1;
        for (int c = 0; c < 3; c++) one.tri_v[c] += e, one.tri_cos0[c] += e, one.tri_len0[c] += e;
        one.angle_k += e, one.stretch_bend_k += e;
    } else {
        one.hinge_count = 1;
        one.hinge_e0 += e, one.hinge_e1 += e, one.hinge_o0 += e, one.hinge_o1 += e, one.hinge_phi0 += e;
        one.hinge_k += e;
    }
    return one;
}

/* The first removal of an accept stage: nothing removed yet, no vertex
 * gathered; where the state is (the fused step's unpublished packed
 * arrays, or the state's arrays). */
static void sb_correction_start(sb_solver* s, sb_breakage* b) {
    b->packed = s->fast && !s->published;
    b->touched_count = 0;
    memset(&b->removed, 0, sizeof b->removed);
    b->correction = SB_CORRECTION_ON;
}

/* Vertex v's position and velocity in double (x3, v3) and no removed force
 * yet, once per accept stage: the correction touches only the vertices of
 * the elements it removes. */
static void sb_correction_gather(const sb_solver* s, sb_breakage* b, uint32_t v) {
    if (b->touched_mark[v]) return;
    b->touched_mark[v] = 1;
    b->touched[b->touched_count++] = v;
    const sb_state* st = &s->state;
    const sb_real* x[3] = {st->x, st->y, st->z};
    const sb_real* u[3] = {st->vx, st->vy, st->vz};
    for (int a = 0; a < 3; a++) {
        b->x3[3 * (size_t)v + a] = b->packed ? s->positions4[4 * (size_t)v + a] : x[a][v];
        b->v3[3 * (size_t)v + a] = b->packed ? s->velocities4[4 * (size_t)v + a] : u[a][v];
        b->removed_forces[3 * (size_t)v + a] = 0.0;
    }
}

/* The vertices of element e of one kind. */
static int sb_element_vertices(const sb_model* m, int kind, uint32_t e, uint32_t out[4]) {
    if (kind == SB_REMOVE_BOND) {
        out[0] = m->bond_i[e], out[1] = m->bond_j[e];
        return 2;
    }
    if (kind == SB_REMOVE_TRIANGLE) {
        for (int c = 0; c < 3; c++) out[c] = m->tri_v[c][e];
        return 3;
    }
    out[0] = m->hinge_e0[e], out[1] = m->hinge_e1[e], out[2] = m->hinge_o0[e], out[3] = m->hinge_o1[e];
    return 4;
}

/* Element e of one kind is about to lose its constants: its forces and
 * energies at the state (the scalar reference's) join the removed ones. */
static void sb_remove(sb_solver* s, sb_breakage* b, int kind, uint32_t e) {
    static const sb_term terms[3][2] = {
        {SB_TERM_BOND, SB_TERM_SPRING}, {SB_TERM_ANGLE, SB_TERM_STRETCH_BEND}, {SB_TERM_BEND, SB_TERM_BEND}};
    if (b->correction == SB_CORRECTION_ARMED) sb_correction_start(s, b);
    if (b->correction != SB_CORRECTION_ON) return;
    uint32_t vertices[4];
    for (int q = sb_element_vertices(&b->live, kind, e, vertices) - 1; q >= 0; q--)
        sb_correction_gather(s, b, vertices[q]);
    sb_model one = sb_single(&b->live, kind, e);
    for (int q = 0; q < (kind == SB_REMOVE_HINGE ? 1 : 2); q++) {
        double energy;
        sb_error err;
        if (sb_reference_term(&one, terms[kind][q], b->x3, b->v3, b->removed_forces, &energy, &err) != SB_OK)
            b->correction = SB_CORRECTION_FAILED; /* a collapsed edge: the full evaluation says so */
        b->removed.term[terms[kind][q]] += energy;
    }
}

/* Whether the integrator ends a step with the half kick of the forces at
 * its end (sb_rekick), which a change of those forces redoes. */
static bool sb_kicks_at_end(const sb_solver* s) {
    return s->def.integrator == SB_INTEGRATOR_VERLET || s->def.integrator == SB_INTEGRATOR_VELOCITY_VERLET;
}

/* Vertex i's inverse mass as the integrators move it. */
static double sb_moving_inv_mass(sb_solver* s, uint32_t i) {
    return s->fast ? s->fast->inv_mass[i] : sb_inv_mass(s)[i];
}

/* The forces and term energies without the removed elements', at the
 * touched vertices only, and their velocities re-kicked (sb_rekick): the
 * packed state's where it is unpublished, else the state's arrays and the
 * packed ones. Returns whether a velocity changed. */
static bool sb_correction_apply(sb_solver* s, sb_breakage* b) {
    sb_state* st = &s->state;
    sb_real* f[3] = {st->fx, st->fy, st->fz};
    sb_real* v[3] = {st->vx, st->vy, st->vz};
    bool kick = sb_kicks_at_end(s);
    for (uint32_t q = 0; q < b->touched_count; q++) {
        uint32_t i = b->touched[q];
        double h = kick ? 0.5 * s->step.dt * sb_moving_inv_mass(s, i) : 0.0;
        b->touched_mark[i] = 0;
        for (int a = 0; a < 3; a++) {
            size_t at = 4 * (size_t)i + a;
            sb_real old = b->packed ? s->forces4[at] : f[a][i];
            sb_real now = (sb_real)(old - b->removed_forces[3 * (size_t)i + a]);
            sb_real velocity = (sb_real)((b->packed ? s->velocities4[at] : v[a][i]) + h * ((double)now - old));
            if (!b->packed) f[a][i] = now, v[a][i] = velocity;
            if (s->fast) s->forces4[at] = now, s->velocities4[at] = velocity;
        }
    }
    b->touched_count = 0;
    for (int t = 0; t < SB_TERM_COUNT; t++) s->energies.term[t] -= b->removed.term[t];
    return kick;
}

/* The touched vertices' marks cleared, the correction dropped. */
static void sb_correction_drop(sb_breakage* b) {
    for (uint32_t q = 0; q < b->touched_count; q++) b->touched_mark[b->touched[q]] = 0;
    b->touched_count = 0;
}

/* The kinetic energy after the correction re-kicked velocities: the fused
 * step's vertex sums again, or left to sb_solver_settle where the step
 * left them for later; the state's otherwise. */
static void sb_correction_energies(sb_solver* s, sb_breakage* b) {
    if (!b->packed)
        sb_update_energies(s);
    else if (!s->forces_stale)
        sb_fast_vertex_energies(s);
}

static void sb_break_bond(sb_solver* s, sb_breakage* b, uint32_t bond, bool notify, sb_crack_cause cause);

/* Once a crack runs, a bond away from its tips breaks only past its limits
 * by the margin (SB_CRACK_MARGIN): the fast kernels flag a bond near those
 * instead, so that the serial pass over the limited bonds runs only when
 * one may break alone (the tips' bonds are looked at after every step). */
static void sb_alone_margins(sb_solver* s) {
    if (s->fast) sb_fast_widen_limits(s->fast, 1.0 + SB_CRACK_MARGIN);
}

/* Whether bond is a ligament: an interior bond (two triangles or more on
 * its edge) with every one of them dead, so no material is left for it to
 * stand for. A bond on the surface's border keeps the border whole. */
static bool sb_ligament(const sb_breakage* b, uint32_t bond) {
    uint32_t first = b->triangles.start[bond], end = b->triangles.start[bond + 1];
    for (uint32_t q = first; q < end; q++)
        if (!b->triangle_dead[b->triangles.element[q]]) return false;
    return end > first + 1;
}

/* Triangle t dies by cause's break: its constants go, its vertices join
 * the crack (and the splitting queue), and its bonds left as ligaments
 * break with it. */
static void sb_drop_triangle(sb_solver* s, sb_breakage* b, uint32_t t, bool notify, sb_crack_cause cause) {
    sb_model* m = &b->live;
    sb_remove(s, b, SB_REMOVE_TRIANGLE, t);
    m->angle_k[t] = m->stretch_bend_k[t] = 0.0;
    for (int c = 0; c < 3; c++) m->tri_len0[c][t] = 0.0;
    if (s->fast) sb_fast_drop_triangle(s->fast, t);
    b->triangle_dead[t] = 1;
    for (int c = 0; c < 3; c++) {
        sb_crack_reach(b, m->tri_v[c][t], cause);
        if (b->topology) sb_topology_queue(b->topology, m->tri_v[c][t]);
    }
    for (int c = 0; c < 3; c++) {
        uint32_t bond = b->triangle_bonds[3 * (size_t)t + c];
        if (bond != SB_NONE && !b->broken[bond] && sb_ligament(b, bond)) sb_break_bond(s, b, bond, notify, cause);
    }
}

/* The hinges and triangles on the bond's edge lose their constants; with
 * tearing, the bond's ends are queued for splitting. */
static void sb_drop_elements(sb_solver* s, sb_breakage* b, uint32_t bond, bool notify, sb_crack_cause cause) {
    sb_model* m = &b->live;
    if (b->topology) {
        sb_topology_queue(b->topology, m->bond_i[bond]);
        sb_topology_queue(b->topology, m->bond_j[bond]);
    }
    for (uint32_t q = b->hinges.start[bond]; q < b->hinges.start[bond + 1]; q++) {
        if (!b->hinge_dead[b->hinges.element[q]]) sb_remove(s, b, SB_REMOVE_HINGE, b->hinges.element[q]);
        m->hinge_k[b->hinges.element[q]] = 0.0;
        if (s->fast) sb_fast_drop_hinge(s->fast, b->hinges.element[q]);
        b->hinge_dead[b->hinges.element[q]] = 1;
    }
    for (uint32_t q = b->triangles.start[bond]; q < b->triangles.start[bond + 1]; q++)
        if (!b->triangle_dead[b->triangles.element[q]]) sb_drop_triangle(s, b, b->triangles.element[q], notify, cause);
}

/* Breaks bond `bond` (once) in the crack `cause` (at itself, or at the
 * bond whose break left it a ligament); the callback too when `notify`. */
static void sb_break_bond(sb_solver* s, sb_breakage* b, uint32_t bond, bool notify, sb_crack_cause cause) {
    sb_model* m = &b->live;
    if (b->broken[bond]) return;
    b->broken[bond] = 1;
    if (b->broken_count++ == 0 && !s->def.shatter) sb_alone_margins(s);
    uint32_t k = sb_limited_index(b, bond);
    if (k != SB_NONE) { /* its limits never match again */
        b->min2[k] = b->tip_min2[k] = -1.0;
        b->max2[k] = b->tip_max2[k] = INFINITY;
    }
    sb_crack_reach(b, m->bond_i[bond], cause);
    sb_crack_reach(b, m->bond_j[bond], cause);
    sb_remove(s, b, SB_REMOVE_BOND, bond);
    m->bond_k[bond] = m->spring_k[bond] = m->spring_damping[bond] = m->bond_r0[bond] = 0.0;
    if (s->fast) sb_fast_break_bond(s->fast, bond);
    if (notify) b->fresh[b->fresh_count++] = bond;
    sb_drop_elements(s, b, bond, notify, cause);
}

static void sb_sever(void* solver, uint32_t bond, double along) {
    (void)along;
    sb_solver* s = solver;
    sb_break_bond(s, s->breakage, bond, true, (sb_crack_cause){bond, bond});
}

/* How far limited bond k is past its limits at p: the larger of l²/max²
 * and min²/l², above 1 exactly when sb_past. */
static double sb_overstrain(const sb_breakage* b, const sb_real* p, uint32_t k) {
    double l2 = sb_length2(b, p, k);
    return fmax(l2 / b->max2[k], b->min2[k] / l2);
}

/* Bond's midpoint (mid) and unit direction (dir) at rest. */
static void sb_rest_line(const sb_model* m, uint32_t bond, double mid[3], double dir[3]) {
    const double* rest[3] = {m->rest_x, m->rest_y, m->rest_z};
    double length = 0.0;
    for (int a = 0; a < 3; a++) {
        mid[a] = 0.5 * (rest[a][m->bond_i[bond]] + rest[a][m->bond_j[bond]]);
        dir[a] = rest[a][m->bond_j[bond]] - rest[a][m->bond_i[bond]];
        length += dir[a] * dir[a];
    }
    for (int a = 0; a < 3; a++) dir[a] /= sqrt(length);
}

/* Whether the crack that reached model vertex u runs across bond: at rest,
 * bond's ends lie on either side of the crack's plane (through the
 * midpoint of u's crack bond, square to it: the pull that opened it), and
 * bond is within 60 degrees of that pull (it carries it). */
static bool sb_runs_across(const sb_breakage* b, uint32_t u, uint32_t bond) {
    const sb_model* m = &b->live;
    const double* rest[3] = {m->rest_x, m->rest_y, m->rest_z};
    double mid[3], pull[3], mid_bond[3], dir[3], unused[3], side_i = 0.0, side_j = 0.0, aligned = 0.0;
    sb_rest_line(m, b->crack[u].at, mid, unused);
    sb_rest_line(m, b->crack[u].pull, unused, pull);
    sb_rest_line(m, bond, mid_bond, dir);
    for (int a = 0; a < 3; a++) {
        side_i += (rest[a][m->bond_i[bond]] - mid[a]) * pull[a];
        side_j += (rest[a][m->bond_j[bond]] - mid[a]) * pull[a];
        aligned += dir[a] * pull[a];
    }
    double cut = side_i / (side_i - side_j); /* where along the bond the plane cuts it, when it does */
    return side_i * side_j < 0.0 && cut >= SB_TIP_CUT && cut <= 1.0 - SB_TIP_CUT && fabs(aligned) >= SB_TIP_ALIGNED;
}

/* Limited bond k breaks in this pass, its crack square to bond pull (the
 * first pick's). */
static void sb_pick(sb_breakage* b, uint32_t k, uint32_t pull, uint32_t* count) {
    if (b->picked[k]) return;
    b->picked[k] = 1;
    b->chosen_pull[k] = pull;
    b->chosen[(*count)++] = k;
}

/* The crack tips' bonds that break: at a cracked vertex, past the tip
 * strength, the crack running across them. */
static void sb_pick_tips(sb_breakage* b, const sb_real* p, uint32_t* count) {
    for (uint32_t t = 0; t < b->tip_count; t++) {
        uint32_t u = b->tips[t];
        for (uint32_t q = b->vertex_start[u]; q < b->vertex_start[u + 1]; q++) {
            uint32_t k = b->vertex_limited[q];
            double l2 = sb_length2(b, p, k);
            bool past = (l2 > b->tip_max2[k]) | (l2 < b->tip_min2[k]);
            if (past && !b->broken[b->limited[k]] && sb_runs_across(b, u, b->limited[k]))
                sb_pick(b, k, b->crack[u].pull, count);
        }
    }
}

/* The bonds past their limits that break away from the tips: those past
 * by the margin, and, while nothing is broken yet, the most overstrained
 * (the lowest such k on a tie), which starts the first crack. */
static void sb_pick_alone(sb_breakage* b, const sb_real* p, uint32_t* count) {
    const double alone = (1.0 + SB_CRACK_MARGIN) * (1.0 + SB_CRACK_MARGIN);
    uint32_t start = SB_NONE;
    double worst = 1.0;
    for (uint32_t k = 0; k < b->limited_count; k++) {
        if (!sb_past(b, p, k)) continue;
        double q = sb_overstrain(b, p, k);
        if (q > alone)
            sb_pick(b, k, b->limited[k], count);
        else if (b->broken_count == 0 && q > worst) {
            worst = q;
            start = k;
        }
    }
    if (start != SB_NONE) sb_pick(b, start, b->limited[start], count);
}

/* Shattering: every bond past a limit, when `past`. */
static void sb_pick_past(sb_breakage* b, const sb_real* p, bool past, uint32_t* count) {
    for (uint32_t k = 0; past && k < b->limited_count; k++)
        if (sb_past(b, p, k)) sb_pick(b, k, b->limited[k], count);
}

static int sb_compare_k(const void* x, const void* y) {
    uint32_t a = *(const uint32_t*)x, c = *(const uint32_t*)y;
    return (a > c) - (a < c);
}

/* The serial pass, the crack rule (the design note): picks the tips' bonds
 * and, when `past` (some bond is past a limit), those breaking alone, then
 * breaks them in bond order; the tips are the cracks' before the pass.
 * Returns whether any broke. */
static bool sb_break_cracks(sb_solver* s, sb_breakage* b, const sb_real* p, bool past) {
    uint32_t count = 0;
    if (s->def.shatter)
        sb_pick_past(b, p, past, &count);
    else {
        sb_pick_tips(b, p, &count);
        if (past) sb_pick_alone(b, p, &count);
    }
    qsort(b->chosen, count, sizeof *b->chosen, sb_compare_k);
    for (uint32_t q = 0; q < count; q++) {
        b->picked[b->chosen[q]] = 0;
        uint32_t k = b->chosen[q];
        sb_break_bond(s, b, b->limited[k], true, (sb_crack_cause){b->limited[k], b->chosen_pull[k]});
    }
    return count > 0;
}

/* The callback for the bonds broken in this accept stage, in bond order. */
static void sb_notify(sb_solver* s, sb_breakage* b) {
    qsort(b->fresh, b->fresh_count, sizeof *b->fresh, sb_compare_k);
    for (uint32_t q = 0; s->def.on_break && q < b->fresh_count; q++) {
        uint32_t bond = b->fresh[q];
        s->def.on_break(s->def.break_user, bond, b->live.bond_i[bond], b->live.bond_j[bond], s->time);
    }
    b->fresh_count = 0;
}

/* Verlet and velocity Verlet end a step with the half kick a⁺ dt/2 of the
 * forces at its end, which belongs to the interval after it: after a break
 * it is the broken state's (otherwise the kinetic energy would keep the
 * broken bonds' last pull, and the adaptive stepper would count it as a
 * gain at every later sub-step). The other integrators' velocities use no
 * force of the step's end. Hard-held vertices (inverse mass 0: the packed
 * one, sb_inv_mass) keep their handle's velocity. */
static void sb_rekick(sb_solver* s, const double* before) {
    if (!sb_kicks_at_end(s)) return;
    sb_state* st = &s->state;
    sb_real* v[3] = {st->vx, st->vy, st->vz};
    const sb_real* f[3] = {st->fx, st->fy, st->fz};
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        double h = 0.5 * s->step.dt * sb_moving_inv_mass(s, i);
        for (int a = 0; a < 3; a++) {
            v[a][i] = (sb_real)(v[a][i] + h * (f[a][i] - before[3 * (size_t)i + a]));
            if (s->fast) s->velocities4[4 * (size_t)i + a] = v[a][i];
        }
    }
}

/* After the breaks (`broke`; `corrected`: their forces taken), the splits
 * and the forces: the broken elements' forces subtracted in place where
 * nothing splits, else everything evaluated again. */
static sb_status sb_after_breaks(sb_solver* s, sb_breakage* b, bool broke, bool corrected) {
    if (!(b->topology && sb_topology_splits(b->topology))) {
        if (b->topology) sb_topology_split(s, b->topology, b->forces); /* the queue drained: nothing to split */
        if (corrected && sb_correction_apply(s, b)) /* in place: only the removed elements' forces go */
            sb_correction_energies(s, b);
        if (corrected || !broke) return SB_OK;
    }
    sb_correction_drop(b);
    sb_fast_publish(s); /* the fused path: the state's arrays, which the evaluation packs again */
    sb_interleave(b->forces, s->state.fx, s->state.fy, s->state.fz, s->state.vertex_count);
    uint32_t made = b->topology ? sb_topology_split(s, b->topology, b->forces) : 0;
    if (made) s->live_vertices = sb_topology_vertex_count(b->topology);
    /* a split vertex's copies each take their own elements' forces: all evaluated again */
    sb_status status = sb_solver_compute_forces(s);
    if (status != SB_OK) return status;
    sb_rekick(s, b->forces);
    sb_update_energies(s); /* the reference's evaluation zeroes kinetic and gravity */
    return SB_OK;
}

/* The accept stage: after a kept (sub-)step of dt, breaks the bonds whose
 * length is past a limit (in bond order, the callback for each), then those
 * a blade crossed (kernels/interaction/cutting.c), splits where the surface
 * came apart, and when any of these happened evaluates the forces and
 * energies again. */
/* A crossing of the step, when cutting through triangles. */
static void sb_note_crossing(void* breakage, uint32_t bond, double along) {
    sb_breakage* b = breakage;
    b->met[b->met_count] = bond;
    b->met_at[b->met_count++] = along;
}

/* The forces and energies after a cut: the fast model built again from the
 * working copy (a cut adds elements, where tearing only moves them within
 * their slots), everything evaluated again, the velocities re-kicked. */
static sb_status sb_cut_refresh(sb_solver* s, sb_breakage* b) {
    sb_status status = s->fast ? sb_fast_rebuild(s, &s->error) : SB_OK;
    if (status == SB_OK) status = sb_solver_compute_forces(s);
    if (status != SB_OK) return status;
    sb_rekick(s, b->forces);
    sb_update_energies(s);
    return SB_OK;
}

/* The accept stage when cutting through triangles (kernels/interaction/cut_mesh.c):
 * the step's crossings refine the mesh, the cut's edges and vertices come
 * apart, and the forces and energies are evaluated again. */
static sb_status sb_cut_accept(sb_solver* s, sb_breakage* b) {
    b->met_count = 0;
    sb_cutting_pass(b->cutting, &b->live, sb_packed_positions(s), sb_cut_mesh_skip(b->cut), s->time - s->step.dt,
                    s->time, sb_note_crossing, b);
    if (b->met_count == 0) return SB_OK;
    sb_fast_publish(s); /* the cut reads and writes the state's arrays */
    sb_interleave(b->forces, s->state.fx, s->state.fy, s->state.fz, s->state.vertex_count);
    for (uint32_t q = 0; q < b->met_count; q++) sb_cut_mesh_cross(s, b->cut, b->met[q], b->met_at[q], b->forces);
    sb_cut_mesh_separate(s, b->cut, b->forces);
    s->live_vertices = sb_cut_mesh_vertex_count(b->cut);
    return sb_cut_refresh(s, b);
}

/* The accept stage when cutting through tetrahedra (kernels/interaction/cut_volume.c):
 * as sb_cut_accept, on the tetrahedra's edges. */
static sb_status sb_cut_volume_accept(sb_solver* s, sb_breakage* b) {
    b->met_count = 0;
    sb_cut_volume* cut = b->volume_cut;
    sb_cutting_pass(b->cutting, sb_cut_volume_edges(cut), sb_packed_positions(s), sb_cut_volume_skip(cut),
                    s->time - s->step.dt, s->time, sb_note_crossing, b);
    if (b->met_count == 0) return SB_OK;
    sb_fast_publish(s); /* the cut reads and writes the state's arrays */
    sb_interleave(b->forces, s->state.fx, s->state.fy, s->state.fz, s->state.vertex_count);
    sb_cut_volume_sweeps(cut, s->time - s->step.dt, s->time);
    for (uint32_t q = 0; q < b->met_count; q++) sb_cut_volume_cross(s, cut, b->met[q], b->met_at[q], b->forces);
    sb_cut_volume_separate(s, cut, b->forces);
    s->live_vertices = sb_cut_volume_vertex_count(cut);
    return sb_cut_refresh(s, b);
}

static sb_status sb_breakage_accept(sb_solver* s, double dt) {
    (void)dt; /* the step's: s->step.dt */
    sb_breakage* b = s->breakage;
    if (!b) return SB_OK;
    if (b->cut) return sb_cut_accept(s, b);
    if (b->volume_cut) return sb_cut_volume_accept(s, b);
    const sb_real* p = sb_packed_positions(s);
    /* the fused step's kernels measured every bond at these positions and flag one near a limit */
    bool measured = sb_fused(s) && s->fast->limits_measured;
    b->correction = SB_CORRECTION_ARMED;
    bool broke = sb_break_cracks(s, b, p, measured ? s->near_limits : sb_any_past(b, p));
    if (b->cutting)
        broke |= sb_cutting_pass(b->cutting, &b->live, p, b->broken, s->time - s->step.dt, s->time, sb_sever, s) > 0;
    bool corrected = b->correction == SB_CORRECTION_ON;
    b->correction = SB_CORRECTION_OFF;
    sb_notify(s, b);
    uint32_t vertices = s->live_vertices;
    sb_status status = sb_after_breaks(s, b, broke, corrected);
    if (status == SB_OK && (broke || s->live_vertices != vertices)) /* the surface changed */
        status = sb_breakage_update_contact(s, &s->error);
    return status;
}

sb_status sb_breakage_update_contact(sb_solver* s, sb_error* err) {
    return s->breakage ? sb_self_contact_retopologize(s, s->breakage->triangle_dead, err) : SB_OK;
}

sb_status sb_breakage_loaded(sb_solver* s, sb_error* err) {
    sb_breakage* b = s->breakage;
    bool cut = b && (b->cut || b->volume_cut);
    sb_status status = cut && s->fast ? sb_fast_rebuild(s, err) : SB_OK;
    return status == SB_OK ? sb_breakage_update_contact(s, err) : status;
}

/* The begin stage: the blades' sweep starts from the vertices' positions now. */
static void sb_breakage_begin(sb_solver* s, double t0, double dt) {
    (void)t0, (void)dt;
    sb_cutting* cutting = s->breakage->cutting;
    if (cutting) sb_cutting_start(cutting, sb_packed_positions(s), s->model->vertex_count);
}

void sb_breakage_subscribe(sb_solver* s) {
    if (!s->breakage) return;
    sb_add_feature(s, (sb_feature){.name = "breakage", .begin = sb_breakage_begin, .accept = sb_breakage_accept});
    sb_contact_set_dead_triangles(s, s->breakage->triangle_dead);
}

/* ---- the saved state (kernels/solver/solver_state.c) ---------------------------- */

/* The broken bonds' count and list, then the cracks' tips: their count,
 * their list and every model vertex's crack bond. */
void sb_breakage_save(const sb_breakage* b, sb_sections_writer* w) {
    sb_sections_put(w, &b->broken_count, sizeof b->broken_count);
    for (uint32_t e = 0; e < b->model_bonds; e++)
        if (b->broken[e]) sb_sections_put(w, &e, sizeof e);
    sb_sections_put(w, &b->tip_count, sizeof b->tip_count);
    sb_sections_put(w, b->tips, b->tip_count * sizeof *b->tips);
    sb_sections_put(w, b->crack, b->model_vertices * sizeof *b->crack);
}

/* The cracks' part of the section at r (its length checked): every tip a
 * model vertex, every crack's bonds bonds of the model or both none. */
static sb_status sb_cracks_check(const sb_breakage* b, sb_cursor r, uint32_t tips, sb_error* err) {
    uint32_t tip;
    sb_crack_cause crack;
    for (uint32_t q = 0; q < tips; q++)
        if (sb_cursor_take(&r, &tip, sizeof tip) && tip >= b->model_vertices)
            return sb_error_set(err, SB_ERR_PARSE, "crack tip %u is not a vertex of the model", tip);
    for (uint32_t v = 0; v < b->model_vertices && sb_cursor_take(&r, &crack, sizeof crack); v++) {
        bool none = crack.at == SB_NONE && crack.pull == SB_NONE;
        if (!none && (crack.at >= b->live.bond_count || crack.pull >= b->live.bond_count))
            return sb_error_set(err, SB_ERR_PARSE, "vertex %u's crack names bonds %u and %u, not the model's", v,
                                crack.at, crack.pull);
    }
    return SB_OK;
}

sb_status sb_breakage_check(const sb_breakage* b, sb_cursor r, sb_error* err) {
    uint32_t count, bond, last = 0;
    if (b->broken_count > 0)
        return sb_error_set(err, SB_ERR_INVALID, "the solver has broken bonds already: load into a new solver");
    uint32_t tips = 0;
    sb_cursor rest = r;
    bool sized = sb_cursor_take(&rest, &count, sizeof count) && rest.left >= 4 * (size_t)count + 4;
    if (sized) {
        rest.at += 4 * (size_t)count; /* the broken bonds, checked below */
        rest.left -= 4 * (size_t)count;
        sb_cursor_take(&rest, &tips, sizeof tips);
    }
    if (!sized || tips > b->model_vertices || rest.left != 4 * (size_t)tips + sizeof *b->crack * b->model_vertices)
        return sb_error_set(err, SB_ERR_PARSE, "the broken bonds' section has the wrong length");
    sb_cursor_take(&r, &count, sizeof count);
    for (uint32_t q = 0; q < count; q++) {
        sb_cursor_take(&r, &bond, sizeof bond);
        bool breakable = bond < b->model_bonds && (b->cutting || sb_limited_index(b, bond) != UINT32_MAX);
        if (!breakable || (q > 0 && bond <= last))
            return sb_error_set(err, SB_ERR_PARSE, "broken bond %u is not a breakable bond of the model in order",
                                bond);
        last = bond;
    }
    return sb_cracks_check(b, rest, tips, err);
}

void sb_breakage_load(sb_solver* s, sb_cursor* r) {
    uint32_t count = 0, bond;
    sb_cursor_take(r, &count, sizeof count);
    sb_breakage* b = s->breakage;
    for (uint32_t q = 0; q < count && sb_cursor_take(r, &bond, sizeof bond); q++)
        sb_break_bond(s, b, bond, false, (sb_crack_cause){bond, bond});
    sb_cursor_take(r, &b->tip_count, sizeof b->tip_count); /* the cracks as they were, not as replayed */
    sb_cursor_take(r, b->tips, b->tip_count * sizeof *b->tips);
    sb_cursor_take(r, b->crack, b->model_vertices * sizeof *b->crack);
}
