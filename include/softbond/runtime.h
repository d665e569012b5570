/** @file
 * The parallel runtime: thread count, core binding, topology report. */
#ifndef SOFTBOND_RUNTIME_H
#define SOFTBOND_RUNTIME_H

#include "softbond/export.h"

#include "softbond/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** How the solver's threads wait for each other at the barriers of a step
 * and for the next step (the solver's own thread team; DESIGN.md, section
 * Threads):
 *   spin     busy-wait: the lowest latency, for a machine the solver has to
 *            itself (the benchmark);
 *   yield    check, then give the core to any other runnable thread;
 *   passive  sleep at once: the cores are free for the host's own threads
 *            (a haptic servo loop, a renderer) whenever the solver waits.
 * spin and yield go to sleep after about a millisecond of waiting, so an
 * idle solver never holds a core. bench/results/runtime.md has the measured
 * effect: on two cores shared with a 1 kHz servo thread no policy keeps the
 * servo on time while the solver's team takes both cores; a team of one
 * thread does. A real-time program on two cores should run the solver on
 * one thread, or on two with passive waits when its other threads run at
 * real-time priority or are mostly idle. */
typedef enum sb_wait_policy { SB_WAIT_SPIN = 0, SB_WAIT_YIELD, SB_WAIT_PASSIVE, SB_WAIT_COUNT } sb_wait_policy;

/** "spin", "yield", "passive". */
SB_API const char* sb_wait_policy_name(sb_wait_policy policy);
/** Returns false when the name is unknown. */
SB_API bool sb_wait_policy_from_name(const char* name, sb_wait_policy* out);

/** The most threads a solver's team may have: sb_runtime_def.threads,
 * SOFTBOND_THREADS and the count of processors are held to it (the
 * `softbond` program's --threads and the scene's threads too). */
#define SB_MAX_THREADS 1024

/** The threads a solver runs on; the host decides. */
typedef struct sb_runtime_def {
    int threads;         /**< the team's size, the calling thread included, 0 to SB_MAX_THREADS;
                          * 0 = sb_runtime_threads(0) */
    bool pin;            /**< bind thread i to core i (hwloc; thread 0 is the one that creates the solver,
                          * given its own binding back when the solver is destroyed); off: the
                          * scheduler places them */
    sb_wait_policy wait; /**< see above */
    bool fixed_width;    /**< run every step on all `threads`; off (the default): a step whose work does not
                          * depend on the thread count runs on the calling thread alone while the team
                          * measures that faster (another process holding a core) */
} sb_runtime_def;

/** threads 0, pin off, wait passive, fixed_width off: a library user shares the machine. A
 * team of 1 starts no thread and runs each step on the caller's thread. */
SB_API sb_runtime_def sb_default_runtime_def(void);

/** The thread count to use: `requested` when > 0, else the SOFTBOND_THREADS
 * environment variable when set, else one per available processor (at
 * most SB_MAX_THREADS). Returns -1 and fills err when `requested` is above
 * SB_MAX_THREADS or SOFTBOND_THREADS is not an integer from 1 to
 * SB_MAX_THREADS. */
SB_API int sb_runtime_threads(int requested, sb_error* err);

/** One line describing the machine and build: cores, processing units,
 * caches, SIMD level and precision. */
SB_API void sb_runtime_describe(char* out, size_t size);

/** "avx512", "avx2" or "scalar": the SIMD level the fast kernels use. */
SB_API const char* sb_runtime_simd(void);

#ifdef __cplusplus
}
#endif
#endif
