/* The Spring Systems library's own formats: IRIT text data (.itd) and
 * POV-Ray mesh2 objects with the film maker's spring_system_* locals.
 * Real files written by hand (tests/data/cube_tetra.itd, shapes.pov): the
 * counts, positions and winding they hold are checked against what the
 * files say (the cube's volume and closedness computed here from the
 * triangles); malformed files written by the tests give SB_ERR_PARSE with
 * "FILE:LINE:" and what is wrong (also run under the address sanitizer by
 * `make test`). A .pov scene run through the program: the fixed floor
 * stays where it is and the free tetrahedron falls. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <string.h>

#include "tests/test_files.h"

#define DATA SB_SOURCE_DIR "/tests/data/"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_seed_formats");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

/* Signed volume enclosed by the triangles (divergence theorem). */
static double enclosed_volume(const sb_mesh* m) {
    double volume = 0.0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const double* a = m->positions + 3 * (size_t)m->triangles[3 * t];
        const double* b = m->positions + 3 * (size_t)m->triangles[3 * t + 1];
        const double* c = m->positions + 3 * (size_t)m->triangles[3 * t + 2];
        double bc[3];
        tu_cross(b, c, bc);
        volume += tu_dot(a, bc) / 6.0;
    }
    return volume;
}

/* Every directed edge appears once and its reverse once: closed, consistently wound. */
static bool closed_and_oriented(const sb_mesh* m) {
    for (uint32_t t = 0; t < m->triangle_count; t++)
        for (int e = 0; e < 3; e++) {
            uint32_t a = m->triangles[3 * t + e], b = m->triangles[3 * t + (e + 1) % 3];
            int same = 0, reverse = 0;
            for (uint32_t u = 0; u < m->triangle_count; u++)
                for (int f = 0; f < 3; f++) {
                    uint32_t c = m->triangles[3 * u + f], d = m->triangles[3 * u + (f + 1) % 3];
                    same += c == a && d == b;
                    reverse += c == b && d == a;
                }
            if (same != 1 || reverse != 1) return false;
        }
    return true;
}

static void assert_position(const sb_mesh* m, uint32_t v, double x, double y, double z) {
    assert_true(v < m->vertex_count);
    assert_true(m->positions[3 * v] == x && m->positions[3 * v + 1] == y && m->positions[3 * v + 2] == z);
}

/* ---- IRIT ----------------------------------------------------------------- */

