/* `factory: net` (scenes/net.c): a 5 x 4 sheet becomes a net of the
 * 4 x 4 + 5 x 3 = 31 bonds along its rows and columns, each one cell long
 * and with the scene's constants, no triangle or hinge terms, and the
 * molecular factory's masses (the sheet's area times density in all);
 * a net that is not a plain generated sheet exits 2 naming the line. */
#define _POSIX_C_SOURCE 200809L
#include "test_util.h"

#include "scenes/scene_model.h"
#include "tests/test_files.h"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_net");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

static sb_model* net_model(const char* const* sets) {
    sb_scene scene;
    sb_error err = {{0}};
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    for (const char* const* s = sets; *s; s++)
        if (sb_scene_set(&scene, *s, &err) != SB_OK) fail_msg("%s", err.message);
    if (sb_scene_validate(&scene, &err) != SB_OK) fail_msg("%s", err.message);
    sb_mesh mesh;
    if (sb_scene_make_mesh(&scene, &mesh, &err) != SB_OK) fail_msg("%s", err.message);
    sb_model* model = sb_scene_build_model(&scene, &mesh, "net", &err);
    if (!model) fail_msg("%s", err.message);
    sb_mesh_free(&mesh);
    sb_scene_free(&scene);
    return model;
}

static void test_rows_and_columns_only(void** state) {
    (void)state;
    const uint32_t nx = 5, ny = 4;
    const double width = 0.4, height = 0.6; /* cells 0.1 x 0.2 */
    sb_model* model =
        net_model((const char*[]){"factory=net", "mesh.nx=5", "mesh.ny=4", "mesh.width=0.4", "mesh.height=0.6",
                                  "bond.k=250", "spring.damping=0.3", "density=0.5", "angle.k=1", "bend.k=1", NULL});
    assert_int_equal(sb_model_vertex_count(model), nx * ny);
    assert_int_equal(sb_model_bond_count(model), (nx - 1) * ny + nx * (ny - 1));
    assert_int_equal(sb_model_triangle_count(model), 0);
    assert_int_equal(sb_model_hinge_count(model), 0);
    bool seen[5 * 4][5 * 4] = {{false}};
    for (uint32_t b = 0; b < sb_model_bond_count(model); b++) {
        sb_bond_info bond = sb_model_bond(model, b);
        uint32_t lo = bond.i < bond.j ? bond.i : bond.j, hi = bond.i ^ bond.j ^ lo;
        bool along_row = hi == lo + 1 && hi % nx != 0, along_column = hi == lo + nx;
        if (!along_row && !along_column) fail_msg("bond %u joins %u and %u across a cell", b, bond.i, bond.j);
        assert_false(seen[lo][hi]);
        seen[lo][hi] = true;
        TU_ASSERT_NEAR(bond.rest_length, along_row ? width / (nx - 1) : height / (ny - 1), 1e-12);
        assert_true(bond.k == 250 && bond.spring_k == 0 && bond.spring_damping == 0.3);
    }
    double mass = 0;
    for (uint32_t v = 0; v < nx * ny; v++) mass += sb_model_mass(model, v);
    TU_ASSERT_NEAR(mass, 0.5 * width * height, 1e-12);
    sb_model_destroy(model);
}

static void test_not_a_plain_sheet(void** state) {
    (void)state;
    const char* why = "'factory' net needs mesh.generator sheet, not renumbered or simplified";
    char message[200];
    snprintf(message, sizeof message, "bad.yaml:2: %s", why);
    tu_assert_scene_fails("mesh: {generator: icosphere}\nfactory: net\n", message);
    tu_assert_scene_fails("mesh: {reorder: true}\nfactory: net\n", message);
    tu_assert_scene_fails("mesh: {target_vertices: 20}\nfactory: net\n", message);
    tu_assert_scene_fails("factory: nets\n", "bad.yaml:1: 'factory' must be molecular, springs, net or membrane, got 'nets'");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rows_and_columns_only),
        cmocka_unit_test(test_not_a_plain_sheet),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
