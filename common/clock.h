/* The wall clock every timing in softbond reads: seconds on the monotonic
 * clock (CLOCK_MONOTONIC), which no change of the system's date moves, so
 * differences of two readings are elapsed times. Its origin is arbitrary. */
#ifndef SB_COMMON_CLOCK_H
#define SB_COMMON_CLOCK_H

double sb_wall_seconds(void);

#endif
