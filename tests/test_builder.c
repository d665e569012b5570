/* The builder (include/softbond/builder.h): compile rejects bad input with a
 * message naming the element, leaves the builder reusable, and the model's
 * accessors return what was added; the mesh factory makes the documented
 * elements and masses. */
#include "tests/test_util.h"

#include <stdio.h>

/* Four vertices of a unit square at z = 0 and four valid bonds (0-1, 1-2,
 * 2-3, 3-0): bond 4 is the next one a test adds. */
static sb_builder* square(void) {
    sb_builder* b = sb_builder_create();
    assert_non_null(b);
    tu_vertex(b, 0, 0, 0, 1, false);
    tu_vertex(b, 1, 0, 0, 1, false);
    tu_vertex(b, 1, 1, 0, 1, false);
    tu_vertex(b, 0, 1, 0, 1, false);
    for (uint32_t i = 0; i < 4; ++i) assert_int_equal(tu_bond(b, i, (i + 1) % 4, -1, 1, 0, 0), i);
    return b;
}

static void test_valid_square_compiles(void** state) {
    (void)state;
    sb_builder* b = square();
    tu_triangle(b, 0, 1, 2, 1, 0);
    sb_model* m = tu_compile(b);
    assert_int_equal(sb_model_vertex_count(m), 4);
    assert_int_equal(sb_model_bond_count(m), 4);
    assert_int_equal(sb_model_triangle_count(m), 1);
    sb_model_destroy(m);
    sb_builder_destroy(b);
}

static void test_index_out_of_range(void** state) {
    (void)state;
    sb_builder* b = square();
    tu_bond(b, 0, 4, -1, 1, 0, 0); /* bond 4: vertex 4 does not exist */
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "bond 4");
    sb_builder_destroy(b);

    b = square();
    tu_triangle(b, 0, 1, 2, 1, 0);
    tu_triangle(b, 0, 2, 17, 1, 0); /* triangle 1 */
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "triangle 1");
    sb_builder_destroy(b);

    b = square();
    tu_triangle(b, 0, 1, 2, 0, 0);
    tu_triangle(b, 0, 2, 3, 0, 0);
    tu_hinge(b, 2, 0, 1, 3, 1.0);
    tu_hinge(b, 2, 0, 1, 9, 1.0); /* hinge 1 */
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "hinge 1");
    sb_builder_destroy(b);
}

static void test_self_bond(void** state) {
    (void)state;
    sb_builder* b = square();
    tu_bond(b, 2, 2, 1.0, 1, 0, 0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "bond 4");
    sb_builder_destroy(b);
}

static void test_duplicate_bond_rejected(void** state) {
    (void)state;
    /* The same pair in the same order... */
    sb_builder* b = square();
    tu_bond(b, 1, 2, -1, 5, 0, 0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "bond 4");
    sb_builder_destroy(b);
    /* ...and reversed: (j, i) is the same bond as (i, j). */
    b = square();
    tu_bond(b, 0, 2, -1, 1, 0, 0); /* bond 4, a diagonal, fine */
    tu_bond(b, 2, 1, -1, 5, 0, 0); /* bond 5 duplicates bond 1 */
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "bond 5");
    sb_builder_destroy(b);
}

static void test_degenerate_triangles(void** state) {
    (void)state;
    /* Repeated vertex. */
    sb_builder* b = square();
    tu_triangle(b, 0, 1, 2, 1, 0);
    tu_triangle(b, 0, 3, 0, 1, 0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "triangle 1");
    sb_builder_destroy(b);

    /* Collinear: vertex 4 on the segment 0-1. */
    b = square();
    tu_vertex(b, 0.5, 0, 0, 1, false);
    tu_triangle(b, 0, 1, 2, 1, 0);
    tu_triangle(b, 0, 1, 4, 1, 0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "triangle 1");
    sb_builder_destroy(b);

    /* Zero area: two distinct vertices at the same position. */
    b = square();
    tu_vertex(b, 1, 1, 0, 1, false); /* vertex 4 on top of vertex 2 */
    tu_triangle(b, 0, 1, 2, 1, 0);
    tu_triangle(b, 1, 2, 4, 1, 0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "triangle 1");
    sb_builder_destroy(b);

    /* A zero-area triangle is rejected even when its constants are 0. */
    b = square();
    tu_vertex(b, 0.5, 0, 0, 1, false);
    tu_triangle(b, 0, 1, 4, 0, 0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "triangle 0");
    sb_builder_destroy(b);
}

