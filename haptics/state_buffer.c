/* The state buffer (softbond/state_buffer.h).
 *
 * Design. max_readers + 2 slots, each a snapshot with its arrays, and one
 * atomic word per slot that counts the readers holding it, with a high bit
 * set while the writer fills it; `latest` names the newest slot.
 *
 *   writer: take a slot other than latest whose word is 0, by compare-and-
 *           swap 0 -> WRITING (so no reader holds it, and none can take it
 *           unnoticed); fill it; clear WRITING (release); latest = slot.
 *   reader: i = latest; add 1 to slot i's word; if WRITING was set, or
 *           latest is no longer i, the writer overtook the reader between
 *           the two: take the 1 back and retry. Otherwise the slot is the
 *           reader's until it takes the 1 back. The second check keeps a
 *           reader's snapshots in order: without it, a reader that read
 *           latest long ago could take a slot the writer had just filled
 *           again and cleared but not yet named latest, and its next read
 *           (of the latest still named) would go back a step (the stress
 *           test saw this under the thread sanitizer).
 *
 * Why this and not a sequence lock or plain triple buffering: a sequence
 * lock copies the data out and retries when the writer was there meanwhile,
 * so a reader of a 100k-vertex snapshot (2.4 MB) would copy it to check it,
 * and would read memory the writer writes (a data race in C11, which the
 * thread sanitizer rightly reports). Triple buffering serves one reader. Here
 * readers read in place, the writer never touches a held slot, and every
 * hand-over is an atomic read-modify-write, so the sanitizer sees the order.
 * With max_readers + 2 slots the writer always finds a free one while at
 * most max_readers readers hold one each: one is latest, max_readers are
 * held, one is left. A reader retries only when the writer published twice
 * during its few instructions between reading latest and taking the slot. */
#include "softbond/state_buffer.h"
#include "common/error.h"
#include "kernels/state/solver_data.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"
#include "kernels/solver/advance.h"

#include <stdatomic.h>
#include <stdlib.h>

#define SB_WRITING 0x80000000u
/* A reader gives up (NULL) after this many overtaken tries: only a writer
 * that publishes faster than a reader can run ten instructions gets there. */
#define SB_ACQUIRE_TRIES 1000

typedef struct sb_slot {
    sb_snapshot snapshot;
    atomic_uint holders; /* readers holding it, | SB_WRITING while written */
} sb_slot;

struct sb_state_buffer {
    int slot_count;
    uint32_t vertex_count;
    sb_slot* slots;
    sb_real* arrays;   /* every slot's positions and velocities */
    atomic_int latest; /* -1 before the first commit */
    atomic_ullong published, skipped;
};

sb_state_buffer* sb_state_buffer_create(uint32_t vertex_count, int max_readers, sb_error* err) {
    if (max_readers < 1 || max_readers > 64) {
        sb_error_set(err, SB_ERR_INVALID, "state buffer: max_readers must be from 1 to 64 (got %d)", max_readers);
        return NULL;
    }
    sb_state_buffer* b = calloc(1, sizeof *b);
    int slots = max_readers + 2;
    size_t per_array = 3 * (size_t)vertex_count;
    if (b) {
        b->slots = calloc((size_t)slots, sizeof *b->slots);
        b->arrays = calloc(2 * per_array * (size_t)slots + 1, sizeof *b->arrays);
    }
    if (!b || !b->slots || !b->arrays) {
        sb_state_buffer_destroy(b);
        sb_error_set(err, SB_ERR_NOMEM, "out of memory for a state buffer of %u vertices", vertex_count);
        return NULL;
    }
    b->slot_count = slots;
    b->vertex_count = vertex_count;
    for (int i = 0; i < slots; i++) {
        sb_snapshot* s = &b->slots[i].snapshot;
        s->vertex_count = vertex_count;
        s->positions = b->arrays + 2 * per_array * (size_t)i;
        s->velocities = s->positions + per_array;
        atomic_init(&b->slots[i].holders, 0);
    }
    atomic_init(&b->latest, -1);
    atomic_init(&b->published, 0);
    atomic_init(&b->skipped, 0);
    return b;
}

void sb_state_buffer_destroy(sb_state_buffer* b) {
    if (!b) return;
    free(b->slots);
    free(b->arrays);
    free(b);
}

