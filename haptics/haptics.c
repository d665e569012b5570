/* Haptics (softbond/haptics.h): the object, its checks, and what the
 * simulation thread calls (drive the tool to the proxy, sense what it
 * touched). The servo's side is haptics/servo.c.
 *
 * Sensing: the tool's contact force from the last step (the impulses it
 * received over the step, sb_solver_contact_force), averaged over
 * sense_time (a vertex pushed out in one step may not touch in the next),
 * gives the model's push and normal; its local stiffness is the secant between the last two steps,
 * (push − push before) / (depth − depth before), depth measured along the
 * normal, kept when it is positive and the depth changed (by more than a
 * nanometre), averaged with the one before (a step's impulses are noisy),
 * and capped at 100 K; 0 out of contact. At first touch the secant from the
 * last step out of contact (push 0) is a lower bound of the stiffness (the
 * surface lay somewhere between), better than none: without it the proxy
 * would be thrown out of a stiff surface by the whole push of one step's
 * penetration and chatter. */
#define _GNU_SOURCE
#include "haptics/haptics_internal.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sb_haptics_def sb_default_haptics_def(void) {
    return (sb_haptics_def){.rate = 1000,
                            .stiffness = 700,
                            .damping = 0.7,
                            .max_force = 3.3,
                            .device_stiffness = 700,
                            .device_max_force = 3.3,
                            .workspace = 0.5,
                            .hand_speed = 10,
                            .stall_time = 0.05,
                            .ramp_time = 0.05,
                            .sense_time = 0.002,
                            .max_speed = 2,
                            .realtime = true,
                            .log_capacity = 65536};
}

static sb_status check_def(const sb_haptics_def* d, sb_error* err) {
    if (!(d->rate >= 10 && d->rate <= 100000))
        return sb_error_set(err, SB_ERR_INVALID, "haptics: rate must be from 10 to 100000 Hz (got %g)", d->rate);
    if (!(d->device_stiffness > 0 && isfinite(d->device_stiffness)))
        return sb_error_set(err, SB_ERR_INVALID, "haptics: device_stiffness must be > 0 (got %g)", d->device_stiffness);
    if (!(d->stiffness > 0 && d->stiffness <= d->device_stiffness))
        return sb_error_set(err, SB_ERR_INVALID,
                            "haptics: coupling stiffness must be > 0 and at most the device's %g N/m (got %g)",
                            d->device_stiffness, d->stiffness);
    double passive = d->stiffness / d->rate / 2;
    if (!(d->damping > passive && isfinite(d->damping)))
        return sb_error_set(err, SB_ERR_INVALID,
                            "haptics: coupling damping must be > K T / 2 = %g N s/m to keep the loop passive (got %g)",
                            passive, d->damping);
    if (!(d->device_max_force > 0 && isfinite(d->device_max_force)))
        return sb_error_set(err, SB_ERR_INVALID, "haptics: device_max_force must be > 0 (got %g)",
                            d->device_max_force);
    if (!(d->max_force > 0 && d->max_force <= d->device_max_force))
        return sb_error_set(err, SB_ERR_INVALID, "haptics: max_force must be > 0 and at most the device's %g N (got %g)",
                            d->device_max_force, d->max_force);
    if (!(d->workspace > 0 && d->workspace <= 1e3))
        return sb_error_set(err, SB_ERR_INVALID, "haptics: workspace must be > 0 and at most 1000 m (got %g)",
                            d->workspace);
    if (!(d->hand_speed > 0 && d->hand_speed <= 1e4))
        return sb_error_set(err, SB_ERR_INVALID, "haptics: hand_speed must be > 0 and at most 10000 m/s (got %g)",
                            d->hand_speed);
    if (!(d->stall_time > 0 && d->ramp_time > 0 && isfinite(d->stall_time) && isfinite(d->ramp_time)))
        return sb_error_set(err, SB_ERR_INVALID, "haptics: stall_time and ramp_time must be > 0");
    if (!(d->sense_time >= 0 && isfinite(d->sense_time)))
        return sb_error_set(err, SB_ERR_INVALID, "haptics: sense_time must be >= 0 (got %g)", d->sense_time);
    if (!(d->max_speed > 0 && isfinite(d->max_speed)))
        return sb_error_set(err, SB_ERR_INVALID, "haptics: max_speed must be > 0 (got %g)", d->max_speed);
    if (d->log_capacity < 1) return sb_error_set(err, SB_ERR_INVALID, "haptics: log_capacity must be >= 1");
    return SB_OK;
}

