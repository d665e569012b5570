/** @file
 * Haptics: a device held by a hand drives a tool (a kinematic collider) in
 * the simulation, and the hand feels the tissue through it.
 *
 * Two threads meet here. The servo thread (sb_haptics_start: its own
 * pthread, a fixed rate, 1000 Hz by default) reads the device, works out the
 * force and writes it back, every tick; the simulation thread (the one that
 * advances the solver) calls sb_haptics_drive before each step (the tool
 * goes to the proxy) and sb_haptics_sense after it (what the tool touched).
 * They share two small lock-free records, each with one writer: the device
 * pose (servo -> simulation) and the contact model (simulation -> servo).
 *
 * The proxy (god-object) is where the tool is in the simulation: it follows
 * the device in free space and is stopped by the tissue, which pushes it
 * back, while the device may go on. The hand feels a virtual coupling, a
 * spring-damper between device and proxy:
 *     f = K (proxy − device) + b (v_proxy − v_device),  |f| <= max_force.
 * Between two simulation steps the servo places the proxy every tick from a
 * local model of the contact the last step found (the tissue's push f_s
 * along its normal n at the proxy p_s and its local stiffness k): the proxy
 * sits where the coupling spring and the tissue balance,
 *     K (s0 − s) + max(0, f_s − k s) = 0   (s, s0: along n, from p_s),
 * so the force follows the hand's motion at the servo rate and does not jump
 * when a new step arrives. A stalled simulation, a non-finite value or a
 * device error ramps the force to zero over ramp_time (and sb_haptics_faults
 * says which); no non-finite value is ever written to a device. */
#ifndef SOFTBOND_HAPTICS_H
#define SOFTBOND_HAPTICS_H

#include "softbond/collider.h"
#include "softbond/export.h"
#include "softbond/solver.h"
#include "softbond/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** What a device reports: its handle's position (m, in the device's frame:
 * added to the tool's rest position in the world), orientation (a unit
 * quaternion w x y z) and buttons (bit i: button i down). */
typedef struct sb_haptic_pose {
    double time;           /**< s, on the servo's clock */
    double position[3];    /**< m, in the device's frame */
    double orientation[4]; /**< unit quaternion, w x y z */
    uint32_t buttons;      /**< bit i set: button i down */
} sb_haptic_pose;

/** ---- the pose buffer: one writer, any number of readers, no lock -------- */

/** One sb_haptic_pose shared between threads; opaque. */
typedef struct sb_pose_buffer sb_pose_buffer;
/** An empty buffer (no pose written yet), or NULL and err set
 * (SB_ERR_NOMEM). Free it with sb_pose_buffer_destroy. */
SB_API sb_pose_buffer* sb_pose_buffer_create(sb_error* err);
/** Frees the buffer; safe on NULL. No thread may use it any more. */
SB_API void sb_pose_buffer_destroy(sb_pose_buffer* buffer);
/** Writer: never waits. */
SB_API void sb_pose_buffer_write(sb_pose_buffer* buffer, const sb_haptic_pose* pose);
/** Reader: the latest pose whole, true; false before the first write or when
 * the writer overtook the reader on every one of a few tries (then *pose is
 * untouched). Never waits for the writer otherwise. */
SB_API bool sb_pose_buffer_read(sb_pose_buffer* buffer, sb_haptic_pose* pose);
/** How many poses have been written so far. Any thread. */
SB_API uint64_t sb_pose_buffer_writes(const sb_pose_buffer* buffer);

/** ---- devices ------------------------------------------------------------ */

/** A device is four calls; the built-in kinds:
 *   "none":     the handle at rest at 0, no buttons; forces are dropped;
 *   "scripted": a CSV trajectory, `time,x,y,z` [`,qw,qx,qy,qz`] [`,button`]
 *               (s, m, unit quaternion, 0/1), times increasing, linear
 *               between rows, held before the first and after the last;
 *   "udp":      poses in and forces out over UDP on 127.0.0.1
 *               (docs/haptics.md has the packets);
 *   "mouse":    the pose the program last gave sb_haptic_device_move (the
 *               viewer's cursor), from any thread; forces are dropped. */
typedef struct sb_haptic_device_def {
    const char* kind; /**< "none", "scripted", "udp", "mouse" */
    const char* file; /**< scripted: the CSV */
    int port;         /**< udp: the port softbond listens on (default 47000) */
} sb_haptic_device_def;

/** Kind "none", no file, port 47000. */
SB_API sb_haptic_device_def sb_default_haptic_device_def(void);

/** A program's own device (a simulated hand in a test, a vendor SDK): read
 * the pose at time (s, the servo's clock) and write a force (N, always
 * finite and clamped), each returning SB_OK or an error; close may be NULL.
 * Called on the servo thread only. */
