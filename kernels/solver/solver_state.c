/* The solver's saved state (softbond/solver.h: sb_solver_save_state,
 * sb_solver_load_state): a checkpoint from which a run continues bitwise.
 *
 * Design. What is saved is everything a step reads that an earlier step
 * wrote, as it is in memory, never recomputed: a force evaluated again
 * from the saved positions could differ in the last bit (the fused step's
 * forces are summed in its own order; a velocity-dependent force used a
 * half-step velocity), and the run would part from the uninterrupted one.
 * So the file holds the step arrays (the state's positions, velocities,
 * forces and Verlet displacement, and the fast path's packed copies of
 * them, stale or not, with the flag that says which is current), the
 * external forces kept for the adaptive stepper, the clock and step count,
 * the last step's length, the adaptive stepper's next sub-step and energy
 * peak, the energies and the last advance's statistics and contact
 * impulses and the bodies' open contact episodes, each collider's moving
 * state (poses, a dynamic body's position,
 * velocity, orientation and angular momentum), each handle's (held or
 * not, poses, grab positions, release time) and the broken bonds, whose
 * zeroed constants follow from them, vbd's velocities of the last
 * step (its first guess compares with them) and the fast implicit Euler's
 * last Δv (its first guess, kernels/integrators/implicit_fast.c). Not saved, because
 * no step carries them over: pbd's and xpbd's λ (zeroed at the start of
 * every step), the self-contact search (refitted from the state), the
 * scratch buffers. A
 * solver that tears (kernels/interaction/topology.c) adds its topology: the split
 * vertices, the elements re-pointed at them, the queue of vertices to look
 * at; the fast model's slots and the masses are set again from it.
 *
 * The file is common/sections.h's: a header (magic "SBSOLVER", version,
 * the size of sb_real, the vertex count, a hash of the model and of the
 * parts of the definition that shape the state: integrator, kernels,
 * adaptive, colliders, handles, self-contact, tearing's caps), then one tagged section per
 * part below, then a checksum. A reader checks all of it and every
 * section's length against what this solver would write before it changes
 * anything, so a refused file leaves the solver as it was. A new kind of
 * state (tearing's topology, say) is a new section in the table. */
#include "kernels/state/solver_data.h"
#include "kernels/state/solver_forces.h"
#include "kernels/solver/adaptive.h"
#include "kernels/interaction/breakage.h"
#include "kernels/interaction/cut_mesh.h"
#include "kernels/interaction/cut_volume.h"
#include "kernels/contact/contact.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/interaction/handle_internal.h"
#include "kernels/integrators/implicit_euler.h"
#include "kernels/integrators/implicit_fast.h"
#include "kernels/integrators/vbd.h"
#include "common/error.h"
#include "common/sections.h"

#include <math.h>
#include <string.h>

#define SB_STATE_MAGIC "SBSOLVER"
/* 2: the energies carry the corotated term; 3: and the membrane term; 4: the
 * cracks' tips; 5: the drifts' carries; 6: the bodies' contact episodes */
#define SB_STATE_VERSION 6

/* A solver's clock and the scalars a step carries over. */
static void sb_clock_save(const sb_solver* s, sb_sections_writer* w) {
    double adaptive[2];
    sb_adaptive_memory(s->adaptive, adaptive);
    double values[6] = {s->time, s->prev_dt, adaptive[0], adaptive[1], s->advance_dt, s->step.dt};
    uint8_t flags[2] = {s->has_displacement, s->published};
    sb_sections_put(w, values, sizeof values);
    sb_sections_put(w, &s->steps, sizeof s->steps);
    sb_sections_put(w, flags, sizeof flags);
}

static void sb_clock_load(sb_solver* s, sb_cursor* r) {
    double values[6];
    uint8_t flags[2];
    sb_cursor_take(r, values, sizeof values);
    sb_cursor_take(r, &s->steps, sizeof s->steps);
    sb_cursor_take(r, flags, sizeof flags);
    s->time = values[0], s->prev_dt = values[1];
    sb_adaptive_restore(s->adaptive, values + 2);
    s->advance_dt = values[4], s->step.dt = values[5];
    s->has_displacement = flags[0] != 0;
    s->published = flags[1] != 0;
}

/* The clock's length and values: the time and the step sizes finite and
 * not negative, the energy peak finite (a NaN time, its checksum recomputed, was taken as it was). */
