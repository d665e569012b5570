/* The solver's thread team.
 *
 * Design. A step of the fast solver is a few passes separated by barriers
 * (kernels/state/solver_fast.c). Until now they ran in OpenMP parallel regions,
 * but libgomp takes its wait policy (OMP_WAIT_POLICY, GOMP_SPINCOUNT) from
 * the environment once, when the library is loaded: a library cannot give
 * one solver a spinning team and another a sleeping one, and libgomp's
 * default spins about 300 000 iterations at every barrier and after every
 * region. On a machine whose two cores the solver shares with a 1 kHz servo
 * thread and a render thread, that spinning is what starves them. So the
 * team is softbond's own: size - 1 worker threads started at creation, a
 * job handed over through an atomic generation counter, and one barrier;
 * every wait goes through sb_wait_while, which the policy shapes:
 *
 *   spin     busy-wait with the CPU's pause hint (a dedicated machine: the
 *            lowest latency; a waiting thread holds its core)
 *   yield    sched_yield between checks (the core is offered to any other
 *            runnable thread, the thread stays runnable)
 *   passive  sleep on a futex at once (the core is free; a wake-up costs a
 *            system call and the scheduler's latency)
 *
 * spin and yield fall back to the futex after SB_SPIN_CHECKS checks, so an
 * idle solver never burns a core for long. passive sleeps at once even at
 * a barrier inside a step, where the threads arrive within microseconds of
 * each other and a futex sleep and wake-up costs tens of microseconds (on
 * a 4-sweep vbd step of 10 000 vertices, 32 barriers, about half the
 * step, until its sweeps waited only for the blocks they read). A short spin before the sleep makes such a step faster,
 * but beside a competing 1 kHz thread it keeps that thread off a core and makes it late far more often
 * (bench/results/notes/team.md has the measurement). So the spin is left to the spin and yield policies.
 *
 * A waker issues FUTEX_WAKE only when a waiter said it sleeps on that very
 * word (each thread's slot names the word it sleeps on; sequentially
 * consistent on both sides, so a waiter either sees the new value or is
 * woken): a block's post in vbd's or xpbd's sweeps, hundreds a step, makes
 * no system call while the other worker sleeps on something else (a team-wide
 * count of sleepers made every post a FUTEX_WAKE then).
 * Barriers count arrivals and bump a generation; the last to arrive
 * releases the others. A job ends when every worker has counted itself
 * finished, those that had no share of it too, so that the job's fields
 * are never rewritten under a worker still reading them. Memory written before a barrier is visible after it
 * (release on the generation, acquire in the wait). A team of one thread
 * starts no thread and calls the job directly. Nothing here allocates after
 * creation.
 *
 * Adapting to a shared machine (sb_team_run_adaptive). When another
 * process holds one of the cores, a worker that is descheduled, or that
 * sleeps at a passive barrier and wakes late, makes the others wait: a
 * step on two threads then takes longer than on one (xpbd on the 100 ×
 * 100 sheet, a niced busy loop on one of two cores: 0.9–1.0 ms against
 * 0.53 ms). What the waits cost cannot be read off the waits alone (a
 * wait measured on two threads does not say what one thread would have
 * taken, and a descheduled worker does not wait, it is waited for), so
 * the team measures the whole job at both widths it may choose: for each
 * job function (a step's job; SB_TEAM_JOBS of them) it keeps a running
 * estimate of the job's wall time at the configured width and on the
 * caller alone, runs the job at the faster, and every SB_TEAM_PROBE_EVERY
 * runs once at the other, so that an estimate is never older than that
 * many runs. A probe costs one step at the slower width: on a quiet
 * machine about 1/SB_TEAM_PROBE_EVERY of a step's time over a run. The
 * choice is between the full width and one thread (not every width in
 * between: on the two-core machines this is built for these are the only
 * two, and one is what the issue asks never to lose to). The jobs'
 * partitions (blocks of colors, units of the xpbd schedule) stay fixed;
 * only which worker runs a block changes, and one worker runs them all in
 * order, as a team of one does, so the result is bitwise the same
 * whichever width ran.
 *
 * Claimed passes (sb_worker_claim). Within a job, a pass whose items are
 * independent (the fused step's vertex chunks, a color's element blocks)
 * need not be split in fixed shares: each worker takes runs of its own
 * share (a quarter of what is left of it at a time) and, when its share
 * is done, runs of the others'. A worker woken late from a passive wait,
 * or slowed by another process on its core, is relieved of the end of its
 * share instead of being waited for at the barrier. Each worker starts on
 * the share sb_worker_range would give it, so in a quiet step every item
 * runs where it ran the step before and its data is in that core's
 * caches: a pass claimed from one counter shared by all, in interleaved
 * runs, was not faster than the fixed split on this machine's two vCPUs
 * (the 100k sheet, spinning waits), though its workers waited less. Every
 * item sums into its own partials, so the result does not depend on
 * which worker took it. The shares' counters are reset by the barrier's
 * last arrival and by sb_team_run, before the others are let go. */
