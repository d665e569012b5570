/* Placement: sb_mesh_transform (scale, then rotate about x, y, z in that
 * order, then translate; a mirror reverses the winding; bad values are
 * refused) and the scene keys mesh.scale (a number or three),
 * mesh.rotate, mesh.translate and mesh.separate_objects. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <string.h>

#include "scenes/scene_model.h"
#include "tests/test_util.h"

static sb_mesh one_triangle(void) {
    sb_mesh m = {0};
    m.vertex_count = 3;
    m.triangle_count = 1;
    m.positions = malloc(9 * sizeof(double));
    m.triangles = malloc(3 * sizeof(uint32_t));
    const double p[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(m.positions, p, sizeof p);
    m.triangles[0] = 0, m.triangles[1] = 1, m.triangles[2] = 2;
    return m;
}

static void assert_point(const double* p, double x, double y, double z) {
    assert_true(fabs(p[0] - x) < 1e-12);
    assert_true(fabs(p[1] - y) < 1e-12);
    assert_true(fabs(p[2] - z) < 1e-12);
}

static void test_each_rotation(void** state) {
    (void)state;
    sb_mesh m = one_triangle();
    sb_mesh_transform_def t = sb_default_mesh_transform_def();
    t.rotate[2] = 90; /* about z: x toward y */
    assert_int_equal(sb_mesh_transform(&m, &t, NULL), SB_OK);
    assert_point(m.positions, 0, 1, 0);
    assert_point(m.positions + 6, 0, 0, 1);
    t = sb_default_mesh_transform_def();
    t.rotate[0] = 90; /* about x: y toward z; (0,1,0) is now (0,0,1) */
    assert_int_equal(sb_mesh_transform(&m, &t, NULL), SB_OK);
    assert_point(m.positions, 0, 0, 1);
    t = sb_default_mesh_transform_def();
    t.rotate[1] = 90; /* about y: z toward x */
    assert_int_equal(sb_mesh_transform(&m, &t, NULL), SB_OK);
    assert_point(m.positions, 1, 0, 0);
    sb_mesh_free(&m);
}

/* rotate [90, 90, 0]: first x then y. (0,1,0) -> x -> (0,0,1) -> y ->
 * (1,0,0); the other order would give (0,0,1). */
static void test_order(void** state) {
    (void)state;
    sb_mesh m = one_triangle();
    sb_mesh_transform_def t = sb_default_mesh_transform_def();
    t.rotate[0] = 90, t.rotate[1] = 90;
    assert_int_equal(sb_mesh_transform(&m, &t, NULL), SB_OK);
    assert_point(m.positions + 3, 1, 0, 0);
    sb_mesh_free(&m);
    /* Scale first, then rotate, then translate: (1,0,0) scaled by 2 along x,
     * turned 90 degrees about z to (0,2,0), moved by (1,2,3). */
    m = one_triangle();
    t = sb_default_mesh_transform_def();
    t.scale[0] = 2, t.scale[1] = 5, t.scale[2] = 7;
    t.rotate[2] = 90;
    t.translate[0] = 1, t.translate[1] = 2, t.translate[2] = 3;
    assert_int_equal(sb_mesh_transform(&m, &t, NULL), SB_OK);
    assert_point(m.positions, 1, 4, 3);
    assert_point(m.positions + 3, -4, 2, 3);
    assert_point(m.positions + 6, 1, 2, 10);
    assert_int_equal(m.triangles[1], 1); /* no mirror, winding kept */
    sb_mesh_free(&m);
}

static void test_mirror_and_errors(void** state) {
    (void)state;
    sb_mesh m = one_triangle();
    sb_mesh_transform_def t = sb_default_mesh_transform_def();
    t.scale[1] = -1;
    assert_int_equal(sb_mesh_transform(&m, &t, NULL), SB_OK);
    assert_int_equal(m.triangles[0], 0);
    assert_int_equal(m.triangles[1], 2);
    assert_int_equal(m.triangles[2], 1);
    t.scale[1] = 0;
    sb_error err = {{0}};
    assert_int_equal(sb_mesh_transform(&m, &t, &err), SB_ERR_INVALID);
    assert_non_null(strstr(err.message, "zero"));
    t = sb_default_mesh_transform_def();
    t.translate[2] = NAN;
    assert_int_equal(sb_mesh_transform(&m, &t, &err), SB_ERR_INVALID);
    assert_point(m.positions, 1, 0, 0); /* unchanged on error */
    sb_mesh_free(&m);
}

