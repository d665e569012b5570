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

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_line_midway),
        cmocka_unit_test(test_line_at_the_start_and_end),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