static sb_status sb_clock_check(const sb_solver* s, sb_cursor r, sb_error* err) {
    (void)s;
    double values[6];
    uint64_t steps;
    uint8_t flags[2];
    if (r.left != sizeof values + sizeof steps + sizeof flags || !sb_cursor_take(&r, values, sizeof values))
        return sb_error_set(err, SB_ERR_PARSE, "section CLCK (clock) has %zu bytes, this solver's %zu", r.left,
                            sizeof values + sizeof steps + sizeof flags);
    static const char* const names[6] = {"time",    "last step", "adaptive sub-step", "adaptive energy peak",
                                         "advance", "step"};
    for (int k = 0; k < 6; k++)
        if (!(isfinite(values[k]) && (values[k] >= 0 || k == 3) && fabs(values[k]) < 1e300))
            return sb_error_set(err, SB_ERR_PARSE, "the clock's %s is out of range (%g)", names[k], values[k]);
    return SB_OK;
}

static void sb_energies_save(const sb_solver* s, sb_sections_writer* w) {
    sb_sections_put(w, &s->energies, sizeof s->energies); /* doubles only */
}

static void sb_energies_load(sb_solver* s, sb_cursor* r) { sb_cursor_take(r, &s->energies, sizeof s->energies); }

/* sb_step_stats field by field (no padding bytes in the file). */
static void sb_stats_save(const sb_solver* s, sb_sections_writer* w) {
    const sb_step_stats* t = &s->stats;
    int32_t iterations[2] = {t->newton_iterations, t->cg_iterations};
    uint32_t counts[5] = {t->substeps, t->rejected, t->contacts, t->self_contacts, t->self_dropped};
    double sizes[2] = {t->last_substep, t->min_substep};
    uint8_t converged = t->converged;
    sb_sections_put(w, iterations, sizeof iterations);
    sb_sections_put(w, counts, sizeof counts);
    sb_sections_put(w, sizes, sizeof sizes);
    sb_sections_put(w, &converged, 1);
}

static void sb_stats_load(sb_solver* s, sb_cursor* r) {
    int32_t iterations[2];
    uint32_t counts[5];
    double sizes[2];
    uint8_t converged;
    sb_cursor_take(r, iterations, sizeof iterations);
    sb_cursor_take(r, counts, sizeof counts);
    sb_cursor_take(r, sizes, sizeof sizes);
    sb_cursor_take(r, &converged, 1);
    s->stats = (sb_step_stats){.newton_iterations = iterations[0],
                               .cg_iterations = iterations[1],
                               .converged = converged != 0,
                               .substeps = counts[0],
                               .rejected = counts[1],
                               .contacts = counts[2],
                               .self_contacts = counts[3],
                               .self_dropped = counts[4],
                               .last_substep = sizes[0],
                               .min_substep = sizes[1]};
}

/* The step arrays, one after another (their count and lengths are this
 * solver's: the length check covers them). */
static void sb_arrays_save(const sb_solver* s, sb_sections_writer* w) {
    sb_real* arrays[SB_STEP_ARRAYS];
    size_t lengths[SB_STEP_ARRAYS];
    int count = sb_solver_step_arrays(s, arrays, lengths);
    for (int a = 0; a < count; a++) sb_sections_put(w, arrays[a], lengths[a] * sizeof(sb_real));
}

static void sb_arrays_load(sb_solver* s, sb_cursor* r) {
    sb_real* arrays[SB_STEP_ARRAYS];
    size_t lengths[SB_STEP_ARRAYS];
    int count = sb_solver_step_arrays(s, arrays, lengths);
    for (int a = 0; a < count; a++) sb_cursor_take(r, arrays[a], lengths[a] * sizeof(sb_real));
}

/* Every value of the step arrays finite, whatever the checksum says: a
 * state that is not finite is refused on load, naming the array and the
 * vertex, rather than failing the first step after it. */