static void test_non_finite_numbers(void** state) {
    (void)state;
    sb_builder* b = square();
    tu_vertex(b, 0.5, NAN, 0, 1, false); /* vertex 4 */
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "vertex 4");
    sb_builder_destroy(b);

    b = square();
    sb_builder_vertex(b, 2)->velocity[2] = INFINITY;
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "vertex 2");
    sb_builder_destroy(b);

    b = square();
    sb_builder_vertex(b, 1)->mass = NAN;
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "vertex 1");
    sb_builder_destroy(b);

    b = square();
    tu_bond(b, 0, 2, -1, NAN, 0, 0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "bond 4");
    sb_builder_destroy(b);

    b = square();
    tu_bond(b, 0, 2, INFINITY, 1, 0, 0); /* infinite rest length */
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "bond 4");
    sb_builder_destroy(b);

    b = square();
    tu_triangle(b, 0, 1, 2, INFINITY, 0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "triangle 0");
    sb_builder_destroy(b);
}

static void test_mass(void** state) {
    (void)state;
    /* Zero mass on a free vertex: rejected. */
    sb_builder* b = square();
    sb_builder_vertex(b, 3)->mass = 0.0;
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "vertex 3");
    /* Negative mass on a free vertex: rejected. */
    sb_builder_vertex(b, 3)->mass = -1.0;
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "vertex 3");
    /* The same vertex fixed: allowed (a pinned vertex never moves). */
    sb_builder_vertex(b, 3)->mass = 0.0;
    sb_builder_vertex(b, 3)->fixed = true;
    sb_model* m = tu_compile(b);
    assert_true(sb_model_is_fixed(m, 3));
    assert_false(sb_model_is_fixed(m, 2));
    sb_model_destroy(m);
    sb_builder_destroy(b);
}

static void test_negative_constants(void** state) {
    (void)state;
    const char* field[3] = {"k", "spring_k", "spring_damping"};
    for (int f = 0; f < 3; ++f) {
        sb_builder* b = square();
        double k = f == 0 ? -1 : 0, sk = f == 1 ? -1 : 0, d = f == 2 ? -1 : 0;
        tu_bond(b, 0, 2, -1, k, sk, d);
        const char* msg = tu_compile_fails(b);
        if (!strstr(msg, "bond 4")) fail_msg("negative bond %s: \"%s\"", field[f], msg);
        sb_builder_destroy(b);
    }
    for (int f = 0; f < 2; ++f) {
        sb_builder* b = square();
        tu_triangle(b, 0, 1, 2, 1, 0);
        tu_triangle(b, 0, 2, 3, f == 0 ? -1 : 0, f == 1 ? -1 : 0);
        TU_ASSERT_CONTAINS(tu_compile_fails(b), "triangle 1");
        sb_builder_destroy(b);
    }
    sb_builder* b = square();
    tu_triangle(b, 0, 1, 2, 0, 0);
    tu_triangle(b, 0, 2, 3, 0, 0);
    tu_hinge(b, 2, 0, 1, 3, -1.0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "hinge 0");
    sb_builder_destroy(b);
}

static void test_degenerate_hinge(void** state) {
    (void)state;
    /* A hinge whose two wing vertices are the same vertex. */
    sb_builder* b = square();
    tu_triangle(b, 0, 1, 2, 0, 0);
    tu_triangle(b, 0, 2, 3, 0, 0);
    tu_hinge(b, 2, 0, 1, 1, 1.0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "hinge 0");
    sb_builder_destroy(b);
    /* A hinge whose edge is a single vertex. */
    b = square();
    tu_triangle(b, 0, 1, 2, 0, 0);
    tu_triangle(b, 0, 2, 3, 0, 0);
    tu_hinge(b, 0, 0, 1, 3, 1.0);
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "hinge 0");
    sb_builder_destroy(b);
}

/* After a failed compile the builder is unchanged: fix the bad vertex and
 * compile again. */
