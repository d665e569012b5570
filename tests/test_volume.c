/* Volumetric models: the TetGen and Gmsh readers (good files, and malformed
 * ones giving SB_ERR_PARSE with FILE:LINE), the boundary surface, the
 * validity check (inverted and zero-volume tetrahedra by index), and the
 * Sudhamani/Lloyd parameters — masses, stiffness and damping — against
 * values computed here by hand for one tetrahedron and for a unit cube
 * split into five. Files are written into a temporary directory. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <unistd.h>

#include "tests/test_files.h"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_volume");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

/* ---- the meshes ---------------------------------------------------------------- */

static const char* const one_node = "# one tetrahedron\n"
                                    "4 3 0 0\n"
                                    "1 0 0 0\n"
                                    "2 1 0 0   # a comment after the point\n"
                                    "\n"
                                    "3 0 1 0\n"
                                    "4 0 0 1\n";
static const char* const one_ele = "1 4 0\n1 1 2 3 4\n";

/* The unit cube, vertex x + 2y + 4z at (x, y, z), as four corner
 * tetrahedra (volume 1/6) around a central one (1/3), all positive. */
static const char* const cube_msh = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
                                    "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 0 0\n$EndEntities\n"
                                    "$Nodes\n2 9 1 9\n"
                                    "3 1 0 8\n1\n2\n3\n4\n5\n6\n7\n8\n"
                                    "0 0 0 0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
                                    "0 9 0 1\n9\n5 5 5\n" /* a point no tetrahedron uses: dropped */
                                    "$EndNodes\n"
                                    "$Elements\n3 7 1 7\n"
                                    "1 1 1 1\n1 1 2\n"   /* a line: skipped */
                                    "2 1 2 1\n2 1 2 3\n" /* a triangle: skipped */
                                    "3 1 4 5\n3 1 2 3 5\n4 4 3 2 8\n5 6 2 5 8\n6 7 5 3 8\n7 2 3 5 8\n"
                                    "$EndElements\n";

static const uint32_t cube_tets[5][4] = {{0, 1, 2, 4}, {3, 2, 1, 7}, {5, 1, 4, 7}, {6, 4, 2, 7}, {1, 2, 4, 7}};

static sb_model* compile_tet(const sb_tet_mesh* mesh, const sb_tissue_def* tissue) {
    sb_error err;
    sb_builder* b = sb_builder_create();
    if (sb_builder_add_tet_mesh(b, mesh, tissue, &err) != SB_OK) fail_msg("add_tet_mesh: %s", err.message);
    sb_model* model = tu_compile(b);
    sb_builder_destroy(b);
    return model;
}

/* The bond of (i, j), failing when absent. */
static sb_bond_info find_bond(const sb_model* model, uint32_t i, uint32_t j) {
    for (uint32_t e = 0; e < sb_model_bond_count(model); e++) {
        sb_bond_info info = sb_model_bond(model, e);
        if ((info.i == i && info.j == j) || (info.i == j && info.j == i)) return info;
    }
    fail_msg("no bond between %u and %u", i, j);
    return (sb_bond_info){0};
}

/* ---- one tetrahedron ------------------------------------------------------------ */

