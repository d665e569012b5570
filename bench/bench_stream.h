/* A STREAM-style triad, a[i] = b[i] + s * c[i], measured in the same run as
 * the kernels so that their achieved bandwidth has a ceiling beside it. */
#ifndef SB_BENCH_STREAM_H
#define SB_BENCH_STREAM_H

#include <stddef.h>

typedef struct sb_triad_result {
    size_t array_bytes; /* each of the three arrays */
    int threads;
    double gb_per_s; /* best of the repetitions, 24 bytes per element (STREAM's count) */
} sb_triad_result;

/* Last-level cache size in bytes (0 when unknown). */
size_t sb_bench_llc_bytes(void);

/* Runs the triad with `threads` OpenMP threads on three double arrays of
 * array_bytes each, `repeats` times, and keeps the best. Returns a negative
 * rate when the arrays cannot be allocated. */
sb_triad_result sb_bench_triad(size_t array_bytes, int threads, int repeats);

#endif
