/* Private: the colliders' contact pass (kernels/contact/contact.c). It
 * takes part in a step as the feature "contact" (start, begin, correct,
 * collect, accept) and through the drift_chunk hook of the fused step. */
#ifndef SB_CONTACT_H
#define SB_CONTACT_H

#include "kernels/state/solver_data.h"
#include "common/sections.h"

/* Checks the colliders, allocates the pass and subscribes it to the step;
 * nothing without colliders. */
sb_status sb_contact_prepare(sb_solver* solver, sb_error* err);
void sb_contact_destroy(sb_solver* solver);
/* Tearing's dead triangles (1 for a triangle on a broken bond's edge,
 * which spans the crack) are out of face contact: they would hold the
 * crack shut against a collider. NULL: none. */
void sb_contact_set_dead_triangles(sb_solver* solver, const uint8_t* dead);
/* Answers vertex i's move from → x among the colliders of `near` (a bit
 * each, those whose bounds the move reaches; x and v updated in place);
 * returns the collider or -1, the impulse m Δv the vertex took and the
 * point of the collider's surface it met (sb_contact.point). */
int sb_contact_vertex(const sb_solver* solver, uint32_t i, uint64_t near, const double from[3], double x[3],
                      double v[3], double impulse[3], double point[3]);
/* The earliest contact of vertex i's move from → to in the step being
 * taken among the colliders whose bounds the move reaches: the collider and
 * *c, or -1. */
int sb_contact_find(const sb_solver* solver, uint32_t i, const double from[3], const double to[3], sb_contact* c);
/* Vertex i's answer to contact c with `collider` (impulse m Δv), told to
 * restitution per body (kernels/contact/body_restitution.c) where it runs;
 * for a pass that answers vertices itself (pbd's and xpbd's sweeps). */
void sb_contact_touch(const sb_solver* solver, uint32_t i, int collider, const sb_contact* c, const double impulse[3]);
/* The velocity answer of contact c for a vertex of velocity v (in place):
 * restitution and Coulomb friction relative to the collider's velocity
 * (the design note of kernels/contact/contact.c). */
void sb_contact_velocity(const sb_contact* c, double v[3]);
/* Where vertex's move from → to of the step ends after contact c
 * (velocity v already answered, x out): along the normal, at the contact
 * point (pushed out by the depth) and then the rest of the step at the
 * answered normal velocity; along the surface, the whole step at the
 * answered tangential velocity, so that a vertex that sticks does not
 * creep and one that slides moves as its velocity says. */
void sb_contact_position(const sb_contact* c, double dt, const double from[3], const double to[3], const double v[3],
                         double x[3]);
/* Whether the box [lo, hi] grown by the contact thickness reaches into
 * collider c's step bounds. */
bool sb_contact_reaches(const sb_solver* solver, uint32_t c, const double lo[3], const double hi[3]);
/* Zeroes a chunk's partial sums; a pass over the chunk then records each
 * answered vertex's impulse m Δv (the collider receives the opposite). */
void sb_contact_chunk_begin(const sb_solver* solver, uint32_t chunk);
void sb_contact_record(const sb_solver* solver, uint32_t chunk, int collider, const double impulse[3]);
/* Adds the torque about a dynamic collider's center of the impulse it
 * receives at the contact point (the opposite of the vertex's) to the
 * chunk's partial sums (nothing for a collider that is not dynamic). */
void sb_contact_record_torque(const sb_solver* solver, uint32_t chunk, int collider, const double point[3],
                              const double impulse[3]);
/* Adds the chunks' partial sums in order into the step's impulses; returns
 * the contacts. */
uint32_t sb_contact_collect(sb_solver* solver);
/* The work the dynamic colliders would lose if the step of dt just taken
 * were kept (adaptive stepping's energy balance); 0 without colliders. */
double sb_contact_step_work(const sb_solver* solver, double dt);
/* Its part of a saved state: the last step's impulses and the advance's. */
void sb_contact_save(const sb_solver* solver, sb_sections_writer* w);
void sb_contact_load(sb_solver* solver, sb_cursor* r);
/* Whether the pass answers restitution per body (kernels/contact/body_restitution.c),
 * and that part of a saved state: the bodies' open contact episodes. */
bool sb_contact_has_bodies(const sb_solver* solver);
void sb_contact_bodies_save(const sb_solver* solver, sb_sections_writer* w);
void sb_contact_bodies_load(sb_solver* solver, sb_cursor* r);

#endif
