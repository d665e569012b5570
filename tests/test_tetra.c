/* `softbond tetra IN OUT` with Debian's tetgen (installed by the set-up,
 * cmake/debian-packages.txt; missing, the test fails, it is never
 * skipped): a closed icosphere written here as OFF fills with tetrahedra
 * of positive volume whose total is the polyhedron's volume (computed here
 * from its triangles) and within 2% of the sphere's 4/3 pi r^3; an open
 * sheet, a missing tetgen, a failing tetgen and a bad OUT name each give a
 * clear error and their exit code. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <string.h>

#include "tests/test_files.h"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_tetra");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

static const char* write_off(const char* name, const sb_mesh* m) {
    const char* path = tu_tmp_path(name);
    FILE* f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "OFF\n%u %u 0\n", m->vertex_count, m->triangle_count);
    for (uint32_t v = 0; v < m->vertex_count; v++)
        fprintf(f, "%.17g %.17g %.17g\n", m->positions[3 * v], m->positions[3 * v + 1], m->positions[3 * v + 2]);
    for (uint32_t t = 0; t < m->triangle_count; t++)
        fprintf(f, "3 %u %u %u\n", m->triangles[3 * t], m->triangles[3 * t + 1], m->triangles[3 * t + 2]);
    fclose(f);
    return path;
}

static sb_mesh icosphere(uint32_t subdivisions, double radius) {
    sb_mesh m;
    sb_error err;
    assert_int_equal(sb_mesh_generate_icosphere(subdivisions, radius, &m, &err), SB_OK);
    return m;
}

/* Volume enclosed by the triangles, (1/6) sum a . (b x c). */
static double enclosed_volume(const sb_mesh* m) {
    double volume = 0.0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        double bc[3];
        tu_cross(m->positions + 3 * (size_t)m->triangles[3 * t + 1], m->positions + 3 * (size_t)m->triangles[3 * t + 2],
                 bc);
        volume += tu_dot(m->positions + 3 * (size_t)m->triangles[3 * t], bc) / 6.0;
    }
    return volume;
}

static tu_result run_tetra(const char* in, const char* out, const char* option, const char* value) {
    const char* args[] = {"tetra", in, out, option, value, NULL};
    return tu_run(args);
}

static void test_icosphere_volume(void** state) {
    (void)state;
    const double radius = 0.5;
    sb_mesh sphere = icosphere(3, radius);
    write_off("sphere.off", &sphere);
    tu_result r = run_tetra("sphere.off", "sphere.node", "--max-volume", "0.002");
    if (r.code != 0) fail_msg("softbond tetra failed (%d): %s", r.code, r.err);
    TU_ASSERT_CONTAINS(r.out, "wrote sphere.node and sphere.ele");
    tu_result_free(&r);

    sb_tet_mesh v;
    sb_error err = {{0}};
    sb_status status = sb_tet_mesh_load_tetgen(tu_tmp_path("sphere.node"), tu_tmp_path("sphere.ele"), &v, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    double total = 0.0, largest = 0.0, smallest = INFINITY;
    for (uint32_t t = 0; t < v.tet_count; t++) {
        const uint32_t* c = v.tets + 4 * (size_t)t;
        double a[3], b[3], d[3], bd[3];
        for (int k = 0; k < 3; k++) {
            a[k] = v.positions[3 * (size_t)c[1] + k] - v.positions[3 * (size_t)c[0] + k];
            b[k] = v.positions[3 * (size_t)c[2] + k] - v.positions[3 * (size_t)c[0] + k];
            d[k] = v.positions[3 * (size_t)c[3] + k] - v.positions[3 * (size_t)c[0] + k];
        }
        tu_cross(b, d, bd);
        double volume = tu_dot(a, bd) / 6.0;
        total += volume;
        largest = fmax(largest, volume);
        smallest = fmin(smallest, volume);
    }
    assert_true(smallest > 0.0);
    TU_ASSERT_LE(largest, 0.002 * (1 + 1e-9)); /* --max-volume */
    double polyhedron = enclosed_volume(&sphere), ball = 4.0 / 3.0 * M_PI * radius * radius * radius;
    TU_ASSERT_NEAR(total, polyhedron, 1e-9 * polyhedron);
    TU_ASSERT_NEAR(total, ball, 0.02 * ball);
    assert_true(v.tet_count > 100); /* the volume bound split it: 0.52 m^3 / 0.002 */
    print_message("tetra: %u points, %u tetrahedra, volume %.9g (polyhedron %.9g, sphere %.9g: %.2f%% short)\n",
                  v.vertex_count, v.tet_count, total, polyhedron, ball, 100.0 * (ball - total) / ball);
    sb_tet_mesh_free(&v);
    sb_mesh_free(&sphere);
}

static void test_open_sheet_refused(void** state) {
    (void)state;
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = def.ny = 4;
    sb_mesh sheet;
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&def, &sheet, &err), SB_OK);
    write_off("sheet.off", &sheet);
    sb_mesh_free(&sheet);
    tu_result r = run_tetra("sheet.off", "sheet.node", NULL, NULL);
    assert_int_equal(r.code, 2);
    TU_ASSERT_CONTAINS(r.err, "sheet.off: the surface is not closed (12 boundary");
    FILE* f = fopen(tu_tmp_path("sheet.node"), "r");
    assert_null(f);
    tu_result_free(&r);
}

