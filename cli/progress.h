/* A progress bar on stderr, drawn only when stderr is a terminal (a note
 * on a run far slower than real time is printed either way):
 *
 *   softbond: [################........................]  40%  t = 2 s  0.8x real time  3 s left
 *
 * the share of the steps done, the simulated time, the real-time factor
 * (simulated over wall-clock seconds) and the time left at the rate so far. */
#ifndef SB_PROGRESS_H
#define SB_PROGRESS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct sb_progress {
    uint64_t total; /* steps */
    double dt;      /* s a step */
    double start;   /* wall clock at the start, s */
    double shown;   /* wall clock of the last drawing, s; < 0 before the first */
    bool enabled;
    bool warned; /* the slow-run note was printed */
} sb_progress;

sb_progress sb_progress_start(uint64_t total, double dt);
/* Redraws at most 10 times a second. */
void sb_progress_update(sb_progress* progress, uint64_t done);
/* Ends the bar's line, so that what follows starts on a fresh one. */
void sb_progress_end(sb_progress* progress);
/* The line after "softbond: " for done of total steps of dt after elapsed
 * wall-clock seconds. */
void sb_progress_format(char* out, size_t size, uint64_t done, uint64_t total, double dt, double elapsed);
/* The note a run gets, terminal or not, once it is clear that it will take
 * far longer than its simulated time (after SB_SLOW_AFTER wall-clock
 * seconds, a projected total over SB_SLOW_FACTOR times the simulated time
 * and over a minute): true and the line after "softbond: " in out, else
 * false. */
enum { SB_SLOW_AFTER = 5, SB_SLOW_FACTOR = 100 };
bool sb_progress_slow_note(char* out, size_t size, uint64_t done, uint64_t total, double dt, double elapsed);

#endif
