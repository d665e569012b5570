/* Private: contact as constraints inside the pbd and xpbd sweeps
 * (kernels/contact/contact_pbd.c), used by kernels/integrators/pbd.c. */
#ifndef SB_CONTACT_PBD_H
#define SB_CONTACT_PBD_H

#include "kernels/state/solver_data.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"

typedef struct sb_pbd_contacts sb_pbd_contacts;

/* The per-chunk contact slots of a solver with colliders (NULL and no error
 * without colliders); false when out of memory. */
bool sb_pbd_contacts_create(const sb_solver* solver, sb_pbd_contacts** out);
void sb_pbd_contacts_destroy(sb_pbd_contacts* contacts);

/* Called by every worker of the sweeps job. find: each free vertex's move
 * from x0 to x (3n interleaved) offered to the colliders, its contact kept:
 * before the first sweep, on the predicted x (then a barrier); `again`,
 * before the last sweep's projection, for the vertices without a contact,
 * on where the sweeps have put them (each worker its own chunks, as
 * project). project: each contact's constraint in x (at the end of every
 * sweep, then a barrier). */
void sb_pbd_contacts_find(const sb_solver* solver, sb_pbd_contacts* contacts, const sb_worker* worker, const double* x0,
                          const double* x, bool again);
void sb_pbd_contacts_project(sb_pbd_contacts* contacts, const sb_worker* worker, double* x);

/* After the sweeps and once the state holds x and v = (x − x0)/dt: each
 * contact's velocity answer and tangential position into the state, the
 * impulses into the chunks' partial sums (kernels/contact/contact.c), then summed
 * into the step's; returns the contacts. */
uint32_t sb_pbd_contacts_answer(sb_solver* solver, sb_pbd_contacts* contacts, const double* x0, const double* x,
                                double dt);

#endif