typedef struct sb_haptic_device_ops {
    /** Fills *pose for `time` (s); required. An error is a device fault. */
    sb_status (*read)(void* user, double time, sb_haptic_pose* pose);
    /** Applies `force` (N) at `time` (s); required.
     * An error is a device fault. */
    sb_status (*write)(void* user, double time, const double force[3]);
    /** Releases `user` at sb_haptic_device_close; may be NULL. */
    void (*close)(void* user);
} sb_haptic_device_ops;

/** A device, built-in or a program's own; opaque. */
typedef struct sb_haptic_device sb_haptic_device;
/** A built-in device, checked (a scripted file's errors name file:line). */
SB_API sb_haptic_device* sb_haptic_device_open(const sb_haptic_device_def* def, sb_error* err);
/** A program's own device: the ops are copied, user is passed to each of
 * them (and stays the caller's unless ops->close frees it). NULL and
 * SB_ERR_INVALID when ops, read or write is NULL; NULL and SB_ERR_NOMEM when
 * out of memory. */
SB_API sb_haptic_device* sb_haptic_device_custom(const sb_haptic_device_ops* ops, void* user, sb_error* err);
/** The device's pose at `time` (s, the servo's clock) into *pose: its read
 * call's status. */
SB_API sb_status sb_haptic_device_read(sb_haptic_device* device, double time, sb_haptic_pose* pose);
/** Sends a force (N) to the device at `time` (s): its write call's status. */
SB_API sb_status sb_haptic_device_write(sb_haptic_device* device, double time, const double force[3]);
/** Closes the device (a custom device's close call, when it has one) and
 * frees it; safe on NULL. Destroy the sb_haptics using it first. */
SB_API void sb_haptic_device_close(sb_haptic_device* device);
/** A "mouse" device's next pose (any thread; the servo reads the latest
 * whole). Nothing for a device of another kind. */
SB_API void sb_haptic_device_move(sb_haptic_device* device, const sb_haptic_pose* pose);
/** Whether `kind` names a built-in device. */
SB_API bool sb_haptic_device_kind_known(const char* kind);

/** ---- the coupling and the servo ----------------------------------------- */

typedef struct sb_haptics_def {
    double rate;             /**< Hz, the servo's (default 1000) */
    double stiffness;        /**< N/m, the coupling's K (default 700 = 0.7 N/mm) */
    double damping;          /**< N s/m, the coupling's b (default K / rate: twice K T / 2) */
    double max_force;        /**< N, |f| never above it (default 3.3); at most device_max_force */
    double device_stiffness; /**< N/m, the device's limit: K above it is refused (default 700) */
    double device_max_force; /**< N, the device's peak: max_force above it is refused (default 3.3, an Omni's) */
    /** m: the device's workspace, a ball of this radius about its origin
     * (default 0.5). A pose outside it is a device fault (the force ramps
     * down, the tool holds its last good pose). */
    double workspace;
    /** m/s: the fastest a hand moves the device (default 10). A pose that
     * far from the last good one faster than this is a device fault. */
    double hand_speed;
    double stall_time;       /**< s without a new step before the force ramps down (default 0.05) */
    double ramp_time;        /**< s, a ramp from full force to zero or back (default 0.05) */
    /** s: the tool's contact force is averaged over about this time (an
     * exponential average, default 0.002): a step's contact impulses come
     * and go, their mean is the tissue's push. 0 = each step's own. */
    double sense_time;
    /** m/s: the fastest the simulation's tool follows the device, on the
     * simulated clock (default 2, a quick hand). When the simulation
     * stalls (a hitch of the machine) the device moves on meanwhile; the
     * tool then catches up at this speed instead of jumping, which would
     * fling the tissue it holds or pass through it. */
    double max_speed;
    bool realtime;         /**< ask for SCHED_FIFO on the servo thread (default true) */
    uint32_t log_capacity; /**< ticks the log holds until drained (default 65536) */
} sb_haptics_def;

/** The defaults given with each field: 1000 Hz, K 700 N/m, b 0.7 N·s/m,
 * 3.3 N, device limit 700 N/m, stall and ramp 0.05 s, sense 0.002 s,
 * 2 m/s, realtime, a log of 65536 ticks. */
SB_API sb_haptics_def sb_default_haptics_def(void);

/** Why the force is ramping down (bits of sb_haptics_faults). */
enum {
    SB_HAPTIC_FAULT_STALL = 1u,     /**< no new simulation step for stall_time */
    SB_HAPTIC_FAULT_NONFINITE = 2u, /**< a pose, the contact model or the force was not finite */
    SB_HAPTIC_FAULT_DEVICE = 4u,    /**< the device's read or write failed */
    /** a finite pose no hand gave: outside the workspace, moved faster than
     * hand_speed from the last good pose, or its orientation not a unit
     * quaternion (norm outside 0.5 to 2) */
    SB_HAPTIC_FAULT_POSE = 8u
};