static sb_mesh scene_mesh(const char* const* sets) {
    sb_scene scene;
    sb_error err = {{0}};
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    for (; *sets; sets++)
        if (sb_scene_set(&scene, *sets, &err) != SB_OK) fail_msg("%s", err.message);
    if (sb_scene_validate(&scene, &err) != SB_OK) fail_msg("%s", err.message);
    sb_mesh m = {0};
    if (sb_scene_make_mesh(&scene, &m, &err) != SB_OK) fail_msg("%s", err.message);
    sb_scene_free(&scene);
    return m;
}

static void bounds(const sb_mesh* m, double lo[3], double hi[3]) {
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (uint32_t v = 0; v < m->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->positions[3 * v + k]);
            hi[k] = fmax(hi[k], m->positions[3 * v + k]);
        }
}

/* A unit icosphere has the box [-1, 1]^3 up to its vertices: scaled by a
 * number, by three and moved. */
static void test_scene_keys(void** state) {
    (void)state;
    double lo[3], hi[3];
    sb_mesh m = scene_mesh((const char*[]){"mesh.generator=icosphere", "mesh.scale=2", NULL});
    bounds(&m, lo, hi);
    for (int k = 0; k < 3; k++) assert_true(fabs(hi[k] - 2) < 1e-9 && fabs(lo[k] + 2) < 1e-9);
    sb_mesh_free(&m);
    m = scene_mesh(
        (const char*[]){"mesh.generator=icosphere", "mesh.scale=[1, 2, 3]", "mesh.translate=[10, 0, -1]", NULL});
    bounds(&m, lo, hi);
    assert_true(fabs(hi[0] - 11) < 1e-9 && fabs(lo[0] - 9) < 1e-9);
    assert_true(fabs(hi[1] - 2) < 1e-9 && fabs(hi[2] - 2) < 1e-9 && fabs(lo[2] + 4) < 1e-9);
    sb_mesh_free(&m);
    /* A 2 x 1 sheet turned 90 degrees about z: 1 wide along x, 2 along y. */
    m = scene_mesh((const char*[]){"mesh.width=2", "mesh.rotate=[0, 0, 90]", NULL});
    bounds(&m, lo, hi);
    assert_true(fabs(hi[0] - lo[0] - 1) < 1e-9 && fabs(hi[1] - lo[1] - 2) < 1e-9);
    sb_mesh_free(&m);
}

static void test_scene_key_errors(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err = {{0}};
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    assert_int_not_equal(sb_scene_set(&scene, "mesh.scale=[1, 2]", &err), SB_OK);
    assert_non_null(strstr(err.message, "mesh.scale"));
    assert_int_equal(sb_scene_set(&scene, "mesh.scale=[1, 0, 1]", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_ERR_INVALID);
    assert_non_null(strstr(err.message, "'mesh.scale' must not be 0"));
    assert_int_equal(sb_scene_set(&scene, "mesh.scale=1", &err), SB_OK);
    assert_int_equal(sb_scene_set(&scene, "mesh.rotate=[0, inf, 0]", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_ERR_INVALID);
    assert_non_null(strstr(err.message, "'mesh.rotate' must be finite"));
    sb_scene_free(&scene);
}

/* The spider's meshes kept apart: more vertices than merged (nothing joined
 * across meshes), the same triangles. Needs assimp-testmodels. */
static void test_scene_separate_objects(void** state) {
    (void)state;
    const char* path = "/usr/share/assimp/models/OBJ/spider.obj";
    FILE* f = fopen(path, "rb");
    if (!f) fail_msg("%s is missing: install Debian's assimp-testmodels (make deps)", path);
    fclose(f);
    sb_mesh merged = scene_mesh(
        (const char*[]){"mesh.generator=file", "mesh.file=/usr/share/assimp/models/STL/Spider_binary.stl", NULL});
    sb_mesh apart =
        scene_mesh((const char*[]){"mesh.generator=file", "mesh.file=/usr/share/assimp/models/OBJ/spider.obj",
                                   "mesh.separate_objects=true", NULL});
    assert_int_equal(apart.triangle_count, merged.triangle_count); /* both 1368 - 56 */
    assert_true(apart.vertex_count > merged.vertex_count);
    sb_mesh_free(&merged);
    sb_mesh_free(&apart);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_each_rotation),     cmocka_unit_test(test_order),
        cmocka_unit_test(test_mirror_and_errors), cmocka_unit_test(test_scene_keys),
        cmocka_unit_test(test_scene_key_errors),  cmocka_unit_test(test_scene_separate_objects),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
