/* The byte and flop models that turn a measured step time into GB/s and
 * GFLOP/s. Both describe the fast kernels' ideal traffic and arithmetic, not
 * what a particular implementation happens to do; see bench_model.c. */
#ifndef SB_BENCH_MODEL_H
#define SB_BENCH_MODEL_H

#include "softbond/softbond.h"

typedef struct sb_bench_counts {
    uint64_t vertices, bonds, triangles, hinges;
    uint64_t elements; /* bonds + angles (3 per triangle) + hinges */
    double bytes_per_step;
    double flops_per_step;
} sb_bench_counts;

sb_bench_counts sb_bench_count(const sb_model* model, bool all_terms);

/* One-paragraph descriptions for the CSV header and the README. */
const char* sb_bench_byte_model_text(void);
const char* sb_bench_flop_model_text(void);

#endif
