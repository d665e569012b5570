/* A scripted input file for `softbond view --script FILE`: keys and mouse
 * events at given simulated times, so the viewer runs without a person.
 * One event a line; `#` starts a comment; times in seconds of simulated
 * time, non-decreasing:
 *
 *   0     key g                  # a key by name (F1..F5, r, s, g, space, n, backspace, p, l, h, c, escape)
 *   0.1   press 480 360          # left button down at pixel (x, y) from the top left
 *   0.1   press right 480 360    # or right / middle
 *   0.2   move 600 360           # the cursor
 *   0.4   release 600 360
 *   0.4   scroll 2               # wheel steps (positive comes closer)
 *   0.5   quit                   # end the viewer
 *
 * Events at time 0 apply before the first step. The simulation waits at
 * each event's time (no step starts at or after it until the event is
 * handled), so an event meets the same state on every run and a script
 * replays identically. Errors name FILE:LINE. */
#ifndef SB_VIEWER_INPUT_SCRIPT_H
#define SB_VIEWER_INPUT_SCRIPT_H

#include "softbond/types.h"
#include "viewer/input.h"

typedef struct sb_input_script {
    sb_view_event* events;
    double* times; /* s, simulated */
    size_t count;
    size_t next; /* the first event not yet given */
} sb_input_script;

sb_status sb_input_script_load(const char* path, sb_input_script* out, sb_error* err);
void sb_input_script_free(sb_input_script* script);
/* The next event due at simulated time `time`, or false. */
bool sb_input_script_next(sb_input_script* script, double time, sb_view_event* event);
/* The time of the next event not yet given; INFINITY when none is left. */
double sb_input_script_next_time(const sb_input_script* script);

#endif