sb_haptics* sb_haptics_create(const sb_haptics_def* def, sb_haptic_device* device, sb_collider* tool,
                              uint32_t collider_index, sb_error* err) {
    if (check_def(def, err) != SB_OK) return NULL;
    if (!device || !tool) {
        sb_error_set(err, SB_ERR_INVALID, "haptics: a device and a tool are required");
        return NULL;
    }
    sb_haptics* h = calloc(1, sizeof *h);
    if (h) {
        h->log = calloc(def->log_capacity, sizeof *h->log);
        h->period_bins = calloc(SB_PERIOD_BINS, sizeof *h->period_bins);
        h->age_bins = calloc(SB_AGE_BINS, sizeof *h->age_bins);
    }
    if (!h || !h->log || !h->period_bins || !h->age_bins) {
        sb_haptics_destroy(h);
        sb_error_set(err, SB_ERR_NOMEM, "haptics: out of memory");
        return NULL;
    }
    h->def = *def;
    h->period = 1 / def->rate;
    h->device = device;
    h->tool = tool;
    h->tool_index = collider_index;
    h->log_capacity = def->log_capacity;
    sb_collider_state(tool, h->rest, NULL);
    memcpy(h->sim_proxy, h->rest, sizeof h->rest);
    h->max_move = 0.5 * sb_collider_inner_radius(tool);
    sb_record_init(&h->pose);
    sb_record_init(&h->contact);
    h->sensed = (sb_contact_model){.normal = {0, 0, 1}};
    h->gain = 1;
    atomic_init(&h->faults, 0);
    atomic_init(&h->log_head, 0);
    atomic_init(&h->log_tail, 0);
    atomic_init(&h->dropped, 0);
    atomic_init(&h->running, false);
    clock_gettime(CLOCK_MONOTONIC, &h->epoch);
    return h;
}

void sb_haptics_destroy(sb_haptics* h) {
    if (!h) return;
    sb_haptics_stop(h);
    free(h->log);
    free(h->period_bins);
    free(h->age_bins);
    free(h);
}

double sb_haptics_clock(const sb_haptics* h) { return sb_haptics_seconds(&h->epoch); }

/* Where the device is taken to be at the end of the step about to run
 * (estimated from the last step's length): the newest pose moved on along
 * the line from the pose before it, for at most one servo period. Steps
 * shorter than the period then move the tool a step's share of the
 * device's move each, as a path would; taking the newest pose as it is
 * moved it a whole period's worth in one step, and the vertices it swept
 * were answered with that speed (20 times the hand's at 20 steps a tick:
 * the syringe's needle, pushed in at 3.5 cm/s, kicked its vertex at
 * 0.7 m/s). Moving on, not towards the newest (a period late), adds no lag
 * to the loop. Steps as long as the period or longer take the newest pose.
 * The orientation is the newest pose's. */
static void device_for_step(const sb_haptics* h, double device[3]) {
    const sb_haptic_pose *from = &h->drive_from, *to = &h->drive_to;
    double step = h->sensed.time - h->sensed_before, span = to->time - from->time;
    double ahead = step < h->period && span > 0 ? fmin(h->period, fmax(0, h->sensed.time + step - to->time)) / span : 0;
    for (int k = 0; k < 3; k++)
        device[k] = h->rest[k] + to->position[k] + ahead * (to->position[k] - from->position[k]);
}

/* How far the tool may move in the step about to run: max_speed over the
 * last step's length (simulated when known) and half its inner radius.
 * After the simulation stalls (a hitch of the machine) the device may be
 * centimetres on: a tool taken there in one step would fling the tissue it
 * presses, or pass through it (its vertices pushed out of its far side). */
static double max_move(const sb_haptics* h) {
    double step = h->sim_step > 0 ? h->sim_step : h->sensed.time - h->sensed_before;
    return step > 0 ? fmin(h->max_move, h->def.max_speed * step) : h->max_move;
}

static void move_at_most(double at[3], const double to[3], double max_move) {
    double d[3] = {to[0] - at[0], to[1] - at[1], to[2] - at[2]};
    double length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double share = length > max_move ? max_move / length : 1;
    for (int k = 0; k < 3; k++) at[k] = share < 1 ? at[k] + share * d[k] : to[k];
}

void sb_haptics_drive(sb_haptics* h) {
    sb_haptic_pose pose;
    if (!sb_record_read(&h->pose, &pose, sizeof pose)) return;
    if (!h->driven || pose.time != h->drive_to.time) {
        h->drive_from = h->driven ? h->drive_to : pose;
        h->drive_to = pose;
        h->driven = true;
    }
    double device[3], translate[3], rotate[3];
    device_for_step(h, device);
    double proxy[3];
    sb_coupling_proxy(&h->sensed, h->def.stiffness, device, proxy);
    if (!sb_finite3(proxy)) return; /* the tool holds: nothing the device sends reaches the solver unless finite */
    move_at_most(h->sim_proxy, proxy, max_move(h));
    for (int k = 0; k < 3; k++) translate[k] = h->sim_proxy[k] - h->rest[k];
    sb_quaternion_to_degrees(pose.orientation, rotate);
    sb_collider_set_pose(h->tool, translate, rotate);
}

