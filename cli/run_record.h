/* run.yaml in every output folder: how the run was made. The resolved
 * scene (sb_scene_write: every key, after --set, defaults included, the
 * paths absolute), so that `softbond run OUT/run.yaml` runs it again
 * bitwise, under comments naming the program's version and commit, the
 * precision, the SIMD level, the kernels, the thread count, the machine
 * and the command line. Written atomically. */
#ifndef SB_RUN_RECORD_H
#define SB_RUN_RECORD_H

#include "scenes/scene.h"

typedef struct sb_run_record {
    const sb_scene* scene;
    int threads;       /* the solver's team */
    int argc;          /* the command's arguments, "run" first */
    char* const* argv;
} sb_run_record;

sb_status sb_run_record_write(const char* path, const sb_run_record* record, sb_error* err);

#endif
