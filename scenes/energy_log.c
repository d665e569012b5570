/* The energy log (see energy_log.h). */
#include "scenes/energy_log.h"
#include "scenes/atomic_file.h"

#include <stdlib.h>

static bool grow(sb_energy_log* log) {
    uint32_t capacity = log->capacity ? 2 * log->capacity : 64;
    double* times = realloc(log->times, capacity * sizeof *times);
    if (times) log->times = times;
    sb_energies* energies = realloc(log->energies, capacity * sizeof *energies);
    if (energies) log->energies = energies;
    sb_step_work* work = realloc(log->work, capacity * sizeof *work);
    if (work) log->work = work;
    if (!times || !energies || !work) return false;
    log->capacity = capacity;
    return true;
}

void sb_step_work_add(sb_step_work* work, const sb_step_stats* stats) {
    work->steps++;
    work->substeps += stats->substeps;
    work->rejected += stats->rejected;
    work->newton += (uint64_t)stats->newton_iterations;
    work->cg += (uint64_t)stats->cg_iterations;
    work->unconverged += !stats->converged;
}

bool sb_energy_log_add(sb_energy_log* log, double time, const sb_energies* energies, const sb_step_work* work) {
    if (log->count == log->capacity && !grow(log)) return false;
    log->times[log->count] = time;
    log->energies[log->count] = *energies;
    log->work[log->count] = *work;
    log->count++;
    return true;
}

void sb_energy_log_free(sb_energy_log* log) {
    free(log->times);
    free(log->energies);
    free(log->work);
    *log = (sb_energy_log){0};
}

static void write_row(FILE* f, double time, const sb_energies* e, const sb_step_work* w) {
    fprintf(f, "%.17g,%.17g", time, e->kinetic);
    for (int t = 0; t < SB_TERM_COUNT; t++) fprintf(f, ",%.17g", e->term[t]);
    fprintf(f, ",%.17g,%.17g", e->gravity, sb_energies_total(e));
    fprintf(f, ",%llu,%llu,%llu,%llu,%llu,%llu\n", (unsigned long long)w->steps, (unsigned long long)w->substeps,
            (unsigned long long)w->rejected, (unsigned long long)w->newton, (unsigned long long)w->cg,
            (unsigned long long)w->unconverged);
}

sb_status sb_energy_log_write(const sb_energy_log* log, const char* path, sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    fprintf(file.stream, "time,kinetic");
    for (int t = 0; t < SB_TERM_COUNT; t++) fprintf(file.stream, ",%s", sb_term_name((sb_term)t));
    fprintf(file.stream, ",gravity,total,steps,substeps,rejected,newton,cg,unconverged\n");
    for (uint32_t i = 0; i < log->count; i++) write_row(file.stream, log->times[i], &log->energies[i], &log->work[i]);
    return sb_atomic_commit(&file, err);
}
