/* Haptics against a simulated tissue, on a virtual clock: a 10 cm sheet of
 * 21 x 21 vertices held along its four sides, a 5 mm sphere for the tool;
 * ten solver steps of 0.1 ms per servo tick of 1 ms, in one thread.
 * - A scripted probe pressed slowly in and held: the force the hand feels
 *   is the sheet's static reaction at the same tool position, computed
 *   separately by a run with the tool on a kinematic path (within 5 %).
 * - Passivity: a simulated hand (a mass on a spring-damper that follows a
 *   tapping trajectory and receives the loop's force) taps the sheet ten
 *   times at the default coupling; the loop's net work on the hand is not
 *   positive (it takes energy out, into the sheet's damping). */
#define _POSIX_C_SOURCE 200809L
#include "test_util.h"
#include "test_files.h"
#include "held_sheet.h"

#define T 1e-3
#define DT 1e-4
#define STEPS_PER_TICK 10
#define SIDE 21
#define REST_Z 0.012      /* m: the tool's centre at rest, 7 mm above the sheet */
#define WINDOW_STEPS 1000 /* 0.1 s */
#define WINDOWS 30

typedef struct tissue {
    held_sheet sheet;
    long steps;
    double reaction[WINDOWS]; /* N: the tool's contact force along z, averaged over each window */
} tissue;

/* The tool's contact force after a step, into its window's average. */
static void record_reaction(tissue* t) {
    double f[3];
    sb_solver_contact_force(t->sheet.solver, 0, f);
    long w = t->steps++ / WINDOW_STEPS;
    if (w < WINDOWS) t->reaction[w] += f[2] / WINDOW_STEPS;
}

/* The sheet, and a sphere at rest above its middle, on the path given (NULL: driven). */
static void tissue_open(tissue* t, const sb_keyframe* path, uint32_t path_count) {
    const double centre[3] = {0.05, 0.05, REST_Z};
    held_sheet_open(&t->sheet, SIDE, 0.1, centre, 0.005, 0.0, path, path_count);
}

/* One servo tick of the whole loop: the simulation's steps during the
 * tick (each drives the tool, then senses it, as `softbond run` does), then
 * the servo's tick. */
static void loop_tick(tissue* t, sb_haptics* h, long i) {
    for (int s = 0; s < STEPS_PER_TICK; s++) {
        sb_haptics_drive(h);
        assert_int_equal(sb_solver_advance(t->sheet.solver, DT), SB_OK);
        record_reaction(t);
        sb_haptics_sense(h, t->sheet.solver, (double)(i - 1) * T + (s + 1) * DT);
    }
    sb_haptics_tick(h, (double)i * T);
}

static sb_haptics* couple(tissue* t, sb_haptic_device* device) {
    sb_error err;
    sb_haptics_def def = sb_default_haptics_def();
    sb_haptics* h = sb_haptics_create(&def, device, t->sheet.tool, 0, &err);
    assert_non_null(h);
    return h;
}

/* The mean over the last `ticks` of the z force the loop sent. */
static double mean_force_z(sb_haptics* h, long ticks, long total) {
    sb_haptic_tick tick;
    double sum = 0;
    for (long i = 0; i < total; i++) {
        assert_int_equal(sb_haptics_drain(h, &tick, 1), 1);
        if (i >= total - ticks) sum += tick.force[2];
    }
    return sum / (double)ticks;
}

/* The scripted device that replays `csv` (written to the test's folder as `name`). */
static sb_haptic_device* open_script(const char* name, const char* csv) {
    sb_haptic_device_def dd = sb_default_haptic_device_def();
    dd.kind = "scripted";
    dd.file = tu_write_file(name, csv);
    sb_error err;
    sb_haptic_device* device = sb_haptic_device_open(&dd, &err);
    assert_non_null(device);
    return device;
}