static void test_irit_objects_separate(void** state) {
    (void)state;
    sb_mesh_load_def def = sb_default_mesh_load_def();
    def.separate_objects = true;
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    sb_mesh_load_report report;
    sb_error err = {{0}};
    sb_status status = sb_mesh_load_ex(DATA "cube_tetra.itd", &def, &objects, &count, &report, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    assert_string_equal(report.reader, "irit");
    assert_int_equal(count, 3); /* CUBE, TETRA, SHEET; GROUP and OUTLINE hold no polygon */
    assert_int_equal(report.object_count, 3);
    assert_int_equal(report.degenerate_faces, 0);
    /* The cube: 6 quads of 24 corners join into 8 vertices, 12 triangles. */
    assert_int_equal(objects[0].vertex_count, 8);
    assert_int_equal(objects[0].triangle_count, 12);
    assert_true(closed_and_oriented(&objects[0]));
    TU_ASSERT_NEAR(enclosed_volume(&objects[0]), 1.0, 1e-12);
    assert_position(&objects[0], 0, 0, 0, 0);
    assert_position(&objects[0], 1, 0, 1, 0);
    assert_int_equal(objects[1].vertex_count, 4);
    assert_int_equal(objects[1].triangle_count, 4);
    assert_true(closed_and_oriented(&objects[1]));
    TU_ASSERT_NEAR(enclosed_volume(&objects[1]), 1.0 / 6.0, 1e-12);
    /* The sheet, "1e0" read as 1; a fan (0, 1, 2), (0, 2, 3). */
    assert_int_equal(objects[2].vertex_count, 4);
    assert_int_equal(objects[2].triangle_count, 2);
    assert_position(&objects[2], 1, 1, 0, 5);
    uint32_t fan[6] = {0, 1, 2, 0, 2, 3};
    assert_memory_equal(objects[2].triangles, fan, sizeof fan);
    sb_mesh_objects_free(objects, count);
}

static void test_irit_merged(void** state) {
    (void)state;
    sb_mesh m;
    sb_error err = {{0}};
    sb_status status = sb_mesh_load(DATA "cube_tetra.itd", &m, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(m.vertex_count, 8 + 4 + 4);
    assert_int_equal(m.triangle_count, 12 + 4 + 2);
    /* The open sheet (area 1, at z = 5, facing +z) adds its cone to the origin, 5/3. */
    TU_ASSERT_NEAR(enclosed_volume(&m), 1.0 + 1.0 / 6.0 + 5.0 / 3.0, 1e-12);
    sb_mesh_free(&m);
}

/* Objects that share a corner are joined when merged, kept apart when separate. */
static void test_irit_join_across_objects(void** state) {
    (void)state;
    const char* path = tu_write_file("two.irit", "[OBJECT A [POLYGON 3 [0 0 0] [1 0 0] [0 1 0]]]\n"
                                                 "[OBJECT B [POLYGON 3 [0 0 0] [0 1 0] [-1 0 0]]]\n");
    sb_mesh m;
    sb_error err = {{0}};
    assert_int_equal(sb_mesh_load(path, &m, &err), SB_OK);
    assert_int_equal(m.vertex_count, 4);
    assert_int_equal(m.triangle_count, 2);
    sb_mesh_free(&m);
    sb_mesh_load_def def = sb_default_mesh_load_def();
    def.separate_objects = true;
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    assert_int_equal(sb_mesh_load_ex(path, &def, &objects, &count, NULL, &err), SB_OK);
    assert_int_equal(count, 2);
    assert_int_equal(objects[0].vertex_count + objects[1].vertex_count, 6);
    sb_mesh_objects_free(objects, count);
}

/* A polygon with a repeated corner: the fan triangle it spoils is dropped and counted. */
static void test_irit_degenerate_dropped(void** state) {
    (void)state;
    const char* path = tu_write_file("repeat.itd", "[OBJECT A [POLYGON 4 [0 0 0] [1 0 0] [1 0 0] [0 1 0]]]\n");
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    sb_mesh_load_report report;
    sb_error err = {{0}};
    assert_int_equal(sb_mesh_load_ex(path, NULL, &objects, &count, &report, &err), SB_OK);
    assert_int_equal(objects[0].vertex_count, 3);
    assert_int_equal(objects[0].triangle_count, 1);
    assert_int_equal(report.degenerate_faces, 1);
    sb_mesh_objects_free(objects, count);
}

typedef struct bad_file {
    const char* text;
    int line; /* 0: the message names the file without a line */
    const char* says;
} bad_file;

static void assert_rejected(const char* name, const bad_file* bad) {
    const char* path = tu_write_file(name, bad->text);
    char where[512];
    if (bad->line > 0)
        snprintf(where, sizeof where, "%s:%d: ", path, bad->line);
    else
        snprintf(where, sizeof where, "%s: ", path);
    sb_mesh m = {0};
    sb_error err = {{0}};
    sb_status status = sb_mesh_load(path, &m, &err);
    if (status != SB_ERR_PARSE)
        fail_msg("%s: expected a parse error, got %s: %s", bad->text, sb_status_name(status), err.message);
    TU_ASSERT_CONTAINS(err.message, where);
    TU_ASSERT_CONTAINS(err.message, bad->says);
    assert_null(m.positions);
}

static void test_irit_malformed(void** state) {
    (void)state;
    static const bad_file bad[] = {
        {"[OBJECT A\n[POLYGON 3\n[0 0 0] [1 0 0] [0 1 0]\n]\n", 1, "unterminated OBJECT"},
        {"[OBJECT A\n[POLYGON [PLANE 0 0 1 0\n3 [0 0 0]\n", 2, "unterminated '['"},
        {"[OBJECT A\n[POLYGON 4\n[0 0 0] [1 0 0] [0 1 0]\n]\n]\n", 4, "lists 3 of its 4 vertices"},
        {"[OBJECT A\n[POLYGON 3\n[0 0 0] [1 0 0] [0 1 0]\n[1 1 0]]\n]\n", 4, "more vertices than its count 3"},
        {"[OBJECT A\n[POLYGON 3\n[0 0 0] [1 x 0] [0 1 0]\n]\n]\n", 3, "malformed number 'x'"},
        {"[OBJECT A\n[POLYGON 3\n[0 0 0] [1 0] [0 1 0]]]\n", 3, "needs x y z"},
        {"[OBJECT A\n[POLYGON 3\n[0 0 0 1] [1 0 0] [0 1 0]]]\n", 3, "x y z only"},
        {"[OBJECT A\n[POLYGON three [0 0 0] [1 0 0] [0 1 0]]]\n", 2, "expected the vertex count, found 'three'"},
        {"[OBJECT A\n[POLYGON 2 [0 0 0] [1 0 0]]]\n", 2, "POLYGON with 2 vertices"},
        {"[OBJECT A\n[POLYGON 3 [0 0 0] [1 0 0] [0 1 1e999]]]\n", 2, "non-finite coordinate"},
        {"# a surface\n[OBJECT S\n[SURFACE BEZIER 2 2 E3\n[0 0 0] [1 0 0] [0 1 0] [1 1 0]]]\n", 3, "freeform geometry"},
        {"[OBJECT A\n[WIDGET 3]]\n", 2, "unknown IRIT object type 'WIDGET'"},
        {"[OBJECT [RGB \"255,0,0] A [POLYGON 3 [0 0 0] [1 0 0] [0 1 0]]]\n", 1, "unterminated string"},
        {"POLYGON 3\n", 1, "expected '[OBJECT', found 'POLYGON'"},
        {"[OBJECT A [NUMBER 3] [POLYLINE 2 [0 0 0] [1 0 0]]]\n", 0, "no polygons"},
        {"", 0, "no polygons"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) assert_rejected("bad.itd", &bad[i]);
}

/* ---- POV-Ray ---------------------------------------------------------------- */

static sb_pov_object* load_shapes(uint32_t* count) {
    sb_pov_object* objects = NULL;
    sb_error err = {{0}};
    sb_status status = sb_pov_load(DATA "shapes.pov", &objects, count, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(*count, 3);
    return objects;
}

static void test_pov_objects_and_locals(void** state) {
    (void)state;
    uint32_t count;
    sb_pov_object* o = load_shapes(&count);
    assert_string_equal(o[0].name, "Floor");
    assert_int_equal(o[0].line, 9);
    assert_int_equal(o[0].given, SB_POV_FIXED);
    assert_true(o[0].fixed);
    assert_int_equal(o[0].mesh.vertex_count, 4);
    assert_int_equal(o[0].mesh.triangle_count, 2);
    assert_position(&o[0].mesh, 3, -2, 2, 0);

    assert_string_equal(o[1].name, "Ball");
    assert_int_equal(o[1].given,
                     SB_POV_KS | SB_POV_KB | SB_POV_DS | SB_POV_DB | SB_POV_MASS | SB_POV_VICINITY | SB_POV_FIXED);
    assert_false(o[1].fixed);
    assert_true(o[1].stretch_k == 600 && o[1].bend_k == 500);
    assert_true(o[1].stretch_damping == 2 && o[1].bend_damping == 1.5);
    assert_true(o[1].mass == 3 && o[1].vicinity == 0.1);
    assert_int_equal(o[1].mesh.vertex_count, 4);
    assert_int_equal(o[1].mesh.triangle_count, 4);
    uint32_t first[3] = {0, 2, 1}, last[3] = {1, 2, 3};
    assert_memory_equal(o[1].mesh.triangles, first, sizeof first);
    assert_memory_equal(o[1].mesh.triangles + 9, last, sizeof last);
    assert_true(closed_and_oriented(&o[1].mesh));
    TU_ASSERT_NEAR(enclosed_volume(&o[1].mesh), 1.0 / 6.0, 1e-12);

    assert_string_equal(o[2].name, "");
    assert_int_equal(o[2].given, 0);
    assert_false(o[2].fixed);
    assert_position(&o[2].mesh, 1, 6, 0, 0); /* the object's translate is not applied */
    sb_pov_objects_free(o, count);
}

static void test_pov_springs_over_defaults(void** state) {
    (void)state;
    uint32_t count;
    sb_pov_object* o = load_shapes(&count);
    sb_spring_mesh_def defaults = sb_default_spring_mesh_def();
    defaults.stretch_k = 11;
    defaults.vicinity_k = 13;
    defaults.mass = 0.5;
    defaults.density = 0;
    sb_spring_mesh_def ball = sb_pov_object_springs(&o[1], &defaults);
    assert_true(ball.stretch_k == 600 && ball.bend_k == 500);
    assert_true(ball.stretch_damping == 2 && ball.bend_damping == 1.5);
    assert_true(ball.vicinity == 0.1 && ball.vicinity_k == 600 && ball.vicinity_damping == 2);
    TU_ASSERT_NEAR(ball.mass, 3.0 / 4.0, 1e-15); /* 3 kg over 4 vertices */
    assert_true(ball.density == 0);
    sb_spring_mesh_def bare = sb_pov_object_springs(&o[2], &defaults);
    assert_memory_equal(&bare, &defaults, sizeof bare);
    sb_pov_objects_free(o, count);
}

static void test_pov_through_mesh_load(void** state) {
    (void)state;
    sb_mesh m;
    sb_error err = {{0}};
    sb_status status = sb_mesh_load(DATA "shapes.pov", &m, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(m.vertex_count, 4 + 4 + 3);
    assert_int_equal(m.triangle_count, 2 + 4 + 1);
    uint32_t bare[3] = {8, 9, 10};
    assert_memory_equal(m.triangles + 3 * 6, bare, sizeof bare);
    sb_mesh_free(&m);
    sb_mesh_load_def def = sb_default_mesh_load_def();
    def.separate_objects = true;
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    sb_mesh_load_report report;
    assert_int_equal(sb_mesh_load_ex(DATA "shapes.pov", &def, &objects, &count, &report, &err), SB_OK);
    assert_string_equal(report.reader, "pov");
    assert_int_equal(count, 3);
    assert_int_equal(objects[1].triangle_count, 4);
    sb_mesh_objects_free(objects, count);
}

#define TRIANGLE "vertex_vectors { 3, <0,0,0>, <1,0,0>, <0,1,0> }\nface_indices { 1, <0,1,2> }\n"

static void test_pov_malformed(void** state) {
    (void)state;
    static const bad_file bad[] = {
        {"camera { location <0,0,-5> }\n#declare A = mesh2 {\n" TRIANGLE, 2, "no closing '}'"},
        {"mesh2 {\nvertex_vectors { 4, <0,0,0>, <1,0,0>, <0,1,0> }\nface_indices { 1, <0,1,2> } }\n", 2,
         "vertex_vectors lists 3 of its 4"},
        {"mesh2 {\nvertex_vectors { 2, <0,0,0>, <1,0,0>, <0,1,0> }\n}\n", 2, "lists more than its count 2"},
        {"mesh2 { vertex_vectors { 3, <0,0,0>, <1,0,0>, <0,1,0> }\nface_indices { 1,\n<0,1,3> } }\n", 3,
         "index 3 out of range (3 vertices)"},
        {"mesh2 { vertex_vectors { 3, <0,0,0>,\n<1,a,0>, <0,1,0> } }\n", 2, "expected a number, found 'a'"},
        {"mesh2 { vertex_vectors { 1.5, <0,0,0> } }\n", 1, "not a whole number"},
        {"mesh2 {\n#local spring_system_ks = -5;\n" TRIANGLE "}\n", 2, "spring_system_ks = -5"},
        {"mesh2 {\n#local spring_system_stiffness = 5;\n" TRIANGLE "}\n", 2, "unknown spring-system local"},
        {"mesh2 {\n#local spring_system_fixed = maybe;\n" TRIANGLE "}\n", 2, "expected true or false, found 'maybe'"},
        {"mesh2 {\n#local spring_system_mass = 2\n" TRIANGLE "}\n", 3, "expected ';'"},
        {"mesh2 {\nface_indices { 1, <0,1,2> } }\n", 2, "face_indices before vertex_vectors"},
        {"mesh2 {\nvertex_vectors { 3, <0,0,0>, <1,0,0>, <0,1,0> } }\n", 1, "mesh2 without triangles"},
        {"camera { location <0, 0, -5> }\nsphere { <0,0,0>, 1 }\n", 0, "no mesh2 object"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) assert_rejected("bad.pov", &bad[i]);
    sb_pov_object* objects = NULL;
    uint32_t count = 0;
    sb_error err = {{0}};
    assert_int_equal(sb_pov_load(tu_tmp_path("missing.pov"), &objects, &count, &err), SB_ERR_IO);
    TU_ASSERT_CONTAINS(err.message, "missing.pov");
    assert_null(objects);
}

/* ---- a .pov scene run by the program ------------------------------------------ */

/* The <Points> of a .vtu frame: 3 * count doubles (caller frees). */
static double* vtu_points(const char* path, uint32_t count) {
    char* text = tu_read_file(path);
    if (!text) fail_msg("%s is missing", path);
    char* p = strstr(text, "<Points>");
    assert_non_null(p);
    p = strstr(p, "<DataArray");
    assert_non_null(p);
    p = strchr(p, '>') + 1;
    double* out = malloc(3 * count * sizeof *out);
    for (uint32_t i = 0; i < 3 * count; i++) {
        char* end;
        out[i] = strtod(p, &end);
        if (end == p) fail_msg("%s: point coordinate %u is not a number", path, i);
        p = end;
    }
    free(text);
    return out;
}

static double mean_z(const double* points, uint32_t first, uint32_t count) {
    double sum = 0.0;
    for (uint32_t v = first; v < first + count; v++) sum += points[3 * v + 2];
    return sum / count;
}

/* shapes.pov for 0.2 s under gravity: the fixed floor (vertices 0-3) stays
 * exactly where the file puts it; the free tetrahedron (4-7, its own
 * constants) and the bare triangle (8-10, the scene's) fall freely, their
 * centroids by g t^2 / 2 (equal vertex masses: internal springs cancel). */
static void test_pov_scene_run(void** state) {
    (void)state;
    tu_write_file("pov.yaml", "mesh: {generator: file, file: " DATA "shapes.pov}\n"
                              "gravity: [0, 0, -9.81]\ndt: 0.0005\nduration: 0.2\nframe_interval: 0.1\n");
    const char* args[] = {"run", "pov.yaml", "--output", "out", NULL};
    tu_result r = tu_run(args);
    if (r.code != 0) fail_msg("softbond run failed (%d): %s", r.code, r.err);
    tu_result_free(&r);
    double* start = vtu_points(tu_tmp_path("out/frame_000000.vtu"), 11);
    double* end = vtu_points(tu_tmp_path("out/frame_000002.vtu"), 11);
    double floor[12] = {-2, -2, 0, 2, -2, 0, 2, 2, 0, -2, 2, 0};
    assert_memory_equal(end, floor, sizeof floor);
    double fall = 0.5 * 9.81 * 0.2 * 0.2;
    TU_ASSERT_NEAR(mean_z(start, 4, 4), 1.25, 1e-9);
    TU_ASSERT_NEAR(mean_z(start, 4, 4) - mean_z(end, 4, 4), fall, 0.01 * fall);
    TU_ASSERT_NEAR(mean_z(start, 8, 3) - mean_z(end, 8, 3), fall, 0.01 * fall);
    free(start);
    free(end);
}

static double min_z(const double* points, uint32_t first, uint32_t count) {
    double low = points[3 * first + 2];
    for (uint32_t v = first; v < first + count; v++) low = fmin(low, points[3 * v + 2]);
    return low;
}

/* shapes.pov with self_collision: the free tetrahedron (vertices 4-7, a
 * body of springs only) lands on the fixed floor and stays on it, at
 * least the contact thickness h above it less the step's slack, where
 * without self_collision it falls through (the factory's triangles are
 * the bodies' surfaces only when self_collision asks for them); the bare
 * triangle (8-10), beside the floor, still falls freely. */
static void test_pov_bodies_collide(void** state) {
    (void)state;
    tu_write_file("land.yaml", "mesh: {generator: file, file: " DATA "shapes.pov}\n"
                               "gravity: [0, 0, -9.81]\ndt: 0.0005\nduration: 1\nframe_interval: 1\n"
                               "drag: 1\ncontact: {thickness: 0.02}\n");
    const double h = 0.02, fall = 0.5 * 9.81;
    for (int self = 0; self <= 1; self++) {
        const char* args[] = {"run",      "land.yaml", "--set", self ? "self_collision=true" : "self_collision=false",
                              "--output", "land",      NULL};
        tu_result r = tu_run(args);
        if (r.code != 0) fail_msg("softbond run failed (%d): %s", r.code, r.err);
        tu_result_free(&r);
        double* end = vtu_points(tu_tmp_path("land/frame_000001.vtu"), 11);
        print_message("self_collision %d: the tetrahedron's lowest point at z = %g m\n", self, min_z(end, 4, 4));
        if (self)
            assert_true(min_z(end, 4, 4) > 0.5 * h && min_z(end, 4, 4) < 1.5 * h);
        else
            assert_true(min_z(end, 4, 4) < -1.0);
        assert_true(mean_z(end, 8, 3) < 1.0 - 0.5 * fall); /* drag slows it a little */
        free(end);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_irit_objects_separate),
        cmocka_unit_test(test_irit_merged),
        cmocka_unit_test(test_irit_join_across_objects),
        cmocka_unit_test(test_irit_degenerate_dropped),
        cmocka_unit_test(test_irit_malformed),
        cmocka_unit_test(test_pov_objects_and_locals),
        cmocka_unit_test(test_pov_springs_over_defaults),
        cmocka_unit_test(test_pov_through_mesh_load),
        cmocka_unit_test(test_pov_malformed),
        cmocka_unit_test(test_pov_scene_run),
        cmocka_unit_test(test_pov_bodies_collide),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
