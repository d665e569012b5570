/* Level of detail: sb_mesh_simplify reaches a vertex target near what was
 * asked, keeps every boundary vertex and the locked ones (at their index
 * when asked), and an error target alone simplifies a flat sheet a lot;
 * the --budget-ms choice, with injected timings (no test times itself). */
#define _POSIX_C_SOURCE 200809L

#include "scenes/budget.h"
#include "scenes/scene_model.h"
#include "tests/test_files.h"

static void assert_valid(const sb_mesh* m) {
    assert_true(m->vertex_count > 0 && m->triangle_count > 0);
    for (size_t i = 0; i < 3 * (size_t)m->triangle_count; i++) assert_true(m->triangles[i] < m->vertex_count);
}

/* An icosphere of 2562 vertices to 600: within 10%. */
static void test_vertex_target(void** state) {
    (void)state;
    sb_mesh m;
    assert_int_equal(sb_mesh_generate_icosphere(4, 1.0, &m, NULL), SB_OK);
    assert_int_equal(m.vertex_count, 2562);
    sb_simplify_def def = sb_default_simplify_def();
    def.target_vertices = 600;
    sb_simplify_report r;
    sb_error err = {{0}};
    if (sb_mesh_simplify(&m, &def, NULL, &r, &err) != SB_OK) fail_msg("%s", err.message);
    assert_valid(&m);
    assert_int_equal(r.vertices_before, 2562);
    assert_int_equal(r.vertices_after, m.vertex_count);
    assert_true(m.vertex_count >= 540 && m.vertex_count <= 660);
    /* still closed: E = 3V - 6 means T = 2V - 4 */
    assert_int_equal(m.triangle_count, 2 * m.vertex_count - 4);
    sb_mesh_free(&m);
}

static bool on_boundary(uint32_t v, uint32_t nx, uint32_t ny) {
    uint32_t row = v / nx, col = v % nx;
    return row == 0 || col == 0 || row == ny - 1 || col == nx - 1;
}

/* A 30 x 30 sheet (116 boundary vertices) to 300 vertices, with an
 * interior vertex locked at its index: every boundary vertex is still
 * there, bitwise in place, and the locked one is vertex 155 still. */
static void test_boundary_and_locked_kept(void** state) {
    (void)state;
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = 30;
    sb_mesh m, original;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &m, NULL), SB_OK);
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &original, NULL), SB_OK);
    uint32_t locked[] = {155}; /* row 5, column 5 */
    sb_simplify_def def = sb_default_simplify_def();
    def.target_vertices = 300;
    def.locked = locked;
    def.locked_count = 1;
    def.keep_locked_indices = true;
    uint32_t* origin = malloc(900 * sizeof *origin);
    sb_error err = {{0}};
    if (sb_mesh_simplify(&m, &def, origin, NULL, &err) != SB_OK) fail_msg("%s", err.message);
    assert_valid(&m);
    assert_true(m.vertex_count < 400);
    assert_true(m.vertex_count >= 116 + 1);
    uint32_t boundary = 0;
    for (uint32_t v = 0; v < m.vertex_count; v++) {
        assert_memory_equal(m.positions + 3 * v, original.positions + 3 * origin[v], 3 * sizeof(double));
        boundary += on_boundary(origin[v], 30, 30);
    }
    assert_int_equal(boundary, 116);
    assert_int_equal(origin[155], 155);
    free(origin);
    sb_mesh_free(&m);
    sb_mesh_free(&original);
}

/* A flat sheet has zero quadric error inside: a small error target alone
 * removes most interior vertices, the boundary stays. */
static void test_error_target(void** state) {
    (void)state;
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = 20;
    sb_mesh m;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &m, NULL), SB_OK);
    sb_simplify_def def = sb_default_simplify_def();
    def.target_error = 1e-3;
    assert_int_equal(sb_mesh_simplify(&m, &def, NULL, NULL, NULL), SB_OK);
    assert_valid(&m);
    assert_true(m.vertex_count < 200);
    assert_true(m.vertex_count >= 76);
    sb_mesh_free(&m);
    def.target_error = -1;
    assert_int_equal(sb_mesh_simplify(&m, &def, NULL, NULL, NULL), SB_ERR_INVALID);
}

/* Levels of 5000, 2000, 800 and 300 vertices measured at 4.0, 1.6, 0.7 and
 * 0.3 ms per step: a budget picks the largest that fits. */
static void test_budget_choice(void** state) {
    (void)state;
    const sb_budget_level levels[] = {{5000, 4.0, 0}, {2000, 1.6, 0}, {800, 0.7, 0}, {300, 0.3, 0}};
    bool fits;
    assert_int_equal(sb_budget_choose(levels, 4, 10.0, INFINITY, &fits), 0);
    assert_true(fits);
    assert_int_equal(sb_budget_choose(levels, 4, 2.0, INFINITY, &fits), 1);
    assert_int_equal(sb_budget_choose(levels, 4, 1.0, INFINITY, &fits), 2);
    assert_int_equal(sb_budget_choose(levels, 4, 0.3, INFINITY, &fits), 3);
    assert_true(fits);
    /* nothing fits: the smallest, and it says so */
    assert_int_equal(sb_budget_choose(levels, 4, 0.1, INFINITY, &fits), 3);
    assert_false(fits);
    /* a smaller budget never picks a larger model */
    int previous = 0;
    for (double budget = 10.0; budget > 0.05; budget *= 0.9) {
        int pick = sb_budget_choose(levels, 4, budget, INFINITY, NULL);
        assert_true(levels[pick].vertices <= levels[previous].vertices);
        previous = pick;
    }
    /* order of the table does not matter; a non-monotone timing is fine */
    const sb_budget_level mixed[] = {{300, 0.3, 0}, {5000, 4.0, 0}, {800, 0.9, 0}, {2000, 0.8, 0}};
    assert_int_equal(sb_budget_choose(mixed, 4, 1.0, INFINITY, NULL), 3);
}