#define _GNU_SOURCE
#include "kernels/runtime/team.h"
#include "common/error.h"

#include <hwloc.h>
#include <limits.h>
#include <linux/futex.h>
#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
#include <stdlib.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

/* Checks before a spinning or yielding waiter goes to sleep: about a
 * millisecond of pause instructions, a few hundred yields. */
#define SB_SPIN_CHECKS 100000
#define SB_YIELD_CHECKS 1000

/* Job functions whose width the team chooses, and how often the width not
 * chosen is measured again (sb_team_run_adaptive). */
#define SB_TEAM_JOBS 8
#define SB_TEAM_PROBE_EVERY 64

/* The word a thread sleeps on (NULL: none), alone on its cache line. */
typedef struct sb_sleeper {
    _Alignas(64) _Atomic(atomic_uint*) on;
} sb_sleeper;

/* How many of a worker's share of the current claimed pass are taken
 * (sb_worker_claim), alone on its cache line: reset by each barrier and
 * each job. */
typedef struct sb_share {
    _Alignas(64) atomic_llong taken;
} sb_share;

/* One job function's measured wall times: seconds[0] on the caller alone,
 * seconds[1] at the configured width (0: not measured yet). */
typedef struct sb_team_choice {
    sb_team_job job;
    double seconds[2];
    uint64_t runs;
} sb_team_choice;

struct sb_team {
    int size;
    sb_wait_policy policy;
    bool fixed_width; /* sb_runtime_def.fixed_width: sb_team_run_adaptive never narrows */
    pthread_t* threads;
    sb_worker* workers;
    /* the job: written by worker 0 before the generation is bumped */
    sb_team_job job;
    void* context;
    int width;
    atomic_uint job_generation;
    atomic_uint finished; /* workers done with the current job (whether they took part or not) */
    atomic_int stop;
    /* the barrier */
    atomic_int arrived;
    atomic_uint barrier_generation;
    sb_share* shares;              /* size: each worker's share of a claimed pass */
    sb_sleeper* sleepers;          /* size: the word each thread sleeps on, NULL when awake */
    hwloc_topology_t topology;     /* for pinning; NULL when not pinned */
    hwloc_bitmap_t caller_binding; /* the calling thread's binding before pinning, given back at destroy */
    /* sb_team_run_adaptive's measurements, used by the calling thread only */
    sb_team_choice choices[SB_TEAM_JOBS];
    uint64_t adaptive_runs, alone_runs;
};

static long sb_futex(atomic_uint* word, int op, unsigned value) {
    return syscall(SYS_futex, (unsigned*)word, op, value, NULL, NULL, 0);
}

static inline void sb_cpu_relax(void) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

