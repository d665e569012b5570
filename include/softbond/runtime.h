/* The parallel runtime: thread count, core binding, topology report. */
#ifndef SOFTBOND_RUNTIME_H
#define SOFTBOND_RUNTIME_H

#include "softbond/export.h"

#include "softbond/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The thread count to use: `requested` when > 0, else the SOFTBOND_THREADS
 * environment variable when set, else one per core. Returns -1 and fills
 * err when SOFTBOND_THREADS is not a positive integer. */
SB_API int sb_runtime_threads(int requested, sb_error* err);

/* Binds the OpenMP threads of a `threads`-wide team one per core (round
 * robin when there are more threads than cores), with hwloc. The fast
 * solver calls it for teams of two threads or more. Returns false
 * when the topology could not be read or binding is not supported; the
 * simulation still runs, unbound. */
SB_API bool sb_runtime_bind(int threads);

/* One line describing the machine and build: cores, processing units,
 * caches, SIMD level and precision. */
SB_API void sb_runtime_describe(char* out, size_t size);

/* "avx512", "avx2" or "scalar": the SIMD level the fast kernels use. */
SB_API const char* sb_runtime_simd(void);

#ifdef __cplusplus
}
#endif
#endif
