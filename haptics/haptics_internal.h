/* The haptics object's parts (softbond/haptics.h): haptics/haptics.c holds
 * what the simulation thread calls, haptics/servo.c the servo's tick and
 * thread. */
#ifndef SB_HAPTICS_INTERNAL_H
#define SB_HAPTICS_INTERNAL_H

#include "softbond/haptics.h"
#include "haptics/coupling.h"
#include "haptics/record.h"

#include <pthread.h>
#include <stdatomic.h>
#include <time.h>

enum {
    SB_PERIOD_BINS = 20000, /* 1 µs each: periods up to 20 ms */
    SB_AGE_BINS = 100000    /* 10 µs each: ages up to 1 s */
};

struct sb_haptics {
    sb_haptics_def def;
    double period; /* s */
    sb_haptic_device* device;
    sb_collider* tool;
    uint32_t tool_index;
    double rest[3]; /* m: the tool's reference point at rest = the device's origin */
    struct timespec epoch;

    sb_record pose;    /* servo -> simulation: sb_haptic_pose */
    sb_record contact; /* simulation -> servo: sb_contact_model */

    /* The simulation thread's own. */
    sb_contact_model sensed;
    double sensed_before;                /* s: the time of the sense before sensed's (a step's length) */
    sb_haptic_pose drive_from, drive_to; /* the device's last two poses the drive read */
    bool driven;
    double mean_force[3]; /* N: the tool's contact force averaged over sense_time */
    double sim_proxy[3];
    double max_move;           /* m: the most the tool moves in a step (half its inner radius) */
    double sim_time, sim_step; /* s: the simulated time at the last sb_haptics_sense, and its step */

    /* The servo's own (one tick at a time). */
    bool ticked;
    double last_time, device_before[3], proxy_before[3], last_force[3], gain;
    bool posed;                   /* a good pose was read */
    double good_position[3], good_time; /* the last good pose's position (device frame) and time */
    sb_contact_model model;
    bool modelled;
    atomic_uint faults;
    uint64_t ticks;
    uint32_t* period_bins;
    uint32_t* age_bins;
    double period_max, late_max;

    /* The log: a ring the servo fills and one other thread drains. */
    sb_haptic_tick* log;
    uint32_t log_capacity;
    atomic_size_t log_head, log_tail;
    atomic_ullong dropped;

    pthread_t thread;
    atomic_bool running;
    bool started;
};

/* Seconds since the epoch on the monotonic clock. */
double sb_haptics_seconds(const struct timespec* epoch);

#endif
