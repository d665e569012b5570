/* The servo (softbond/haptics.h): one tick, and the thread that runs ticks
 * at a fixed rate.
 *
 * A tick reads the device, publishes its pose, reads the latest contact
 * model, places the proxy (haptics/coupling.c), works out the coupling's
 * force, applies the watchdogs' gain and writes the force to the device,
 * then logs the tick and measures it. It allocates nothing, takes no lock
 * and makes no system call but the device's own I/O; the thread adds the
 * clock reads (vDSO) and the sleep.
 *
 * Watchdogs: the tick's faults (no new contact model for stall_time, a
 * non-finite pose, model or force, a device error, a pose no hand gave:
 * outside the workspace, faster than hand_speed from the last good one, or
 * an orientation not a unit quaternion) set the gain's target to
 * 0, else 1; the gain moves towards it by period / ramp_time a tick, so the
 * force falls from any value to zero within ramp_time (plus a tick) and
 * comes back as gently when the fault clears. The force ramped is the last
 * finite one, so nothing non-finite ever reaches the device.
 *
 * The thread sleeps to absolute deadlines (clock_nanosleep, TIMER_ABSTIME),
 * so lateness does not accumulate; a tick more than a period late starts the
 * deadlines again from now rather than running a burst of ticks. */
#define _GNU_SOURCE
#include "haptics/haptics_internal.h"
#include "common/error.h"

#include <errno.h>
#include <math.h>
#include <sched.h>
#include <string.h>

double sb_haptics_seconds(const struct timespec* epoch) {
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return (double)(now.tv_sec - epoch->tv_sec) + 1e-9 * (double)(now.tv_nsec - epoch->tv_nsec);
}

static void count_in(uint32_t* bins, int count, double value, double width) {
    double b = value / width;
    bins[b < 0 ? 0 : b >= count - 1 ? count - 1 : (int)b]++;
}

static void measure(sb_haptics* h, double time, double age) {
    if (h->ticked) {
        double period = time - h->last_time;
        count_in(h->period_bins, SB_PERIOD_BINS, period, 1e-6);
        if (period > h->period_max) h->period_max = period;
    }
    count_in(h->age_bins, SB_AGE_BINS, age, 1e-5);
    h->ticks++;
}

static void log_tick(sb_haptics* h, const sb_haptic_tick* tick) {
    size_t head = atomic_load_explicit(&h->log_head, memory_order_relaxed);
    size_t tail = atomic_load_explicit(&h->log_tail, memory_order_acquire);
    if (head - tail >= h->log_capacity) {
        atomic_fetch_add_explicit(&h->dropped, 1, memory_order_relaxed);
        return;
    }
    h->log[head % h->log_capacity] = *tick;
    atomic_store_explicit(&h->log_head, head + 1, memory_order_release);
}

static bool pose_finite(const sb_haptic_pose* p) {
    return sb_finite3(p->position) && isfinite(p->orientation[0]) && sb_finite3(p->orientation + 1);
}

static bool model_finite(const sb_contact_model* m) {
    return sb_finite3(m->proxy) && sb_finite3(m->normal) && isfinite(m->force) && isfinite(m->stiffness);
}

/* Whether a finite pose is one a hand gave: inside the workspace, no
 * faster than hand_speed from the last good pose (over the time since it,
 * so a pose that jumped is taken once the time makes the move possible),
 * and a unit quaternion give or take a factor of 2 (normalized here). A
 * pose at 1e308 m is finite, but the tool taken there overflowed the
 * proxy's arithmetic to NaN and poisoned the simulation for good. */
static bool pose_plausible(const sb_haptics* h, sb_haptic_pose* pose, double time) {
    double r2 = 0, d2 = 0, q2 = 0;
    for (int k = 0; k < 3; k++) {
        r2 += pose->position[k] * pose->position[k];
        double d = pose->position[k] - h->good_position[k];
        d2 += d * d;
    }
    for (int k = 0; k < 4; k++) q2 += pose->orientation[k] * pose->orientation[k];
    if (!(r2 <= h->def.workspace * h->def.workspace) || !(q2 >= 0.25 && q2 <= 4)) return false;
    double reach = h->def.hand_speed * (time - h->good_time);
    if (h->posed && !(d2 <= reach * reach)) return false;
    double q = sqrt(q2);
    for (int k = 0; k < 4; k++) pose->orientation[k] /= q;
    return true;
}

/* The device in the world, or the last good one when it fails, is not
 * finite or is not a pose a hand gave. */
static uint32_t read_device(sb_haptics* h, double time, double device[3]) {
    sb_haptic_pose pose;
    uint32_t faults = 0;
    if (sb_haptic_device_read(h->device, time, &pose) != SB_OK)
        faults |= SB_HAPTIC_FAULT_DEVICE;
    else if (!pose_finite(&pose))
        faults |= SB_HAPTIC_FAULT_NONFINITE;
    else if (!pose_plausible(h, &pose, time))
        faults |= SB_HAPTIC_FAULT_POSE;
    if (faults) {
        memcpy(device, h->device_before, sizeof h->device_before);
        return faults;
    }
    pose.time = time;
    memcpy(h->good_position, pose.position, sizeof h->good_position);
    h->good_time = time;
    h->posed = true;
    sb_record_write(&h->pose, &pose, sizeof pose);
    for (int k = 0; k < 3; k++) device[k] = h->rest[k] + pose.position[k];
    return 0;
}