/** One servo tick as the log keeps it (and haptics.csv writes it). */
typedef struct sb_haptic_tick {
    double time;      /**< s, the servo's clock */
    double device[3]; /**< m, world */
    double proxy[3];  /**< m, world */
    double force[3];  /**< N, what was written to the device */
    uint64_t step;    /**< the simulation step of the contact model used */
    double age;       /**< s, how old that model was */
} sb_haptic_tick;

/** A device coupled to a tool, with its servo thread; opaque. */
typedef struct sb_haptics sb_haptics;

/** Couples device and tool: the tool is a built-in kinematic collider (its
 * rest position is the device's origin in the world), collider_index its
 * index in the solver's colliders (sb_solver_contact_force). Checks def (a
 * message names the bad field: stiffness above device_stiffness, damping at
 * or below K T / 2, ...). The device is the caller's to close after
 * sb_haptics_destroy. */
SB_API sb_haptics* sb_haptics_create(const sb_haptics_def* def, sb_haptic_device* device, sb_collider* tool,
                                     uint32_t collider_index, sb_error* err);
SB_API void sb_haptics_destroy(sb_haptics* haptics); /**< stops the thread first */

/** The servo thread on the monotonic clock, ticks on absolute deadlines.
 * *realtime is set to whether SCHED_FIFO was granted (may be NULL). */
SB_API sb_status sb_haptics_start(sb_haptics* haptics, bool* realtime, sb_error* err);
/** Stops the servo thread and waits for it to end; nothing is written to
 * the device afterwards (it keeps the last force it was given). Does
 * nothing when the thread is not running; sb_haptics_start may start it
 * again. */
SB_API void sb_haptics_stop(sb_haptics* haptics);
/** Seconds on the servo's clock (0 at sb_haptics_create): what the
 * simulation thread passes to sb_haptics_sense. */
SB_API double sb_haptics_clock(const sb_haptics* haptics);
/** A virtual clock: one tick at `time` (s), on the calling thread (a test
 * steps it; never while the servo thread runs). */
SB_API void sb_haptics_tick(sb_haptics* haptics, double time);

/** Simulation thread, before a step: the tool goes to the proxy for the
 * device at the step's end (sb_collider_set_pose): the latest pose, moved
 * on along the device's last move when steps are shorter than the servo's
 * period (the step's length taken from the last two sb_haptics_sense).
 * It moves at most max_speed times the step's length (simulated, from
 * sb_haptics_sense; from the sensed times after sb_haptics_sense_force)
 * and at most half its sb_collider_inner_radius in one step, so a device
 * that jumped on while the simulation stalled does not take it through
 * the tissue: it catches up over the next steps. */
SB_API void sb_haptics_drive(sb_haptics* haptics);
/** Simulation thread, after a step: the tool's contact force becomes the
 * contact model the servo reads; `time` on the servo's clock. */
SB_API void sb_haptics_sense(sb_haptics* haptics, const sb_solver* solver, double time);
/** The same with the force (N) the tissue put on the tool found by other
 * means (a program's own tissue model, a test's wall) at its step. */
SB_API void sb_haptics_sense_force(sb_haptics* haptics, const double force[3], uint64_t step, double time);
/** Simulation thread: the proxy the last sb_haptics_drive put the tool at (m, world). */
SB_API void sb_haptics_proxy(const sb_haptics* haptics, double proxy[3]);

/** Any thread. */
SB_API uint32_t sb_haptics_faults(const sb_haptics* haptics);
/** Takes up to max logged ticks, oldest first (one thread at a time);
 * sb_haptics_dropped counts those lost because the log was full. */
SB_API size_t sb_haptics_drain(sb_haptics* haptics, sb_haptic_tick* out, size_t max);
/** Ticks not logged because the log (log_capacity) was full. Any thread. */
SB_API uint64_t sb_haptics_dropped(const sb_haptics* haptics);

/** The servo's own measurements: read them after sb_haptics_stop (the
 * servo thread writes them while it runs), or between ticks on the virtual
 * clock. Percentiles from 1 µs bins (periods) and 10 µs bins (ages). */
typedef struct sb_haptics_stats {
    uint64_t ticks; /**< ticks run since sb_haptics_create */
    /** @var period_median
     * s, the median time between the starts of two ticks
     * @var period_p99
     * s, its 99th percentile */
    double period_median, period_p99, period_max; /**< s, between the starts of ticks */
    double late_max;                              /**< s, the most a tick woke after its deadline */
    /** s, the median age of the contact model a tick used */
    double age_median, age_p99; /**< s, of the contact model each tick used */
} sb_haptics_stats;
/** The measurements so far; the percentiles are 0 before enough ticks. */
SB_API sb_haptics_stats sb_haptics_statistics(const sb_haptics* haptics);

#ifdef __cplusplus
}
#endif
#endif
