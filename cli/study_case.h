/* One run of a study (sweep, fit): `softbond run` of the base scene with
 * the case's overrides, as a child process of this program (its own
 * executable, /proc/self/exe), its output folder DIR holding log.csv,
 * run.yaml, end_positions.csv and its stdout.txt and stderr.txt.
 *
 * A child per case keeps a case's failure — a blow-up, a bad value, even a
 * crash — inside that case: the study records it and goes on. */
#ifndef SB_STUDY_CASE_H
#define SB_STUDY_CASE_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

#include "softbond/types.h"

typedef struct sb_study_run {
    const char* scene;
    const char* const* sets; /* "key=value", in order: later ones win */
    size_t set_count;
    const char* dir;     /* the run's output folder, made if missing */
    const char* threads; /* --threads N of each run, or NULL */
} sb_study_run;

/* What became of a run: its exit status (0 done, 1 output, 2 input, 3
 * solver; 128 + N killed by signal N) and, when it failed, the last line
 * of its stderr without the "softbond: " prefix. */
typedef struct sb_study_outcome {
    int status;
    char message[512];
} sb_study_outcome;

/* The environment variable by which a run knows the study that started
 * it: the study's pid. */
#define SB_STUDY_PARENT_ENV "SOFTBOND_STUDY_PARENT"

/* Starts the run; its pid in *pid. The run ends with the study (see
 * sb_study_end_with_parent). */
sb_status sb_study_spawn(const sb_study_run* run, pid_t* pid, sb_error* err);
/* The outcome of a run that waitpid reported with wait_status. */
void sb_study_outcome_read(int wait_status, const char* dir, sb_study_outcome* out);
/* Starts the run and waits for it. */
sb_status sb_study_run_wait(const sb_study_run* run, sb_study_outcome* out, sb_error* err);

/* In a run a study started (SB_STUDY_PARENT_ENV set): asks the kernel to
 * end this process when the study ends, and ends it at once if the study
 * already has. A study killed midway (a sweep stopped by SIGKILL, to be
 * resumed) would otherwise leave its runs writing into their cases'
 * folders, where the resumed study runs the same cases again: two runs
 * in one folder, one of them failing on the other's files. Nothing
 * outside a study's runs. */
void sb_study_end_with_parent(void);

/* Removes the folder and the files in it (a run's folder has no subfolders
 * unless frames were written in one). */
void sb_study_remove_dir(const char* dir);

#endif
