/* Files that appear whole or not at all: written to NAME.tmp, renamed to
 * NAME on commit, removed on abort.
 *
 * Only a regular file (or a new one) is replaced so. A symbolic link is
 * followed: its target is written through NAME.tmp beside the target and
 * renamed over it, so the link stays. A path that is not a regular file
 * (a device such as /dev/null or /dev/full, a pipe) is written in place,
 * never replaced; a directory is refused ("is a directory"). */
#ifndef SB_ATOMIC_FILE_H
#define SB_ATOMIC_FILE_H

#include <stdio.h>

#include "softbond/types.h"

typedef struct sb_atomic_file {
    FILE* stream;   /* write here between open and commit */
    char* path;     /* as given, for messages */
    char* target;   /* where the file goes: path, or a link's target */
    char* tmp_path; /* target.tmp; NULL when written in place */
    int error;      /* the first failed sb_atomic_write's errno, 0 before */
} sb_atomic_file;

sb_status sb_atomic_open(sb_atomic_file* file, const char* path, sb_error* err);
/* Where the bytes go until the commit: NAME.tmp, or NAME itself when it
 * is written in place. Another program (povray, ffmpeg) may write there
 * between open and commit. */
static inline const char* sb_atomic_write_path(const sb_atomic_file* file) {
    return file->tmp_path ? file->tmp_path : file->target;
}
/* fwrite that keeps the first failure's errno for commit's message (a full
 * disk said 'Input/output error': the errno was gone by commit). */
void sb_atomic_write(sb_atomic_file* file, const void* data, size_t size);
/* Flushes, closes and renames; on any failure removes NAME.tmp. */
sb_status sb_atomic_commit(sb_atomic_file* file, sb_error* err);
/* Closes and removes NAME.tmp; safe after a failed open. */
void sb_atomic_abort(sb_atomic_file* file);

#endif
