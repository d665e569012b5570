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
/* After tearing changed the surface (kernels/interaction/topology.c: elements
 * re-pointed to split vertices; triangles dead, per triangle_dead, which
 * tearing keeps): the unique edges and their owners, and the hierarchy's
 * corners and connected patches, again from the model's triangles. O(the
 * triangles); nothing without self-contact. */
sb_status sb_self_contact_retopologize(sb_solver* solver, const uint8_t* triangle_dead, sb_error* err);

/* The pass takes part in a step as the feature "self-contact" (begin,
 * correct, collect) and through the fused step's before_drift hook (the
 * packed positions before the drift) and after_drift hook (on every worker,
 * after the drift and the colliders' contact: corrects the packed
 * positions, velocities, displacements and forces of the vertices it
 * touches, then returns with all workers past a barrier). */

#endif
