/* The progress bar (see progress.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/progress.h"
#include "common/clock.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

enum { BAR_WIDTH = 40 };

sb_progress sb_progress_start(uint64_t total, double dt) {
    return (sb_progress){.total = total ? total : 1,
                         .dt = dt,
                         .start = sb_wall_seconds(),
                         .shown = -1.0,
                         .enabled = isatty(fileno(stderr)) != 0};
}

void sb_progress_format(char* out, size_t size, uint64_t done, uint64_t total, double dt, double elapsed) {
    if (done > total) done = total;
    int percent = (int)(100 * done / (total ? total : 1));
    char bar[BAR_WIDTH + 1];
    int filled = percent * BAR_WIDTH / 100;
    for (int i = 0; i < BAR_WIDTH; i++) bar[i] = i < filled ? '#' : '.';
    bar[BAR_WIDTH] = '\0';
    double simulated = (double)done * dt;
    int used = snprintf(out, size, "[%s] %3d%%  t = %.4g s", bar, percent, simulated);
    if (done == 0 || !(elapsed > 0.0) || used < 0 || (size_t)used >= size) return;
    double left = elapsed * (double)(total - done) / (double)done;
    snprintf(out + used, size - (size_t)used, "  %.3gx real time  %.0f s left", simulated / elapsed, left);
}

bool sb_progress_slow_note(char* out, size_t size, uint64_t done, uint64_t total, double dt, double elapsed) {
    if (done == 0 || done >= total || !(elapsed >= SB_SLOW_AFTER)) return false;
    double simulated = (double)total * dt, projected = elapsed * (double)total / (double)done;
    if (!(projected > SB_SLOW_FACTOR * simulated && projected > 60.0)) return false;
    snprintf(out, size,
             "this run will take about %.3g s of wall-clock time for %.3g s simulated (%.3g s a step, %.3gx slower "
             "than real time); check the scene's lengths and dt for a slip of units",
             projected, simulated, elapsed / (double)done, projected / simulated);
    return true;
}

void sb_progress_update(sb_progress* progress, uint64_t done) {
    if (!progress->warned) {
        char note[300];
        double elapsed = sb_wall_seconds() - progress->start;
        if (elapsed >= SB_SLOW_AFTER &&
            sb_progress_slow_note(note, sizeof note, done, progress->total, progress->dt, elapsed)) {
            progress->warned = true;
            fprintf(stderr, "%ssoftbond: %s\n", progress->enabled ? "\n" : "", note);
            fflush(stderr);
        }
    }
    if (!progress->enabled) return;
    double now = sb_wall_seconds();
    if (progress->shown >= 0.0 && now - progress->shown < 0.1 && done < progress->total) return;
    progress->shown = now;
    char line[200];
    sb_progress_format(line, sizeof line, done, progress->total, progress->dt, now - progress->start);
    fprintf(stderr, "\rsoftbond: %s\033[K", line);
    fflush(stderr);
}

void sb_progress_end(sb_progress* progress) {
    if (progress->enabled && progress->shown >= 0.0) fputc('\n', stderr);
    progress->shown = -1.0;
}