static void test_felt_force_is_the_static_reaction(void** state) {
    (void)state;
    /* Down 14 mm over 2 s (the sphere's bottom 7.5 mm into the sheet), held 1 s. */
    sb_haptic_device* device = open_script("press.csv", "time,x,y,z\n0,0,0,0\n2,0,0,-0.014\n3,0,0,-0.014\n");
    tissue t = {0};
    tissue_open(&t, NULL, 0);
    sb_haptics* h = couple(&t, device);
    const long ticks = 3000;
    for (long i = 0; i < ticks; i++) loop_tick(&t, h, i);
    double felt = mean_force_z(h, 200, ticks), proxy[3];
    sb_haptics_proxy(h, proxy);
    sb_haptics_destroy(h);
    sb_haptic_device_close(device);
    held_sheet_close(&t.sheet);

    /* The same sheet with the tool on a kinematic path to where the proxy
     * ended, held there: the sheet's reaction, averaged over 0.2 s. */
    sb_keyframe path[3] = {{.time = 0}, {.time = 2}, {.time = 3}};
    for (int k = 1; k < 3; k++) path[k].translate[2] = proxy[2] - REST_Z;
    tissue s = {0};
    tissue_open(&s, path, 3);
    double reaction = 0;
    for (long i = 0; i < ticks * STEPS_PER_TICK; i++) {
        assert_int_equal(sb_solver_advance(s.sheet.solver, DT), SB_OK);
        double f[3];
        sb_solver_contact_force(s.sheet.solver, 0, f);
        if (i >= (ticks - 200) * STEPS_PER_TICK) reaction += f[2] / (200.0 * STEPS_PER_TICK);
    }
    held_sheet_close(&s.sheet);
    print_message("proxy %.3f mm below rest, felt %.4f N, static reaction %.4f N\n", 1e3 * (REST_Z - proxy[2]), felt,
                  reaction);
    assert_true(reaction > 0.03); /* the sheet was pressed */
    TU_ASSERT_NEAR(felt, reaction, 0.05 * reaction);
}

/* The probe of the first test driven by the scripted device and, in a
 * separate run, moved along the same trajectory as a kinematic path: the
 * sheet's reaction on it over time (0.1 s averages) is the same within 5 %
 * of its peak. Not closer: the proxy stops short of the device by the felt
 * force over K (0.07 mm here), where the sheet pushes 0.0015 N less (3 %). The syringe of the interaction issue
 * makes this comparison with a needle: tests/test_haptics_syringe.c. */
static void test_scripted_device_matches_the_kinematic_path(void** state) {
    (void)state;
    sb_haptic_device* device = open_script("press2.csv", "time,x,y,z\n0,0,0,0\n2,0,0,-0.014\n3,0,0,-0.014\n");
    tissue* felt = calloc(1, sizeof *felt);
    tissue_open(felt, NULL, 0);
    sb_haptics* h = couple(felt, device);
    for (long i = 0; i < 3000; i++) loop_tick(felt, h, i);
    sb_haptic_tick tick;
    while (sb_haptics_drain(h, &tick, 1)) {
    }
    sb_haptics_destroy(h);
    sb_haptic_device_close(device);

    sb_keyframe path[3] = {
        {.time = 0}, {.time = 2, .translate = {0, 0, -0.014}}, {.time = 3, .translate = {0, 0, -0.014}}};
    tissue* moved = calloc(1, sizeof *moved);
    tissue_open(moved, path, 3);
    for (long i = 0; i < 3000 * STEPS_PER_TICK; i++) {
        assert_int_equal(sb_solver_advance(moved->sheet.solver, DT), SB_OK);
        record_reaction(moved);
    }
    double peak = 0;
    for (int w = 0; w < WINDOWS; w++) peak = fmax(peak, fabs(moved->reaction[w]));
    assert_true(peak > 0.03);
    for (int w = 0; w < WINDOWS; w++) TU_ASSERT_NEAR(felt->reaction[w], moved->reaction[w], 0.05 * peak);
    print_message("reaction at 3 s: %.4f N driven by the device, %.4f N on the path\n", felt->reaction[WINDOWS - 1],
                  moved->reaction[WINDOWS - 1]);
    held_sheet_close(&felt->sheet);
    held_sheet_close(&moved->sheet);
    free(felt);
    free(moved);
}

/* The probe pressed 14 mm in over a second (as in the first test), then
 * the simulation stalls for 0.15 s (a hitch of the machine: the servo
 * ticks on, no step comes) while the hand goes 21 mm further in; then the
 * steps resume. The tool catches up at max_speed, the sheet's middle under
 * it. Taken there in one step, it flung the sheet's middle, which came
 * back over the top of the tool: it had passed through. */
