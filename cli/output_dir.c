/* The output folder (see output_dir.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/output_dir.h"
#include "common/error.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* errno ENOTDIR when path is there but not a folder (mkdir's EEXIST read
 * 'File exists', as if the folder were the trouble). */
static bool make_one(const char* path) {
    struct stat info;
    if (mkdir(path, 0777) == 0) return true;
    if (errno != EEXIST) return false;
    if (stat(path, &info) == 0 && S_ISDIR(info.st_mode)) return true;
    errno = ENOTDIR;
    return false;
}

/* Makes every prefix of path that ends before a '/', then path itself. */
static bool make_parents(char* path) {
    if (path[0] == '\0') {
        errno = ENOENT;
        return false;
    }
    for (char* slash = strchr(path + 1, '/'); slash; slash = strchr(slash + 1, '/')) {
        *slash = '\0';
        bool made = make_one(path);
        *slash = '/';
        if (!made) return false;
    }
    return make_one(path);
}

sb_status sb_output_dir_create(sb_output_dir* out, const char* requested, const char* scene_name, sb_error* err) {
    size_t size = requested ? strlen(requested) + 1 : strlen(scene_name) + 5;
    out->dir = malloc(size);
    if (!out->dir) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    if (requested)
        snprintf(out->dir, size, "%s", requested);
    else
        snprintf(out->dir, size, "out/%s", scene_name);
    if (make_parents(out->dir)) return SB_OK;
    if (errno == ENOTDIR)
        return sb_error_set(err, SB_ERR_IO,
                            "%s: cannot create the output folder: it, or a folder above it, is a file (not a folder)",
                            out->dir);
    return sb_error_set(err, SB_ERR_IO, "%s: cannot create the output folder: %s", out->dir, strerror(errno));
}

const char* sb_output_dir_path(sb_output_dir* out, const char* file) {
    snprintf(out->path, sizeof out->path, "%s/%s", out->dir, file);
    return out->path;
}

void sb_output_dir_free(sb_output_dir* out) {
    free(out->dir);
    out->dir = NULL;
}
