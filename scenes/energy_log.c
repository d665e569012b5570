/* The energy log (see energy_log.h). */
#define _POSIX_C_SOURCE 200809L
#include "scenes/energy_log.h"
#include "scenes/atomic_file.h"

#include <stdlib.h>
#include <string.h>

static bool grow(sb_energy_log* log) {
    uint32_t capacity = log->capacity ? 2 * log->capacity : 64;
    double* times = realloc(log->times, capacity * sizeof *times);
    if (times) log->times = times;
    sb_energies* energies = realloc(log->energies, capacity * sizeof *energies);
    if (energies) log->energies = energies;
    sb_step_work* work = realloc(log->work, capacity * sizeof *work);
    if (work) log->work = work;
    uint32_t* contacts = realloc(log->contacts, capacity * sizeof *contacts);
    if (contacts) log->contacts = contacts;
    size_t per_row = 3 * (size_t)log->collider_count;
    double* forces = realloc(log->forces, capacity * (per_row ? per_row : 1) * sizeof *forces);
    if (forces) log->forces = forces;
    if (!times || !energies || !work || !contacts || !forces) return false;
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

bool sb_energy_log_add_collider(sb_energy_log* log, const char* name) {
    if (log->count > 0) return false;
    char** names = realloc(log->collider_names, (log->collider_count + 1) * sizeof *names);
    if (!names) return false;
    log->collider_names = names;
    if (!(names[log->collider_count] = strdup(name))) return false;
    log->collider_count++;
    /* the force rows are sized by the collider count: start them afresh */
    free(log->forces);
    log->forces = NULL;
    log->capacity = 0;
    return true;
}

bool sb_energy_log_add(sb_energy_log* log, double time, const sb_energies* energies, const sb_step_work* work,
                       uint32_t contacts, const double* forces) {
    if (log->count == log->capacity && !grow(log)) return false;
    size_t per_row = 3 * (size_t)log->collider_count;
    log->times[log->count] = time;
    log->energies[log->count] = *energies;
    log->work[log->count] = *work;
    log->contacts[log->count] = contacts;
    if (per_row) memcpy(log->forces + log->count * per_row, forces, per_row * sizeof *forces);
    log->count++;
    return true;
}

void sb_energy_log_free(sb_energy_log* log) {
    free(log->times);
    free(log->energies);
    free(log->work);
    free(log->contacts);
    free(log->forces);
    for (uint32_t c = 0; c < log->collider_count; c++) free(log->collider_names[c]);
    free(log->collider_names);
    *log = (sb_energy_log){0};
}

static void write_row(FILE* f, const sb_energy_log* log, uint32_t i) {
    const sb_energies* e = &log->energies[i];
    const sb_step_work* w = &log->work[i];
    fprintf(f, "%.17g,%.17g", log->times[i], e->kinetic);
    for (int t = 0; t < SB_TERM_COUNT; t++) fprintf(f, ",%.17g", e->term[t]);
    fprintf(f, ",%.17g,%.17g", e->gravity, sb_energies_total(e));
    fprintf(f, ",%llu,%llu,%llu,%llu,%llu,%llu,%u", (unsigned long long)w->steps, (unsigned long long)w->substeps,
            (unsigned long long)w->rejected, (unsigned long long)w->newton, (unsigned long long)w->cg,
            (unsigned long long)w->unconverged, log->contacts[i]);
    const double* forces = log->forces + (size_t)i * 3 * log->collider_count;
    for (uint32_t k = 0; k < 3 * log->collider_count; k++) fprintf(f, ",%.17g", forces[k]);
    fputc('\n', f);
}

sb_status sb_energy_log_write(const sb_energy_log* log, const char* path, sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    fprintf(file.stream, "time,kinetic");
    for (int t = 0; t < SB_TERM_COUNT; t++) fprintf(file.stream, ",%s", sb_term_name((sb_term)t));
    fprintf(file.stream, ",gravity,total,steps,substeps,rejected,newton,cg,unconverged,contacts");
    for (uint32_t c = 0; c < log->collider_count; c++) {
        const char* name = log->collider_names[c];
        fprintf(file.stream, ",%s_fx,%s_fy,%s_fz", name, name, name);
    }
    fputc('\n', file.stream);
    for (uint32_t i = 0; i < log->count; i++) write_row(file.stream, log, i);
    return sb_atomic_commit(&file, err);
}