static void test_tetgen_missing_or_failing(void** state) {
    (void)state;
    sb_mesh sphere = icosphere(1, 1.0);
    write_off("small.off", &sphere);
    sb_mesh_free(&sphere);
    const char* args[] = {"tetra", "small.off", "small.node", NULL};
    tu_result r = tu_run_env("SOFTBOND_TETGEN", "/nonexistent/tetgen", args);
    assert_int_equal(r.code, 1);
    TU_ASSERT_CONTAINS(r.err, "/nonexistent/tetgen: program not found (Debian: apt-get install tetgen)");
    tu_result_free(&r);
    r = tu_run_env("SOFTBOND_TETGEN", "false", args);
    assert_int_equal(r.code, 1);
    TU_ASSERT_CONTAINS(r.err, "false -pq1.414F failed (exit 1)");
    tu_result_free(&r);
}

/* Two closed tetrahedra that pass through each other: closed edge by edge,
 * but TetGen cannot mesh it. */
static void test_tetgen_error_shown(void** state) {
    (void)state;
    tu_write_file("crossing.off", "OFF\n8 8 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                                  "0.2 0.2 0.2\n1.2 0.2 0.2\n0.2 1.2 0.2\n0.2 0.2 1.2\n"
                                  "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n3 4 6 5\n3 4 5 7\n3 4 7 6\n3 5 6 7\n");
    tu_result r = run_tetra("crossing.off", "crossing.node", NULL, NULL);
    assert_int_equal(r.code, 1);
    TU_ASSERT_CONTAINS(r.err, "softbond: tetgen -pq1.414F");
    TU_ASSERT_CONTAINS(r.err, "self-intersecting");
    tu_result_free(&r);
}

static void test_bad_arguments(void** state) {
    (void)state;
    const char* cases[][6] = {
        {"tetra", "in.off", "out.vtk", NULL, NULL, "OUT must end in .node or .ele"},
        {"tetra", "in.off", NULL, NULL, NULL, "missing OUT"},
        {"tetra", "in.off", "out.node", "--quality", "1", "must be > 1"},
        {"tetra", "in.off", "out.node", "--max-volume", "x", "--max-volume: expected a number"},
        {"tetra", "in.off", "out.node", "--frobnicate", NULL, "unknown option '--frobnicate'"},
        {"tetra", "missing.off", "out.node", NULL, NULL, "missing.off: cannot open"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        tu_result r = tu_run(cases[i]);
        assert_int_equal(r.code, 2);
        TU_ASSERT_CONTAINS(r.err, cases[i][5]);
        tu_result_free(&r);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_icosphere_volume),
        cmocka_unit_test(test_open_sheet_refused),
        cmocka_unit_test(test_tetgen_missing_or_failing),
        cmocka_unit_test(test_tetgen_error_shown),
        cmocka_unit_test(test_bad_arguments),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