static void test_compile_again_after_failure(void** state) {
    (void)state;
    sb_builder* b = square();
    sb_builder_vertex(b, 1)->mass = -2.0;
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "vertex 1");
    TU_ASSERT_CONTAINS(tu_compile_fails(b), "vertex 1");
    sb_builder_vertex(b, 1)->mass = 2.0;
    sb_model* m = tu_compile(b);
    assert_true(sb_model_mass(m, 1) == 2.0);
    sb_model_destroy(m);
    /* Compiling twice gives two independent models. */
    sb_model* m1 = tu_compile(b);
    sb_model* m2 = tu_compile(b);
    assert_ptr_not_equal(m1, m2);
    sb_model_destroy(m1);
    assert_int_equal(sb_model_vertex_count(m2), 4);
    sb_model_destroy(m2);
    sb_builder_destroy(b);
}

static void test_accessors(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    sb_vertex_def defs[3];
    for (int i = 0; i < 3; ++i) {
        defs[i] = sb_default_vertex_def();
        defs[i].position[0] = 0.25 * i + 0.1;
        defs[i].position[1] = -0.5 * i * i; /* not collinear */
        defs[i].position[2] = 1.0 / 3.0 + i;
        defs[i].velocity[0] = 1.5 * i;
        defs[i].velocity[1] = -2.0;
        defs[i].velocity[2] = 0.125 * i;
        defs[i].mass = 0.3 + i;
        defs[i].fixed = i == 1;
        assert_int_equal(sb_builder_add_vertex(b, &defs[i]), i);
    }
    assert_int_equal(sb_builder_vertex_count(b), 3);
    sb_vertex_def* v1 = sb_builder_vertex(b, 1);
    assert_non_null(v1);
    assert_true(v1->position[2] == defs[1].position[2]);
    assert_true(v1->mass == defs[1].mass);
    assert_true(v1->fixed);
    assert_int_equal(tu_bond(b, 0, 1, -1, 2.0, 0, 0), 0);
    assert_int_equal(tu_bond(b, 1, 2, -1, 0, 3.0, 0.1), 1);
    assert_int_equal(tu_triangle(b, 0, 1, 2, 0.5, 0), 0);
    sb_model* m = tu_compile(b);
    assert_int_equal(sb_model_vertex_count(m), 3);
    assert_int_equal(sb_model_bond_count(m), 2);
    assert_int_equal(sb_model_triangle_count(m), 1);
    assert_int_equal(sb_model_hinge_count(m), 0);
    for (uint32_t i = 0; i < 3; ++i) {
        double p[3], v[3];
        sb_model_rest_position(m, i, p);
        sb_model_initial_velocity(m, i, v);
        for (int d = 0; d < 3; ++d) {
            assert_true(p[d] == defs[i].position[d]);
            /* A pinned vertex never moves: its initial velocity reads 0. */
            assert_true(v[d] == (defs[i].fixed ? 0.0 : defs[i].velocity[d]));
        }
        assert_true(sb_model_mass(m, i) == defs[i].mass);
        assert_true(sb_model_is_fixed(m, i) == defs[i].fixed);
    }
    assert_true(sb_model_term_enabled(m, SB_TERM_BOND));
    assert_true(sb_model_term_enabled(m, SB_TERM_SPRING));
    assert_true(sb_model_term_enabled(m, SB_TERM_ANGLE));
    assert_false(sb_model_term_enabled(m, SB_TERM_STRETCH_BEND));
    assert_false(sb_model_term_enabled(m, SB_TERM_BEND));
    sb_model_destroy(m);
    sb_builder_destroy(b);

    const char* names[SB_TERM_COUNT] = {"bond", "angle", "stretch_bend", "spring", "bend", "corotated", "membrane"};
    for (int t = 0; t < SB_TERM_COUNT; ++t) assert_string_equal(sb_term_name((sb_term)t), names[t]);
}

/* A negative rest length means the current distance; an explicit one is
 * kept. Checked through the bond energy ½ k (r − r0)². */