static sb_status sb_arrays_check(const sb_solver* s, sb_cursor r, sb_error* err) {
    static const char* const names[SB_STEP_ARRAYS] = {"x",
                                                      "y",
                                                      "z",
                                                      "vx",
                                                      "vy",
                                                      "vz",
                                                      "fx",
                                                      "fy",
                                                      "fz",
                                                      "displacement x",
                                                      "displacement y",
                                                      "displacement z",
                                                      "position carry x",
                                                      "position carry y",
                                                      "position carry z",
                                                      "packed positions",
                                                      "packed velocities",
                                                      "packed displacements",
                                                      "packed forces",
                                                      "packed position carries"};
    sb_real* arrays[SB_STEP_ARRAYS];
    size_t lengths[SB_STEP_ARRAYS], total = 0;
    int count = sb_solver_step_arrays(s, arrays, lengths);
    for (int a = 0; a < count; a++) total += lengths[a] * sizeof(sb_real);
    if (r.left != total)
        return sb_error_set(err, SB_ERR_PARSE, "section ARRS (step arrays) has %zu bytes, this solver's %zu", r.left,
                            total);
    for (int a = 0; a < count; a++)
        for (size_t k = 0; k < lengths[a]; k++) {
            sb_real value;
            sb_cursor_take(&r, &value, sizeof value);
            if (!isfinite(value))
                return sb_error_set(err, SB_ERR_PARSE, "the step arrays' %s of vertex %zu is not finite", names[a],
                                    lengths[a] == s->state.vertex_count ? k : k / 4);
        }
    return SB_OK;
}

static size_t sb_external_bytes(const sb_solver* s) { return 3 * (size_t)s->state.vertex_count * sizeof(double); }
static void sb_external_save(const sb_solver* s, sb_sections_writer* w) {
    sb_sections_put(w, s->external, sb_external_bytes(s));
}
static void sb_external_load(sb_solver* s, sb_cursor* r) { sb_cursor_take(r, s->external, sb_external_bytes(s)); }

static void sb_colliders_save(const sb_solver* s, sb_sections_writer* w) {
    for (uint32_t c = 0; c < s->def.collider_count; c++) sb_collider_save(s->def.colliders[c], w);
}

static void sb_colliders_load(sb_solver* s, sb_cursor* r) {
    for (uint32_t c = 0; c < s->def.collider_count; c++) sb_collider_load(s->def.colliders[c], r);
}

static void sb_broken_save(const sb_solver* s, sb_sections_writer* w) { sb_breakage_save(s->breakage, w); }
static sb_status sb_broken_check(const sb_solver* s, sb_cursor r, sb_error* err) {
    return sb_breakage_check(s->breakage, r, err);
}

static void sb_topology_part_save(const sb_solver* s, sb_sections_writer* w) {
    sb_topology_save(sb_breakage_topology(s->breakage), w);
}
static void sb_topology_part_load(sb_solver* s, sb_cursor* r) {
    sb_topology* topology = sb_breakage_topology_to_load(s->breakage);
    sb_topology_load(s, topology, r);
    s->live_vertices = sb_topology_vertex_count(topology);
}

static void sb_cut_part_save(const sb_solver* s, sb_sections_writer* w) {
    sb_cut_mesh_save(sb_breakage_cut_mesh(s->breakage), w);
}
static void sb_cut_part_load(sb_solver* s, sb_cursor* r) {
    sb_cut_mesh* cut = sb_breakage_cut_mesh(s->breakage);
    sb_cut_mesh_load(s, cut, r);
    s->live_vertices = sb_cut_mesh_vertex_count(cut);
}

static void sb_cut_volume_part_save(const sb_solver* s, sb_sections_writer* w) {
    sb_cut_volume_save(sb_breakage_cut_volume(s->breakage), w);
}
static void sb_cut_volume_part_load(sb_solver* s, sb_cursor* r) {
    sb_cut_volume* cut = sb_breakage_cut_volume(s->breakage);
    sb_cut_volume_load(s, cut, r);
    s->live_vertices = sb_cut_volume_vertex_count(cut);
}

static bool sb_always(const sb_solver* s) {
    (void)s;
    return true;
}
static bool sb_has_external(const sb_solver* s) { return s->external != NULL; }
static bool sb_has_impulses(const sb_solver* s) { return s->contact != NULL; }
static bool sb_has_colliders(const sb_solver* s) { return s->def.collider_count > 0; }
static bool sb_has_handles(const sb_solver* s) { return s->def.handle_count > 0; }
static bool sb_has_breakage(const sb_solver* s) { return s->breakage != NULL; }
static bool sb_has_topology(const sb_solver* s) { return sb_breakage_topology(s->breakage) != NULL; }
static bool sb_has_cut_mesh(const sb_solver* s) { return sb_breakage_cut_mesh(s->breakage) != NULL; }
static bool sb_has_cut_volume(const sb_solver* s) { return sb_breakage_cut_volume(s->breakage) != NULL; }
static bool sb_has_vbd(const sb_solver* s) { return s->vbd != NULL; }
static bool sb_has_implicit_fast(const sb_solver* s) { return sb_implicit_fast_of(s) != NULL; }