static void test_one_tetrahedron_by_hand(void** state) {
    (void)state;
    tu_write_file("one.node", one_node);
    tu_write_file("one.ele", one_ele);
    sb_error err;
    sb_tet_mesh mesh;
    assert_int_equal(sb_tet_mesh_load(tu_tmp_path("one.ele"), &mesh, &err), SB_OK);
    assert_int_equal(mesh.vertex_count, 4);
    assert_int_equal(mesh.tet_count, 1);
    TU_ASSERT_NEAR(sb_tet_volume(mesh.positions, mesh.positions + 3, mesh.positions + 6, mesh.positions + 9), 1.0 / 6.0,
                   1e-15);
    sb_tissue_def tissue = {.young_modulus = 3500.0, .density = 1000.0, .damping = 1.0};
    sb_model* model = compile_tet(&mesh, &tissue);
    /* m = ρ V / 4; l = (6√2 V)^(1/3) = 2^(1/6); k = (√2/25) l E; d = √(k (m_i + m_j)) / l0 */
    double m = 1000.0 / 6.0 / 4.0;
    double k = sqrt(2.0) / 25.0 * pow(2.0, 1.0 / 6.0) * 3500.0;
    assert_int_equal(sb_model_vertex_count(model), 4);
    for (uint32_t v = 0; v < 4; v++) TU_ASSERT_NEAR(sb_model_mass(model, v), m, 1e-12);
    assert_int_equal(sb_model_bond_count(model), 6);
    for (uint32_t e = 0; e < 6; e++) {
        sb_bond_info info = sb_model_bond(model, e);
        double l0 = info.i == 0 ? 1.0 : sqrt(2.0);
        TU_ASSERT_NEAR(info.rest_length, l0, 1e-15);
        TU_ASSERT_NEAR(info.spring_k, k, 1e-12 * k);
        TU_ASSERT_NEAR(info.spring_damping, sqrt(k * 2.0 * m) / l0, 1e-12 * k);
        assert_true(info.k == 0.0);
    }
    sb_model_destroy(model);
    /* the damping factor scales d and nothing else */
    tissue.damping = 0.0;
    model = compile_tet(&mesh, &tissue);
    assert_true(sb_model_bond(model, 0).spring_damping == 0.0);
    TU_ASSERT_NEAR(sb_model_bond(model, 0).spring_k, k, 1e-12 * k);
    sb_model_destroy(model);
    sb_tet_mesh_free(&mesh);
}

/* ---- the cube ---------------------------------------------------------------------- */

static void test_cube_mass_and_stiffness(void** state) {
    (void)state;
    sb_error err;
    sb_tet_mesh mesh;
    assert_int_equal(sb_tet_mesh_load(tu_write_file("cube.msh", cube_msh), &mesh, &err), SB_OK);
    assert_int_equal(mesh.vertex_count, 8); /* node 9 dropped */
    assert_int_equal(mesh.tet_count, 5);
    for (uint32_t t = 0; t < 5; t++)
        for (int c = 0; c < 4; c++) assert_int_equal(mesh.tets[4 * t + c], cube_tets[t][c]);
    sb_tissue_def liver;
    assert_true(sb_tissue_from_name("liver", &liver));
    TU_ASSERT_NEAR(liver.young_modulus, 3500.0, 0.0);
    TU_ASSERT_NEAR(liver.density, 1060.0, 0.0);
    sb_model* model = compile_tet(&mesh, &liver);
    /* total mass ρ · 1 m³; a corner of one corner tetrahedron gets ρ (1/6) / 4,
     * vertex 1 (three corners and the centre) ρ (3/6 + 1/3) / 4 */
    double total = 0.0;
    for (uint32_t v = 0; v < 8; v++) total += sb_model_mass(model, v);
    TU_ASSERT_NEAR(total, 1060.0, 1e-9);
    TU_ASSERT_NEAR(sb_model_mass(model, 0), 1060.0 / 24.0, 1e-10);
    TU_ASSERT_NEAR(sb_model_mass(model, 1), 1060.0 * (0.5 + 1.0 / 3.0) / 4.0, 1e-10);
    /* 12 cube edges and 6 face diagonals */
    assert_int_equal(sb_model_bond_count(model), 18);
    double c = sqrt(2.0) / 25.0 * 3500.0;
    double corner_l = pow(2.0, 1.0 / 6.0), centre_l = sqrt(2.0); /* (6√2/6)^(1/3), (6√2/3)^(1/3) */
    sb_bond_info edge = find_bond(model, 0, 1);                  /* one corner tetrahedron */
    sb_bond_info diagonal = find_bond(model, 1, 2);              /* two corners and the centre */
    TU_ASSERT_NEAR(edge.spring_k, c * corner_l, 1e-12 * c);
    TU_ASSERT_NEAR(diagonal.spring_k, c * (2.0 * corner_l + centre_l), 1e-12 * c);
    double m1 = sb_model_mass(model, 1), m2 = sb_model_mass(model, 2);
    TU_ASSERT_NEAR(diagonal.spring_damping, sqrt(diagonal.spring_k * (m1 + m2)) / sqrt(2.0), 1e-9);
    sb_model_destroy(model);
    /* gallbladder: the same with E = 1.5 kPa */
    sb_tissue_def gallbladder;
    assert_true(sb_tissue_from_name("gallbladder", &gallbladder));
    assert_false(sb_tissue_from_name("spleen", &gallbladder));
    assert_true(sb_tissue_from_name("gallbladder", &gallbladder));
    model = compile_tet(&mesh, &gallbladder);
    TU_ASSERT_NEAR(find_bond(model, 0, 1).spring_k, c * corner_l * 1500.0 / 3500.0, 1e-12 * c);
    sb_model_destroy(model);
    sb_tet_mesh_free(&mesh);
}

