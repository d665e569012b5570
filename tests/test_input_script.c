/* The viewer's input script reader (viewer/input_script.c) without a
 * window: what `softbond view --script FILE` refuses before it opens one. */
#define _POSIX_C_SOURCE 200809L
#include "test_util.h"
#include "test_files.h"

#include "viewer/input_script.h"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_input_script");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

static void assert_load_fails(const char* path, sb_status status, const char* message) {
    sb_input_script s;
    sb_error err;
    assert_int_equal(sb_input_script_load(path, &s, &err), status);
    if (!strstr(err.message, message)) fail_msg("expected '%s' in: %s", message, err.message);
}

/* A directory was an empty script (exit 0; without
 * --frames the viewer ran forever). */
static void test_directory_is_refused(void** state) {
    (void)state;
    char message[400];
    snprintf(message, sizeof message, "%s: is a directory, not a script", tu_tmp_dir);
    assert_load_fails(tu_tmp_dir, SB_ERR_IO, message);
}

/* A NUL byte was 'line longer than 510 bytes'; a long
 * line is named as one, with its length. */
static void test_nul_and_long_lines_named(void** state) {
    (void)state;
    static const char nul[] = "0 key F1\n0.5 key\0 F2\n";
    FILE* f = fopen(tu_tmp_path("nul.txt"), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(nul, 1, sizeof nul - 1, f), sizeof nul - 1);
    fclose(f);
    assert_load_fails(tu_tmp_path("nul.txt"), SB_ERR_INVALID, "nul.txt:2: a NUL byte in the line");
    char text[1200] = "0 key F1\n# ";
    size_t n = strlen(text);
    memset(text + n, 'x', 600);
    strcpy(text + n + 600, "\n1 key F2\n");
    tu_write_file("long.txt", text);
    assert_load_fails(tu_tmp_path("long.txt"), SB_ERR_INVALID, "long.txt:2: line longer than 510 bytes (603)");
    /* a good script still loads, a line of exactly 510 bytes too */
    char good[700] = "0 key F1\n0.5 key F2 #";
    n = strlen(good) - strlen("0 key F1\n");
    memset(good + strlen(good), 'y', 510 - n);
    strcpy(good + strlen("0 key F1\n") + 510, "\n");
    tu_write_file("good.txt", good);
    sb_input_script s;
    sb_error err;
    if (sb_input_script_load(tu_tmp_path("good.txt"), &s, &err) != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(s.count, 2);
    sb_input_script_free(&s);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_directory_is_refused),
        cmocka_unit_test(test_nul_and_long_lines_named),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
