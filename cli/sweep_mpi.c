/* The MPI task farm (sweep_job.h) and the studies' MPI (study_mpi.h), with Open MPI: every rank reads the
 * sweep file and makes the same cases; rank 0 hands out case numbers one
 * at a time, each other rank runs the case it is given (a child process,
 * as the local farm does: a case that crashes does not take its rank with
 * it) and sends back the case's row, and rank 0 writes it into the table
 * and hands that rank the next case, until none is left and each rank is
 * told to stop. Results are gathered as they finish, in any order; the
 * table is the same whatever the rank count, but for wall times.
 *
 * A rank that dies: Open MPI 4 (Debian 12's) has no fault tolerance that a
 * program can use (the ULFM extensions are Open MPI 5's, and off by
 * default): when a rank exits abnormally, mpirun ends the whole job. The
 * table on disk is then whole, holding every case finished before; the
 * cases that were running are not in it, and `--resume DIR` runs them
 * again, with the cases never started. Within a rank, a case's own crash
 * is a row with its signal, like any failure.
 *
 * Without MPI (SB_MPI off) the command runs the local farm only. */
#define _POSIX_C_SOURCE 200809L
#include "cli/sweep_job.h"
#include "common/error.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifdef SB_MPI
#include <mpi.h>

enum { TAG_CASE = 1, TAG_ROW = 2 };
static const unsigned long long STOP = ~0ull;

/* mpirun (Open MPI's, or a PMIx launcher) sets these in each rank. */
static bool launched(void) { return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMIX_RANK"); }

/* Rank 0: the next case to `rank`, or STOP. */
static void hand_out(sb_sweep_job* job, int rank, size_t* next) {
    unsigned long long c = *next < job->design.case_count ? (unsigned long long)*next : STOP;
    if (*next < job->design.case_count) *next = sb_sweep_next_case(job, *next + 1);
    MPI_Send(&c, 1, MPI_UNSIGNED_LONG_LONG, rank, TAG_CASE, MPI_COMM_WORLD);
}

/* Waits for a row from any rank. Open MPI's blocking probe spins on its
 * shared-memory queue and would take a core from the runs; rank 0 only
 * hands out work, so it looks every millisecond and sleeps in between. */
static void wait_for_row(MPI_Status* probe) {
    int arrived = 0;
    for (;;) {
        MPI_Iprobe(MPI_ANY_SOURCE, TAG_ROW, MPI_COMM_WORLD, &arrived, probe);
        if (arrived) return;
        nanosleep(&(struct timespec){0, 1000000}, NULL);
    }
}

/* Rank 0: one row from any rank, added; the next case sent there. */
static sb_status gather_one(sb_sweep_job* job, size_t* next, sb_error* err) {
    MPI_Status probe;
    wait_for_row(&probe);
    int length;
    MPI_Get_count(&probe, MPI_CHAR, &length);
    char* row = malloc((size_t)length + 1);
    if (!row) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    MPI_Recv(row, length, MPI_CHAR, probe.MPI_SOURCE, TAG_ROW, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    row[length] = '\0';
    size_t c = (size_t)strtoull(row, NULL, 10);
    sb_status status = sb_sweep_table_add(&job->table, c, row, err);
    hand_out(job, probe.MPI_SOURCE, next);
    return status;
}

static sb_status lead(sb_sweep_job* job, int size, sb_error* err) {
    size_t next = sb_sweep_next_case(job, 0);
    int busy = 0;
    for (int rank = 1; rank < size; rank++) {
        busy += next < job->design.case_count;
        hand_out(job, rank, &next);
    }
    sb_status status = SB_OK;
    while (busy > 0) {
        bool more = next < job->design.case_count; /* the rank that answers gets another case, or stops */
        sb_status one = gather_one(job, &next, err);
        if (status == SB_OK) status = one;
        busy -= !more;
    }
    return status;
}

static sb_status follow(sb_sweep_job* job, sb_error* err) {
    for (;;) {
        unsigned long long c;
        MPI_Recv(&c, 1, MPI_UNSIGNED_LONG_LONG, 0, TAG_CASE, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (c == STOP) return SB_OK;
        char* row = sb_sweep_case_run(job, (size_t)c);
        if (!row) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
        MPI_Send(row, (int)strlen(row), MPI_CHAR, 0, TAG_ROW, MPI_COMM_WORLD);
        free(row);
    }
}

sb_status sb_study_mpi_begin(int* rank, int* size, sb_error* err) {
    (void)err;
    *rank = 0, *size = 1;
    if (!launched()) return SB_OK;
    MPI_Init(NULL, NULL);
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
    return SB_OK;
}

void sb_study_mpi_end(int code) {
    if (!launched()) return;
    if (code != 0) MPI_Abort(MPI_COMM_WORLD, code);
    MPI_Finalize();
}

sb_status sb_sweep_farm_mpi(sb_sweep_job* job, int rank, int size, sb_error* err) {
    return rank == 0 ? lead(job, size, err) : follow(job, err);
}

void sb_study_mpi_best(double* score, double* keys, size_t key_count, double* curve, size_t curve_count,
                       long* evaluations) {
    if (!launched()) return;
    int rank;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    struct {
        double score;
        int rank;
    } mine = {*score, rank}, best;
    MPI_Allreduce(&mine, &best, 1, MPI_DOUBLE_INT, MPI_MINLOC, MPI_COMM_WORLD);
    *score = best.score;
    MPI_Bcast(keys, (int)key_count, MPI_DOUBLE, best.rank, MPI_COMM_WORLD);
    MPI_Bcast(curve, (int)curve_count, MPI_DOUBLE, best.rank, MPI_COMM_WORLD);
    long total;
    MPI_Allreduce(evaluations, &total, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    *evaluations = total;
}

#else

/* Started by mpirun with more than one rank: each would run the whole sweep. */
sb_status sb_study_mpi_begin(int* rank, int* size, sb_error* err) {
    *rank = 0, *size = 1;
    const char* ranks = getenv("OMPI_COMM_WORLD_SIZE");
    if (ranks && atoi(ranks) > 1)
        return sb_error_set(err, SB_ERR_INVALID,
                            "this softbond is built without MPI (CMake option SB_MPI off): run the sweep without "
                            "mpirun (--workers N), or build with Open MPI (libopenmpi-dev)");
    return SB_OK;
}

void sb_study_mpi_end(int code) { (void)code; }

sb_status sb_sweep_farm_mpi(sb_sweep_job* job, int rank, int size, sb_error* err) {
    (void)rank, (void)size;
    return sb_sweep_farm_local(job, err);
}

void sb_study_mpi_best(double* score, double* keys, size_t key_count, double* curve, size_t curve_count,
                       long* evaluations) {
    (void)score, (void)keys, (void)key_count, (void)curve, (void)curve_count, (void)evaluations;
}

#endif
