/* The progress bar's line: the share done, the simulated time, the
 * real-time factor and the time left, from numbers worked out by hand. */
#include "tests/test_util.h"
#include "cli/progress.h"

static void test_line_midway(void** state) {
    (void)state;
    char line[200];
    /* 400 of 1000 steps of 5 ms in 2.5 s: 40 %, 2 s simulated, 2 / 2.5 = 0.8x,
     * 600 steps left at 2.5 s per 400 = 3.75 s */
    sb_progress_format(line, sizeof line, 400, 1000, 0.005, 2.5);
    assert_string_equal(line, "[################........................]  40%  t = 2 s  0.8x real time  4 s left");
}

static void test_line_at_the_start_and_end(void** state) {
    (void)state;
    char line[200];
    sb_progress_format(line, sizeof line, 0, 1000, 0.005, 0.0);
    assert_string_equal(line, "[........................................]   0%  t = 0 s");
    /* past the end counts as the end: 5 s simulated in 10 s */
    sb_progress_format(line, sizeof line, 1200, 1000, 0.005, 10.0);
    assert_string_equal(line, "[########################################] 100%  t = 5 s  0.5x real time  0 s left");
}

/* A run far slower than its simulated time says so, on a
 * terminal or not (contact.thickness: 10 in a scene of centimetres: 1.3 s
 * a step instead of 10 ms, and nothing printed off a terminal). */
static void test_slow_run_note(void** state) {
    (void)state;
    char line[300];
    /* 1 s simulated at 1 ms steps; 4 steps in 5.2 s: 1300 s projected */
    assert_true(sb_progress_slow_note(line, sizeof line, 4, 1000, 0.001, 5.2));
    assert_string_equal(line, "this run will take about 1.3e+03 s of wall-clock time for 1 s simulated (1.3 s a step, "
                              "1.3e+03x slower than real time); check the scene's lengths and dt for a slip of units");
    /* the same scene at 10 ms a step: 10 s projected, no note */
    assert_false(sb_progress_slow_note(line, sizeof line, 520, 1000, 0.001, 5.2));
    /* too early to tell, or done */
    assert_false(sb_progress_slow_note(line, sizeof line, 4, 1000, 0.001, 4.9));
    assert_false(sb_progress_slow_note(line, sizeof line, 1000, 1000, 0.001, 5000));
    /* 100x slower than real time but under a minute: no note */
    assert_false(sb_progress_slow_note(line, sizeof line, 100, 200, 0.001, 25));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_line_midway),
        cmocka_unit_test(test_line_at_the_start_and_end),
        cmocka_unit_test(test_slow_run_note),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
