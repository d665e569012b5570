/* The local farm (sweep_job.h): up to --workers runs at once, each a child
 * process; as each ends (waitpid), its row goes into the table and the next
 * case starts. */
#define _POSIX_C_SOURCE 200809L
#include "cli/sweep_job.h"
#include "common/clock.h"
#include "common/error.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

typedef struct slot {
    pid_t pid; /* 0 = free */
    size_t c;
    double start;
} slot;

static sb_status add_row(sb_sweep_job* job, size_t c, char* row, sb_error* err) {
    if (!row) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    return sb_sweep_table_add(&job->table, c, row, err);
}

/* Starts case c in a free slot; a run that cannot start is its row at once. */
static sb_status start(sb_sweep_job* job, slot* s, size_t c, sb_error* err) {
    sb_error why;
    s->c = c;
    s->start = sb_wall_seconds();
    if (sb_sweep_case_start(job, c, &s->pid, &why) == SB_OK) return SB_OK;
    s->pid = 0;
    return add_row(job, c, sb_sweep_case_unstarted(job, c, &why), err);
}

/* Waits for one run to end and records it; returns its slot freed. */
static sb_status reap(sb_sweep_job* job, slot* slots, long count, sb_error* err) {
    int wait_status;
    pid_t pid;
    while ((pid = waitpid(-1, &wait_status, 0)) < 0)
        if (errno != EINTR) return sb_error_set(err, SB_ERR_IO, "waitpid: %s", strerror(errno));
    for (long k = 0; k < count; k++) {
        if (slots[k].pid != pid) continue;
        slots[k].pid = 0;
        return add_row(job, slots[k].c,
                       sb_sweep_case_finish(job, slots[k].c, wait_status, sb_wall_seconds() - slots[k].start), err);
    }
    return SB_OK; /* not a run of ours */
}

sb_status sb_sweep_farm_local(sb_sweep_job* job, sb_error* err) {
    slot* slots = calloc((size_t)job->workers, sizeof *slots);
    if (!slots) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    sb_status status = SB_OK;
    long running = 0;
    size_t next = sb_sweep_next_case(job, 0);
    while (status == SB_OK && (next < job->design.case_count || running > 0)) {
        for (long k = 0; k < job->workers && next < job->design.case_count && status == SB_OK; k++) {
            if (slots[k].pid) continue;
            size_t c = next;
            next = sb_sweep_next_case(job, next + 1);
            status = start(job, &slots[k], c, err);
        }
        running = 0;
        for (long k = 0; k < job->workers; k++) running += slots[k].pid != 0;
        if (status == SB_OK && running > 0) status = reap(job, slots, job->workers, err);
        running = 0;
        for (long k = 0; k < job->workers; k++) running += slots[k].pid != 0;
    }
    free(slots);
    return status;
}