/* Returns once *word differs from old. */
static void sb_wait_while(sb_team* t, int thread, atomic_uint* word, unsigned old) {
    int checks = t->policy == SB_WAIT_SPIN ? SB_SPIN_CHECKS : t->policy == SB_WAIT_YIELD ? SB_YIELD_CHECKS : 0;
    for (int i = 0; i < checks; i++) {
        if (atomic_load_explicit(word, memory_order_acquire) != old) return;
        if (t->policy == SB_WAIT_YIELD)
            sched_yield();
        else
            sb_cpu_relax();
    }
    atomic_store(&t->sleepers[thread].on, word);
    while (atomic_load(word) == old) sb_futex(word, FUTEX_WAIT_PRIVATE, old);
    atomic_store(&t->sleepers[thread].on, NULL);
}

/* Wakes whoever sleeps on word (its new value already stored). */
static void sb_wake(sb_team* t, atomic_uint* word) {
    for (int i = 0; i < t->size; i++)
        if (atomic_load(&t->sleepers[i].on) == word) {
            sb_futex(word, FUTEX_WAKE_PRIVATE, INT_MAX);
            return;
        }
}

/* Bumps *word and wakes whoever sleeps on it. */
static void sb_bump(sb_team* t, atomic_uint* word) {
    atomic_fetch_add(word, 1);
    sb_wake(t, word);
}

static void sb_shares_reset(sb_team* t, int width) {
    for (int i = 0; i < width; i++) atomic_store_explicit(&t->shares[i].taken, 0, memory_order_relaxed);
}

void sb_worker_barrier(const sb_worker* w) {
    if (w->width == 1) return;
    sb_team* t = w->team;
    unsigned generation = atomic_load_explicit(&t->barrier_generation, memory_order_acquire);
    if (atomic_fetch_add_explicit(&t->arrived, 1, memory_order_acq_rel) == w->width - 1) {
        atomic_store_explicit(&t->arrived, 0, memory_order_relaxed);
        sb_shares_reset(t, w->width); /* published by the bump */
        sb_bump(t, &t->barrier_generation);
    } else {
        sb_wait_while(t, w->index, &t->barrier_generation, generation);
    }
}

void sb_worker_wait_at_least(const sb_worker* w, atomic_uint* word, unsigned target) {
    for (unsigned seen; (seen = atomic_load_explicit(word, memory_order_acquire)) < target;)
        sb_wait_while(w->team, w->index, word, seen);
}

void sb_worker_post(const sb_worker* w, atomic_uint* word, unsigned value) {
    if (w->width == 1) {
        atomic_store_explicit(word, value, memory_order_relaxed);
        return;
    }
    atomic_store(word, value); /* sequentially consistent, before the sleepers are read */
    sb_wake(w->team, word);
}

void sb_worker_range(const sb_worker* w, int64_t count, int64_t* begin, int64_t* end) {
    int64_t share = count / w->width, extra = count % w->width, i = w->index;
    *begin = i * share + (i < extra ? i : extra);
    *end = *begin + share + (i < extra);
}

/* Takes the next run of a share of `count` items into [*begin, *end)
 * (offsets in the share): a quarter of what is left, at least one, so
 * that the first runs are long (few updates of the counter) and the last
 * short (whoever takes them, the workers finish together). */
static bool sb_share_take(sb_share* share, int64_t count, int64_t* begin, int64_t* end) {
    long long start = atomic_load_explicit(&share->taken, memory_order_relaxed), size;
    do {
        if (start >= count) return false;
        size = (count - start) / 4;
        size = size < 1 ? 1 : size;
    } while (!atomic_compare_exchange_weak_explicit(&share->taken, &start, start + size, memory_order_relaxed,
                                                    memory_order_relaxed));
    *begin = start, *end = start + size;
    return true;
}

/* From the worker's own share first (sb_worker_range's: each worker keeps
 * to the same items pass after pass, and their data stays in its caches),
 * then from the others', in turn. */