sb_snapshot* sb_state_buffer_begin(sb_state_buffer* b) {
    int latest = atomic_load_explicit(&b->latest, memory_order_relaxed); /* only the writer changes it */
    for (int k = 1; k <= b->slot_count; k++) {
        int i = (latest + k + b->slot_count) % b->slot_count; /* oldest first */
        unsigned expected = 0;
        if (i != latest && atomic_compare_exchange_strong_explicit(&b->slots[i].holders, &expected, SB_WRITING,
                                                                   memory_order_acquire, memory_order_relaxed))
            return &b->slots[i].snapshot;
    }
    return NULL;
}

void sb_state_buffer_commit(sb_state_buffer* b, sb_snapshot* snapshot) {
    sb_slot* slot = (sb_slot*)snapshot; /* the snapshot is the slot's first member */
    snapshot->sequence = atomic_load_explicit(&b->published, memory_order_relaxed) + 1;
    atomic_fetch_and_explicit(&slot->holders, ~SB_WRITING, memory_order_release);
    atomic_store_explicit(&b->latest, (int)(slot - b->slots), memory_order_release);
    atomic_store_explicit(&b->published, snapshot->sequence, memory_order_release);
}

const sb_snapshot* sb_state_buffer_acquire(sb_state_buffer* b) {
    for (int tries = 0; tries < SB_ACQUIRE_TRIES; tries++) {
        int i = atomic_load_explicit(&b->latest, memory_order_acquire);
        if (i < 0) return NULL;
        unsigned before = atomic_fetch_add_explicit(&b->slots[i].holders, 1, memory_order_acq_rel);
        if (!(before & SB_WRITING) && atomic_load_explicit(&b->latest, memory_order_acquire) == i)
            return &b->slots[i].snapshot;
        atomic_fetch_sub_explicit(&b->slots[i].holders, 1, memory_order_release);
    }
    return NULL;
}

void sb_state_buffer_release(sb_state_buffer* b, const sb_snapshot* snapshot) {
    (void)b;
    if (snapshot) atomic_fetch_sub_explicit(&((sb_slot*)snapshot)->holders, 1, memory_order_release);
}

uint64_t sb_state_buffer_published(const sb_state_buffer* b) {
    return atomic_load_explicit(&((sb_state_buffer*)b)->published, memory_order_acquire);
}

uint64_t sb_state_buffer_skipped(const sb_state_buffer* b) {
    return atomic_load_explicit(&((sb_state_buffer*)b)->skipped, memory_order_relaxed);
}

/* Fills the scalars of a snapshot whose arrays hold the solver's state, and
 * makes it the latest. */
static void sb_commit_solver(sb_state_buffer* b, sb_snapshot* s, const sb_solver* solver) {
    s->step = sb_solver_step_count(solver);
    s->time = sb_solver_time(solver);
    s->energies = sb_solver_energies(solver);
    s->vertex_count = sb_solver_vertex_count(solver); /* tearing adds vertices within the buffer's room */
    sb_state_buffer_commit(b, s);
}

/* Gives a slot taken by sb_state_buffer_begin back unpublished. */
static void sb_abandon(sb_snapshot* snapshot) {
    atomic_fetch_and_explicit(&((sb_slot*)snapshot)->holders, ~SB_WRITING, memory_order_release);
}

sb_status sb_solver_publish(const sb_solver* solver, sb_state_buffer* b) {
    if (sb_solver_vertex_capacity(solver) != b->vertex_count) return SB_ERR_INVALID;
    sb_snapshot* s = sb_state_buffer_begin(b);
    if (!s) {
        atomic_fetch_add_explicit(&b->skipped, 1, memory_order_relaxed);
        return SB_ERR_BUSY;
    }
    sb_solver_copy_state(solver, s->positions, s->velocities);
    sb_commit_solver(b, s, solver);
    return SB_OK;
}

sb_status sb_solver_advance_published(sb_solver* solver, double dt, sb_state_buffer* b) {
    if (sb_solver_vertex_capacity(solver) != b->vertex_count) return SB_ERR_INVALID;
    sb_snapshot* s = sb_state_buffer_begin(b);
    if (!s) {
        atomic_fetch_add_explicit(&b->skipped, 1, memory_order_relaxed);
        return sb_solver_advance(solver, dt);
    }
    sb_status status = sb_solver_advance_into(solver, dt, s->positions, s->velocities);
    if (status == SB_OK)
        sb_commit_solver(b, s, solver);
    else
        sb_abandon(s);
    return status;
}
