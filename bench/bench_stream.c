/* STREAM triad (McCalpin's rules, our own loop): the arrays are first
 * touched by the same threads and schedule that run the triad, each array is
 * at least 4× the last-level cache so nothing stays cached between passes,
 * and the rate counts 3 × 8 bytes per element (two reads, one write; the
 * write-allocate read that a plain store also costs is not counted, as in
 * STREAM). The byte model of the kernels counts writes the same way. */
#include "bench/bench_stream.h"
#include "common/clock.h"

#include <omp.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* Line `name` of cache index `index`'s sysfs directory into out; false when absent. */
static bool sb_cache_field(int index, const char* name, char* out, int size) {
    char path[128];
    snprintf(path, sizeof path, "/sys/devices/system/cpu/cpu0/cache/index%d/%s", index, name);
    FILE* f = fopen(path, "r");
    if (!f) return false;
    bool ok = fgets(out, size, f) != NULL;
    fclose(f);
    return ok;
}

size_t sb_bench_llc_bytes(void) {
    size_t bytes = 0;
    int top = 0;
    char text[64];
    for (int index = 0; index < 16 && sb_cache_field(index, "level", text, sizeof text); index++) {
        int level = atoi(text);
        if (!sb_cache_field(index, "type", text, sizeof text) || strncmp(text, "Instruction", 11) == 0) continue;
        if (level < top || !sb_cache_field(index, "size", text, sizeof text)) continue;
        char* unit;
        unsigned long long size = strtoull(text, &unit, 10);
        size <<= *unit == 'K' ? 10 : *unit == 'M' ? 20 : *unit == 'G' ? 30 : 0;
        top = level;
        bytes = (size_t)size;
    }
    return bytes;
}

size_t sb_bench_cpuid_l3_bytes(void) {
    long size = 0;
#ifdef _SC_LEVEL3_CACHE_SIZE
    size = sysconf(_SC_LEVEL3_CACHE_SIZE);
#endif
    return size > 0 ? (size_t)size : 0;
}

static void sb_triad_pass(double* restrict a, const double* restrict b, const double* restrict c, size_t n, double s,
                          int threads) {
#pragma omp parallel for num_threads(threads) schedule(static)
    for (size_t i = 0; i < n; i++) a[i] = b[i] + s * c[i];
}

sb_triad_result sb_bench_triad(size_t array_bytes, int threads, int repeats) {
    sb_triad_result r = {array_bytes, threads, -1.0};
    size_t n = array_bytes / sizeof(double);
    size_t bytes = (n * sizeof(double) + 63) / 64 * 64;
    double* a = aligned_alloc(64, bytes);
    double* b = aligned_alloc(64, bytes);
    double* c = aligned_alloc(64, bytes);
    if (a && b && c) {
#pragma omp parallel for num_threads(threads) schedule(static)
        for (size_t i = 0; i < n; i++) {
            a[i] = 0.0;
            b[i] = 1.0;
            c[i] = 2.0;
        }
        sb_triad_pass(a, b, c, n, 3.0, threads); /* warm-up */
        double best = 1e300;
        for (int k = 0; k < repeats; k++) {
            double t0 = sb_wall_seconds();
            sb_triad_pass(a, b, c, n, 3.0, threads);
            double t = sb_wall_seconds() - t0;
            if (t < best) best = t;
        }
        /* keep the result alive: the compiler must not drop the passes */
        volatile double sink = a[n / 2];
        (void)sink;
        r.gb_per_s = 3.0 * sizeof(double) * (double)n / best * 1e-9;
    }
    free(a);
    free(b);
    free(c);
    return r;
}