bool sb_worker_claim(const sb_worker* w, sb_claims* c, int64_t* begin, int64_t* end) {
    if (w->width == 1) {
        if (c->taken || c->count <= 0) return false;
        c->taken = true;
        *begin = 0, *end = c->count;
        return true;
    }
    for (int k = 0; k < w->width; k++) {
        sb_worker owner = {w->team, (w->index + k) % w->width, w->width};
        int64_t first, last;
        sb_worker_range(&owner, c->count, &first, &last);
        if (sb_share_take(&w->team->shares[owner.index], last - first, begin, end)) {
            *begin += first, *end += first;
            return true;
        }
    }
    return false;
}

static void sb_pin(sb_team* t, int index) {
    if (!t->topology) return;
    int cores = hwloc_get_nbobjs_by_type(t->topology, HWLOC_OBJ_CORE);
    hwloc_obj_t core = hwloc_get_obj_by_type(t->topology, HWLOC_OBJ_CORE, cores > 0 ? index % cores : 0);
    if (core) hwloc_set_cpubind(t->topology, core->cpuset, HWLOC_CPUBIND_THREAD);
}

static void* sb_worker_main(void* arg) {
    sb_worker* w = arg;
    sb_team* t = w->team;
    sb_pin(t, w->index);
    unsigned seen = 0;
    for (;;) {
        sb_wait_while(t, w->index, &t->job_generation, seen);
        seen = atomic_load_explicit(&t->job_generation, memory_order_acquire);
        if (atomic_load_explicit(&t->stop, memory_order_acquire)) return NULL;
        if (w->index < t->width) {
            sb_worker job_view = {t, w->index, t->width};
            t->job(t->context, &job_view);
        }
        sb_bump(t, &t->finished); /* the join: worker 0 waits for every worker */
    }
}

void sb_team_run(sb_team* t, int width, sb_team_job job, void* context) {
    width = width < 1 ? 1 : width > t->size ? t->size : width;
    sb_worker main_view = {t, 0, width};
    if (width == 1) {
        job(context, &main_view);
        return;
    }
    t->job = job;
    t->context = context;
    t->width = width;
    atomic_store_explicit(&t->finished, 0, memory_order_relaxed); /* no worker touches it before the bump */
    sb_shares_reset(t, width);
    sb_bump(t, &t->job_generation);
    job(context, &main_view);
    /* Every worker, not only the job's: one that skipped the job must have
     * read the job's width before the next job rewrites it. */
    for (unsigned done; (done = atomic_load_explicit(&t->finished, memory_order_acquire)) != (unsigned)t->size - 1;)
        sb_wait_while(t, 0, &t->finished, done);
}

