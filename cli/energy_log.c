/* The energy log (see energy_log.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/energy_log.h"
#include "common/error.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void sb_step_work_add(sb_step_work* work, const sb_step_stats* stats) {
    work->steps++;
    work->substeps += stats->substeps;
    work->rejected += stats->rejected;
    work->newton += (uint64_t)stats->newton_iterations;
    work->cg += (uint64_t)stats->cg_iterations;
    work->unconverged += !stats->converged;
}

bool sb_energy_log_add_collider(sb_energy_log* log, const char* name) {
    if (log->file) return false;
    char** names = realloc(log->collider_names, (log->collider_count + 1) * sizeof *names);
    if (!names) return false;
    log->collider_names = names;
    if (!(names[log->collider_count] = strdup(name))) return false;
    log->collider_count++;
    return true;
}

/* A write or flush that failed: the file's name and the cause. */
static sb_status write_fail(const sb_energy_log* log, sb_error* err) {
    return sb_error_set(err, SB_ERR_IO, "%s: cannot write: %s", log->path, strerror(errno ? errno : EIO));
}

static sb_status flush(const sb_energy_log* log, sb_error* err) {
    errno = 0;
    return fflush(log->file) == 0 && !ferror(log->file) ? SB_OK : write_fail(log, err);
}

sb_status sb_energy_log_open(sb_energy_log* log, const char* path, sb_error* err) {
    if (!(log->path = strdup(path))) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    if (!(log->file = fopen(path, "w"))) return write_fail(log, err);
    fprintf(log->file, "time,kinetic");
    for (int t = 0; t < SB_TERM_COUNT; t++) fprintf(log->file, ",%s", sb_term_name((sb_term)t));
    fprintf(log->file, ",gravity,total,steps,substeps,rejected,newton,cg,unconverged,contacts");
    for (uint32_t c = 0; c < log->collider_count; c++) {
        const char* name = log->collider_names[c];
        fprintf(log->file, ",%s_fx,%s_fy,%s_fz", name, name, name);
    }
    if (log->broken_column) fprintf(log->file, ",broken");
    fputc('\n', log->file);
    return flush(log, err);
}

sb_status sb_energy_log_resume(sb_energy_log* log, const char* path, uint64_t bytes, double* times, uint32_t count,
                               sb_error* err) {
    log->times = times;
    log->count = log->capacity = count;
    if (!(log->path = strdup(path))) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    if (!(log->file = fopen(path, "r+"))) return write_fail(log, err);
    struct stat info;
    if (fstat(fileno(log->file), &info) != 0 || (uint64_t)info.st_size < bytes)
        return sb_error_set(err, SB_ERR_IO, "%s: shorter than the checkpoint's %llu bytes", path,
                            (unsigned long long)bytes);
    errno = 0;
    if (ftruncate(fileno(log->file), (off_t)bytes) != 0 || fseeko(log->file, (off_t)bytes, SEEK_SET) != 0)
        return write_fail(log, err);
    return SB_OK;
}

uint64_t sb_energy_log_bytes(const sb_energy_log* log) {
    off_t at = ftello(log->file);
    return at > 0 ? (uint64_t)at : 0;
}

static void write_row(FILE* f, double time, const sb_energies* e, const sb_step_work* w, uint32_t contacts,
                      const double* forces, uint32_t force_count) {
    fprintf(f, "%.17g,%.17g", time, e->kinetic);
    for (int t = 0; t < SB_TERM_COUNT; t++) fprintf(f, ",%.17g", e->term[t]);
    fprintf(f, ",%.17g,%.17g", e->gravity, sb_energies_total(e));
    fprintf(f, ",%llu,%llu,%llu,%llu,%llu,%llu,%u", (unsigned long long)w->steps, (unsigned long long)w->substeps,
            (unsigned long long)w->rejected, (unsigned long long)w->newton, (unsigned long long)w->cg,
            (unsigned long long)w->unconverged, contacts);
    for (uint32_t k = 0; k < force_count; k++) fprintf(f, ",%.17g", forces[k]);
}

static bool keep_time(sb_energy_log* log, double time) {
    if (log->count == log->capacity) {
        uint32_t capacity = log->capacity ? 2 * log->capacity : 64;
        double* times = realloc(log->times, capacity * sizeof *times);
        if (!times) return false;
        log->times = times;
        log->capacity = capacity;
    }
    log->times[log->count++] = time;
    return true;
}

sb_status sb_energy_log_add(sb_energy_log* log, double time, const sb_energies* energies, const sb_step_work* work,
                            uint32_t contacts, const double* forces, uint32_t broken, sb_error* err) {
    if (!keep_time(log, time)) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    write_row(log->file, time, energies, work, contacts, forces, 3 * log->collider_count);
    if (log->broken_column) fprintf(log->file, ",%u", broken);
    fputc('\n', log->file);
    return flush(log, err);
}

sb_status sb_energy_log_close(sb_energy_log* log, sb_error* err) {
    sb_status status = SB_OK;
    if (log->file && fclose(log->file) != 0) status = write_fail(log, err);
    free(log->times);
    free(log->path);
    for (uint32_t c = 0; c < log->collider_count; c++) free(log->collider_names[c]);
    free(log->collider_names);
    *log = (sb_energy_log){0};
    return status;
}