/* One part of the state. A section is read back in table order, after all
 * were checked: the broken bonds first (they zero constants and queue
 * vertices for tearing), tearing's topology (its queue, the split vertices
 * and the elements re-pointed at them, their masses), the handles (they
 * pin their vertices and sum gravity again), and the arrays and energies
 * last, as saved. `check` is for a section whose length varies;
 * the others must be as long as this solver's own. */
typedef struct sb_state_part {
    char tag[4];
    const char* what;
    bool (*present)(const sb_solver* s);
    void (*save)(const sb_solver* s, sb_sections_writer* w);
    sb_status (*check)(const sb_solver* s, sb_cursor r, sb_error* err);
    void (*load)(sb_solver* s, sb_cursor* r);
} sb_state_part;

static const sb_state_part sb_parts[] = {
    {{'B', 'R', 'K', 'N'}, "broken bonds", sb_has_breakage, sb_broken_save, sb_broken_check, sb_breakage_load},
    {{'T', 'O', 'P', 'O'}, "tearing's topology", sb_has_topology, sb_topology_part_save, NULL, sb_topology_part_load},
    {{'C', 'U', 'T', 'M'}, "the cut mesh", sb_has_cut_mesh, sb_cut_part_save, NULL, sb_cut_part_load},
    {{'C', 'U', 'T', 'V'}, "the cut volume", sb_has_cut_volume, sb_cut_volume_part_save, NULL, sb_cut_volume_part_load},
    {{'H', 'N', 'D', 'L'}, "handles", sb_has_handles, sb_handles_save, NULL, sb_handles_load},
    {{'C', 'O', 'L', 'L'}, "colliders", sb_has_colliders, sb_colliders_save, NULL, sb_colliders_load},
    {{'I', 'M', 'P', 'S'}, "contact impulses", sb_has_impulses, sb_contact_save, NULL, sb_contact_load},
    {{'B', 'O', 'D', 'Y'},
     "contact episodes",
     sb_contact_has_bodies,
     sb_contact_bodies_save,
     NULL,
     sb_contact_bodies_load},
    {{'E', 'X', 'T', 'F'}, "external forces", sb_has_external, sb_external_save, NULL, sb_external_load},
    {{'V', 'B', 'D', 'V'}, "vbd's last velocities", sb_has_vbd, sb_vbd_save, NULL, sb_vbd_load},
    {{'I', 'M', 'P', 'G'}, "implicit guess", sb_has_implicit_fast, sb_implicit_fast_save, NULL, sb_implicit_fast_load},
    {{'A', 'R', 'R', 'S'}, "step arrays", sb_always, sb_arrays_save, sb_arrays_check, sb_arrays_load},
    {{'C', 'L', 'C', 'K'}, "clock", sb_always, sb_clock_save, sb_clock_check, sb_clock_load},
    {{'S', 'T', 'A', 'T'}, "step statistics", sb_always, sb_stats_save, NULL, sb_stats_load},
    {{'E', 'N', 'R', 'G'}, "energies", sb_always, sb_energies_save, NULL, sb_energies_load},
};
enum { SB_PART_COUNT = sizeof sb_parts / sizeof sb_parts[0] };

/* What a saved state must belong to: the model, and the choices of the
 * definition that decide which arrays and sections the state has. */