static void test_cube_surface(void** state) {
    (void)state;
    sb_error err;
    sb_mesh surface;
    assert_int_equal(sb_mesh_load(tu_write_file("cube2.msh", cube_msh), &surface, &err), SB_OK);
    assert_int_equal(surface.vertex_count, 8);
    assert_int_equal(surface.triangle_count, 12);
    /* every face points away from the centre */
    for (uint32_t t = 0; t < 12; t++) {
        const uint32_t* v = surface.triangles + 3 * t;
        const double *a = surface.positions + 3 * v[0], *b = surface.positions + 3 * v[1],
                     *c = surface.positions + 3 * v[2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3], out[3] = {a[0] - 0.5, a[1] - 0.5, a[2] - 0.5};
        tu_cross(u, w, n);
        assert_true(tu_dot(n, out) > 0.0);
    }
    sb_mesh_free(&surface);
}

/* ---- bad tetrahedra ---------------------------------------------------------------- */

static void cube_mesh(sb_tet_mesh* mesh) {
    sb_error err;
    assert_int_equal(sb_tet_mesh_load(tu_write_file("cube3.msh", cube_msh), mesh, &err), SB_OK);
}

static void test_inverted_and_flat_reported(void** state) {
    (void)state;
    sb_error err;
    sb_tet_mesh mesh;
    cube_mesh(&mesh);
    assert_int_equal(sb_tet_mesh_check(&mesh, &err), SB_OK);
    uint32_t* t = mesh.tets + 4 * 3; /* tetrahedron 3: swap two corners */
    uint32_t s = t[1];
    t[1] = t[2];
    t[2] = s;
    assert_int_equal(sb_tet_mesh_check(&mesh, &err), SB_ERR_INVALID);
    TU_ASSERT_CONTAINS(err.message, "tetrahedron 3 ");
    TU_ASSERT_CONTAINS(err.message, "inverted");
    sb_builder* b = sb_builder_create();
    sb_tissue_def liver = sb_default_tissue_def();
    assert_int_equal(sb_builder_add_tet_mesh(b, &mesh, &liver, &err), SB_ERR_INVALID);
    assert_int_equal(sb_builder_vertex_count(b), 0);
    sb_builder_destroy(b);
    t[2] = t[1];
    t[1] = s;
    /* tetrahedron 4 flattened: its corner 7 moved into the plane of 1, 2, 4 */
    double* p7 = mesh.positions + 3 * 7;
    p7[0] = p7[1] = p7[2] = 1.0 / 3.0;
    assert_int_equal(sb_tet_mesh_check(&mesh, &err), SB_ERR_INVALID);
    TU_ASSERT_CONTAINS(err.message, "tetrahedron 4 ");
    TU_ASSERT_CONTAINS(err.message, "zero volume");
    /* A huge tetrahedron was 'zero volume (inf m^3)' */
    sb_tet_mesh_free(&mesh);
    cube_mesh(&mesh);
    for (uint32_t v = 0; v < 3 * mesh.vertex_count; v++) mesh.positions[v] *= 1e150;
    assert_int_equal(sb_tet_mesh_check(&mesh, &err), SB_ERR_INVALID);
    TU_ASSERT_CONTAINS(err.message, "tetrahedron 0 ");
    TU_ASSERT_CONTAINS(err.message, "too large to compute (its longest edge ");
    TU_ASSERT_CONTAINS(err.message, "e+150 m, its volume overflows): a slip of units?");
    assert_null(strstr(err.message, "zero volume"));
    sb_tet_mesh_free(&mesh);
}

/* ---- malformed files ---------------------------------------------------------------- */

/* Loading fails with SB_ERR_PARSE and a message starting "PATH:LINE:". */
static void expect_parse_error(const char* path, int line, const char* what) {
    sb_error err;
    sb_tet_mesh mesh;
    assert_int_equal(sb_tet_mesh_load(path, &mesh, &err), SB_ERR_PARSE);
    assert_null(mesh.positions);
    char prefix[512];
    snprintf(prefix, sizeof prefix, "%s:%d: ", path, line);
    if (strncmp(err.message, prefix, strlen(prefix)) != 0)
        fail_msg("expected \"%s...\", got \"%s\"", prefix, err.message);
    TU_ASSERT_CONTAINS(err.message, what);
}

