/* Private: tearing's topology, the surface splitting where bonds broke
 * (kernels/interaction/topology.c). */
#ifndef SB_TOPOLOGY_H
#define SB_TOPOLOGY_H

#include "mesh/model_internal.h"
#include "common/sections.h"

struct sb_solver;
typedef struct sb_topology sb_topology;

/* For the working copy `live` (kernels/interaction/breakage.c), whose vertex arrays
 * hold model_vertices vertices and then dormant spare slots (fixed, mass
 * 0) up to live->vertex_count, and whose element index arrays are its own.
 * The flags are breakage's, read as they change: per bond, triangle and
 * hinge. NULL and *ok false when out of memory. */
sb_topology* sb_topology_create(sb_model* live, uint32_t model_vertices, uint32_t per_step, const uint8_t* broken,
                                const uint8_t* triangle_dead, const uint8_t* hinge_dead, bool* ok);
void sb_topology_destroy(sb_topology* topology);

/* A vertex whose triangles may have come apart (on a dead triangle or a
 * broken bond): it waits, once, in a first-in first-out queue. */
void sb_topology_queue(sb_topology* topology, uint32_t vertex);
/* Whether a queued vertex has come apart (two fans or more with a live
 * triangle), so that sb_topology_split will split it: a look at the
 * queued vertices' stars only. */
bool sb_topology_splits(sb_topology* topology);

/* Splits the queued vertices in queue order, at most the per-step cap of
 * new vertices (a vertex that would pass it waits for the next call): the
 * working copy, the fast model's slots, the solver's state and inverse
 * masses, and `before` (3 per vertex: the forces before breaking, which the
 * Verlet re-kick subtracts) shared between the copies by mass. Returns the
 * vertices made. */
uint32_t sb_topology_split(struct sb_solver* solver, sb_topology* topology, double* before);

/* The vertices in use: the model's, then the copies made so far. */
uint32_t sb_topology_vertex_count(const sb_topology* topology);
/* The model vertex `vertex` is a copy of (itself for a model vertex). */
uint32_t sb_topology_origin(const sb_topology* topology, uint32_t vertex);
/* Splits not made because no spare vertex was left. */
uint32_t sb_topology_refused(const sb_topology* topology);

/* The topology's state for the saved state (kernels/solver/solver_state.c): its
 * counts, queue, origins and stars, and the working copy's vertex arrays
 * and element indices; read back from as many bytes as sb_topology_save
 * writes (the caller checked the length), after the broken bonds were
 * broken again: every vertex's mass set again where the solver keeps it
 * (unpinned: the handles pin theirs after) and every element's fast slot
 * pointed at its vertices. */
void sb_topology_save(const sb_topology* topology, sb_sections_writer* w);
void sb_topology_load(struct sb_solver* solver, sb_topology* topology, sb_cursor* r);

#endif