static void test_rest_length(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    tu_vertex(b, 0, 0, 0, 1, false);
    tu_vertex(b, 3, 4, 0, 1, false); /* distance 5 */
    tu_vertex(b, 0, 0, 1, 1, false);
    tu_bond(b, 0, 1, -1.0, 2.0, 0, 0); /* r0 = 5 */
    sb_model* m = tu_compile(b);
    double x[9] = {0, 0, 0, 3.6, 4.8, 0, 0, 0, 1}, f[9] = {0}, e = -1; /* r = 6 */
    sb_error err;
    assert_int_equal(sb_reference_term(m, SB_TERM_BOND, x, NULL, f, &e, &err), SB_OK);
    TU_ASSERT_NEAR(e, 0.5 * 2.0 * 1.0, 1e-13); /* ½·2·(6 − 5)² */
    sb_model_destroy(m);
    sb_builder_destroy(b);

    b = sb_builder_create();
    tu_vertex(b, 0, 0, 0, 1, false);
    tu_vertex(b, 3, 4, 0, 1, false);
    tu_bond(b, 0, 1, 2.0, 2.0, 0, 0); /* r0 = 2 */
    m = tu_compile(b);
    memset(f, 0, sizeof f);
    assert_int_equal(sb_reference_term(m, SB_TERM_BOND, x, NULL, f, &e, &err), SB_OK);
    TU_ASSERT_NEAR(e, 0.5 * 2.0 * 16.0, 1e-12); /* ½·2·(6 − 2)² */
    sb_model_destroy(m);
    sb_builder_destroy(b);
}

/* ---- the mesh factory --------------------------------------------------------- */

/* The unit square split along 0-2: triangles (0,1,2) and (0,2,3), edges
 * 0-1, 1-2, 2-0, 2-3, 3-0 (five), one interior edge 0-2. */
