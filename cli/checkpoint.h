/* `softbond run`'s checkpoints: --checkpoint-every T writes
 * DIR/checkpoint.sbck (atomically, cli/atomic_file.c) after the first
 * frame at or past each multiple of T seconds of simulated time; --resume
 * DIR reads it back and the run goes on from that frame as if it had not
 * stopped. The file is common/sections.h's layout (magic "SBCHKPNT"): the
 * header's hash is the scene's (every resolved key but the duration, and
 * the bytes of every file the scene reads, so a checkpoint of another
 * scene, of the same scene with other --set values, or with a mesh file
 * edited since, is refused; the "FILE" section lists the files and their
 * hashes, so the refusal names the file that changed), its vertex count
 * the mesh's; the sections are the
 * run's own state ("RUN ": the frames written, log.csv's length after
 * them, the interval and when the next checkpoint is due, the stop
 * conditions' state; "TIME": each frame's time, for frames.pvd) and the
 * solver's saved state ("SOLV", sb_solver_save_state: the solver's own
 * header, hash and checksum inside). */
#ifndef SB_CHECKPOINT_H
#define SB_CHECKPOINT_H

#include "cli/cli.h"
#include "cli/stop.h"

/* The files a scene reads (mesh.file, the colliders' files; a TetGen
 * mesh's other file), absolute, and the hash of each one's bytes. */
enum { SB_CHECKPOINT_FILES_MAX = 64 };
typedef struct sb_checkpoint_files {
    uint32_t count;
    char* paths[SB_CHECKPOINT_FILES_MAX];
    uint64_t hashes[SB_CHECKPOINT_FILES_MAX];
} sb_checkpoint_files;

void sb_checkpoint_files_free(sb_checkpoint_files* files);

/* The run's side of a checkpoint. */
typedef struct sb_run_state {
    uint64_t frames;    /* frames written (rows of log.csv) */
    uint64_t log_bytes; /* log.csv's length after them */
    double every, next; /* s: the interval, and when the next checkpoint is due */
    sb_stop stop;
    double* times; /* each frame's time (frames of them; read: the caller frees) */
    const sb_checkpoint_files* files; /* written: the scene's files ("FILE" section), or NULL */
} sb_run_state;

/* The hash a checkpoint of this scene carries: the resolved scene (every
 * key's value after --set, as sb_scene_write gives it) but its duration, so
 * that --resume may go on to a longer one, and the bytes of every file the
 * scene reads (files, when not NULL, gets their paths and hashes: the
 * caller frees them); args is not used. */
sb_status sb_checkpoint_scene_hash(const sb_scene* scene, const sb_cli_args* args, uint64_t* hash,
                                   sb_checkpoint_files* files, sb_error* err);

/* Writes the checkpoint at path atomically. */
sb_status sb_checkpoint_write(const char* path, uint64_t scene_hash, uint32_t vertex_count, const sb_run_state* run,
                              const sb_solver* solver, sb_error* err);

/* Reads the checkpoint at path: checks it whole (one line naming the path
 * for a missing, truncated or corrupt file, another format version, the
 * other precision, another scene or mesh, more than max_frames frames),
 * then loads the solver's state (made as the saving run's was) and fills
 * run. Nothing is changed when it fails. */
sb_status sb_checkpoint_read(const char* path, uint64_t scene_hash, uint32_t vertex_count, uint64_t max_frames,
                             sb_run_state* run, sb_solver* solver, sb_error* err);

#endif