static void test_tool_after_a_stall_does_not_pass_through(void** state) {
    (void)state;
    sb_haptic_device* device =
        open_script("plunge.csv", "time,x,y,z\n0,0,0,0\n1,0,0,-0.014\n1.1,0,0,-0.014\n1.2,0,0,-0.035\n2,0,0,-0.035\n");
    tissue t = {0};
    tissue_open(&t, NULL, 0);
    sb_haptics* h = couple(&t, device);
    const long stall_from = 1100, stall_to = 1250, ticks = 1500;
    sb_haptic_tick tick;
    for (long i = 0; i < ticks; i++) {
        if (i >= stall_from && i < stall_to)
            sb_haptics_tick(h, (double)i * T);
        else
            loop_tick(&t, h, i);
        while (sb_haptics_drain(h, &tick, 1)) {
        }
    }
    static double x[3 * SIDE * SIDE];
    sb_solver_get_positions(t.sheet.solver, x);
    const uint32_t middle = (SIDE / 2) * SIDE + SIDE / 2;
    double proxy[3];
    sb_haptics_proxy(h, proxy);
    print_message("after the stall: the tool's centre at z %.2f mm, the sheet's middle at z %.2f mm\n", 1e3 * proxy[2],
                  1e3 * x[3 * middle + 2]);
    TU_ASSERT_LE(proxy[2], REST_Z - 0.030);    /* it caught up, short by the felt force over K */
    TU_ASSERT_LE(x[3 * middle + 2], proxy[2]); /* under the tool, not over it */
    sb_haptics_destroy(h);
    sb_haptic_device_close(device);
    held_sheet_close(&t.sheet);
}

/* ---- the simulated hand ------------------------------------------------ */

typedef struct hand {
    double z, v;  /* m, m/s: the hand's (device's) height, from the device's origin */
    double force; /* N: the loop's last force on it, along z */
    double time;  /* s: how far it has been integrated */
    double work;  /* J: the loop's work on the hand */
    double peak;  /* N: the largest force felt */
} hand;

enum { HAND_TAPS = 10 };
#define HAND_MASS 0.1      /* kg */
#define HAND_STIFFNESS 300 /* N/m: the arm's pull towards where it means to be */
#define HAND_DAMPING 3     /* N s/m */

/* Where the arm means the hand to be: taps 18 mm down from the origin at 2 Hz. */
static double hand_target(double time) { return -0.018 * fmax(0, sin(2 * M_PI * 2 * time)); }

static sb_status hand_read(void* user, double time, sb_haptic_pose* pose) {
    hand* h = user;
    for (; h->time < time - 1e-12; h->time += T) { /* semi-implicit Euler at the servo's rate */
        double a = (HAND_STIFFNESS * (hand_target(h->time) - h->z) - HAND_DAMPING * h->v + h->force) / HAND_MASS;
        h->v += a * T;
        double dz = h->v * T;
        h->work += h->force * dz;
        h->z += dz;
    }
    *pose = (sb_haptic_pose){.time = time, .position = {0, 0, h->z}, .orientation = {1, 0, 0, 0}};
    return SB_OK;
}

static sb_status hand_write(void* user, double time, const double force[3]) {
    (void)time;
    hand* h = user;
    h->force = force[2];
    h->peak = fmax(h->peak, fabs(force[2]));
    return SB_OK;
}

static void test_tapping_hand_gains_no_energy(void** state) {
    (void)state;
    hand hand = {0};
    static const sb_haptic_device_ops ops = {hand_read, hand_write, NULL};
    sb_error err;
    sb_haptic_device* device = sb_haptic_device_custom(&ops, &hand, &err);
    tissue t = {0};
    tissue_open(&t, NULL, 0);
    sb_haptics* h = couple(&t, device);
    const long ticks = (long)(HAND_TAPS / 2.0 / T);
    sb_haptic_tick tick;
    for (long i = 0; i < ticks; i++) {
        loop_tick(&t, h, i);
        while (sb_haptics_drain(h, &tick, 1)) {
        }
    }
    print_message("the loop's work on the hand over %d taps: %.3g J; peak force %.3f N\n", HAND_TAPS, hand.work,
                  hand.peak);
    assert_true(hand.peak > 0.1); /* it did touch */
    TU_ASSERT_LE(hand.work, 0);
    sb_haptics_destroy(h);
    sb_haptic_device_close(device);
    held_sheet_close(&t.sheet);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_felt_force_is_the_static_reaction),
        cmocka_unit_test(test_scripted_device_matches_the_kinematic_path),
        cmocka_unit_test(test_tapping_hand_gains_no_energy),
        cmocka_unit_test(test_tool_after_a_stall_does_not_pass_through),
    };
    if (tu_make_tmp_dir("haptics_tissue") != 0) return 1;
    int failed = cmocka_run_group_tests(tests, NULL, NULL);
    tu_remove_tmp_dir();
    return failed;
}
