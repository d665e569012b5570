/* `softbond info MESH` run as a child process on small meshes written into
 * a temporary directory: counts, boundary and non-manifold edges,
 * components, closedness and colors of an icosphere, an open sheet, two
 * separate triangles, a fin of three triangles on one edge and a
 * tetrahedral cube; exit 2 and one line on a missing file. Then scenes
 * using the spring factory and a tetrahedral mesh file with a material. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/test_files.h"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_info");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

/* An OBJ file of a mesh. */
static void write_obj(const char* name, const sb_mesh* mesh) {
    FILE* f = fopen(tu_tmp_path(name), "w");
    assert_non_null(f);
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        fprintf(f, "v %.17g %.17g %.17g\n", mesh->positions[3 * v], mesh->positions[3 * v + 1],
                mesh->positions[3 * v + 2]);
    for (uint32_t t = 0; t < mesh->triangle_count; t++)
        fprintf(f, "f %u %u %u\n", mesh->triangles[3 * t] + 1, mesh->triangles[3 * t + 1] + 1,
                mesh->triangles[3 * t + 2] + 1);
    fclose(f);
}

/* The whole line "name: value\n" is in the output. */
static void assert_line(const char* out, const char* line) {
    char needle[256];
    snprintf(needle, sizeof needle, "\n%s\n", line);
    size_t n = strlen(out);
    char* padded = malloc(n + 2);
    padded[0] = '\n';
    memcpy(padded + 1, out, n + 1);
    if (!strstr(padded, needle)) fail_msg("expected the line \"%s\" in:\n%s", line, out);
    free(padded);
}

static void test_icosphere(void** state) {
    (void)state;
    sb_error err;
    sb_mesh mesh = {0};
    assert_int_equal(sb_mesh_generate_icosphere(2, 1.0, &mesh, &err), SB_OK);
    write_obj("sphere.obj", &mesh);
    sb_mesh_free(&mesh);
    tu_result r = tu_run((const char*[]){"info", "sphere.obj", NULL});
    assert_int_equal(r.code, 0);
    assert_string_equal(r.err, "");
    assert_line(r.out, "vertices: 162");
    assert_line(r.out, "edges: 480"); /* 3V - 6 */
    assert_line(r.out, "triangles: 320");
    assert_line(r.out, "boundary edges: 0");
    assert_line(r.out, "non-manifold edges: 0");
    assert_line(r.out, "components: 1");
    assert_line(r.out, "closed: yes");
    assert_non_null(strstr(r.out, "bounding box: [-1, "));
    /* a vertex of degree 6 needs at least 6 bond colors; at most 64 exist */
    const char* colors = strstr(r.out, "colors: bonds ");
    assert_non_null(colors);
    int bonds = atoi(colors + strlen("colors: bonds "));
    assert_true(bonds >= 6 && bonds < 64);
    tu_result_free(&r);
}

