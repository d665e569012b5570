/* The progress bar (see progress.h): redrawn when the percentage changes. */
#define _POSIX_C_SOURCE 200809L
#include "scenes/progress.h"

#include <stdio.h>
#include <unistd.h>

enum { BAR_WIDTH = 40 };

sb_progress sb_progress_start(uint64_t total) {
    return (sb_progress){.total = total ? total : 1, .shown = -1, .enabled = isatty(fileno(stderr)) != 0};
}

static void draw(int percent) {
    char bar[BAR_WIDTH + 1];
    int filled = percent * BAR_WIDTH / 100;
    for (int i = 0; i < BAR_WIDTH; i++) bar[i] = i < filled ? '#' : '.';
    bar[BAR_WIDTH] = '\0';
    fprintf(stderr, "\rsoftbond: [%s] %3d%%", bar, percent);
    fflush(stderr);
}

void sb_progress_update(sb_progress* progress, uint64_t done) {
    int percent = (int)(100 * (done < progress->total ? done : progress->total) / progress->total);
    if (!progress->enabled || percent == progress->shown) return;
    progress->shown = percent;
    draw(percent);
}

void sb_progress_end(sb_progress* progress) {
    if (progress->enabled && progress->shown >= 0) fputc('\n', stderr);
    progress->shown = -1;
}
