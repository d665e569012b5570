/* Private: restitution a body obeys (kernels/contact/body_restitution.c).
 * The contact pass (kernels/contact/contact.c) owns it: the vertex answers
 * report their contacts to it, and after the pass it limits each body's
 * outward velocity to e times the speed it came in with. */
#ifndef SB_BODY_RESTITUTION_H
#define SB_BODY_RESTITUTION_H

#include "kernels/state/solver_data.h"
#include "common/sections.h"

typedef struct sb_body_restitution sb_body_restitution;

/* The bodies of the solver's model (its connected parts) and their state
 * into *out; NULL where nothing is to be done (a model that can tear: its
 * parts change as it runs; pbd and xpbd: their sweeps project the
 * contacts). */
sb_status sb_body_restitution_create(const sb_solver* solver, sb_body_restitution** out, sb_error* err);
void sb_body_restitution_destroy(sb_body_restitution* bodies);
/* A step (or an adaptive sub-step) starts: the contacts reported from now
 * on are its own. */
void sb_body_restitution_begin(sb_body_restitution* bodies);
/* Whether a vertex of the chunk belongs to a body: the touches of the
 * others are ignored (a lone vertex, a body with a fixed vertex), so a pass
 * need not report them. */
bool sb_body_restitution_follows(const sb_body_restitution* bodies, uint32_t chunk);
/* Vertex i was answered by contact c of collider `collider`, taking the
 * impulse m Δv at c's point; called by the pass that owns i's chunk (a
 * vertex answered twice in a step keeps its first contact and the sum of
 * its impulses). */
void sb_body_restitution_touch(sb_body_restitution* bodies, uint32_t i, int collider, const sb_contact* c,
                               const double impulse[3]);
/* After the step's contact pass: each body in contact keeps at most e
 * times its approach speed outward; the velocity taken off is a uniform
 * Δv of the body (on the packed state of the fused step when `packed`, on
 * the state's arrays otherwise), and its impulse and torque go into
 * `step` (6 per collider: impulses, then torques, as the contact pass's).
 * Returns whether a body's velocity changed. */
bool sb_body_restitution_apply(sb_solver* solver, sb_body_restitution* bodies, bool packed, double dt, double* step);
/* The step is kept: its contact episodes become the state. */
void sb_body_restitution_accept(sb_body_restitution* bodies);
/* The episodes in a saved state (a fixed length for the solver). */
void sb_body_restitution_save(const sb_body_restitution* bodies, sb_sections_writer* w);
void sb_body_restitution_load(sb_body_restitution* bodies, sb_cursor* r);

#endif
