/* A progress bar on stderr, drawn only when stderr is a terminal. */
#ifndef SB_PROGRESS_H
#define SB_PROGRESS_H

#include <stdbool.h>
#include <stdint.h>

typedef struct sb_progress {
    uint64_t total; /* steps */
    int shown;      /* percent last drawn, -1 before the first */
    bool enabled;
} sb_progress;

sb_progress sb_progress_start(uint64_t total);
void sb_progress_update(sb_progress* progress, uint64_t done);
/* Ends the bar's line, so that what follows starts on a fresh one. */
void sb_progress_end(sb_progress* progress);

#endif