/* With errors measured (5000 vertices: the full model, 0; then 2, 6 and
 * 20 mm): a tolerance leaves out the levels beyond it, then the budget
 * picks among the rest; when none of those fits, the smallest of them. */
static void test_budget_choice_within_an_error(void** state) {
    (void)state;
    const sb_budget_level levels[] = {{5000, 4.0, 0}, {2000, 1.6, 0.002}, {800, 0.7, 0.006}, {300, 0.3, 0.020}};
    bool fits;
    assert_int_equal(sb_budget_choose(levels, 4, 1.0, 0.01, &fits), 2);
    assert_true(fits);
    assert_int_equal(sb_budget_choose(levels, 4, 1.0, 0.005, &fits), 1); /* 800 is too coarse; 2000 misses 1 ms */
    assert_false(fits);
    assert_int_equal(sb_budget_choose(levels, 4, 0.5, 0.001, &fits), 0); /* only the full model is within 1 mm */
    assert_false(fits);
    assert_int_equal(sb_budget_choose(levels, 4, 0.5, 0.0, &fits), 0);
    assert_int_equal(sb_budget_choose(levels, 4, 0.5, INFINITY, &fits), 3);
    assert_true(fits);
}

/* The scene keys: a 30 x 30 sheet to about 300 vertices, vertex 155 fixed
 * keeps its index and place; a tetrahedral file refuses. */
static void test_scene_keys(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err = {{0}};
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    const char* sets[] = {"mesh.nx=30", "mesh.ny=30", "mesh.target_vertices=300", "fixed=[155]", NULL};
    for (const char** s = sets; *s; s++) assert_int_equal(sb_scene_set(&scene, *s, &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    sb_mesh m;
    if (sb_scene_make_mesh(&scene, &m, &err) != SB_OK) fail_msg("%s", err.message);
    assert_true(m.vertex_count >= 280 && m.vertex_count <= 330);
    assert_true(fabs(m.positions[3 * 155] - 5.0 / 29.0) < 1e-12);
    assert_true(fabs(m.positions[3 * 155 + 1] - 5.0 / 29.0) < 1e-12);
    sb_model* model = sb_scene_build_model(&scene, &m, "sheet", &err);
    if (!model) fail_msg("%s", err.message);
    sb_model_destroy(model);
    sb_mesh_free(&m);
    assert_int_equal(sb_scene_set(&scene, "mesh.target_error=-1", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_ERR_INVALID);
    assert_non_null(strstr(err.message, "mesh.target_error"));
    sb_scene_free(&scene);
}

/* Runs softbond with args: it exits with code and says `said` on stdout
 * (code 0) or stderr; `not_said` (if not NULL) is not on stdout. */
static void run_says(const char* const* args, int code, const char* said, const char* not_said) {
    tu_result r = tu_run(args);
    assert_int_equal(r.code, code);
    if (!strstr(code == 0 ? r.out : r.err, said)) fail_msg("'%s' not said:\n%s%s", said, r.out, r.err);
    if (not_said) assert_null(strstr(r.out, not_said));
    tu_result_free(&r);
}

/* softbond run --budget-ms: a budget nothing misses picks the full mesh, one
 * nothing meets picks the smallest and says so; a bad value is refused.
 * (The choice depends on the timings only through these extremes.) With
 * --max-error: nothing fits 1e-9 ms; within 1 m every level is (the
 * smallest picked), within 0 m only the full model, whose error is 0. */
static void test_run_budget(void** state) {
    (void)state;
    assert_int_equal(tu_make_tmp_dir("sb_test_lod"), 0);
    tu_write_file("s.yaml", "mesh: {nx: 24, ny: 24}\nduration: 0.0002\noutput: {frames: false}\n");
    const char* args[] = {"run", "s.yaml", "--budget-ms", "1e9", "--output", "out", NULL};
    run_says(args, 0, "softbond: picked 576 vertices (", NULL);
    args[3] = "1e-9";
    run_says(args, 0, "nothing fits 1e-09 ms: the smallest", NULL);
    args[3] = "-3";
    run_says(args, 2, "--budget-ms: expected a number of milliseconds > 0, got '-3'", NULL);
    const char* within[] = {"run", "s.yaml", "--budget-ms", "1e-9", "--max-error", "1", "--output", "out", NULL};
    run_says(within, 0, "each level's RMS distance from the full model after 0.0002 s", NULL);
    run_says(within, 0, "nothing within the error fits 1e-09 ms: the smallest within the error;",
             "picked 576 vertices");
    within[5] = "0";
    run_says(within, 0, "softbond: picked 576 vertices (", NULL);
    run_says(within, 0, "; 0 m RMS from the full model, 0 % of its motion)", NULL);
    within[5] = "-1";
    run_says(within, 2, "--max-error: expected a distance in metres >= 0, got '-1'", NULL);
    const char* alone[] = {"run", "s.yaml", "--max-error", "0.01", "--output", "out", NULL};
    run_says(alone, 2, "--max-error: needs --budget-ms", NULL);
    assert_int_equal(tu_remove_tmp_dir(), 0);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vertex_target),
        cmocka_unit_test(test_boundary_and_locked_kept),
        cmocka_unit_test(test_error_target),
        cmocka_unit_test(test_budget_choice),
        cmocka_unit_test(test_budget_choice_within_an_error),
        cmocka_unit_test(test_scene_keys),
        cmocka_unit_test(test_run_budget),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