static void test_malformed_tetgen(void** state) {
    (void)state;
    tu_write_file("a.node", "4 3 0 0\n1 0 0 0\n2 1 0 x\n3 0 1 0\n4 0 0 1\n");
    tu_write_file("a.ele", one_ele);
    expect_parse_error(tu_tmp_path("a.node"), 3, "coordinates");
    tu_write_file("b.node", one_node);
    tu_write_file("b.ele", "1 4 0\n\n1 1 2 3 5\n");
    expect_parse_error(tu_tmp_path("b.ele"), 3, "point 5 does not exist");
    tu_write_file("c.node", "4 2 0 0\n");
    expect_parse_error(tu_tmp_path("c.node"), 1, "dimension 2");
    tu_write_file("d.node", "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n");
    tu_write_file("d.ele", one_ele);
    expect_parse_error(tu_tmp_path("d.node"), 5, "end of file");
    tu_write_file("e.node", one_node);
    tu_write_file("e.ele", "2 4 0\n1 1 2 3 4\n3 1 2 3 4\n");
    expect_parse_error(tu_tmp_path("e.ele"), 3, "numbered 3, expected 2");
    sb_error err;
    sb_tet_mesh mesh;
    assert_int_equal(sb_tet_mesh_load(tu_tmp_path("missing.node"), &mesh, &err), SB_ERR_IO);
    TU_ASSERT_CONTAINS(err.message, "missing.node");
}

static void test_malformed_gmsh(void** state) {
    (void)state;
    expect_parse_error(tu_write_file("a.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"), 2, "version 2.2");
    expect_parse_error(tu_write_file("b.msh", "$MeshFormat\n4.1 1 8\n$EndMeshFormat\n"), 2, "binary");
    expect_parse_error(tu_write_file("c.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n"
                                              "3 1 0 1\n1\n0 0 zero\n$EndNodes\n"),
                       8, "coordinates");
    expect_parse_error(tu_write_file("d.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 1 1 1\n"
                                              "3 1 0 1\n1\n0 0 0\n$EndNodes\n$Elements\n1 1 1 1\n"
                                              "3 1 4 1\n1 1 2 3 4\n$EndElements\n"),
                       13, "node 2 does not exist");
    expect_parse_error(tu_write_file("e.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Comments\nhello\n"), 4,
                       "no $EndComments");
    sb_error err;
    sb_tet_mesh mesh;
    const char* none = tu_write_file("f.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    assert_int_equal(sb_tet_mesh_load(none, &mesh, &err), SB_ERR_PARSE);
    TU_ASSERT_CONTAINS(err.message, "no tetrahedra");
}

/* Gmsh 4.0: node blocks give "tag x y z" per line and element block
 * headers start with the entity tag. */
static void test_gmsh_40(void** state) {
    (void)state;
    sb_error err;
    sb_tet_mesh mesh;
    const char* path = tu_write_file("v40.msh", "$MeshFormat\n4 0 8\n$EndMeshFormat\n$Nodes\n1 4\n1 3 0 4\n"
                                                "10 0 0 0\n11 1 0 0\n12 0 1 0\n13 0 0 1\n$EndNodes\n"
                                                "$Elements\n1 1\n1 3 4 1\n1 10 11 12 13\n$EndElements\n");
    assert_int_equal(sb_tet_mesh_load(path, &mesh, &err), SB_OK);
    assert_int_equal(mesh.vertex_count, 4);
    assert_int_equal(mesh.tet_count, 1);
    TU_ASSERT_NEAR(mesh.positions[3 * 3 + 2], 1.0, 0.0);
    sb_tet_mesh_free(&mesh);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_one_tetrahedron_by_hand),
        cmocka_unit_test(test_cube_mass_and_stiffness),
        cmocka_unit_test(test_cube_surface),
        cmocka_unit_test(test_inverted_and_flat_reported),
        cmocka_unit_test(test_malformed_tetgen),
        cmocka_unit_test(test_malformed_gmsh),
        cmocka_unit_test(test_gmsh_40),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
