/* The isolated call behind the assimp import (mesh/io/isolate.c): an
 * answer comes back byte for byte; a child that crashes, aborts, hangs or
 * allocates past its limit becomes an error saying so, in about the time
 * limit, and the caller lives on. */
#define _POSIX_C_SOURCE 200809L

#include <signal.h>
#include <stdio.h>
#include <time.h>
#include <unistd.h>

#include "tests/test_util.h"
#include "common/clock.h"
#include "mesh/io/isolate.h"

/* 3 MB of a known pattern: more than a pipe holds at once. */
static void answer_pattern(void* arg, sb_blob* answer) {
    size_t size = *(const size_t*)arg;
    answer->data = malloc(size);
    for (size_t i = 0; i < size; i++) answer->data[i] = (unsigned char)(i * 7 + i / 251);
    answer->size = size;
}

static void crash(void* arg, sb_blob* answer) {
    (void)arg;
    (void)answer;
    raise(SIGSEGV);
}

static void hang(void* arg, sb_blob* answer) {
    (void)arg;
    (void)answer;
    for (;;) pause();
}

/* Allocates and touches 1 MB blocks until malloc fails, then aborts as an
 * importer does on std::bad_alloc left uncaught. */
static void allocate_forever(void* arg, sb_blob* answer) {
    (void)answer;
    size_t* blocks = arg;
    for (;;) {
        char* block = malloc(1 << 20);
        if (!block) abort();
        memset(block, 1, 1 << 20);
        ++*blocks;
    }
}

static void test_answer_comes_back_whole(void** state) {
    (void)state;
    size_t size = 3 << 20;
    sb_isolate_limits limits = {10.0, (size_t)256 << 20};
    sb_blob answer;
    char why[160] = "";
    assert_int_equal(sb_isolate_run(answer_pattern, &size, &limits, &answer, why, sizeof why), SB_OK);
    assert_int_equal(answer.size, size);
    for (size_t i = 0; i < size; i++)
        if (answer.data[i] != (unsigned char)(i * 7 + i / 251)) fail_msg("byte %zu differs", i);
    free(answer.data);
}

static void test_crash_is_reported(void** state) {
    (void)state;
    sb_isolate_limits limits = {10.0, (size_t)256 << 20};
    sb_blob answer;
    char why[160] = "";
    assert_int_equal(sb_isolate_run(crash, NULL, &limits, &answer, why, sizeof why), SB_ERR_IO);
    assert_null(answer.data);
    assert_string_equal(why, "killed by signal 11, Segmentation fault");
}

static void test_hang_is_cut_at_the_time_limit(void** state) {
    (void)state;
    sb_isolate_limits limits = {0.5, (size_t)256 << 20};
    sb_blob answer;
    char why[160] = "";
    double start = sb_wall_seconds();
    assert_int_equal(sb_isolate_run(hang, NULL, &limits, &answer, why, sizeof why), SB_ERR_IO);
    double took = sb_wall_seconds() - start;
    assert_string_equal(why, "no answer within 0.5 s");
    assert_true(took >= 0.5 && took < 5.0);
}

static void test_allocation_storm_is_stopped(void** state) {
    (void)state;
    sb_isolate_limits limits = {3.0, (size_t)64 << 20};
    sb_blob answer;
    char why[160] = "";
    size_t blocks = 0;
    double start = sb_wall_seconds();
    assert_int_equal(sb_isolate_run(allocate_forever, &blocks, &limits, &answer, why, sizeof why), SB_ERR_IO);
    assert_true(sb_wall_seconds() - start < 10.0);
    /* it aborts; under the address sanitizer its allocator reports the
     * failure and exits, or stalls in its report until the time limit */
    if (strcmp(why, "killed by signal 6, Aborted") != 0 && strcmp(why, "it exited with code 1 without an answer") != 0)
        assert_string_equal(why, "no answer within 3 s");
    assert_int_equal(blocks, 0); /* the child's count stays in the child */
}

int main(void) {
    alarm(60);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_answer_comes_back_whole),
        cmocka_unit_test(test_crash_is_reported),
        cmocka_unit_test(test_hang_is_cut_at_the_time_limit),
        cmocka_unit_test(test_allocation_storm_is_stopped),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
