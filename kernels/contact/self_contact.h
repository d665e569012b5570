/* Private: contact of the model's triangles with each other
 * (kernels/contact/self_contact.c). */
#ifndef SB_SELF_CONTACT_H
#define SB_SELF_CONTACT_H

#include "kernels/runtime/team.h"
#include "softbond/types.h"

typedef struct sb_solver sb_solver;
typedef struct sb_self_contact sb_self_contact;

/* Made in sb_solver_create when def.self_collision is set. */
sb_status sb_self_contact_prepare(sb_solver* solver, sb_error* err);
void sb_self_contact_destroy(sb_self_contact* self);

/* The fused step: keeps packed positions [begin, end) (reals, 4 a vertex)
 * as the start of the step's moves, before its drift moves them. */
void sb_self_contact_save_packed(sb_solver* solver, size_t begin, size_t end);
/* The fused step, after the drift and the collider pass, called by every
 * worker of the job: corrects the packed positions, velocities and
 * displacements (d = v dt) of the vertices it touches, and their forces
 * (gravity and drag at the new velocity), then returns with all workers
 * past a barrier. */
void sb_self_contact_packed(const sb_worker* worker, sb_solver* solver, double dt);

/* Every other step: keeps the state's positions before the step ... */
void sb_self_contact_save_state(sb_solver* solver);
/* ... and corrects the state's arrays after it (and after the collider
 * pass); returns the pairs corrected. */
uint32_t sb_self_contact_state_pass(sb_solver* solver, double dt);

/* Pairs corrected in the last step, and candidates dropped because the
 * buffers were full (for the stats). */
uint32_t sb_self_contact_count(const sb_self_contact* self);
uint32_t sb_self_contact_dropped(const sb_self_contact* self);

#endif