static void test_open_and_split_meshes(void** state) {
    (void)state;
    /* a 3 x 3 sheet: 8 boundary edges of 16 */
    tu_write_file("sheet.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 0 2 0\nv 1 2 0\nv 2 2 0\n"
                               "f 1 2 5\nf 1 5 4\nf 2 3 6\nf 2 6 5\nf 4 5 8\nf 4 8 7\nf 5 6 9\nf 5 9 8\n");
    tu_result r = tu_run((const char*[]){"info", "sheet.obj", NULL});
    assert_int_equal(r.code, 0);
    assert_line(r.out, "vertices: 9");
    assert_line(r.out, "edges: 16");
    assert_line(r.out, "boundary edges: 8");
    assert_line(r.out, "closed: no");
    assert_line(r.out, "bounding box: [0, 0, 0] .. [2, 2, 0] m");
    tu_result_free(&r);
    /* two separate triangles and an unused vertex: three components */
    tu_write_file("two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\nv 9 9 9\nf 1 2 3\nf 4 5 6\n");
    r = tu_run((const char*[]){"info", "two.obj", NULL});
    assert_int_equal(r.code, 0);
    assert_line(r.out, "components: 3");
    assert_line(r.out, "colors: bonds 3, triangles 1");
    tu_result_free(&r);
    /* a fin: three triangles on the edge 1-2 */
    tu_write_file("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
    r = tu_run((const char*[]){"info", "fin.obj", NULL});
    assert_int_equal(r.code, 0);
    assert_line(r.out, "non-manifold edges: 1");
    assert_line(r.out, "boundary edges: 6");
    assert_line(r.out, "closed: no");
    tu_result_free(&r);
}

static const char* const cube_node =
    "8 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 1 1 0\n4 0 0 1\n5 1 0 1\n6 0 1 1\n7 1 1 1\n";
static const char* const cube_ele = "5 4 0\n0 0 1 2 4\n1 3 2 1 7\n2 5 1 4 7\n3 6 4 2 7\n4 1 2 4 7\n";

static void test_tetrahedral_cube(void** state) {
    (void)state;
    tu_write_file("cube.node", cube_node);
    tu_write_file("cube.ele", cube_ele);
    tu_result r = tu_run((const char*[]){"info", "cube.node", NULL});
    assert_int_equal(r.code, 0);
    assert_line(r.out, "vertices: 8");
    assert_line(r.out, "triangles: 12 (the boundary)");
    assert_line(r.out, "tetrahedra: 5");
    assert_line(r.out, "volume: 1 m^3");
    assert_line(r.out, "tetrahedra check: ok");
    assert_line(r.out, "edges: 18");
    assert_line(r.out, "closed: yes");
    assert_line(r.out, "springs: 18");
    tu_result_free(&r);
}

/* A tetrahedron split at an interior vertex (4) into four: the interior
 * vertex is on no surface edge but joins the body through its tetrahedra. */
static void test_interior_vertex(void** state) {
    (void)state;
    tu_write_file("split.node", "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 0.25 0.25 0.25\n");
    tu_write_file("split.ele", "4 4 0\n0 0 2 1 4\n1 0 1 3 4\n2 0 3 2 4\n3 1 2 3 4\n");
    tu_result r = tu_run((const char*[]){"info", "split.node", NULL});
    assert_int_equal(r.code, 0);
    assert_line(r.out, "tetrahedra check: ok");
    assert_line(r.out, "edges: 6");
    assert_line(r.out, "springs: 10");
    assert_line(r.out, "components: 1");
    assert_line(r.out, "closed: yes");
    tu_result_free(&r);
}

static void test_bad_input(void** state) {
    (void)state;
    tu_result r = tu_run((const char*[]){"info", "missing.obj", NULL});
    assert_int_equal(r.code, 2);
    assert_string_equal(r.out, "");
    assert_string_equal(r.err, "softbond: missing.obj: cannot open: No such file or directory\n");
    tu_result_free(&r);
    tu_write_file("bad.ele", "1 4 0\n1 1 2 3 4\n");
    tu_write_file("bad.node", "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 one 0\n4 0 0 1\n");
    r = tu_run((const char*[]){"info", "bad.node", NULL});
    assert_int_equal(r.code, 2);
    assert_string_equal(r.out, "");
    assert_non_null(strstr(r.err, "bad.node:4: "));
    tu_result_free(&r);
    r = tu_run((const char*[]){"info", NULL});
    assert_int_equal(r.code, 2);
    assert_string_equal(r.err, "softbond: missing MESH (see softbond info --help)\n");
    tu_result_free(&r);
}

/* ---- scenes ---------------------------------------------------------------------- */

static int count_lines(const char* text) {
    int n = 0;
    for (; *text; text++) n += *text == '\n';
    return n;
}

/* A tissue that states its Young's modulus gets, by default
 * (tissue.model: auto), the quadratic finite elements: the cube's 8
 * vertices and a vertex at the middle of each of its 18 edges (12 sides, 6
 * face diagonals) in the frames, its 12 boundary triangles split in four;
 * `springs` keeps the papers' model on the 8. */
static void test_tissue_model_by_default(void** state) {
    (void)state;
    tu_write_file("cube.node", cube_node);
    tu_write_file("cube.ele", cube_ele);
    tu_write_file("physical.yaml", "mesh: {generator: file, file: cube.node}\ntissue: {young_modulus: 20000}\n"
                                   "pin: bottom_edge\ngravity: [0, -9.81, 0]\ndt: 0.0001\nduration: 0.001\n"
                                   "frame_interval: 0.001\n");
    static const struct {
        const char *set, *piece;
    } cases[] = {{"tissue.model=auto", "NumberOfPoints=\"26\" NumberOfCells=\"48\""},
                 {"tissue.model=corotated_quadratic", "NumberOfPoints=\"26\" NumberOfCells=\"48\""},
                 {"tissue.model=springs", "NumberOfPoints=\"8\" NumberOfCells=\"12\""}};
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        tu_result r =
            tu_run((const char*[]){"run", "physical.yaml", "--set", cases[c].set, "--output", "physical", NULL});
        if (r.code != 0) fail_msg("%s: run failed: %s", cases[c].set, r.err);
        char* frame = tu_read_file(tu_tmp_path("physical/frame_000001.vtu"));
        assert_non_null(frame);
        TU_ASSERT_CONTAINS(frame, cases[c].piece);
        free(frame);
        tu_result_free(&r);
    }
}

/* Rayleigh's stiffness damping is built for both orders of element and
 * the springs: a tissue stated by E (the quadratic elements by default)
 * takes it, as the linear elements do; a negative one is refused with one
 * line naming the key. */
