/* The parallel runtime: how many threads, and where they run (hwloc). */
#include "softbond/runtime.h"
#include "common/error.h"
#include "kernels/wide.h"

#include <errno.h>
#include <hwloc.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

int sb_runtime_threads(int requested, sb_error* err) {
    if (requested > 0) return requested;
    const char* env = getenv("SOFTBOND_THREADS");
    if (env && *env) {
        char* end;
        errno = 0;
        long n = strtol(env, &end, 10);
        if (errno || *end || n < 1 || n > 1024) {
            sb_error_set(err, SB_ERR_INVALID, "SOFTBOND_THREADS='%s' is not a thread count from 1 to 1024", env);
            return -1;
        }
        return (int)n;
    }
    return omp_get_num_procs();
}

const char* sb_runtime_simd(void) { return SB_SIMD_NAME; }

static int sb_core_count(hwloc_topology_t topology) {
    int cores = hwloc_get_nbobjs_by_type(topology, HWLOC_OBJ_CORE);
    return cores > 0 ? cores : 1;
}

bool sb_runtime_bind(int threads) {
    hwloc_topology_t topology;
    if (hwloc_topology_init(&topology) != 0) return false;
    bool ok = hwloc_topology_load(topology) == 0;
    int cores = ok ? sb_core_count(topology) : 1;
    int failures = 0;
    if (ok) {
#pragma omp parallel num_threads(threads) reduction(+ : failures)
        {
            hwloc_obj_t core = hwloc_get_obj_by_type(topology, HWLOC_OBJ_CORE, omp_get_thread_num() % cores);
            failures += !core || hwloc_set_cpubind(topology, core->cpuset, HWLOC_CPUBIND_THREAD) != 0;
        }
    }
    hwloc_topology_destroy(topology);
    return ok && failures == 0;
}

static unsigned long long sb_cache_kib(hwloc_topology_t topology, hwloc_obj_type_t type) {
    hwloc_obj_t cache = hwloc_get_obj_by_type(topology, type, 0);
    return cache && cache->attr ? cache->attr->cache.size / 1024 : 0;
}

void sb_runtime_describe(char* out, size_t size) {
    hwloc_topology_t topology;
    if (hwloc_topology_init(&topology) != 0 || hwloc_topology_load(topology) != 0) {
        snprintf(out, size, "topology unknown; SIMD %s; %s", SB_SIMD_NAME, SB_DOUBLE ? "double" : "float");
        return;
    }
    snprintf(out, size, "%d cores, %d PUs, L2 %llu KiB, L3 %llu KiB; SIMD %s (%d lanes); %s", sb_core_count(topology),
             hwloc_get_nbobjs_by_type(topology, HWLOC_OBJ_PU), sb_cache_kib(topology, HWLOC_OBJ_L2CACHE),
             sb_cache_kib(topology, HWLOC_OBJ_L3CACHE), SB_SIMD_NAME, SB_WIDTH, SB_DOUBLE ? "double" : "float");
    hwloc_topology_destroy(topology);
}
