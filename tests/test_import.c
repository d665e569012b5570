/* Import through assimp on real files from Debian's assimp-testmodels
 * (installed by the set-up, cmake/debian-packages.txt; a missing model
 * fails the test, it is never skipped): the Wuson in three formats gives the
 * same counts, the spider's binary STL drops the degenerate facets its
 * header counts, sphereWithHole keeps every facet, 3DS files load, a file's
 * meshes can be kept apart; every file of the package's invalid/ folder
 * gives SB_ERR_PARSE or SB_ERR_IO naming the file (run under the address
 * sanitizer by `make test`). A small STL written here checks the degenerate
 * count exactly, and `softbond info` prints it. */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <stdio.h>
#include <string.h>

#include "tests/test_files.h"

#define MODELS "/usr/share/assimp/models/"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_import");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

/* Fails loudly when the package is not installed. */
static void require_model(const char* path) {
    FILE* f = fopen(path, "rb");
    if (f == NULL) fail_msg("%s is missing: install Debian's assimp-testmodels (make deps)", path);
    fclose(f);
}

static sb_mesh_load_report load_merged(const char* path, sb_mesh* mesh) {
    require_model(path);
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    sb_mesh_load_report report;
    sb_error err = {{0}};
    sb_status status = sb_mesh_load_ex(path, NULL, &objects, &count, &report, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(count, 1);
    assert_int_equal(report.object_count, 1);
    *mesh = objects[0];
    free(objects);
    return report;
}

/* Every index names a vertex and every position is finite. */
static void assert_valid(const sb_mesh* m) {
    assert_true(m->vertex_count > 0);
    assert_true(m->triangle_count > 0);
    for (size_t i = 0; i < 3 * (size_t)m->triangle_count; i++) assert_true(m->triangles[i] < m->vertex_count);
    for (size_t i = 0; i < 3 * (size_t)m->vertex_count; i++) assert_true(isfinite(m->positions[i]));
}

/* The Wuson as STL, PLY and AC3D: the same surface, 2117 vertices once
 * identical positions are joined and 3732 triangles (the OFF file has 3732
 * faces too), none degenerate. */
static void test_wuson_formats_agree(void** state) {
    (void)state;
    const char* paths[] = {MODELS "STL/Wuson.stl", MODELS "PLY/Wuson.ply", MODELS "AC/Wuson.ac"};
    for (size_t i = 0; i < 3; i++) {
        sb_mesh m;
        sb_mesh_load_report r = load_merged(paths[i], &m);
        assert_valid(&m);
        assert_string_equal(r.reader, "assimp");
        assert_int_equal(m.vertex_count, 2117);
        assert_int_equal(m.triangle_count, 3732);
        assert_int_equal(r.degenerate_faces, 0);
        sb_mesh_free(&m);
    }
    sb_mesh off;
    sb_error err;
    assert_int_equal(sb_mesh_load(MODELS "OFF/Wuson.off", &off, &err), SB_OK);
    assert_int_equal(off.triangle_count, 3732);
    sb_mesh_free(&off);
}

/* Spider_binary.stl's header counts 1368 facets, as many as spider.obj has
 * triangles; 56 of them are degenerate: kept + dropped = 1368. */
static void test_spider_degenerates(void** state) {
    (void)state;
    sb_mesh m;
    sb_mesh_load_report r = load_merged(MODELS "STL/Spider_binary.stl", &m);
    assert_valid(&m);
    assert_int_equal(m.triangle_count + r.degenerate_faces, 1368);
    assert_int_equal(r.degenerate_faces, 56);
    sb_mesh_free(&m);
    sb_mesh obj;
    sb_error err;
    require_model(MODELS "OBJ/spider.obj");
    assert_int_equal(sb_mesh_load(MODELS "OBJ/spider.obj", &obj, &err), SB_OK);
    assert_int_equal(obj.triangle_count, 1368);
    sb_mesh_free(&obj);
}

/* sphereWithHole.stl: 285 facets in the file, all kept; an open surface. */
static void test_sphere_with_hole(void** state) {
    (void)state;
    sb_mesh m;
    sb_mesh_load_report r = load_merged(MODELS "STL/sphereWithHole.stl", &m);
    assert_valid(&m);
    assert_int_equal(m.triangle_count, 285);
    assert_int_equal(r.degenerate_faces, 0);
    assert_true(m.vertex_count < 3 * 285); /* corners joined */
    sb_mesh_free(&m);
}

static void test_3ds_files(void** state) {
    (void)state;
    const char* paths[] = {MODELS "3DS/fels.3ds", MODELS "3DS/test1.3ds", MODELS "3DS/RotatingCube.3DS"};
    for (size_t i = 0; i < 3; i++) {
        sb_mesh m;
        load_merged(paths[i], &m);
        assert_valid(&m);
        sb_mesh_free(&m);
    }
}

/* The spider through assimp has several meshes: kept apart they are
 * several objects whose triangles add up to the merged count; each object
 * is valid on its own. */
static void test_separate_objects(void** state) {
    (void)state;
    const char* path = MODELS "OBJ/spider.obj";
    require_model(path);
    sb_mesh_load_def def = sb_default_mesh_load_def();
    assert_false(def.separate_objects);
    def.separate_objects = true;
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    sb_mesh_load_report r;
    sb_error err = {{0}};
    if (sb_mesh_load_ex(path, &def, &objects, &count, &r, &err) != SB_OK) fail_msg("%s", err.message);
    assert_true(count > 1);
    assert_int_equal(r.object_count, count);
    assert_string_equal(r.reader, "assimp");
    uint32_t triangles = 0, vertices = 0;
    for (uint32_t i = 0; i < count; i++) {
        assert_valid(&objects[i]);
        triangles += objects[i].triangle_count;
        vertices += objects[i].vertex_count;
    }
    assert_int_equal(triangles + r.degenerate_faces, 1368);
    sb_mesh_objects_free(objects, count);
    /* STL has one mesh: one object either way, the same as merged. */
    sb_mesh merged;
    sb_mesh_load_report rm = load_merged(MODELS "STL/Wuson.stl", &merged);
    assert_int_equal(sb_mesh_load_ex(MODELS "STL/Wuson.stl", &def, &objects, &count, &r, &err), SB_OK);
    assert_int_equal(count, 1);
    assert_int_equal(objects[0].vertex_count, merged.vertex_count);
    assert_int_equal(objects[0].triangle_count, merged.triangle_count);
    assert_int_equal(r.degenerate_faces, rm.degenerate_faces);
    sb_mesh_objects_free(objects, count);
    sb_mesh_free(&merged);
    (void)vertices;
}

/* Every file of invalid/: an error naming the file, in both modes. */
static void test_invalid_folder(void** state) {
    (void)state;
    DIR* dir = opendir(MODELS "invalid");
    if (dir == NULL) fail_msg(MODELS "invalid is missing: install Debian's assimp-testmodels (make deps)");
    int files = 0;
    for (struct dirent* e; (e = readdir(dir)) != NULL;) {
        if (e->d_name[0] == '.') continue;
        char path[512];
        snprintf(path, sizeof path, MODELS "invalid/%s", e->d_name);
        for (int separate = 0; separate < 2; separate++) {
            sb_mesh_load_def def = {.separate_objects = separate};
            sb_mesh* objects = NULL;
            uint32_t count = 7;
            sb_error err = {{0}};
            sb_status status = sb_mesh_load_ex(path, &def, &objects, &count, NULL, &err);
            if (status != SB_ERR_PARSE && status != SB_ERR_IO)
                fail_msg("%s (separate %d): status %d, '%s'", path, separate, (int)status, err.message);
            if (strstr(err.message, path) == NULL) fail_msg("'%s' does not name %s", err.message, path);
            assert_null(objects);
            assert_int_equal(count, 0);
        }
        sb_mesh m;
        sb_error err = {{0}};
        assert_int_not_equal(sb_mesh_load(path, &m, &err), SB_OK);
        assert_null(m.positions);
        files++;
    }
    closedir(dir);
    assert_true(files >= 14); /* the package ships 15 */
}

/* Three facets: one good, one with two equal corners, one collinear. */
static void test_degenerate_count_and_info(void** state) {
    (void)state;
    tu_write_file("three.stl",
                  "solid t\n"
                  "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
                  "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 0 0\nendloop\nendfacet\n"
                  "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 2 2 0\nendloop\nendfacet\n"
                  "endsolid t\n");
    sb_mesh m;
    sb_mesh_load_report r = load_merged(tu_tmp_path("three.stl"), &m);
    assert_int_equal(m.triangle_count, 1);
    assert_int_equal(r.degenerate_faces, 2);
    sb_mesh_free(&m);
    tu_result run = tu_run((const char*[]){"info", "three.stl", NULL});
    assert_int_equal(run.code, 0);
    assert_non_null(strstr(run.out, "\ndegenerate faces dropped: 2\n"));
    tu_result_free(&run);
    /* Only degenerate facets: an error that says so. */
    tu_write_file("flat.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 2 2 0\n"
                              "endloop\nendfacet\nendsolid t\n");
    sb_error err = {{0}};
    assert_int_equal(sb_mesh_load(tu_tmp_path("flat.stl"), &m, &err), SB_ERR_PARSE);
    assert_non_null(strstr(err.message, "1 degenerate triangles dropped"));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wuson_formats_agree),       cmocka_unit_test(test_spider_degenerates),
        cmocka_unit_test(test_sphere_with_hole),          cmocka_unit_test(test_3ds_files),
        cmocka_unit_test(test_separate_objects),          cmocka_unit_test(test_invalid_folder),
        cmocka_unit_test(test_degenerate_count_and_info),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