static double quad_positions[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
static uint32_t quad_triangles[6] = {0, 1, 2, 0, 2, 3};

static sb_mesh quad_mesh(void) {
    sb_mesh mesh = {4, quad_positions, 2, quad_triangles};
    return mesh;
}

static sb_material_def material(double bend_k, double density) {
    sb_material_def mat = sb_default_material_def();
    mat.bond_k = 10;
    mat.angle_k = 1;
    mat.stretch_bend_k = 0.5;
    mat.spring_k = 0;
    mat.spring_damping = 0;
    mat.bend_k = bend_k;
    mat.mass = 0.7;
    mat.density = density;
    return mat;
}

static void test_add_mesh_counts(void** state) {
    (void)state;
    for (int with_bend = 0; with_bend < 2; ++with_bend) {
        sb_mesh mesh = quad_mesh();
        sb_material_def mat = material(with_bend ? 0.3 : 0.0, 0.0);
        sb_builder* b = sb_builder_create();
        sb_error err;
        sb_status s = sb_builder_add_mesh(b, &mesh, &mat, &err);
        if (s != SB_OK) fail_msg("sb_builder_add_mesh: %s", err.message);
        assert_int_equal(sb_builder_vertex_count(b), 4);
        sb_model* m = tu_compile(b);
        assert_int_equal(sb_model_vertex_count(m), 4);
        assert_int_equal(sb_model_bond_count(m), 5);
        assert_int_equal(sb_model_triangle_count(m), 2);
        assert_int_equal(sb_model_hinge_count(m), with_bend ? 1 : 0);
        assert_true(sb_model_term_enabled(m, SB_TERM_BOND));
        assert_true(sb_model_term_enabled(m, SB_TERM_ANGLE));
        assert_true(sb_model_term_enabled(m, SB_TERM_STRETCH_BEND));
        assert_false(sb_model_term_enabled(m, SB_TERM_SPRING));
        assert_true(sb_model_term_enabled(m, SB_TERM_BEND) == (with_bend != 0));
        for (uint32_t v = 0; v < 4; ++v) {
            double p[3];
            sb_model_rest_position(m, v, p); /* order kept */
            for (int d = 0; d < 3; ++d) assert_true(p[d] == quad_positions[3 * v + d]);
            assert_true(sb_model_mass(m, v) == 0.7); /* density 0: mass per vertex */
            assert_false(sb_model_is_fixed(m, v));
        }
        /* The model is at rest: every term's energy is 0 there. */
        double* x = tu_rest_positions(m);
        double f[12];
        sb_energies en;
        assert_int_equal(sb_reference_forces(m, x, NULL, f, &en, &err), SB_OK);
        TU_ASSERT_LE(fabs(sb_energies_internal(&en)), 1e-24);
        free(x);
        sb_model_destroy(m);
        sb_builder_destroy(b);
    }
}

static void test_add_mesh_density(void** state) {
    (void)state;
    /* A 1 × 2 rectangle: triangle areas 1 each, density 3 kg/m². Vertices 0
     * and 2 are in both triangles, 1 and 3 in one; each vertex gets a third
     * of its triangles' mass. */
    double positions[12] = {0, 0, 0, 1, 0, 0, 1, 2, 0, 0, 2, 0};
    sb_mesh mesh = {4, positions, 2, quad_triangles};
    sb_material_def mat = material(0, 3.0);
    sb_builder* b = sb_builder_create();
    sb_error err;
    assert_int_equal(sb_builder_add_mesh(b, &mesh, &mat, &err), SB_OK);
    sb_model* m = tu_compile(b);
    const double expected[4] = {2 * 1.0 * 3.0 / 3, 1.0 * 3.0 / 3, 2 * 1.0 * 3.0 / 3, 1.0 * 3.0 / 3};
    double total = 0;
    for (uint32_t v = 0; v < 4; ++v) {
        TU_ASSERT_NEAR(sb_model_mass(m, v), expected[v], 1e-14);
        total += sb_model_mass(m, v);
    }
    TU_ASSERT_NEAR(total, 2.0 * 3.0, 1e-13); /* area 2 × density 3 */
    sb_model_destroy(m);
    sb_builder_destroy(b);
}

/* Vertices already in the builder shift the mesh's indices. */
static void test_add_mesh_after_vertices(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    tu_vertex(b, 5, 5, 5, 1, true);
    sb_mesh mesh = quad_mesh();
    sb_material_def mat = material(0.3, 0);
    sb_error err;
    assert_int_equal(sb_builder_add_mesh(b, &mesh, &mat, &err), SB_OK);
    assert_int_equal(sb_builder_vertex_count(b), 5);
    sb_model* m = tu_compile(b);
    assert_int_equal(sb_model_bond_count(m), 5);
    assert_int_equal(sb_model_hinge_count(m), 1);
    double p[3];
    sb_model_rest_position(m, 3, p);
    assert_true(p[0] == 1 && p[1] == 1 && p[2] == 0);
    sb_model_destroy(m);
    sb_builder_destroy(b);
}

/* An edge shared by three triangles: fine without hinges, an error with. */
static void test_add_mesh_nonmanifold(void** state) {
    (void)state;
    double positions[15] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1};
    uint32_t triangles[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    sb_mesh mesh = {5, positions, 3, triangles};
    sb_error err;
    sb_material_def mat = material(0, 0);
    sb_builder* b = sb_builder_create();
    assert_int_equal(sb_builder_add_mesh(b, &mesh, &mat, &err), SB_OK);
    sb_model* m = tu_compile(b);
    assert_int_equal(sb_model_bond_count(m), 7);
    assert_int_equal(sb_model_triangle_count(m), 3);
    sb_model_destroy(m);
    sb_builder_destroy(b);

    mat = material(0.3, 0);
    b = sb_builder_create();
    memset(&err, 0, sizeof err);
    assert_int_not_equal(sb_builder_add_mesh(b, &mesh, &mat, &err), SB_OK);
    assert_true(err.message[0] != '\0');
    sb_builder_destroy(b);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_valid_square_compiles),
        cmocka_unit_test(test_index_out_of_range),
        cmocka_unit_test(test_self_bond),
        cmocka_unit_test(test_duplicate_bond_rejected),
        cmocka_unit_test(test_degenerate_triangles),
        cmocka_unit_test(test_non_finite_numbers),
        cmocka_unit_test(test_mass),
        cmocka_unit_test(test_negative_constants),
        cmocka_unit_test(test_degenerate_hinge),
        cmocka_unit_test(test_compile_again_after_failure),
        cmocka_unit_test(test_accessors),
        cmocka_unit_test(test_rest_length),
        cmocka_unit_test(test_add_mesh_counts),
        cmocka_unit_test(test_add_mesh_density),
        cmocka_unit_test(test_add_mesh_after_vertices),
        cmocka_unit_test(test_add_mesh_nonmanifold),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
