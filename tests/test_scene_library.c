/* The scene library (include/softbond/scene.h) as an embedding program uses
 * it: this test includes the public headers only and links the shared
 * libraries. Committed scenes load with the counts their YAML and `softbond
 * info` give (the default sheet, 30 x 30; moon_hook's crescent.obj, 3198
 * vertices, with a table and a hook), a solver made from what the call
 * returned advances, overrides change what they name, and a missing file,
 * an unknown key in a file or in an override fail with the status and the
 * one-line message naming the file and line (or the override). */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "softbond/scene.h"
#include "softbond/softbond.h"

#define SCENES SB_SOURCE_DIR "/scenes/"

static sb_scene_file* load(const char* path, const char* const* overrides, size_t count) {
    sb_scene_file* scene = NULL;
    sb_error err;
    sb_status status = sb_scene_file_load(path, overrides, count, &scene, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    assert_non_null(scene);
    return scene;
}

/* Makes a solver from the scene and advances it `steps` steps of its dt. */
static sb_solver* run(const sb_scene_file* scene, int steps) {
    sb_error err;
    sb_solver* solver = sb_solver_create(sb_scene_file_model(scene), sb_scene_file_solver_def(scene), &err);
    if (!solver) fail_msg("%s", err.message);
    for (int i = 0; i < steps; i++) assert_int_equal(sb_solver_advance(solver, sb_scene_file_dt(scene)), SB_OK);
    assert_int_equal(sb_solver_step_count(solver), (uint64_t)steps);
    assert_true(fabs(sb_solver_time(solver) - steps * sb_scene_file_dt(scene)) < 1e-9);
    return solver;
}

static void test_default_scene(void** state) {
    (void)state;
    sb_scene_file* scene = load(SCENES "default.yaml", NULL, 0);
    const sb_solver_def* def = sb_scene_file_solver_def(scene);
    assert_int_equal(sb_model_vertex_count(sb_scene_file_model(scene)), 30 * 30); /* mesh.nx x mesh.ny */
    assert_int_equal(def->collider_count, 0);
    assert_int_equal(def->handle_count, 0);
    assert_true(sb_scene_file_dt(scene) == 0.0001);
    assert_true(sb_scene_file_duration(scene) == 5.0);
    assert_true(fabs(sb_scene_file_frame_interval(scene) - 1.0 / 30.0) < 1e-12);
    assert_string_equal(sb_scene_file_name(scene), "default");
    assert_true(def->gravity[2] == -9.81);

    /* 200 steps (20 ms): the free sheet falls, the pinned top corners stay */
    sb_solver* solver = run(scene, 200);
    uint32_t n = sb_solver_vertex_count(solver);
    assert_int_equal(n, 900);
    double* p = malloc(3 * (size_t)n * sizeof *p);
    assert_non_null(p);
    sb_solver_get_positions(solver, p);
    double lowest = 0.0, highest = -1.0;
    for (uint32_t i = 0; i < n; i++) {
        lowest = fmin(lowest, p[3 * i + 2]);
        highest = fmax(highest, p[3 * i + 2]);
    }
    assert_true(lowest < -1e-4);   /* g t^2 / 2 = 2 mm by now, less where the bonds hold */
    assert_true(highest > -1e-12); /* the pinned corners */
    free(p);
    sb_solver_destroy(solver);
    sb_scene_file_destroy(scene);
}

/* A mesh file next to the scene, a plane collider and a hard handle. */
static void test_colliders_and_handles(void** state) {
    (void)state;
    sb_scene_file* scene = load(SCENES "moon_hook.yaml", NULL, 0);
    const sb_solver_def* def = sb_scene_file_solver_def(scene);
    assert_int_equal(sb_model_vertex_count(sb_scene_file_model(scene)), 3198); /* softbond info scenes/crescent.obj */
    assert_int_equal(def->collider_count, 1);
    assert_non_null(def->colliders[0]);
    assert_int_equal(def->handle_count, 1);
    assert_true(sb_scene_file_dt(scene) == 0.0001);
    sb_solver* solver = run(scene, 50);
    sb_solver_destroy(solver);
    sb_scene_file_destroy(scene);
}

static void test_overrides(void** state) {
    (void)state;
    const char* const sets[] = {"mesh.nx=12", "dt=0.0005", "dt=0.0002", "stop.kinetic_energy=0.25"};
    sb_scene_file* scene = load(SCENES "default.yaml", sets, 4);
    assert_int_equal(sb_model_vertex_count(sb_scene_file_model(scene)), 12 * 30);
    assert_true(sb_scene_file_dt(scene) == 0.0002); /* the later override wins */
    double value = 0.0;
    sb_error err;
    assert_int_equal(sb_scene_file_number(scene, "mesh.nx", &value, &err), SB_OK);
    assert_true(value == 12.0);
    assert_int_equal(sb_scene_file_number(scene, "stop.kinetic_energy", &value, &err), SB_OK);
    assert_true(value == 0.25);
    assert_int_equal(sb_scene_file_number(scene, "bond.k", &value, &err), SB_OK);
    assert_true(value == 1000.0); /* the file's */
    assert_int_equal(sb_scene_file_number(scene, "integrator", &value, &err), SB_ERR_INVALID);
    assert_non_null(strstr(err.message, "integrator"));
    assert_int_equal(sb_scene_file_number(scene, "no.such", &value, &err), SB_ERR_INVALID);
    sb_solver_destroy(run(scene, 10));
    sb_scene_file_destroy(scene);
}

static void assert_load_fails(const char* path, const char* const* sets, size_t count, sb_status status,
                              const char* start) {
    sb_scene_file* scene = (sb_scene_file*)&scene; /* not NULL: the call must clear it */
    sb_error err;
    assert_int_equal(sb_scene_file_load(path, sets, count, &scene, &err), status);
    assert_null(scene);
    if (strncmp(err.message, start, strlen(start)) != 0) fail_msg("'%s' does not start with '%s'", err.message, start);
}

static void test_errors(void** state) {
    (void)state;
    assert_load_fails(SCENES "no_such_scene.yaml", NULL, 0, SB_ERR_IO, SCENES "no_such_scene.yaml: cannot open");

    char dir[] = "/tmp/sb_test_scene_library_XXXXXX", path[64], expected[160];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/bad.yaml", dir);
    FILE* f = fopen(path, "w");
    assert_non_null(f);
    fputs("dt: 0.001\nbond:\n  kk: 1\n", f);
    fclose(f);
    snprintf(expected, sizeof expected, "%s:3: unknown key 'bond.kk' (did you mean 'bond.k'?)", path);
    assert_load_fails(path, NULL, 0, SB_ERR_PARSE, expected);
    remove(path);
    rmdir(dir);

    const char* const bad_set[] = {"bond.kk=1"};
    assert_load_fails(SCENES "default.yaml", bad_set, 1, SB_ERR_PARSE, "--set bond.kk=1: unknown key 'bond.kk'");
    /* a value out of range: the checks after loading name the override too */
    const char* const bad_dt[] = {"dt=-1"};
    assert_load_fails(SCENES "default.yaml", bad_dt, 1, SB_ERR_INVALID, "--set dt=-1: ");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_scene),
        cmocka_unit_test(test_colliders_and_handles),
        cmocka_unit_test(test_overrides),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
