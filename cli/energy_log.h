/* The per-frame log of a run, log.csv, written row by row as the frames
 * come (each row flushed, so a killed run leaves every whole row):
 * time,kinetic,bond,angle,stretch_bend,spring,bend,corotated,membrane,gravity,total (the
 * energies of the frame's state, J) then
 * steps,substeps,rejected,newton,cg,unconverged (the solver's work since
 * the previous frame, from sb_solver_last_step; all 0 on frame 0), then
 * contacts (the vertex contacts of the last advance before the frame) and
 * per collider <name>_fx,<name>_fy,<name>_fz (the force it received from
 * the bodies over that advance, N, sb_solver_contact_force; 0 on frame 0),
 * and, when the model can break (broken_column), broken: the bonds broken
 * so far (sb_solver_broken_count). */
#ifndef SB_ENERGY_LOG_H
#define SB_ENERGY_LOG_H

#include <stdio.h>

#include "softbond/softbond.h"

/* The solver's work over some steps, summed. */
typedef struct sb_step_work {
    uint64_t steps;       /* sb_solver_advance calls */
    uint64_t substeps;    /* sub-steps accepted (= steps without adaptive) */
    uint64_t rejected;    /* adaptive: sub-steps retried at half the size */
    uint64_t newton;      /* implicit_euler: Newton iterations */
    uint64_t cg;          /* implicit_euler: conjugate-gradient iterations */
    uint64_t unconverged; /* implicit_euler: steps whose Newton solve missed its tolerance */
} sb_step_work;

/* Adds one step's statistics to `work`. */
void sb_step_work_add(sb_step_work* work, const sb_step_stats* stats);

typedef struct sb_energy_log {
    FILE* file;    /* log.csv, open from sb_energy_log_open */
    char* path;    /* for messages */
    double* times; /* each row's, for the frames' index */
    uint32_t count, capacity;
    char** collider_names;
    uint32_t collider_count;
    bool broken_column; /* set before the log is opened */
} sb_energy_log;

/* Adds a collider's three force columns; only before the log is opened.
 * Returns false when out of memory. */
bool sb_energy_log_add_collider(sb_energy_log* log, const char* name);
/* Creates (or empties) the file at path and writes the header. */
sb_status sb_energy_log_open(sb_energy_log* log, const char* path, sb_error* err);
/* Goes on with the log at path as a checkpoint left it (cli/checkpoint.h):
 * cut to `bytes` (the rows after the checkpoint are written again), the
 * frames' times taken over (count of them, malloc'd: the log frees them). */
sb_status sb_energy_log_resume(sb_energy_log* log, const char* path, uint64_t bytes, double* times, uint32_t count,
                               sb_error* err);
/* The bytes written so far (every row is flushed). */
uint64_t sb_energy_log_bytes(const sb_energy_log* log);
/* Writes and flushes a row, 17 significant digits; forces holds 3 per
 * collider (may be NULL without colliders); broken is written only with
 * broken_column. */
sb_status sb_energy_log_add(sb_energy_log* log, double time, const sb_energies* energies, const sb_step_work* work,
                            uint32_t contacts, const double* forces, uint32_t broken, sb_error* err);
/* Closes the file (reporting a failed close) and frees the log. */
sb_status sb_energy_log_close(sb_energy_log* log, sb_error* err);

#endif