static double depth_along(const double normal[3], const double point[3]) {
    return -(normal[0] * point[0] + normal[1] * point[1] + normal[2] * point[2]);
}

void sb_haptics_sense(sb_haptics* h, const sb_solver* solver, double time) {
    double f[3];
    sb_solver_contact_force(solver, h->tool_index, f);
    h->sim_step = sb_solver_time(solver) - h->sim_time;
    h->sim_time = sb_solver_time(solver);
    sb_haptics_sense_force(h, f, sb_solver_step_count(solver), time);
}

/* The exponential average of the tool's contact force over sense_time. */
static void average_force(sb_haptics* h, const double f[3], double time) {
    double dt = h->sensed.step > 0 ? time - h->sensed.time : 0;
    double keep = h->def.sense_time > 0 && dt > 0 ? h->def.sense_time / (h->def.sense_time + dt) : 0;
    if (h->sensed.step == 0) keep = 0;
    for (int k = 0; k < 3; k++) h->mean_force[k] = keep * h->mean_force[k] + (1 - keep) * f[k];
}

void sb_haptics_sense_force(sb_haptics* h, const double force[3], uint64_t step, double time) {
    if (!sb_finite3(force) || !isfinite(time)) return; /* the last model stands (and goes stale: a stall) */
    average_force(h, force, time);
    const double* f = h->mean_force;
    double push = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    sb_contact_model* m = &h->sensed;
    if (push > 0)
        for (int k = 0; k < 3; k++) m->normal[k] = f[k] / push;
    double moved_in = depth_along(m->normal, h->sim_proxy) - depth_along(m->normal, m->proxy);
    if (push <= 0)
        m->stiffness = 0;
    else if (fabs(moved_in) > 1e-9) {
        double secant = (push - m->force) / moved_in;
        if (secant > 0)
            m->stiffness = fmin(m->force > 0 ? 0.5 * (m->stiffness + secant) : secant, 100 * h->def.stiffness);
    }
    m->force = push;
    m->step = step;
    h->sensed_before = m->time;
    m->time = time;
    memcpy(m->proxy, h->sim_proxy, sizeof m->proxy);
    sb_record_write(&h->contact, m, sizeof *m);
}

void sb_haptics_proxy(const sb_haptics* h, double proxy[3]) { memcpy(proxy, h->sim_proxy, sizeof h->sim_proxy); }

uint32_t sb_haptics_faults(const sb_haptics* h) { return atomic_load_explicit(&h->faults, memory_order_relaxed); }

size_t sb_haptics_drain(sb_haptics* h, sb_haptic_tick* out, size_t max) {
    size_t tail = atomic_load_explicit(&h->log_tail, memory_order_relaxed);
    size_t head = atomic_load_explicit(&h->log_head, memory_order_acquire);
    size_t n = 0;
    for (; n < max && tail + n < head; n++) out[n] = h->log[(tail + n) % h->log_capacity];
    atomic_store_explicit(&h->log_tail, tail + n, memory_order_release);
    return n;
}

uint64_t sb_haptics_dropped(const sb_haptics* h) { return atomic_load_explicit(&h->dropped, memory_order_relaxed); }

static double percentile(const uint32_t* bins, int count, uint64_t total, double fraction, double width) {
    uint64_t rank = (uint64_t)ceil(fraction * (double)total), seen = 0;
    for (int i = 0; i < count; i++) {
        seen += bins[i];
        if (seen >= rank && seen > 0) return (i + 0.5) * width;
    }
    return 0;
}

sb_haptics_stats sb_haptics_statistics(const sb_haptics* h) {
    uint64_t periods = h->ticks > 0 ? h->ticks - 1 : 0;
    return (sb_haptics_stats){.ticks = h->ticks,
                              .period_median = percentile(h->period_bins, SB_PERIOD_BINS, periods, 0.5, 1e-6),
                              .period_p99 = percentile(h->period_bins, SB_PERIOD_BINS, periods, 0.99, 1e-6),
                              .period_max = h->period_max,
                              .late_max = h->late_max,
                              .age_median = percentile(h->age_bins, SB_AGE_BINS, h->ticks, 0.5, 1e-5),
                              .age_p99 = percentile(h->age_bins, SB_AGE_BINS, h->ticks, 0.99, 1e-5)};
}
