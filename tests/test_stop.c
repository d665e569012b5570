/* The run's stop conditions (cli/stop.c): the bouncing ball stops by
 * its kinetic energy, below the threshold and before the watchdog, and the
 * log ends there; a run the watchdog ends says so and ends at
 * stop.max_time; without stop keys the duration ends the run; bad values
 * exit 2 naming the line. */
#define _POSIX_C_SOURCE 200809L
#include "test_util.h"

#include "cli/stop.h"
#include "tests/test_files.h"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_stop");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

/* The last row of DIR/log.csv: its time and kinetic energy (the first two
 * columns), and how many rows there are. */
static int last_row(const char* dir, double* time, double* kinetic) {
    char name[400];
    snprintf(name, sizeof name, "%s/log.csv", dir);
    char* log = tu_read_file(name);
    assert_non_null(log);
    int rows = -1; /* the header */
    const char* last = log;
    for (const char* line = log; *line; line = strchr(line, '\n') + 1) {
        rows++;
        last = line;
        if (!strchr(line, '\n')) break;
    }
    char* end;
    *time = strtod(last, &end);
    assert_true(*end == ',');
    *kinetic = strtod(end + 1, &end);
    free(log);
    return rows;
}

static void test_bouncing_ball_stops_when_still(void** state) {
    (void)state;
    tu_result r = tu_run((const char*[]){"run", SB_SOURCE_DIR "/scenes/bouncing_ball.yaml", "--set",
                                         "output.frames=false", "--output", "ball", NULL});
    if (r.code != 0) fail_msg("%s", r.err);
    const char* said = strstr(r.out, "softbond: stopped at t = ");
    assert_non_null(said);
    assert_non_null(strstr(said, "below stop.kinetic_energy (0.0001 J)"));
    double t = strtod(said + strlen("softbond: stopped at t = "), NULL);
    tu_result_free(&r);
    double time, kinetic;
    int rows = last_row(tu_tmp_path("ball"), &time, &kinetic);
    print_message("bouncing ball: stopped at t = %g s with %g J (%d rows)\n", time, kinetic, rows);
    TU_ASSERT_LE(kinetic, 1e-4);
    assert_true(time >= 2.0);        /* not before stop.min_time */
    assert_true(time < 10.0 - 0.02); /* before the watchdog (the duration) */
    TU_ASSERT_NEAR(time, t, 1e-5 * t);
    assert_true(rows > 100 && rows < 500); /* frames every 0.02 s up to the stop, and the stop's */
}

static const char* const falling_sheet = "mesh: {generator: sheet, nx: 4, ny: 4, width: 0.1, height: 0.1}\n"
                                         "pin: top_corners\n"
                                         "dt: 0.001\n"
                                         "duration: 1\n"
                                         "frame_interval: 0.05\n"
                                         "output: {frames: false}\n";

static void test_watchdog(void** state) {
    (void)state;
    tu_write_file("swing.yaml", falling_sheet);
    /* a swinging sheet never gets below 1 nJ in 0.3 s */
    tu_result r = tu_run((const char*[]){"run", "swing.yaml", "--set", "stop={kinetic_energy: 1e-9, max_time: 0.3}",
                                         "--output", "swing", NULL});
    if (r.code != 0) fail_msg("%s", r.err);
    assert_non_null(strstr(r.out, "softbond: stopped at t = 0.3 s: watchdog (stop.max_time 0.3 s reached; kinetic "
                                  "energy "));
    tu_result_free(&r);
    double time, kinetic;
    assert_int_equal(last_row(tu_tmp_path("swing"), &time, &kinetic), 7); /* 0, 0.05, ..., 0.3 */
    TU_ASSERT_NEAR(time, 0.3, 1e-9);
    assert_true(kinetic > 1e-9);
    /* a watchdog later than the duration: the duration ends the run */
    r = tu_run((const char*[]){"run", "swing.yaml", "--set", "duration=0.1", "--set", "stop.max_time=5", "--output",
                               "plain", NULL});
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "softbond: stopped at t = 0.1 s: duration reached"));
    tu_result_free(&r);
    /* no stop keys: the run ends at its duration and says only where its output is */
    r = tu_run((const char*[]){"run", "swing.yaml", "--set", "duration=0.1", "--output", "plain", NULL});
    assert_int_equal(r.code, 0);
    assert_null(strstr(r.out, "stopped"));
    tu_result_free(&r);
}

static void test_bad_stop_keys(void** state) {
    (void)state;
    tu_write_file("bad_stop.yaml", "dt: 0.001\nstop:\n  min_time: -1\n");
    tu_result r = tu_run((const char*[]){"run", "bad_stop.yaml", "--output", "never", NULL});
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "bad_stop.yaml:3: 'stop.min_time' must be >= 0, got -1"));
    tu_result_free(&r);
    tu_write_file("bad_stop2.yaml", "stop: {kinetic_energy: nan}\n");
    r = tu_run((const char*[]){"run", "bad_stop2.yaml", "--output", "never", NULL});
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "bad_stop2.yaml:1: 'stop.kinetic_energy' must be finite"));
    tu_result_free(&r);
    tu_write_file("bad_stop3.yaml", "stop:\n  max_tme: 3\n");
    r = tu_run((const char*[]){"run", "bad_stop3.yaml", "--output", "never", NULL});
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "bad_stop3.yaml:2: unknown key 'stop.max_tme'"));
    tu_result_free(&r);
}

/* The kinetic-energy stop is armed (the run reads the energies after a
 * step) only with stop.kinetic_energy set and from min_time on; unarmed, a
 * kinetic energy of 0 does not stop the run. */
static void test_watches_only_when_armed(void** state) {
    (void)state;
    sb_stop none = {.kinetic_energy = 0, .min_time = 0, .duration = 1};
    assert_false(sb_stop_watches(&none, 0.5));
    assert_false(sb_stop_after_step(&none, 0.5, 0.0));
    sb_stop later = {.kinetic_energy = 1e-3, .min_time = 0.2, .duration = 1};
    assert_false(sb_stop_watches(&later, 0.1));
    assert_false(sb_stop_after_step(&later, 0.1, 0.0));
    assert_true(sb_stop_watches(&later, 0.2));
    assert_false(sb_stop_after_step(&later, 0.2, 2e-3));
    assert_true(sb_stop_after_step(&later, 0.3, 5e-4));
    assert_int_equal(later.reason, SB_STOP_KINETIC_ENERGY);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bouncing_ball_stops_when_still),
        cmocka_unit_test(test_watchdog),
        cmocka_unit_test(test_bad_stop_keys),
        cmocka_unit_test(test_watches_only_when_armed),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
