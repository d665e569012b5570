/* The MPI a study uses (cli/sweep_mpi.c; Open MPI, CMake option SB_MPI):
 * starting and ending it under mpirun, and a fit's results gathered from
 * every rank. Without MPI, or when not started by mpirun, this process is
 * rank 0 of 1 and the calls do nothing. */
#ifndef SB_STUDY_MPI_H
#define SB_STUDY_MPI_H

#include <stddef.h>

#include "softbond/types.h"

/* MPI_Init under mpirun: this rank and the rank count (0 and 1 otherwise).
 * A program built without MPI refuses to run as one of several ranks. */
sb_status sb_study_mpi_begin(int* rank, int* size, sb_error* err);
/* MPI_Finalize; with code != 0, MPI_Abort (the other ranks may wait on this one). */
void sb_study_mpi_end(int code);

/* Every rank's best fit made every rank's: the lowest score, the keys and
 * the curve of the rank that had it; evaluations summed over the ranks. */
void sb_study_mpi_best(double* score, double* keys, size_t key_count, double* curve, size_t curve_count,
                       long* evaluations);

#endif
