/* The scene's `handles` (scenes/handles.c): hook_pull.yaml runs, its soft
 * handle's force columns are in log.csv, and the same for 1 and 2 threads;
 * a hard handle selected by `at` has its vertex on its path in the last
 * frame; bad entries exit 2 naming the line. */
#define _POSIX_C_SOURCE 200809L
#include "test_util.h"

#include "tests/test_files.h"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_handle_scene");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

static char* read_output(const char* dir, const char* file) {
    char name[400];
    snprintf(name, sizeof name, "%s/%s", tu_tmp_path(dir), file);
    char* text = tu_read_file(name);
    assert_non_null(text);
    return text;
}

static void test_hook_pull_runs(void** state) {
    (void)state;
    char* logs[2];
    for (int threads = 1; threads <= 2; threads++) {
        char dir[16], count[4];
        snprintf(dir, sizeof dir, "hook%d", threads);
        snprintf(count, sizeof count, "%d", threads);
        tu_result r =
            tu_run((const char*[]){"run", SB_SOURCE_DIR "/scenes/hook_pull.yaml", "--set", "duration=0.4", "--set",
                                   "output.frames=false", "--threads", count, "--output", dir, NULL});
        if (r.code != 0) fail_msg("%s", r.err);
        tu_result_free(&r);
        logs[threads - 1] = read_output(dir, "log.csv");
    }
    /* the soft handle's columns, the hard one has none */
    assert_non_null(strstr(logs[0], ",contacts,grasper_fx,grasper_fy,grasper_fz\n"));
    assert_null(strstr(logs[0], "hook_f"));
    assert_string_equal(logs[0], logs[1]);
    free(logs[0]);
    free(logs[1]);
}

/* A weightless sheet with a hard handle on the vertex at (1, 1, 0) moved
 * by [0.1, 0, 0.2] in 0.1 s: the frame at 0.1 s has it exactly there. */
static void test_hard_handle_on_its_path(void** state) {
    (void)state;
    tu_write_file("lift.yaml", "mesh: {generator: sheet, nx: 3, ny: 3, width: 1, height: 1}\n"
                               "gravity: [0, 0, 0]\n"
                               "pin: left_edge\n"
                               "handles:\n"
                               "  - at: [1, 1, 0]\n"
                               "    path: [{time: 0, translate: [0, 0, 0]}, {time: 0.1, translate: [0.1, 0, 0.2]}]\n"
                               "dt: 0.001\n"
                               "duration: 0.1\n"
                               "frame_interval: 0.1\n"
                               "output: {formats: obj}\n");
    tu_result r = tu_run((const char*[]){"run", "lift.yaml", "--output", "lift", NULL});
    if (r.code != 0) fail_msg("%s", r.err);
    tu_result_free(&r);
    char* obj = read_output("lift", "frame_000001.obj");
    /* the exporter may write the vertices in its own order: the nearest to the target */
    double nearest = INFINITY, x, y, z;
    for (const char* line = strstr(obj, "\nv "); line; line = strstr(line + 1, "\nv ")) {
        assert_int_equal(sscanf(line + 1, "v %lf %lf %lf", &x, &y, &z), 3);
        nearest = fmin(nearest, sqrt((x - 1.1) * (x - 1.1) + (y - 1.0) * (y - 1.0) + (z - 0.2) * (z - 0.2)));
    }
    TU_ASSERT_LE(nearest, 1e-6);
    free(obj);
}

static void assert_handles_fail(const char* entries, const char* message) {
    char text[1024];
    snprintf(text, sizeof text, "mesh: {generator: sheet, nx: 3, ny: 3}\ndt: 0.001\nhandles:\n%s", entries);
    tu_write_file("bad.yaml", text);
    tu_result r = tu_run((const char*[]){"run", "bad.yaml", "--output", "never", NULL});
    if (r.code != 2 || !strstr(r.err, message))
        fail_msg("expected exit 2 and '%s', got %d: %s", message, r.code, r.err);
    tu_result_free(&r);
}

static void test_bad_handles(void** state) {
    (void)state;
    assert_handles_fail("  - {name: hook}\n", "bad.yaml:4: 'handles[0].vertices' is not set");
    assert_handles_fail("  - {vertices: [1], at: [0, 0, 0]}\n",
                        "bad.yaml:4: 'handles[0].at': give vertices or at, not both");
    assert_handles_fail("  - vertices: [1]\n    radius: 0.1\n",
                        "bad.yaml:5: 'handles[0].radius' applies to at, not to vertices");
    assert_handles_fail("  - vertices: [1, -2]\n",
                        "bad.yaml:4: 'handles[0].vertices' expects vertex indices (whole numbers >= 0), got '-2'");
    assert_handles_fail("  - vertices: [1, 1]\n", "bad.yaml:4: 'handles[0].vertices': vertex 1 is listed twice");
    assert_handles_fail("  - vertices: [99]\n",
                        "bad.yaml:4: 'handles[0].vertices': vertex 99 is not in the model (9 vertices)");
    assert_handles_fail("  - at: [5, 5, 5]\n    radius: 0.1\n",
                        "bad.yaml:4: 'handles[0].at': no vertex within radius 0.1 of [5, 5, 5]");
    assert_handles_fail("  - vertices: [1]\n    stiffness: -1\n",
                        "bad.yaml:5: 'handles[0].stiffness' must be >= 0, got -1");
    assert_handles_fail("  - vertices: [1]\n    stifness: 1\n",
                        "bad.yaml:5: unknown key 'handles[0].stifness' (did you mean 'handles[0].stiffness'?)");
    assert_handles_fail("  - vertices: [1]\n    path:\n      - {time: 1}\n      - {time: 0}\n",
                        "bad.yaml:7: 'handles[0].path[1].time' (0) must be > the time before it (1)");
    assert_handles_fail("  - {vertices: [1], interpolation: cubic}\n",
                        "bad.yaml:4: 'handles[0].interpolation' must be linear or smooth, got 'cubic'");
    assert_handles_fail("  - {vertices: [1], release_at: -1}\n", "bad.yaml:4: 'handles[0].release_at' must be >= 0");
    assert_handles_fail("  - {vertices: [1], name: a}\n  - {vertices: [2], name: a}\n",
                        "bad.yaml:5: 'handles[1].name': 'a' is already handles[0]'s name");
    /* --set is checked the same way */
    tu_write_file("ok.yaml", "mesh: {generator: sheet, nx: 3, ny: 3}\ndt: 0.001\n");
    tu_result r = tu_run(
        (const char*[]){"run", "ok.yaml", "--set", "handles=[{vertices: [1], damping: x}]", "--output", "never", NULL});
    assert_int_equal(r.code, 2);
    assert_non_null(
        strstr(r.err, "--set handles=[{vertices: [1], damping: x}]: 'handles[0].damping' expects a number"));
    tu_result_free(&r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hook_pull_runs),
        cmocka_unit_test(test_hard_handle_on_its_path),
        cmocka_unit_test(test_bad_handles),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
