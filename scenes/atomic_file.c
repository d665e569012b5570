/* Atomic files (see atomic_file.h). */
#define _POSIX_C_SOURCE 200809L
#include "scenes/atomic_file.h"
#include "common/error.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

static void release(sb_atomic_file* file) {
    free(file->path);
    free(file->tmp_path);
    file->stream = NULL;
    file->path = file->tmp_path = NULL;
}

static sb_status fail(sb_atomic_file* file, sb_error* err, const char* what) {
    sb_error_set(err, SB_ERR_IO, "%s: %s: %s", file->path, what, strerror(errno));
    sb_atomic_abort(file);
    return SB_ERR_IO;
}

sb_status sb_atomic_open(sb_atomic_file* file, const char* path, sb_error* err) {
    size_t size = strlen(path) + 5;
    file->stream = NULL;
    file->path = strdup(path);
    file->tmp_path = malloc(size);
    if (!file->path || !file->tmp_path) {
        release(file);
        return sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    }
    snprintf(file->tmp_path, size, "%s.tmp", path);
    file->stream = fopen(file->tmp_path, "wb");
    return file->stream ? SB_OK : fail(file, err, "cannot write");
}

sb_status sb_atomic_commit(sb_atomic_file* file, sb_error* err) {
    bool written = fflush(file->stream) == 0 && !ferror(file->stream);
    int closed = fclose(file->stream);
    file->stream = NULL;
    if (!written || closed != 0) return fail(file, err, "cannot write");
    if (rename(file->tmp_path, file->path) != 0) return fail(file, err, "cannot rename");
    release(file);
    return SB_OK;
}

void sb_atomic_abort(sb_atomic_file* file) {
    if (file->stream) fclose(file->stream);
    if (file->tmp_path) remove(file->tmp_path);
    release(file);
}
