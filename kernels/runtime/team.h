/* Private: the solver's thread team (kernels/runtime/team.c). */
#ifndef SB_TEAM_H
#define SB_TEAM_H

#include "softbond/runtime.h"

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

typedef struct sb_team sb_team;

/* One thread's view of a job: its index (0 is the thread that called
 * sb_team_run) and the number of threads sharing the job. */
typedef struct sb_worker {
    sb_team* team;
    int index, width;
} sb_worker;

typedef void (*sb_team_job)(void* context, const sb_worker* worker);

/* A team of def->threads threads (resolved by sb_runtime_threads): the
 * caller and threads - 1 workers started here. NULL and err filled on
 * failure. */
sb_team* sb_team_create(const sb_runtime_def* def, sb_error* err);
void sb_team_destroy(sb_team* team);
int sb_team_size(const sb_team* team);

/* Runs job(context, worker) on the first `width` threads of the team (1 to
 * the team's size; the calling thread is worker 0) and returns when all
 * have returned. A width of 1 calls the job directly: no other thread
 * wakes. Never allocates. */
void sb_team_run(sb_team* team, int width, sb_team_job job, void* context);

/* sb_team_run for a step's job whose result does not depend on how many
 * workers run it (each worker's share is whole blocks of a fixed partition,
 * and one worker alone runs them all in order). The team times the job at
 * `width` and on the caller alone, keeps a running estimate of each per job
 * function, runs the job at the faster and, every SB_TEAM_PROBE_EVERY runs,
 * once at the other, so that a machine whose load changes is followed
 * (team.c's design note says why). With sb_runtime_def.fixed_width it is
 * sb_team_run. Never allocates. */
void sb_team_run_adaptive(sb_team* team, int width, sb_team_job job, void* context);

/* Runs of sb_team_run_adaptive so far, and how many of them went on the
 * caller alone (for benchmarks' reports). */
void sb_team_adaptive_counts(const sb_team* team, uint64_t* runs, uint64_t* alone);

/* Waits until every worker of the job has arrived (the policy decides how:
 * spin, yield or sleep); all memory written before it is visible after it. */
void sb_worker_barrier(const sb_worker* worker);

/* Point-to-point waits, for jobs whose workers need only some of the
 * others' work (kernels/integrators/fast_pbd.c's sweeps): sb_worker_wait_at_least
 * returns once *word >= target (waiting as the policy says, as at a
 * barrier); sb_worker_post stores value into *word and wakes whoever
 * sleeps on it. Memory written before a post is visible after a wait that
 * saw its value. */
void sb_worker_wait_at_least(const sb_worker* worker, atomic_uint* word, unsigned target);
void sb_worker_post(const sb_worker* worker, atomic_uint* word, unsigned value);

/* This worker's share [begin, end) of count items split into contiguous
 * equal parts, the first ones one longer (OpenMP's schedule(static)). */
void sb_worker_range(const sb_worker* worker, int64_t count, int64_t* begin, int64_t* end);

/* A pass whose items any worker of the job may take: each call of
 * sb_worker_claim hands this worker the next run [begin, end) of the
 * count items (false when none is left): from its own share of them (the
 * one sb_worker_range gives it) while that lasts, then from the others',
 * so that a worker that runs slower (another process on its core, a late
 * wake-up) is relieved of the end of its share. For a pass whose items'
 * results do not depend on which worker ran them. The shares' counters
 * are reset by every barrier and at the start of every job: such a pass
 * begins after a barrier or at its job's start, ends at a barrier or at
 * the job's end, and is the only one between them. Alone (a width of 1)
 * the one claim is every item. */
typedef struct sb_claims {
    int64_t count;
    bool taken; /* alone: the one claim was made */
} sb_claims;
static inline sb_claims sb_worker_claims(int64_t count) { return (sb_claims){count, false}; }
bool sb_worker_claim(const sb_worker* worker, sb_claims* claims, int64_t* begin, int64_t* end);

/* Sets *flag to 1 (for a flag any worker may raise). */
static inline void sb_worker_raise(atomic_int* flag) { atomic_store_explicit(flag, 1, memory_order_relaxed); }

#endif
