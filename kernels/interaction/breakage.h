/* Private: the solver's side of breakage (kernels/interaction/breakage.c). */
#ifndef SB_BREAKAGE_H
#define SB_BREAKAGE_H

#include "softbond/solver.h"
#include "mesh/model_internal.h"
#include "common/sections.h"
#include "kernels/interaction/topology.h"

/* New vertices a step may make by default (sb_solver_def.max_splits_per_step). */
#define SB_DEFAULT_SPLITS_PER_STEP 256

typedef struct sb_breakage sb_breakage;

/* At solver creation, before the fast model: for a breakable model or one
 * with blades, the solver's working copy of it (its per-element constants
 * the solver's own, zeroed as bonds break) and the lists breaking needs,
 * in *out; NULL otherwise. Errors: a bad blade, out of memory. */
sb_status sb_breakage_create(const sb_model* model, const sb_solver_def* def, sb_breakage** out, sb_error* err);
void sb_breakage_destroy(sb_breakage* breakage);
/* The model every kernel of the solver reads: the working copy. */
const sb_model* sb_breakage_model(const sb_breakage* breakage);

/* Subscribes breakage to the step as the feature "breakage", whose accept
 * stage, after each kept (sub-)step, breaks the bonds past a limit and
 * those a blade crossed and splits where the surface came apart (nothing
 * for a solver without breakage). The solver's live_vertices follow the
 * splits. */
void sb_breakage_subscribe(sb_solver* solver);

/* The broken bonds, for the saved state (kernels/solver/solver_state.c): written;
 * checked (each a limited bond of the model, in increasing order, into a
 * solver with none broken yet); broken again, without the callback. */
void sb_breakage_save(const sb_breakage* breakage, sb_sections_writer* w);
sb_status sb_breakage_check(const sb_breakage* breakage, sb_cursor r, sb_error* err);
void sb_breakage_load(sb_solver* solver, sb_cursor* r);

uint32_t sb_breakage_count(const sb_breakage* breakage);
bool sb_breakage_broken(const sb_breakage* breakage, uint32_t bond);
/* Tearing's topology, NULL when the solver does not tear (the second for
 * loading a saved state). */
const sb_topology* sb_breakage_topology(const sb_breakage* breakage);
sb_topology* sb_breakage_topology_to_load(sb_breakage* breakage);
/* Cutting through triangles' mesh, NULL without (sb_solver_def.cut_through). */
struct sb_cut_mesh* sb_breakage_cut_mesh(const sb_breakage* breakage);
/* Cutting through tetrahedra's mesh, NULL without (sb_solver_def.cut_through on a model of tetrahedra). */
struct sb_cut_volume* sb_breakage_cut_volume(const sb_breakage* breakage);
/* Whether a triangle lost its constants to a broken bond on its edge. */
bool sb_breakage_triangle_dead(const sb_breakage* breakage, uint32_t triangle);
/* Self-contact after the surface changed (bonds broken, vertices split: an
 * accept stage's, a loaded state's): its features and hierarchy from the
 * working copy again, the dead triangles out of it. */
sb_status sb_breakage_update_contact(sb_solver* solver, sb_error* err);
/* After a state was loaded: the fast model built again from the working
 * copy when a cut changed its elements (sb_fast_rebuild), then self-contact
 * as sb_breakage_update_contact. */
sb_status sb_breakage_loaded(sb_solver* solver, sb_error* err);

#endif
