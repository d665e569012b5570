/* Private: the solver's side of breakage (kernels/breakage.c). */
#ifndef SB_BREAKAGE_H
#define SB_BREAKAGE_H

#include "softbond/solver.h"
#include "mesh/model_internal.h"

typedef struct sb_breakage sb_breakage;

/* At solver creation, before the fast model: for a breakable model, the
 * solver's working copy of it (its per-element constants the solver's own,
 * zeroed as bonds break) and the lists breaking needs; NULL otherwise
 * (*ok false when out of memory). */
sb_breakage* sb_breakage_create(const sb_model* model, bool* ok);
void sb_breakage_destroy(sb_breakage* breakage);
/* The model every kernel of the solver reads: the working copy. */
const sb_model* sb_breakage_model(const sb_breakage* breakage);

/* After an accepted (sub-)step: breaks the bonds whose length is past a
 * limit (in bond order, the callback for each), and when any broke,
 * evaluates the forces and energies again. */
sb_status sb_breakage_after_step(sb_solver* solver);

uint32_t sb_breakage_count(const sb_breakage* breakage);
bool sb_breakage_broken(const sb_breakage* breakage, uint32_t bond);

#endif
