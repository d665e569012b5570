/* Atomic files (see atomic_file.h). */
#define _XOPEN_SOURCE 700
#include "common/atomic_file.h"
#include "common/error.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static void release(sb_atomic_file* file) {
    free(file->path);
    free(file->target);
    free(file->tmp_path);
    file->stream = NULL;
    file->path = file->target = file->tmp_path = NULL;
}

static sb_status fail(sb_atomic_file* file, sb_error* err, const char* what, int code) {
    sb_error_set(err, SB_ERR_IO, "%s: %s: %s", file->path, what, strerror(code));
    sb_atomic_abort(file);
    return SB_ERR_IO;
}

/* Where to write: the path itself, or the target of a link (a dangling
 * link is written through, in place). *in_place when it is not a
 * regular file. */
static char* resolve_target(const char* path, bool* in_place) {
    struct stat info;
    *in_place = false;
    if (lstat(path, &info) != 0) return strdup(path); /* a new file */
    if (S_ISLNK(info.st_mode)) {
        char* target = realpath(path, NULL);
        if (target && stat(target, &info) == 0) {
            *in_place = !S_ISREG(info.st_mode);
            return target;
        }
        free(target);
        *in_place = true;
        return strdup(path);
    }
    *in_place = !S_ISREG(info.st_mode);
    return strdup(path);
}

static bool is_directory(const char* path) {
    struct stat info;
    return stat(path, &info) == 0 && S_ISDIR(info.st_mode);
}

sb_status sb_atomic_open(sb_atomic_file* file, const char* path, sb_error* err) {
    bool in_place;
    *file = (sb_atomic_file){.path = strdup(path), .target = resolve_target(path, &in_place)};
    if (!file->path || !file->target) {
        release(file);
        return sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    }
    if (is_directory(file->target)) {
        release(file);
        return sb_error_set(err, SB_ERR_IO, "%s: is a directory", path);
    }
    if (in_place) {
        file->stream = fopen(file->target, "wb");
        return file->stream ? SB_OK : fail(file, err, "cannot write", errno);
    }
    size_t size = strlen(file->target) + 5;
    if (!(file->tmp_path = malloc(size))) {
        release(file);
        return sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    }
    snprintf(file->tmp_path, size, "%s.tmp", file->target);
    file->stream = fopen(file->tmp_path, "wb");
    return file->stream ? SB_OK : fail(file, err, "cannot write", errno);
}

void sb_atomic_write(sb_atomic_file* file, const void* data, size_t size) {
    errno = 0;
    if (fwrite(data, 1, size, file->stream) != size && !file->error) file->error = errno ? errno : EIO;
}

sb_status sb_atomic_commit(sb_atomic_file* file, sb_error* err) {
    errno = 0;
    bool written = fflush(file->stream) == 0 && !ferror(file->stream);
    int code = file->error ? file->error : errno;
    int closed = fclose(file->stream);
    if (closed != 0 && written) code = errno;
    file->stream = NULL;
    if (!written || closed != 0) return fail(file, err, "cannot write", code ? code : EIO);
    if (file->tmp_path && rename(file->tmp_path, file->target) != 0) return fail(file, err, "cannot rename", errno);
    release(file);
    return SB_OK;
}

void sb_atomic_abort(sb_atomic_file* file) {
    if (file->stream) fclose(file->stream);
    if (file->tmp_path) remove(file->tmp_path);
    release(file);
}
