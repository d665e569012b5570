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

/* The last-level cache of the first core in bytes, as the OS reports it
 * (the largest level of /sys/devices/system/cpu/cpu0/cache); 0 when it
 * reports none, as the virtual machine the benchmarks ran in does. */
size_t sb_bench_llc_bytes(void);
/* The L3 size the processor's cpuid gives (sysconf's _SC_LEVEL3_CACHE_SIZE,
 * the legacy leaf 0x80000006 on AMD where the cache-topology leaf is
 * missing); 0 when unknown. Not what a core shares: in that virtual machine
 * (a Turin-like EPYC, 32 MiB of L3 a die) it reads 508 MiB, about a whole
 * package's. */
size_t sb_bench_cpuid_l3_bytes(void);

/* Runs the triad with `threads` OpenMP threads on three double arrays of
 * array_bytes each, `repeats` times, and keeps the best. Returns a negative
 * rate when the arrays cannot be allocated. */
sb_triad_result sb_bench_triad(size_t array_bytes, int threads, int repeats);

#endif