static void test_tissue_takes_stiffness_damping(void** state) {
    (void)state;
    tu_write_file("cube.node", cube_node);
    tu_write_file("cube.ele", cube_ele);
    tu_write_file("damped.yaml", "mesh: {generator: file, file: cube.node}\n"
                                 "tissue: {young_modulus: 20000, stiffness_damping: 0.001}\n"
                                 "pin: bottom_edge\ndt: 0.0001\nduration: 0.001\nframe_interval: 0.001\n");
    const char* models[] = {"tissue.model=corotated_quadratic", "tissue.model=corotated"};
    for (int c = 0; c < 2; c++) {
        tu_result r = tu_run((const char*[]){"run", "damped.yaml", "--set", models[c], "--output", "damped", NULL});
        if (r.code != 0) fail_msg("%s refused stiffness damping: %s", models[c], r.err);
        tu_result_free(&r);
    }
    tu_result r = tu_run(
        (const char*[]){"run", "damped.yaml", "--set", "tissue.stiffness_damping=-0.001", "--output", "damped", NULL});
    assert_int_equal(r.code, 2);
    TU_ASSERT_CONTAINS(r.err, "'tissue.stiffness_damping' must be >= 0, got -0.001");
    tu_result_free(&r);
}

static void test_tissue_scene(void** state) {
    (void)state;
    tu_write_file("cube.node", cube_node);
    tu_write_file("cube.ele", cube_ele);
    tu_write_file("tissue.yaml", "mesh: {generator: file, file: cube.node}\nmaterial: gallbladder\n"
                                 "pin: bottom_edge\ngravity: [0, -9.81, 0]\ndt: 0.0001\nduration: 0.01\n"
                                 "frame_interval: 0.005\noutput: {frames: false}\n");
    tu_result r = tu_run((const char*[]){"run", "tissue.yaml", "--output", "tissue", NULL});
    if (r.code != 0) fail_msg("run failed: %s", r.err);
    char* log = tu_read_file(tu_tmp_path("tissue/log.csv"));
    assert_non_null(log);
    assert_int_equal(count_lines(log), 4); /* header and frames 0, 1, 2 */
    assert_non_null(strstr(log, "spring"));
    free(log);
    tu_result_free(&r);
    r = tu_run((const char*[]){"run", "tissue.yaml", "--set", "material=spleen", NULL});
    assert_int_equal(r.code, 2);
    assert_string_equal(r.err,
                        "softbond: --set material=spleen: 'material' must be liver or gallbladder, got 'spleen'\n");
    tu_result_free(&r);
    /* an inverted tetrahedron is named */
    tu_write_file("cube.ele", "5 4 0\n0 0 1 2 4\n1 3 1 2 7\n2 5 1 4 7\n3 6 4 2 7\n4 1 2 4 7\n");
    r = tu_run((const char*[]){"run", "tissue.yaml", NULL});
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "tetrahedron 1 "));
    assert_non_null(strstr(r.err, "inverted"));
    tu_result_free(&r);
}

static void test_springs_scene(void** state) {
    (void)state;
    tu_write_file("springs.yaml", "mesh: {generator: sheet, nx: 6, ny: 6}\nfactory: springs\n"
                                  "springs: {stretch: {k: 50, damping: 0.1}, bend: {k: 5, damping: 0.01},\n"
                                  "          vicinity: {distance: 0.25, k: 5, damping: 0.01}}\n"
                                  "pin: top_edge\nduration: 0.01\nframe_interval: 0.01\noutput: {frames: false}\n");
    tu_result r = tu_run((const char*[]){"run", "springs.yaml", "--output", "springs", NULL});
    if (r.code != 0) fail_msg("run failed: %s", r.err);
    tu_result_free(&r);
    r = tu_run((const char*[]){"run", "springs.yaml", "--set", "factory=mm", NULL});
    assert_int_equal(r.code, 2);
    assert_string_equal(
        r.err, "softbond: --set factory=mm: 'factory' must be molecular, springs, net or membrane, got 'mm'\n");
    tu_result_free(&r);
    r = tu_run((const char*[]){"run", "springs.yaml", "--set", "springs.vicinity.distance=-1", NULL});
    assert_int_equal(r.code, 2);
    tu_result_free(&r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_icosphere),
        cmocka_unit_test(test_open_and_split_meshes),
        cmocka_unit_test(test_tetrahedral_cube),
        cmocka_unit_test(test_interior_vertex),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_tissue_scene),
        cmocka_unit_test(test_tissue_model_by_default),
        cmocka_unit_test(test_tissue_takes_stiffness_damping),
        cmocka_unit_test(test_springs_scene),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
