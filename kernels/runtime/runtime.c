/* The parallel runtime: how many threads, the wait policies' names, and a
 * description of the machine (hwloc). The team itself is kernels/runtime/team.c. */
#define _GNU_SOURCE
#include "softbond/runtime.h"
#include "common/error.h"
#include "common/name_table.h"
#include "kernels/runtime/wide.h"

#include <errno.h>
#include <hwloc.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char* const sb_wait_names[SB_WAIT_COUNT] = {"spin", "yield", "passive"};

const char* sb_wait_policy_name(sb_wait_policy policy) { return sb_name_of(sb_wait_names, SB_WAIT_COUNT, (int)policy); }

bool sb_wait_policy_from_name(const char* name, sb_wait_policy* out) {
    int i = sb_name_index(sb_wait_names, SB_WAIT_COUNT, name);
    if (i >= 0) *out = (sb_wait_policy)i;
    return i >= 0;
}

sb_runtime_def sb_default_runtime_def(void) {
    return (sb_runtime_def){.threads = 0, .pin = false, .wait = SB_WAIT_PASSIVE, .fixed_width = false};
}

/* The processors this process may run on. */
static int sb_available_processors(void) {
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0) return CPU_COUNT(&set);
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

int sb_runtime_threads(int requested, sb_error* err) {
    if (requested > SB_MAX_THREADS) {
        sb_error_set(err, SB_ERR_INVALID, "threads: %d is above the most a solver takes (%d)", requested,
                     SB_MAX_THREADS);
        return -1;
    }
    if (requested > 0) return requested;
    const char* env = getenv("SOFTBOND_THREADS");
    if (env && *env) {
        char* end;
        errno = 0;
        long n = strtol(env, &end, 10);
        if (errno || *end || n < 1 || n > SB_MAX_THREADS) {
            sb_error_set(err, SB_ERR_INVALID, "SOFTBOND_THREADS='%s' is not a thread count from 1 to %d", env,
                         SB_MAX_THREADS);
            return -1;
        }
        return (int)n;
    }
    int processors = sb_available_processors();
    return processors < SB_MAX_THREADS ? processors : SB_MAX_THREADS;
}

const char* sb_runtime_simd(void) { return SB_SIMD_NAME; }

static int sb_core_count(hwloc_topology_t topology) {
    int cores = hwloc_get_nbobjs_by_type(topology, HWLOC_OBJ_CORE);
    return cores > 0 ? cores : 1;
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