static uint64_t sb_state_hash(const sb_solver* s) {
    const sb_model* m = s->given_model;
    size_t n = m->vertex_count, nb = m->bond_count, nt = m->triangle_count, nh = m->hinge_count;
    struct {
        const void* data;
        size_t bytes;
    } parts[] = {{&m->vertex_count, 4},
                 {&m->bond_count, 4},
                 {&m->triangle_count, 4},
                 {&m->hinge_count, 4},
                 {m->rest_x, 8 * n},
                 {m->rest_y, 8 * n},
                 {m->rest_z, 8 * n},
                 {m->vel_x, 8 * n},
                 {m->vel_y, 8 * n},
                 {m->vel_z, 8 * n},
                 {m->mass, 8 * n},
                 {m->fixed, n},
                 {m->bond_i, 4 * nb},
                 {m->bond_j, 4 * nb},
                 {m->bond_r0, 8 * nb},
                 {m->bond_k, 8 * nb},
                 {m->spring_k, 8 * nb},
                 {m->spring_damping, 8 * nb},
                 {m->bond_break_min, 8 * nb},
                 {m->bond_break_max, 8 * nb},
                 {m->tri_v[0], 4 * nt},
                 {m->tri_v[1], 4 * nt},
                 {m->tri_v[2], 4 * nt},
                 {m->tri_cos0[0], 8 * nt},
                 {m->tri_cos0[1], 8 * nt},
                 {m->tri_cos0[2], 8 * nt},
                 {m->angle_k, 8 * nt},
                 {m->stretch_bend_k, 8 * nt},
                 {m->hinge_e0, 4 * nh},
                 {m->hinge_e1, 4 * nh},
                 {m->hinge_o0, 4 * nh},
                 {m->hinge_o1, 4 * nh},
                 {m->hinge_phi0, 8 * nh},
                 {m->hinge_k, 8 * nh}};
    uint64_t h = SB_HASH_START;
    for (size_t p = 0; p < sizeof parts / sizeof *parts; p++) h = sb_hash(h, parts[p].data, parts[p].bytes);
    if (m->tet_count) { /* only then, so that the hashes of models without them stay as they were */
        size_t nq = m->tet_count;
        h = sb_hash(h, &m->tet_count, 4);
        for (int c = 0; c < 4; c++) h = sb_hash(h, m->tet_v[c], 4 * nq);
        for (int c = 0; c < 9; c++) h = sb_hash(h, m->tet_dm_inv[c], 8 * nq);
        h = sb_hash(h, m->tet_volume, 8 * nq);
        h = sb_hash(h, m->tet_mu, 8 * nq);
        h = sb_hash(h, m->tet_lambda, 8 * nq);
        bool quadratic = false; /* the middles only then, as above */
        for (size_t t = 0; t < nq; t++) quadratic |= m->tet_nodes[t] == SB_TET_NODES;
        for (int c = 4; quadratic && c < SB_TET_NODES; c++) h = sb_hash(h, m->tet_v[c], 4 * nq);
        if (m->tet_damped) h = sb_hash(h, m->tet_beta, 8 * nq); /* undamped models' hashes as they were */
    }
    if (m->membrane_count) { /* likewise */
        size_t nm = m->membrane_count;
        h = sb_hash(h, &m->membrane_count, 4);
        for (int c = 0; c < 3; c++) h = sb_hash(h, m->membrane_v[c], 4 * nm);
        for (int c = 0; c < 4; c++) h = sb_hash(h, m->membrane_dm_inv[c], 8 * nm);
        h = sb_hash(h, m->membrane_volume, 8 * nm);
        h = sb_hash(h, m->membrane_mu, 8 * nm);
        h = sb_hash(h, m->membrane_lambda, 8 * nm);
        if (m->membrane_damped) h = sb_hash(h, m->membrane_beta, 8 * nm); /* as the tetrahedra's */
    }
    if (m->plate_count) { /* a flat sheet's bending; models without it hash as they did */
        size_t np = m->plate_count;
        h = sb_hash(h, m->plate_nodes, np);
        h = sb_hash(h, m->plate_v, 4 * SB_PLATE_NODES * np);
        h = sb_hash(h, m->plate_c, 8 * 3 * SB_PLATE_NODES * np);
        h = sb_hash(h, m->plate_a, 8 * np);
        h = sb_hash(h, m->plate_b, 8 * np);
    }
    const sb_solver_def* d = &s->def;
    int32_t choices[6] = {
        d->integrator,           d->kernels, d->adaptive, d->self_collision, (int32_t)d->collider_count,
        (int32_t)d->handle_count};
    h = sb_hash(h, choices, sizeof choices);
    for (uint32_t c = 0; c < d->collider_count; c++) h = sb_hash(h, &d->colliders[c]->dynamic, sizeof(bool));
    for (uint32_t k = 0; k < d->handle_count; k++) {
        uint32_t count = sb_handle_vertex_count(d->handles[k]);
        h = sb_hash(h, &count, sizeof count);
    }
    return h;
}

static sb_sections_header sb_state_header(const sb_solver* s) {
    sb_sections_header header = {.version = SB_STATE_VERSION,
                                 .real_size = sizeof(sb_real),
                                 .vertex_count = s->state.vertex_count,
                                 .hash = sb_state_hash(s)};
    memcpy(header.magic, SB_STATE_MAGIC, 8);
    return header;
}

