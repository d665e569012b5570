/* A sweep's cases, run (see sweep_job.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/sweep_job.h"
#include "cli/study_case.h"
#include "cli/sweep_row.h"
#include "common/clock.h"
#include "common/error.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

enum { CASE_DIR_SIZE = 4096 };

static void case_dir(const sb_sweep_job* job, size_t c, char* out, size_t size) {
    snprintf(out, size, "%s/cases/%06zu", job->dir, c);
}

/* The file's sets, the command line's, the case's values, and (unless the
 * outputs are kept) no frames. */
typedef struct case_sets {
    const char** all;
    char* values; /* axis_count texts of SB_SWEEP_VALUE_SIZE + 256 bytes */
    size_t count;
} case_sets;

enum { SET_SIZE = SB_SWEEP_VALUE_SIZE + 256 };

static sb_status make_sets(const sb_sweep_job* job, size_t c, case_sets* s, sb_error* err) {
    const sb_sweep_spec* spec = &job->spec;
    size_t most = spec->set_count + job->set_count + spec->axis_count + 1;
    s->all = calloc(most, sizeof *s->all);
    s->values = malloc(spec->axis_count * SET_SIZE + 1);
    if (!s->all || !s->values) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    s->count = 0;
    for (size_t i = 0; i < spec->set_count; i++) s->all[s->count++] = spec->sets[i];
    for (size_t i = 0; i < job->set_count; i++) s->all[s->count++] = job->sets[i];
    for (size_t a = 0; a < spec->axis_count; a++) {
        char* text = s->values + a * SET_SIZE;
        sb_sweep_design_set(spec, &job->design, c, a, text, SET_SIZE);
        s->all[s->count++] = text;
    }
    if (!spec->keep_outputs) s->all[s->count++] = "output.frames=false";
    return SB_OK;
}

static void free_sets(case_sets* s) {
    free(s->all);
    free(s->values);
}

sb_status sb_sweep_case_start(const sb_sweep_job* job, size_t c, pid_t* pid, sb_error* err) {
    char dir[CASE_DIR_SIZE];
    case_dir(job, c, dir, sizeof dir);
    case_sets sets = {0};
    sb_status status = make_sets(job, c, &sets, err);
    sb_study_run run = {job->spec.scene, sets.all, sets.count, dir, job->threads};
    if (status == SB_OK) status = sb_study_spawn(&run, pid, err);
    free_sets(&sets);
    return status;
}

char* sb_sweep_case_finish(const sb_sweep_job* job, size_t c, int wait_status, double seconds) {
    char dir[CASE_DIR_SIZE];
    case_dir(job, c, dir, sizeof dir);
    sb_study_outcome outcome;
    sb_study_outcome_read(wait_status, dir, &outcome);
    char* row = sb_sweep_row(&job->spec, &job->design, c, dir, &outcome, seconds);
    if (!job->spec.keep_outputs) sb_study_remove_dir(dir);
    return row;
}

char* sb_sweep_case_unstarted(const sb_sweep_job* job, size_t c, const sb_error* why) {
    sb_study_outcome outcome = {.status = 1};
    snprintf(outcome.message, sizeof outcome.message, "%s", why->message);
    return sb_sweep_row(&job->spec, &job->design, c, "", &outcome, 0.0);
}

char* sb_sweep_case_run(const sb_sweep_job* job, size_t c) {
    double start = sb_wall_seconds();
    pid_t pid;
    sb_error err;
    if (sb_sweep_case_start(job, c, &pid, &err) != SB_OK) return sb_sweep_case_unstarted(job, c, &err);
    int wait_status = 0;
    while (waitpid(pid, &wait_status, 0) < 0 && errno == EINTR) continue;
    return sb_sweep_case_finish(job, c, wait_status, sb_wall_seconds() - start);
}

size_t sb_sweep_next_case(const sb_sweep_job* job, size_t c) {
    while (c < job->design.case_count && job->table.rows && job->table.rows[c]) c++;
    return c;
}
