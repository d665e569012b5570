/* A sweep under way: its file, its cases, its results table, and how each
 * case is run (study_case.h) — shared by the farms that hand the cases out:
 * worker processes on this machine (sweep_farm.c) or MPI ranks
 * (sweep_mpi.c). */
#ifndef SB_SWEEP_JOB_H
#define SB_SWEEP_JOB_H

#include <sys/types.h>

#include "cli/study_mpi.h"
#include "cli/sweep_design.h"
#include "cli/sweep_spec.h"
#include "cli/sweep_table.h"

typedef struct sb_sweep_job {
    sb_sweep_spec spec;
    sb_sweep_design design;
    sb_sweep_table table;    /* rank 0's (the one that writes) */
    char* dir;               /* the sweep's folder: sweep.csv, cases/, the charts */
    const char* const* sets; /* the command line's --set, after the file's */
    size_t set_count;
    const char* threads; /* --threads of each run, or NULL */
    long workers;        /* --workers: runs at once on this machine */
} sb_sweep_job;

/* Starts case c's run in DIR/cases/NNNNNN. */
sb_status sb_sweep_case_start(const sb_sweep_job* job, size_t c, pid_t* pid, sb_error* err);
/* Case c's row once its run ended (waitpid's status), its folder removed
 * unless keep_outputs; NULL when out of memory. */
char* sb_sweep_case_finish(const sb_sweep_job* job, size_t c, int wait_status, double seconds);
/* Runs case c to its end: its row (a run that could not start is a row too). */
char* sb_sweep_case_run(const sb_sweep_job* job, size_t c);
/* The row of a case whose run could not start: status 1 and why. */
char* sb_sweep_case_unstarted(const sb_sweep_job* job, size_t c, const sb_error* why);

/* The next case from c on that the table does not hold yet (case_count when none). */
size_t sb_sweep_next_case(const sb_sweep_job* job, size_t c);

/* The farms: each runs every case the table lacks and adds its row. */
sb_status sb_sweep_farm_local(sb_sweep_job* job, sb_error* err);
/* Under mpirun with size > 1: rank 0 hands out the cases and writes the
 * table, the others run them. */
sb_status sb_sweep_farm_mpi(sb_sweep_job* job, int rank, int size, sb_error* err);

#endif
