/** @file
 * The state buffer: how other threads see a running simulation. One writer
 * (the thread that advances the solver) publishes snapshots; any number of
 * readers (a haptic servo loop, a viewer, a logger) take the latest one
 * without locks. The writer never waits for a reader, a reader never sees
 * half of one step and half of another, and a reader waits for the writer
 * only by retrying an acquire that the writer overtook (twice at most in
 * practice; DESIGN.md, section Threads, says why this design). */
#ifndef SOFTBOND_STATE_BUFFER_H
#define SOFTBOND_STATE_BUFFER_H

#include "softbond/export.h"
#include "softbond/reference.h"
#include "softbond/solver.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One published state. Arrays are 3n interleaved (x y z per vertex). */
typedef struct sb_snapshot {
    uint64_t sequence;     /**< 1 for the first snapshot published, then 2, 3, ... */
    uint64_t step;         /**< the solver's step count (sb_solver_step_count) */
    double time;           /**< s, simulated */
    sb_energies energies;  /**< J: the state's energies (sb_solver_energies) */
    uint32_t vertex_count; /**< the vertices it holds: a tearing solver's grow (sb_solver_vertex_count) */
    sb_real* positions;    /**< m */
    sb_real* velocities;   /**< m/s */
} sb_snapshot;

/** The snapshots' slots and who holds them; opaque. */
typedef struct sb_state_buffer sb_state_buffer;

/** A buffer for snapshots of vertex_count vertices that up to max_readers
 * threads may hold at once (each holding one snapshot at a time); it keeps
 * max_readers + 2 slots. Allocates everything here. For a solver, give
 * sb_solver_vertex_capacity(solver): the model's vertex count, plus the
 * spare vertices of a solver that tears (softbond/solver.h); a snapshot's
 * vertex_count says how many of them it holds. */
SB_API sb_state_buffer* sb_state_buffer_create(uint32_t vertex_count, int max_readers, sb_error* err);
/** Frees the buffer and its snapshots; safe on NULL. No thread may hold
 * or write a snapshot any more. */
SB_API void sb_state_buffer_destroy(sb_state_buffer* buffer);

/** Writer: copies the solver's current state (positions, velocities, step,
 * time, energies) into a free slot, in parallel on the solver's threads,
 * and makes it the latest. Never blocks and never allocates. SB_ERR_BUSY
 * when every slot is held (more readers than max_readers); SB_ERR_INVALID
 * when the buffer's vertex count is not the solver's capacity. */
SB_API sb_status sb_solver_publish(const sb_solver* solver, sb_state_buffer* buffer);

/** Writer: sb_solver_advance, then the new state published as by
 * sb_solver_publish, but cheaper: where the fused Verlet step runs (the
 * fast kernels, verlet or velocity_verlet, not adaptive) its last pass
 * writes the snapshot while each chunk of vertices is still in cache, with
 * no extra pass over memory and no extra wake-up of the solver's threads;
 * other integrators copy after the advance. Returns the advance's status
 * (nothing is published when it fails); when every slot is held the advance
 * still runs, nothing is published and sb_state_buffer_skipped counts it.
 * SB_ERR_INVALID, before advancing, when the buffer's vertex count is not the
 * solver's capacity. */
SB_API sb_status sb_solver_advance_published(sb_solver* solver, double dt, sb_state_buffer* buffer);

/** Publications skipped because every slot was held. Any thread. */
SB_API uint64_t sb_state_buffer_skipped(const sb_state_buffer* buffer);

/** Writer, for other producers (a replay, a test): a free slot to fill, or
 * NULL when every slot is held; then commit it to make it the latest. */
SB_API sb_snapshot* sb_state_buffer_begin(sb_state_buffer* buffer);
/** Writer: makes the snapshot from sb_state_buffer_begin, filled, the
 * latest and sets its sequence. */
SB_API void sb_state_buffer_commit(sb_state_buffer* buffer, sb_snapshot* snapshot);

/** Reader: the latest snapshot, held until released (the writer does not
 * touch it meanwhile), or NULL before the first publication. */
SB_API const sb_snapshot* sb_state_buffer_acquire(sb_state_buffer* buffer);
/** Reader: lets go of a snapshot from sb_state_buffer_acquire (once each;
 * it must not be read afterwards). Nothing for NULL. */
SB_API void sb_state_buffer_release(sb_state_buffer* buffer, const sb_snapshot* snapshot);

/** How many snapshots have been committed. Any thread. */
SB_API uint64_t sb_state_buffer_published(const sb_state_buffer* buffer);

#ifdef __cplusplus
}
#endif
#endif
