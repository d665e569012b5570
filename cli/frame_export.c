/* Atomic frames in each format (see frame_export.h).
 *
 * One table maps a format (scenes/frame_formats.h) to its extension and writer: vtu writes
 * the surface and the bonds (vtk.c), every other format goes through
 * sb_mesh_export (ply, obj, gltf, glb by assimp; irit and pov by softbond).
 *
 * A frame in one format can be several files: the .vtu and its bonds .vtu,
 * an OBJ and its .mtl, a glTF and its .bin. They are written under their
 * final names into a staging folder DIR/.frame_000042.<ext>.tmp, then
 * renamed into DIR one by one (a rename within one file system is atomic),
 * companions first and the main file last; the staging folder is then
 * removed. A failed write removes the staging folder and what it held. A
 * crash may leave a staging folder or a companion behind, never a main file
 * half written or without its companions; a later run clears a stale
 * staging folder of the same name before it uses it. */
#define _POSIX_C_SOURCE 200809L
#include "cli/frame_export.h"
#include "common/error.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct staging {
    char dir[4096];  /* DIR/.frame_000042.<ext>.tmp */
    char main[4096]; /* the main file inside it */
    const char* out; /* DIR */
    const char* main_name;
} staging;

/* ---- paths and the staging folder ------------------------------------------ */

static sb_status join(char* out, const char* dir, const char* name, sb_error* err) {
    int length = snprintf(out, 4096, "%s/%s", dir, name);
    if (length >= 0 && length < 4096) return SB_OK;
    return sb_error_set(err, SB_ERR_IO, "%s/%s: path too long", dir, name);
}

static bool is_entry(const char* name) { return strcmp(name, ".") != 0 && strcmp(name, "..") != 0; }

/* Removes the staging folder and everything in it; quiet when absent. */
static void stage_remove(const staging* stage) {
    DIR* dir = opendir(stage->dir);
    struct dirent* entry;
    char path[4096];
    while (dir && (entry = readdir(dir)))
        if (is_entry(entry->d_name) && join(path, stage->dir, entry->d_name, NULL) == SB_OK) remove(path);
    if (dir) closedir(dir);
    rmdir(stage->dir);
}

static sb_status stage_create(staging* stage, const char* out, const char* main_name, sb_error* err) {
    char name[64];
    snprintf(name, sizeof name, ".%.40s.tmp", main_name);
    stage->out = out;
    stage->main_name = main_name;
    sb_status status = join(stage->dir, out, name, err);
    if (status == SB_OK) status = join(stage->main, stage->dir, main_name, err);
    if (status != SB_OK) return status;
    stage_remove(stage);
    if (mkdir(stage->dir, 0777) == 0) return SB_OK;
    return sb_error_set(err, SB_ERR_IO, "%s: cannot create: %s", stage->dir, strerror(errno));
}

static sb_status move_out(const staging* stage, const char* name, sb_error* err) {
    char from[4096], to[4096];
    sb_status status = join(from, stage->dir, name, err);
    if (status == SB_OK) status = join(to, stage->out, name, err);
    if (status != SB_OK || rename(from, to) == 0) return status;
    return sb_error_set(err, SB_ERR_IO, "%s: cannot rename to %s: %s", from, to, strerror(errno));
}

static sb_status move_companions(const staging* stage, sb_error* err) {
    DIR* dir = opendir(stage->dir);
    if (!dir) return sb_error_set(err, SB_ERR_IO, "%s: cannot list: %s", stage->dir, strerror(errno));
    sb_status status = SB_OK;
    struct dirent* entry;
    while (status == SB_OK && (entry = readdir(dir)))
        if (is_entry(entry->d_name) && strcmp(entry->d_name, stage->main_name) != 0)
            status = move_out(stage, entry->d_name, err);
    closedir(dir);
    return status;
}

/* Companions first, the main file last. */
static sb_status stage_publish(const staging* stage, sb_error* err) {
    sb_status status = move_companions(stage, err);
    if (status == SB_OK) status = move_out(stage, stage->main_name, err);
    stage_remove(stage);
    return status;
}

/* ---- writers --------------------------------------------------------------- */

/* One frame in one format, to write into its staging folder. */
typedef struct frame_job {
    const char* format;
    const staging* stage;
    uint32_t index;
    const sb_vtk_frame* frame;
    const double* up;
} frame_job;

static sb_status write_vtu(const frame_job* job, sb_error* err) {
    char name[64], path[4096];
    sb_vtk_frame_name(job->index, "_bonds.vtu", name, sizeof name);
    sb_status status = join(path, job->stage->dir, name, err);
    if (status == SB_OK) status = sb_vtk_write_bonds(path, job->frame, err);
    if (status == SB_OK) status = sb_vtk_write_frame(job->stage->main, job->frame, err);
    return status;
}

static sb_status write_mesh(const frame_job* job, sb_error* err) {
    sb_mesh_export_def def = sb_default_mesh_export_def();
    def.positions = job->frame->positions;
    for (int k = 0; k < 3; k++) def.up[k] = job->up[k];
    return sb_mesh_export(job->stage->main, job->format, job->frame->mesh, &def, err);
}

/* ---- the table ------------------------------------------------------------- */

typedef sb_status (*frame_writer)(const frame_job* job, sb_error* err);

typedef struct frame_format {
    const char* extension; /* NULL: sb_mesh_export_extension's */
    frame_writer write;
} frame_format;

/* In the bit order of scenes/frame_formats.c's names. */
static const frame_format formats[SB_FRAME_FORMAT_COUNT] = {
    {".vtu", write_vtu}, {NULL, write_mesh}, {NULL, write_mesh}, {NULL, write_mesh},
    {NULL, write_mesh},  {NULL, write_mesh}, {NULL, write_mesh},
};

static sb_status export_one(uint32_t i, const sb_frame_export_def* def, const char* out, uint32_t index,
                            const sb_vtk_frame* frame, sb_error* err) {
    const frame_format* format = &formats[i];
    const char* name = sb_frame_format_name(i);
    const char* extension = format->extension ? format->extension : sb_mesh_export_extension(name);
    char main_name[64];
    sb_vtk_frame_name(index, extension, main_name, sizeof main_name);
    staging stage;
    sb_status status = stage_create(&stage, out, main_name, err);
    if (status != SB_OK) return status;
    status = format->write(&(frame_job){name, &stage, index, frame, def->up}, err);
    if (status == SB_OK) return stage_publish(&stage, err);
    stage_remove(&stage);
    return status;
}

sb_status sb_frame_export(const sb_frame_export_def* def, const sb_output_dir* out, uint32_t index,
                          const sb_vtk_frame* frame, sb_error* err) {
    for (uint32_t i = 0; i < SB_FRAME_FORMAT_COUNT; i++) {
        if (!(def->formats & (1u << i))) continue;
        sb_status status = export_one(i, def, out->dir, index, frame, err);
        if (status != SB_OK) return status;
    }
    return SB_OK;
}
