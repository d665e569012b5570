/* Haptics on a virtual clock (the test steps the servo; nothing is timed):
 * the scripted device and its errors, the mouse device, the UDP device's packets, the
 * coupling against an elastic wall worked out by hand (two springs in
 * series), the clamp and the stiffness limit on every tick, the watchdogs'
 * ramps, and the refusals. */
#define _POSIX_C_SOURCE 200809L
#include "test_util.h"
#include "test_files.h"

#include "haptics/coupling.h"
#include "haptics/udp_protocol.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <time.h>

#define RATE 1000.0
#define T (1 / RATE)
#define K 700.0 /* the default coupling */
#define NEVER 1e30

static void quaternion_multiply(const double a[4], const double b[4], double out[4]) {
    out[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
    out[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
    out[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
    out[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
}

static bool finite3(const double v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }
static double norm3(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* ---- a device the test drives: a depth path, and the forces it got ---- */

typedef struct test_device {
    double depth, ramp_until;    /* m: z goes to −depth linearly until ramp_until (s), then holds */
    double nan_from, error_from; /* s: a NaN pose, a failing read from then on */
    double burst_from, burst_until, burst_x; /* s, s, m: x is burst_x over [burst_from, burst_until) */
    double force[3];
    bool wrote_nonfinite;
} test_device;

static sb_status test_read(void* user, double time, sb_haptic_pose* pose) {
    test_device* d = user;
    *pose = (sb_haptic_pose){.time = time, .orientation = {1, 0, 0, 0}};
    pose->position[2] = -d->depth * fmin(1, time / d->ramp_until);
    if (time >= d->nan_from) pose->position[0] = NAN;
    if (time >= d->burst_from && time < d->burst_until) pose->position[0] = d->burst_x;
    return time >= d->error_from ? SB_ERR_IO : SB_OK;
}

static sb_status test_write(void* user, double time, const double force[3]) {
    (void)time;
    test_device* d = user;
    if (!finite3(force)) d->wrote_nonfinite = true;
    memcpy(d->force, force, sizeof d->force);
    return SB_OK;
}

/* ---- the rig: a sphere tool at the origin, an elastic wall z < 0 ------- */

typedef struct rig {
    test_device device;
    sb_haptic_device* handle;
    sb_collider* tool;
    sb_haptics* haptics;
    double wall; /* N/m: the wall pushes the proxy out by wall × depth */
    uint64_t step;
    double sim_stops; /* s: no step from then on */
} rig;

static void rig_open(rig* r, const sb_haptics_def* def, double wall) {
    static const sb_haptic_device_ops ops = {test_read, test_write, NULL};
    sb_error err;
    r->handle = sb_haptic_device_custom(&ops, &r->device, &err);
    sb_collider_def c = sb_default_collider_def();
    c.shape = SB_COLLIDER_SPHERE;
    c.radius = 0.005;
    r->tool = sb_collider_create(&c, &err);
    assert_non_null(r->tool);
    r->haptics = sb_haptics_create(def, r->handle, r->tool, 0, &err);
    assert_non_null(r->haptics);
    r->wall = wall;
    if (r->sim_stops == 0) r->sim_stops = NEVER;
}

static void rig_close(rig* r) {
    sb_haptics_destroy(r->haptics);
    sb_haptic_device_close(r->handle);
    sb_collider_destroy(r->tool);
}

/* The simulation's side, a step every `every` ticks: drive the tool, then
 * tell the servo what the wall did to it. */
static void rig_sim_step(rig* r, double time) {
    sb_haptics_drive(r->haptics);
    double proxy[3], force[3] = {0, 0, 0};
    sb_haptics_proxy(r->haptics, proxy);
    force[2] = r->wall * fmax(0, -proxy[2]);
    sb_haptics_sense_force(r->haptics, force, ++r->step, time);
}

/* Runs ticks [from, to) and calls check on each logged tick with the one before. */
typedef void (*tick_check)(const rig* r, const sb_haptic_tick* tick, const sb_haptic_tick* before, bool new_step);

static void rig_run(rig* r, long from, long to, int every, tick_check check) {
    sb_haptic_tick before = {0}, tick;
    uint64_t step_before = 0;
    for (long i = from; i < to; i++) {
        double time = (double)i * T;
        if (i % every == 0 && time < r->sim_stops) rig_sim_step(r, time);
        sb_haptics_tick(r->haptics, time);
        assert_int_equal(sb_haptics_drain(r->haptics, &tick, 1), 1);
        assert_false(r->device.wrote_nonfinite);
        for (int k = 0; k < 3; k++) assert_true(tick.force[k] == r->device.force[k]);
        if (check && i > from) check(r, &tick, &before, tick.step != step_before);
        before = tick;
        step_before = tick.step;
    }
}

static sb_haptics_def rig_def(void) {
    sb_haptics_def def = sb_default_haptics_def();
    def.rate = RATE;
    def.sense_time = 0; /* the wall's force is exact: no impulses to average */
    return def;
}

static test_device pressing(double depth, double ramp_until) {
    return (test_device){
        .depth = depth, .ramp_until = ramp_until, .nan_from = NEVER, .error_from = NEVER, .burst_from = NEVER};
}

/* Every tick: never above max_force; the coupling spring's force
 * K (proxy − device) changes by at most K times the device's move (the
 * hand never feels stiffer than the coupling) while one simulation step's
 * model lasts, and by under 2 % of the force when a new step arrives,
 * except at first touch (the step that finds the contact brings the push
 * of its own penetration at once). */
static void check_limits(const rig* r, const sb_haptic_tick* tick, const sb_haptic_tick* before, bool new_step) {
    TU_ASSERT_LE(norm3(tick->force), 3.3 * (1 + 1e-12));
    double spring[3], spring_before[3], moved[3], change[3];
    for (int k = 0; k < 3; k++) {
        spring[k] = K * (tick->proxy[k] - tick->device[k]);
        spring_before[k] = K * (before->proxy[k] - before->device[k]);
        moved[k] = tick->device[k] - before->device[k];
        change[k] = spring[k] - spring_before[k];
    }
    if (!new_step)
        TU_ASSERT_LE(norm3(change), K * norm3(moved) * (1 + 1e-9) + 1e-12);
    else if (norm3(spring_before) > 0)
        TU_ASSERT_LE(norm3(change), 0.02 * fmax(norm3(spring), 0.1) + K * norm3(moved));
    (void)r;
}

/* A wall softer than the coupling (300 N/m), the device pressed 2 mm in
 * over a second and held: the hand feels the two springs in series,
 * K k / (K + k) × 2 mm = 0.42 N, straight out of the wall. */
static void test_wall_feels_springs_in_series(void** state) {
    (void)state;
    for (int every = 1; every <= 8; every *= 2) {
        rig r = {.device = pressing(0.002, 1.0)};
        sb_haptics_def def = rig_def();
        rig_open(&r, &def, 300);
        rig_run(&r, 0, 2000, every, check_limits);
        TU_ASSERT_NEAR(r.device.force[2], K * 300 / (K + 300) * 0.002, 1e-6);
        TU_ASSERT_NEAR(r.device.force[0], 0, 1e-12);
        assert_int_equal(sb_haptics_faults(r.haptics), 0);
        rig_close(&r);
    }
}

/* A wall 100 times stiffer than the coupling: the hand feels at most the
 * coupling (K k / (K + k) × 2 mm, 1 % under K × 2 mm); pressed 10 mm in,
 * the force is clamped at max_force on every tick from there. */
static void test_stiff_wall_is_felt_through_the_coupling_and_clamped(void** state) {
    (void)state;
    rig r = {.device = pressing(0.002, 1.0)};
    sb_haptics_def def = rig_def();
    rig_open(&r, &def, 100 * K);
    rig_run(&r, 0, 2000, 4, check_limits);
    TU_ASSERT_NEAR(r.device.force[2], K * 100 / 101 * 0.002, 1e-5);
    rig_close(&r);

    rig deep = {.device = pressing(0.010, 1.0)};
    rig_open(&deep, &def, 100 * K);
    rig_run(&deep, 0, 2000, 4, check_limits);
    TU_ASSERT_NEAR(deep.device.force[2], 3.3, 1e-12);
    rig_close(&deep);
}

/* Simulation steps shorter than the servo's period (ten a tick here), the
 * device moving at 10 mm/s, nothing touched: each step takes the tool a
 * step's share of the device's move (1 µm), on from the newest pose along
 * the device's last move, so it is where the device is at the step's end;
 * it does not jump a tick's move (10 µm) at the first step of each tick. */
static void test_short_steps_move_the_tool_a_steps_share(void** state) {
    (void)state;
    rig r = {.device = pressing(0.01, 1.0)};
    sb_haptics_def def = rig_def();
    rig_open(&r, &def, 0);
    const int steps = 10;
    double before[3] = {0, 0, 0}, proxy[3];
    sb_haptic_tick tick;
    for (long i = 0; i < 20; i++) {
        sb_haptics_tick(r.haptics, (double)i * T);
        assert_int_equal(sb_haptics_drain(r.haptics, &tick, 1), 1);
        for (int s = 1; s <= steps; s++) {
            double step_end = (double)i * T + s * T / steps;
            sb_haptics_drive(r.haptics);
            sb_haptics_proxy(r.haptics, proxy);
            if (i >= 2) { /* two poses read, two steps sensed */
                TU_ASSERT_NEAR(proxy[2], -0.01 * step_end, 1e-12);
                TU_ASSERT_NEAR(before[2] - proxy[2], 0.01 * T / steps, 1e-12);
            }
            memcpy(before, proxy, sizeof before);
            sb_haptics_sense_force(r.haptics, (double[3]){0, 0, 0}, ++r.step, step_end);
        }
    }
    rig_close(&r);
}

/* The watchdogs: the force ramps from its value to exactly zero within
 * ramp_time of the fault (stall: stall_time after the last step), never
 * rising meanwhile, and comes back when a stall ends. */
static void assert_ramps_down(rig* r, double fault_at, uint32_t fault) {
    double full = 0.42, ramp = r->haptics ? 0.05 : 0;
    long start = 1000, fault_tick = (long)(fault_at * RATE);
    rig_run(r, 0, start, 4, NULL);
    TU_ASSERT_NEAR(r->device.force[2], full, 1e-3);
    double before = r->device.force[2];
    for (long i = start; i < fault_tick + (long)((ramp + 0.01) * RATE); i++) {
        rig_run(r, i, i + 1, 4, NULL);
        double f = norm3(r->device.force), time = (double)i * T;
        TU_ASSERT_LE(f, before + 1e-6);
        if (time < fault_at - T) TU_ASSERT_NEAR(f, full, 1e-3);
        if (time >= fault_at + ramp + T) assert_true(f == 0);
        if (time >= fault_at + T) assert_true(sb_haptics_faults(r->haptics) & fault);
        before = f;
    }
}

static void test_stalled_simulation_ramps_to_zero_and_back(void** state) {
    (void)state;
    rig r = {.device = pressing(0.002, 0.5), .sim_stops = 1.2001}; /* the last step at 1.2 s */
    sb_haptics_def def = rig_def();
    rig_open(&r, &def, 300);
    assert_ramps_down(&r, 1.2 + def.stall_time, SB_HAPTIC_FAULT_STALL);
    r.sim_stops = NEVER; /* the simulation goes on: the force comes back within ramp_time */
    long now = (long)(1.4 * RATE);
    rig_run(&r, now, now + (long)(def.ramp_time * RATE) + 2, 4, NULL);
    TU_ASSERT_NEAR(r.device.force[2], 0.42, 1e-3);
    assert_int_equal(sb_haptics_faults(r.haptics), 0);
    rig_close(&r);
}

static void test_nonfinite_pose_and_device_error_ramp_to_zero(void** state) {
    (void)state;
    sb_haptics_def def = rig_def();
    rig nan = {.device = pressing(0.002, 0.5)};
    nan.device.nan_from = 1.3;
    rig_open(&nan, &def, 300);
    assert_ramps_down(&nan, 1.3, SB_HAPTIC_FAULT_NONFINITE);
    rig_close(&nan);
    rig broken = {.device = pressing(0.002, 0.5)};
    broken.device.error_from = 1.3;
    rig_open(&broken, &def, 300);
    assert_ramps_down(&broken, 1.3, SB_HAPTIC_FAULT_DEVICE);
    rig_close(&broken);
}

/* A burst of finite poses no hand gives (1e308 m, far
 * outside the workspace; 1e20; −1e200; a 0.3 m jump within a tick) is a
 * device fault: the force ramps to zero, the tool holds its last good pose
 * (finite), and when good poses come back the force is back within
 * ramp_time. Before, the 1e308 burst overflowed the proxy to NaN: the
 * force stayed 0 for the rest of the run. */
static void assert_burst_recovers(double x, double from, double until) {
    sb_haptics_def def = rig_def();
    rig r = {.device = pressing(0.002, 0.5)};
    r.device.burst_from = from;
    r.device.burst_until = until;
    r.device.burst_x = x;
    rig_open(&r, &def, 300);
    long done; /* the ticks run so far */
    if (until - from > def.ramp_time + 0.02) {
        assert_ramps_down(&r, from, SB_HAPTIC_FAULT_POSE);
        done = (long)(from * RATE) + (long)((def.ramp_time + 0.01) * RATE);
    } else {
        done = (long)(from * RATE) + 2;
        rig_run(&r, 0, done, 4, NULL);
        assert_true(sb_haptics_faults(r.haptics) & SB_HAPTIC_FAULT_POSE);
    }
    double proxy[3];
    sb_haptics_proxy(r.haptics, proxy);
    assert_true(finite3(proxy));
    TU_ASSERT_LE(fabs(proxy[0]), 1e-9); /* held where the last good pose put it */
    long now = (long)(until * RATE) + 1;
    rig_run(&r, done, now + (long)(def.ramp_time * RATE) + 3, 4, NULL);
    assert_int_equal(sb_haptics_faults(r.haptics), 0);
    TU_ASSERT_NEAR(r.device.force[2], 0.42, 1e-3);
    sb_haptics_proxy(r.haptics, proxy);
    assert_true(finite3(proxy));
    rig_close(&r);
}

static void test_absurd_pose_burst_is_a_fault_and_recovers(void** state) {
    (void)state;
    assert_burst_recovers(1e308, 1.3, 1.4);
    assert_burst_recovers(1e20, 1.3, 1.4);
    assert_burst_recovers(-1e200, 1.3, 1.4);
    assert_burst_recovers(0.6, 1.3, 1.4);   /* just outside the 0.5 m workspace */
    assert_burst_recovers(0.3, 1.3, 1.305); /* inside it, but 0.3 m in a tick: 300 m/s */
}

static void assert_refused(sb_haptics_def def, const char* words) {
    rig r = {0};
    static const sb_haptic_device_ops ops = {test_read, test_write, NULL};
    sb_error err;
    r.handle = sb_haptic_device_custom(&ops, &r.device, &err);
    sb_collider_def c = sb_default_collider_def();
    r.tool = sb_collider_create(&c, &err);
    err.message[0] = 0;
    assert_null(sb_haptics_create(&def, r.handle, r.tool, 0, &err));
    if (!strstr(err.message, words)) fail_msg("expected '%s' in: %s", words, err.message);
    sb_haptic_device_close(r.handle);
    sb_collider_destroy(r.tool);
}

static void test_limits_refused(void** state) {
    (void)state;
    sb_haptics_def def = rig_def();
    def.stiffness = 800; /* above the device's 700 N/m */
    assert_refused(def, "at most the device's 700");
    def = rig_def();
    def.damping = 0.3; /* not above K T / 2 = 0.35 */
    assert_refused(def, "damping must be > K T / 2");
    def = rig_def();
    def.max_force = NAN;
    assert_refused(def, "max_force");
    def = rig_def();
    def.max_force = 1000; /* above the device's 3.3 N */
    assert_refused(def, "max_force must be > 0 and at most the device's 3.3 N");
    def = rig_def();
    def.workspace = INFINITY;
    assert_refused(def, "workspace");
    def = rig_def();
    def.hand_speed = 0;
    assert_refused(def, "hand_speed");
    def = rig_def();
    def.rate = 0;
    assert_refused(def, "rate");
}

/* The servo on its own thread: it ticks, stops when told, and what it
 * measured is consistent (periods at least as long as the median, ticks
 * counted); no figure of its timing is asserted. */
static void test_servo_thread_runs_and_stops(void** state) {
    (void)state;
    rig r = {.device = pressing(0.002, 0.5)};
    sb_haptics_def def = rig_def();
    rig_open(&r, &def, 300);
    bool realtime;
    sb_error err;
    assert_int_equal(sb_haptics_start(r.haptics, &realtime, &err), SB_OK);
    assert_int_equal(sb_haptics_start(r.haptics, &realtime, &err), SB_ERR_INVALID);
    while (sb_haptics_clock(r.haptics) < 0.05) nanosleep(&(struct timespec){.tv_nsec = 5000000}, NULL);
    sb_haptics_stop(r.haptics);
    sb_haptics_stats stats = sb_haptics_statistics(r.haptics);
    assert_true(stats.ticks > 0);
    TU_ASSERT_LE(stats.period_median, stats.period_max + 1e-6);
    TU_ASSERT_LE(stats.period_median, stats.period_p99);
    sb_haptic_tick ticks[64];
    assert_true(sb_haptics_drain(r.haptics, ticks, 64) > 0);
    assert_false(r.device.wrote_nonfinite);
    rig_close(&r);
}

/* ---- in a scene ------------------------------------------------------- */

static const char* probe_scene(const char* haptics) {
    static char text[2048];
    snprintf(text, sizeof text,
             "mesh: {generator: sheet, nx: 5, ny: 5, width: 0.02, height: 0.02}\n"
             "bond: {k: 50}\npin: left_edge\ngravity: [0, 0, 0]\n"
             "colliders:\n  - {type: sphere, name: probe, center: [0.01, 0.01, 0.004], radius: 0.002}\n"
             "  - {type: plane, name: floor, point: [0, 0, -1]}\n"
             "haptics:\n%s\n"
             "dt: 0.0001\nduration: 0.05\nthreads: 1\noutput: {frames: false}\n",
             haptics);
    return tu_write_file("probe.yaml", text);
}

static tu_result run_probe(const char* haptics) {
    const char* args[] = {"run", probe_scene(haptics), "--output", tu_tmp_path("probe_out"), "--no-realtime", NULL};
    return tu_run(args);
}

static void assert_scene_refused(const char* haptics, const char* message) {
    tu_result r = run_probe(haptics);
    assert_int_equal(r.code, 2);
    if (!strstr(r.err, message)) fail_msg("expected '%s' in: %s", message, r.err);
    tu_result_free(&r);
}

/* A scene with a scripted device: haptics.csv has the header and a row
 * per tick, the device where the script says; bad keys are refused with
 * their line. */
static void test_scene_runs_the_servo_and_writes_haptics_csv(void** state) {
    (void)state;
    tu_write_file("down.csv", "time,x,y,z\n0,0,0,0\n1,0,0,-0.01\n");
    tu_result r = run_probe("  device: scripted\n  file: down.csv\n  tool: probe");
    if (r.code != 0) fail_msg("%s", r.err);
    tu_result_free(&r);
    char* csv = tu_read_file(tu_tmp_path("probe_out/haptics.csv"));
    assert_non_null(csv);
    const char header[] = "time,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,step\n";
    assert_true(strncmp(csv, header, sizeof header - 1) == 0);
    double time, device[3];
    const char* row = strchr(csv, '\n') + 1;
    assert_int_equal(sscanf(row, "%lf,%lf,%lf,%lf", &time, &device[0], &device[1], &device[2]), 4);
    TU_ASSERT_NEAR(device[0], 0.01, 1e-12);               /* the tool's rest position plus the script's */
    TU_ASSERT_NEAR(device[2], 0.004 - 0.01 * time, 1e-8); /* the time is written to the microsecond */
    free(csv);

    assert_scene_refused("  device: phantom\n  tool: probe", "probe.yaml:9: 'haptics.device': expected none, scripted");
    assert_scene_refused("  device: scripted\n  tool: probe", "needs haptics.file");
    assert_scene_refused("  device: udp", "needs haptics.tool");
    assert_scene_refused("  tool: knife", "probe.yaml:9: 'haptics.tool': no collider is named 'knife'");
    assert_scene_refused("  tool: floor", "cannot be a tool");
    assert_scene_refused("  tool: probe\n  coupling: {stiffness: 900}", "probe.yaml:10: coupling stiffness");
    assert_scene_refused("  tool: probe\n  coupling: {damping: 0.1}", "probe.yaml:10: coupling damping");
    assert_scene_refused("  device: scripted\n  file: nothere.csv\n  tool: probe", "nothere.csv");
}

/* The tool turns with the device: a quaternion becomes the collider's
 * rotation in degrees about x, then y, then z (R = Rz Ry Rx). */
static void test_quaternion_to_degrees(void** state) {
    (void)state;
    double d[3];
    const double half = M_PI / 360; /* half an angle of one degree, in radians */
    sb_quaternion_to_degrees((double[4]){cos(90 * half), 0, 0, sin(90 * half)}, d);
    TU_ASSERT_NEAR(d[0], 0, 1e-12);
    TU_ASSERT_NEAR(d[1], 0, 1e-12);
    TU_ASSERT_NEAR(d[2], 90, 1e-12);
    /* Rz(30) Ry(20) Rx(10) as the product of the three quaternions. */
    double qx[4] = {cos(10 * half), sin(10 * half), 0, 0}, qy[4] = {cos(20 * half), 0, sin(20 * half), 0},
           qz[4] = {cos(30 * half), 0, 0, sin(30 * half)}, zy[4], q[4];
    quaternion_multiply(qz, qy, zy);
    quaternion_multiply(zy, qx, q);
    sb_quaternion_to_degrees(q, d);
    TU_ASSERT_NEAR(d[0], 10, 1e-12);
    TU_ASSERT_NEAR(d[1], 20, 1e-12);
    TU_ASSERT_NEAR(d[2], 30, 1e-12);
}

/* ---- the scripted device ---------------------------------------------- */

static void test_scripted_device_interpolates(void** state) {
    (void)state;
    const char* path = tu_write_file("path.csv", "time,x,y,z,qw,qx,qy,qz,button\n"
                                                 "0,0,0,0,1,0,0,0,0\n"
                                                 "1,1,2,3,0.7071067811865476,0,0,0.7071067811865476,1\n");
    sb_haptic_device_def def = sb_default_haptic_device_def();
    def.kind = "scripted";
    def.file = path;
    sb_error err;
    sb_haptic_device* d = sb_haptic_device_open(&def, &err);
    assert_non_null(d);
    sb_haptic_pose p;
    assert_int_equal(sb_haptic_device_read(d, 0.25, &p), SB_OK);
    TU_ASSERT_NEAR(p.position[0], 0.25, 1e-15);
    TU_ASSERT_NEAR(p.position[1], 0.5, 1e-15);
    TU_ASSERT_NEAR(p.position[2], 0.75, 1e-15);
    assert_int_equal(p.buttons, 0);
    assert_int_equal(sb_haptic_device_read(d, 0.5, &p), SB_OK); /* halfway: 45 degrees about z */
    TU_ASSERT_NEAR(p.orientation[0], cos(M_PI / 8), 1e-12);
    TU_ASSERT_NEAR(p.orientation[3], sin(M_PI / 8), 1e-12);
    assert_int_equal(sb_haptic_device_read(d, -1, &p), SB_OK);
    TU_ASSERT_NEAR(p.position[2], 0, 0);
    assert_int_equal(sb_haptic_device_read(d, 7, &p), SB_OK);
    TU_ASSERT_NEAR(p.position[2], 3, 0);
    assert_int_equal(p.buttons, 1);
    double force[3] = {1, 2, 3};
    assert_int_equal(sb_haptic_device_write(d, 7, force), SB_OK);
    sb_haptic_device_close(d);
}

/* The mouse device: at rest at the origin until moved, then the last pose
 * given, at the time asked; sb_haptic_device_move leaves other kinds alone. */
static void test_mouse_device_gives_the_last_move(void** state) {
    (void)state;
    sb_haptic_device_def def = sb_default_haptic_device_def();
    def.kind = "mouse";
    sb_error err;
    sb_haptic_device* d = sb_haptic_device_open(&def, &err);
    assert_non_null(d);
    sb_haptic_pose p;
    assert_int_equal(sb_haptic_device_read(d, 0.5, &p), SB_OK);
    assert_true(p.time == 0.5 && p.position[0] == 0 && p.position[2] == 0 && p.orientation[0] == 1 && p.buttons == 0);
    sb_haptic_pose moved = {.position = {0.01, -0.02, 0.03}, .orientation = {1, 0, 0, 0}, .buttons = 1};
    sb_haptic_device_move(d, &moved);
    moved.position[2] = 0.04;
    sb_haptic_device_move(d, &moved);
    assert_int_equal(sb_haptic_device_read(d, 0.75, &p), SB_OK);
    assert_true(p.time == 0.75 && p.position[0] == 0.01 && p.position[1] == -0.02 && p.position[2] == 0.04);
    assert_int_equal(p.buttons, 1);
    double force[3] = {1, 2, 3};
    assert_int_equal(sb_haptic_device_write(d, 1, force), SB_OK);
    sb_haptic_device_close(d);
    def.kind = "none";
    d = sb_haptic_device_open(&def, &err);
    sb_haptic_device_move(d, &moved);
    assert_int_equal(sb_haptic_device_read(d, 0, &p), SB_OK);
    assert_true(p.position[2] == 0);
    sb_haptic_device_close(d);
}

static void assert_scripted_refused(const char* text, const char* where) {
    sb_haptic_device_def def = sb_default_haptic_device_def();
    def.kind = "scripted";
    def.file = tu_write_file("bad.csv", text);
    sb_error err;
    assert_null(sb_haptic_device_open(&def, &err));
    if (!strstr(err.message, where)) fail_msg("expected '%s' in: %s", where, err.message);
}

static void test_scripted_device_errors_name_the_line(void** state) {
    (void)state;
    assert_scripted_refused("time,x,y\n0,0,0\n", "bad.csv:1: the header");
    assert_scripted_refused("time,x,y,z\n0,0,0,0\n0,1,1,1\n", "bad.csv:3: times must increase");
    assert_scripted_refused("time,x,y,z\n0,0,0\n", "bad.csv:2:");
    assert_scripted_refused("time,x,y,z\n0,0,0,0,5\n", "bad.csv:2: expected 4 columns, found 5");
    assert_scripted_refused("time,x,y,z,qw,qx,qy,qz\n0,0,0,0,2,0,0,0\n", "bad.csv:2: the quaternion");
    assert_scripted_refused("time,x,y,z,button\n0,0,0,0,0.5\n", "bad.csv:2: button");
    assert_scripted_refused("time,x,y,z\n", "no rows");
    /* A NUL byte in a row was read as the row cut there (exit 0) */
    static const char nul_row[] = "time,x,y,z\n0,0,0,0\n1,0,0,-0.01\0" "5\n";
    FILE* f = fopen(tu_tmp_path("nul.csv"), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(nul_row, 1, sizeof nul_row - 1, f), sizeof nul_row - 1);
    fclose(f);
    sb_haptic_device_def nul = sb_default_haptic_device_def();
    nul.kind = "scripted";
    nul.file = tu_tmp_path("nul.csv");
    sb_error nul_err;
    assert_null(sb_haptic_device_open(&nul, &nul_err));
    if (!strstr(nul_err.message, "nul.csv:3: a NUL byte in the line")) fail_msg("got: %s", nul_err.message);
    /* A 200 kB field was 'line 3: expected 4 columns' (fgets cut it into lines) */
    size_t big = 200000;
    char* text = malloc(big + 64);
    assert_non_null(text);
    int n = snprintf(text, 64, "time,x,y,z\n0,0,0,0\n1,0,0,");
    memset(text + n, '1', big);
    strcpy(text + n + big, "\n2,0,0,0\n");
    assert_scripted_refused(text, "bad.csv:3: the line is 200007 bytes long, more than a row needs (at most 4096)");
    free(text);
    text = malloc(600);
    assert_non_null(text);
    n = snprintf(text, 64, "time,x,y,z\n\n\n0,0,0,0\n1,0,0,");
    memset(text + n, '1', 300);
    strcpy(text + n + 300, "\n");
    assert_scripted_refused(text, "bad.csv:5: column 4 is 300 bytes long (at most 256)");
    free(text);
    assert_scripted_refused("time,x,y,z\n\n0,0,0,0\n\n1,0,abc,0\n", "bad.csv:5: column 3: expected a number, got 'abc'");
    sb_haptic_device_def dir = sb_default_haptic_device_def();
    dir.kind = "scripted";
    dir.file = tu_tmp_dir;
    sb_error dir_err;
    assert_null(sb_haptic_device_open(&dir, &dir_err));
    assert_non_null(strstr(dir_err.message, "is a directory"));
    sb_haptic_device_def def = sb_default_haptic_device_def();
    def.kind = "scripted";
    def.file = "/nonexistent/path.csv";
    sb_error err;
    assert_null(sb_haptic_device_open(&def, &err));
    assert_non_null(strstr(err.message, "/nonexistent/path.csv"));
    def.kind = "phantom";
    assert_null(sb_haptic_device_open(&def, &err));
    assert_non_null(strstr(err.message, "unknown kind 'phantom'"));
}

/* ---- the UDP device ----------------------------------------------------- */

static void test_udp_device_takes_poses_and_answers_forces(void** state) {
    (void)state;
    sb_haptic_device_def def = sb_default_haptic_device_def();
    def.kind = "udp";
    def.port = 40000 + (int)(getpid() % 20000);
    sb_error err;
    sb_haptic_device* d = sb_haptic_device_open(&def, &err);
    if (!d) fail_msg("%s", err.message);
    sb_haptic_pose p;
    assert_int_equal(sb_haptic_device_read(d, 0, &p), SB_OK); /* nothing yet: at rest */
    assert_true(p.position[0] == 0 && p.orientation[0] == 1);

    int s = socket(AF_INET, SOCK_DGRAM, 0);
    struct sockaddr_in to = {.sin_family = AF_INET, .sin_port = htons((uint16_t)def.port)};
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    unsigned char packet[SB_UDP_POSE_SIZE];
    for (uint32_t i = 1; i <= 3; i++) { /* the newest of those waiting counts */
        sb_udp_pose pose = {.sequence = i, .time = i, .position = {0.01 * i, 0, -0.02}, .orientation = {0, 1, 0, 0}};
        pose.buttons = i;
        sb_udp_pose_pack(&pose, packet);
        assert_int_equal(sendto(s, packet, sizeof packet, 0, (struct sockaddr*)&to, sizeof to), sizeof packet);
    }
    assert_int_equal(sendto(s, "junk", 4, 0, (struct sockaddr*)&to, sizeof to), 4); /* ignored */
    nanosleep(&(struct timespec){.tv_nsec = 20000000}, NULL); /* loopback delivery: only for the datagrams to arrive */
    assert_int_equal(sb_haptic_device_read(d, 1.0, &p), SB_OK);
    TU_ASSERT_NEAR(p.position[0], 0.03, 0);
    TU_ASSERT_NEAR(p.position[2], -0.02, 0);
    TU_ASSERT_NEAR(p.orientation[1], 1, 0);
    assert_int_equal(p.buttons, 3);

    double force[3] = {0.5, -1, 2};
    assert_int_equal(sb_haptic_device_write(d, 1.0, force), SB_OK);
    unsigned char answer[64];
    ssize_t n = recv(s, answer, sizeof answer, 0);
    uint32_t sequence;
    double time, got[3];
    assert_true(sb_udp_force_unpack(answer, (long)n, &sequence, &time, got));
    assert_int_equal(sequence, 3);
    TU_ASSERT_NEAR(time, 1.0, 0);
    for (int k = 0; k < 3; k++) TU_ASSERT_NEAR(got[k], force[k], 0);
    /* Silence past the timeout is a device error. */
    assert_int_equal(sb_haptic_device_read(d, 1.3, &p), SB_ERR_IO);
    close(s);
    sb_haptic_device_close(d);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wall_feels_springs_in_series),
        cmocka_unit_test(test_stiff_wall_is_felt_through_the_coupling_and_clamped),
        cmocka_unit_test(test_short_steps_move_the_tool_a_steps_share),
        cmocka_unit_test(test_stalled_simulation_ramps_to_zero_and_back),
        cmocka_unit_test(test_nonfinite_pose_and_device_error_ramp_to_zero),
        cmocka_unit_test(test_absurd_pose_burst_is_a_fault_and_recovers),
        cmocka_unit_test(test_limits_refused),
        cmocka_unit_test(test_servo_thread_runs_and_stops),
        cmocka_unit_test(test_scene_runs_the_servo_and_writes_haptics_csv),
        cmocka_unit_test(test_quaternion_to_degrees),
        cmocka_unit_test(test_scripted_device_interpolates),
        cmocka_unit_test(test_mouse_device_gives_the_last_move),
        cmocka_unit_test(test_scripted_device_errors_name_the_line),
        cmocka_unit_test(test_udp_device_takes_poses_and_answers_forces),
    };
    if (tu_make_tmp_dir("haptics") != 0) return 1;
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    tu_remove_tmp_dir();
    return failed;
}