/* The whole state into w (counting only when w has no buffer). */
static bool sb_state_write(const sb_solver* s, sb_sections_writer* w, void* buffer, size_t capacity) {
    sb_sections_header header = sb_state_header(s);
    sb_sections_begin(w, buffer, capacity, &header);
    for (int p = 0; p < SB_PART_COUNT; p++) {
        if (!sb_parts[p].present(s)) continue;
        sb_sections_open(w, sb_parts[p].tag);
        sb_parts[p].save(s, w);
        sb_sections_close(w);
    }
    return sb_sections_end(w);
}

size_t sb_solver_state_size(const sb_solver* s) {
    sb_sections_writer w;
    sb_state_write(s, &w, NULL, 0);
    return w.size;
}

sb_status sb_solver_save_state(const sb_solver* s, void* buffer, size_t size, sb_error* err) {
    sb_solver_settle((sb_solver*)s); /* the forces and energies it writes: a pbd step may have left them for later */
    sb_sections_writer w;
    if (!buffer || !sb_state_write(s, &w, buffer, size))
        return sb_error_set(err, SB_ERR_INVALID, "solver state: a buffer of %zu bytes is too small (it takes %zu)",
                            size, sb_solver_state_size(s));
    return SB_OK;
}

/* The length this solver's own part p has. */
static size_t sb_part_length(const sb_solver* s, int p) {
    sb_sections_writer w;
    sb_sections_begin(&w, NULL, 0, &(sb_sections_header){0});
    size_t start = w.size;
    sb_parts[p].save(s, &w);
    return w.size - start;
}

static sb_status sb_check_header(const sb_solver* s, const sb_sections_header* h, sb_error* err) {
    if (h->real_size != sizeof(sb_real))
        return sb_error_set(err, SB_ERR_INVALID, "solver state: written by a %s build, this one is %s",
                            h->real_size == 8 ? "double" : "float", sizeof(sb_real) == 8 ? "double" : "float");
    if (h->vertex_count != s->state.vertex_count)
        return sb_error_set(err, SB_ERR_INVALID, "solver state: %u vertices, this solver's model has %u",
                            h->vertex_count, s->state.vertex_count);
    if (h->hash != sb_state_hash(s))
        return sb_error_set(err, SB_ERR_INVALID,
                            "solver state: saved from another model or solver set-up (hash %016llx, this one "
                            "%016llx)",
                            (unsigned long long)h->hash, (unsigned long long)sb_state_hash(s));
    return SB_OK;
}

/* Every part this solver has is there, of the right length. */
static sb_status sb_check_parts(const sb_solver* s, const sb_sections_reader* r, sb_cursor found[SB_PART_COUNT],
                                sb_error* err) {
    for (int p = 0; p < SB_PART_COUNT; p++) {
        const sb_state_part* part = &sb_parts[p];
        if (!part->present(s)) continue;
        if (!sb_sections_find(r, part->tag, &found[p]))
            return sb_error_set(err, SB_ERR_PARSE, "solver state: no section %.4s (%s)", part->tag, part->what);
        if (part->check) {
            sb_status status = part->check(s, found[p], err);
            if (status != SB_OK) return sb_error_prefix(err, status, "solver state");
        } else if (found[p].left != sb_part_length(s, p))
            return sb_error_set(err, SB_ERR_PARSE, "solver state: section %.4s (%s) has %zu bytes, this solver's %zu",
                                part->tag, part->what, found[p].left, sb_part_length(s, p));
    }
    return SB_OK;
}

sb_status sb_solver_load_state(sb_solver* s, const void* buffer, size_t size, sb_error* err) {
    sb_sections_reader r;
    sb_cursor found[SB_PART_COUNT];
    sb_status status = sb_sections_read(&r, buffer, size, SB_STATE_MAGIC, SB_STATE_VERSION, "solver state", err);
    if (status == SB_OK) status = sb_check_header(s, &r.header, err);
    if (status == SB_OK) status = sb_check_parts(s, &r, found, err);
    if (status != SB_OK) return status;
    for (int p = 0; p < SB_PART_COUNT; p++)
        if (sb_parts[p].present(s)) sb_parts[p].load(s, &found[p]);
    s->forces_stale = false; /* saved settled */
    return sb_breakage_loaded(s, err);
}