static double sb_seconds(void) {
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

/* job's measurements (a free entry taken for a new job); NULL when all are taken. */
static sb_team_choice* sb_team_choice_of(sb_team* t, sb_team_job job) {
    for (int i = 0; i < SB_TEAM_JOBS; i++) {
        if (!t->choices[i].job) t->choices[i].job = job;
        if (t->choices[i].job == job) return &t->choices[i];
    }
    return NULL;
}

/* 1: run at the configured width, 0: on the caller alone. Each is measured
 * once first, then the faster runs, but every SB_TEAM_PROBE_EVERY-th run
 * the other. */
static int sb_team_choose(const sb_team_choice* c) {
    if (c->seconds[1] == 0.0) return 1;
    if (c->seconds[0] == 0.0) return 0;
    int faster = c->seconds[0] < c->seconds[1] ? 0 : 1;
    return c->runs % SB_TEAM_PROBE_EVERY == 0 ? 1 - faster : faster;
}

void sb_team_run_adaptive(sb_team* t, int width, sb_team_job job, void* context) {
    sb_team_choice* c = width > 1 && t->size > 1 && !t->fixed_width ? sb_team_choice_of(t, job) : NULL;
    if (!c) {
        sb_team_run(t, width, job, context);
        return;
    }
    int side = sb_team_choose(c);
    double start = sb_seconds();
    sb_team_run(t, side ? width : 1, job, context);
    double took = sb_seconds() - start, *estimate = &c->seconds[side];
    *estimate =
        *estimate == 0.0 ? took : 0.5 * (*estimate + took); /* a load that comes or goes shows within a few runs */
    c->runs++;
    t->adaptive_runs++;
    t->alone_runs += side == 0;
}

void sb_team_adaptive_counts(const sb_team* t, uint64_t* runs, uint64_t* alone) {
    *runs = t->adaptive_runs;
    *alone = t->alone_runs;
}

int sb_team_size(const sb_team* t) { return t->size; }

void sb_team_destroy(sb_team* t) {
    if (!t) return;
    atomic_store(&t->stop, 1);
    sb_bump(t, &t->job_generation);
    for (int i = 1; i < t->size; i++)
        if (t->workers[i].team) pthread_join(t->threads[i], NULL);
    if (t->caller_binding) { /* the host's thread gets its own binding back */
        hwloc_set_cpubind(t->topology, t->caller_binding, HWLOC_CPUBIND_THREAD);
        hwloc_bitmap_free(t->caller_binding);
    }
    if (t->topology) hwloc_topology_destroy(t->topology);
    free(t->threads);
    free(t->workers);
    free(t->sleepers);
    free(t->shares);
    free(t);
}

static hwloc_topology_t sb_load_topology(void) {
    hwloc_topology_t topology;
    if (hwloc_topology_init(&topology) != 0) return NULL;
    if (hwloc_topology_load(topology) != 0) {
        hwloc_topology_destroy(topology);
        return NULL;
    }
    return topology;
}

sb_team* sb_team_create(const sb_runtime_def* def, sb_error* err) {
    if ((unsigned)def->wait >= SB_WAIT_COUNT) {
        sb_error_set(err, SB_ERR_INVALID, "unknown wait policy %d", (int)def->wait);
        return NULL;
    }
    int size = sb_runtime_threads(def->threads, err);
    if (size < 1) return NULL;
    sb_team* t = calloc(1, sizeof *t);
    if (t) {
        t->threads = calloc((size_t)size, sizeof *t->threads);
        t->workers = calloc((size_t)size, sizeof *t->workers);
        t->sleepers = aligned_alloc(_Alignof(sb_sleeper), (size_t)size * sizeof *t->sleepers);
        t->shares = aligned_alloc(_Alignof(sb_share), (size_t)size * sizeof *t->shares);
    }
    if (t && t->sleepers)
        for (int i = 0; i < size; i++) atomic_init(&t->sleepers[i].on, NULL);
    if (t && t->shares)
        for (int i = 0; i < size; i++) atomic_init(&t->shares[i].taken, 0);
    if (!t || !t->threads || !t->workers || !t->sleepers || !t->shares) {
        sb_team_destroy(t);
        sb_error_set(err, SB_ERR_NOMEM, "out of memory for a team of %d threads", size);
        return NULL;
    }
    t->size = size;
    t->policy = def->wait;
    t->fixed_width = def->fixed_width;
    if (def->pin) t->topology = sb_load_topology(); /* unpinned when the topology cannot be read */
    if (t->topology && (t->caller_binding = hwloc_bitmap_alloc()) &&
        hwloc_get_cpubind(t->topology, t->caller_binding, HWLOC_CPUBIND_THREAD) != 0) {
        hwloc_bitmap_free(t->caller_binding);
        t->caller_binding = NULL;
    }
    sb_pin(t, 0);
    for (int i = 1; i < size; i++) {
        t->workers[i] = (sb_worker){t, i, size};
        if (pthread_create(&t->threads[i], NULL, sb_worker_main, &t->workers[i]) != 0) {
            t->workers[i].team = NULL;
            t->size = i; /* the ones started are joined */
            sb_team_destroy(t);
            sb_error_set(err, SB_ERR_NOMEM, "could not start thread %d of a team of %d", i, size);
            return NULL;
        }
    }
    return t;
}
