/* Files that appear whole or not at all: written to NAME.tmp, renamed to
 * NAME on commit, removed on abort. */
#ifndef SB_ATOMIC_FILE_H
#define SB_ATOMIC_FILE_H

#include <stdio.h>

#include "softbond/types.h"

typedef struct sb_atomic_file {
    FILE* stream; /* write here between open and commit */
    char* path;
    char* tmp_path;
} sb_atomic_file;

sb_status sb_atomic_open(sb_atomic_file* file, const char* path, sb_error* err);
/* Flushes, closes and renames; on any failure removes NAME.tmp. */
sb_status sb_atomic_commit(sb_atomic_file* file, sb_error* err);
/* Closes and removes NAME.tmp; safe after a failed open. */
void sb_atomic_abort(sb_atomic_file* file);

#endif