static uint32_t read_model(sb_haptics* h, double time) {
    sb_contact_model m;
    if (sb_record_read(&h->contact, &m, sizeof m)) {
        if (!model_finite(&m)) return SB_HAPTIC_FAULT_NONFINITE;
        h->model = m;
        h->modelled = true;
    }
    double since = time - (h->modelled ? h->model.time : 0);
    return since > h->def.stall_time ? SB_HAPTIC_FAULT_STALL : 0;
}

void sb_haptics_tick(sb_haptics* h, double time) {
    double device[3], proxy[3], force[3];
    uint32_t faults = read_device(h, time, device);
    faults |= read_model(h, time);
    if (h->modelled)
        sb_coupling_proxy(&h->model, h->def.stiffness, device, proxy);
    else
        memcpy(proxy, device, sizeof proxy);
    if (!h->ticked) {
        memcpy(h->device_before, device, sizeof device);
        memcpy(h->proxy_before, proxy, sizeof proxy);
    }
    sb_coupling_force(h->def.stiffness, h->def.damping, h->period, device, h->device_before, proxy, h->proxy_before,
                      h->def.max_force, force);
    if (sb_finite3(force) && sb_finite3(proxy))
        memcpy(h->last_force, force, sizeof force);
    else
        faults |= SB_HAPTIC_FAULT_NONFINITE;

    double target = faults ? 0 : 1, step = h->period / h->def.ramp_time;
    h->gain = target < h->gain ? fmax(target, h->gain - step) : fmin(target, h->gain + step);
    sb_haptic_tick tick = {.time = time, .step = h->model.step, .age = h->modelled ? time - h->model.time : time};
    for (int k = 0; k < 3; k++) {
        tick.device[k] = device[k];
        tick.proxy[k] = sb_finite3(proxy) ? proxy[k] : h->proxy_before[k];
        tick.force[k] = h->gain * h->last_force[k];
    }
    if (sb_haptic_device_write(h->device, time, tick.force) != SB_OK) faults |= SB_HAPTIC_FAULT_DEVICE;
    atomic_store_explicit(&h->faults, faults, memory_order_relaxed);
    log_tick(h, &tick);
    measure(h, time, tick.age);
    memcpy(h->device_before, device, sizeof device);
    memcpy(h->proxy_before, tick.proxy, sizeof tick.proxy);
    h->last_time = time;
    h->ticked = true;
}

static void add_seconds(struct timespec* t, double seconds) {
    long long ns = t->tv_nsec + (long long)llround(seconds * 1e9);
    t->tv_sec += (time_t)(ns / 1000000000LL);
    t->tv_nsec = (long)(ns % 1000000000LL);
}

static double seconds_between(const struct timespec* a, const struct timespec* b) {
    return (double)(b->tv_sec - a->tv_sec) + 1e-9 * (double)(b->tv_nsec - a->tv_nsec);
}

static void* servo_loop(void* context) {
    sb_haptics* h = context;
    struct timespec deadline, now;
    clock_gettime(CLOCK_MONOTONIC, &deadline);
    while (atomic_load_explicit(&h->running, memory_order_acquire)) {
        sb_haptics_tick(h, sb_haptics_seconds(&h->epoch));
        add_seconds(&deadline, h->period);
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, NULL) == EINTR) {
        }
        clock_gettime(CLOCK_MONOTONIC, &now);
        double late = seconds_between(&deadline, &now);
        if (late > h->late_max) h->late_max = late;
        if (late > h->period) deadline = now;
    }
    return NULL;
}

sb_status sb_haptics_start(sb_haptics* h, bool* realtime, sb_error* err) {
    if (h->started) return sb_error_set(err, SB_ERR_INVALID, "haptics: the servo thread is already running");
    atomic_store(&h->running, true);
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    bool fifo = false;
    if (h->def.realtime) {
        struct sched_param param = {.sched_priority = sched_get_priority_max(SCHED_FIFO) - 10};
        pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
        pthread_attr_setschedpolicy(&attr, SCHED_FIFO);
        pthread_attr_setschedparam(&attr, &param);
        fifo = pthread_create(&h->thread, &attr, servo_loop, h) == 0;
    }
    pthread_attr_destroy(&attr);
    if (!fifo && pthread_create(&h->thread, NULL, servo_loop, h) != 0) {
        atomic_store(&h->running, false);
        return sb_error_set(err, SB_ERR_IO, "haptics: cannot start the servo thread");
    }
    h->started = true;
    if (realtime) *realtime = fifo;
    return SB_OK;
}

void sb_haptics_stop(sb_haptics* h) {
    if (!h->started) return;
    atomic_store(&h->running, false);
    pthread_join(h->thread, NULL);
    h->started = false;
}
