/* The Spring Systems mesh factory (sb_builder_add_spring_mesh) and the
 * vicinity search (sb_vicinity_pairs): spring counts on known meshes (a
 * closed icosphere has E = 3V − 6 edges; a sheet gets a bend spring per
 * interior edge), constants and rest lengths of each kind, no duplicate
 * pairs, and the grid search against a brute-force O(n²) search on random
 * points. */
#include "tests/test_util.h"

static sb_model* build_springs(const sb_mesh* mesh, const sb_spring_mesh_def* def) {
    sb_error err;
    sb_builder* b = sb_builder_create();
    sb_status status = sb_builder_add_spring_mesh(b, mesh, def, &err);
    if (status != SB_OK) fail_msg("sb_builder_add_spring_mesh: %s", err.message);
    sb_model* model = tu_compile(b);
    sb_builder_destroy(b);
    return model;
}

static sb_spring_mesh_def stretch_only(void) {
    sb_spring_mesh_def d = sb_default_spring_mesh_def();
    d.bend_k = d.bend_damping = 0.0;
    return d;
}

static void test_icosphere_edges(void** state) {
    (void)state;
    for (uint32_t s = 0; s <= 3; s++) {
        sb_error err;
        sb_mesh mesh = {0};
        assert_int_equal(sb_mesh_generate_icosphere(s, 1.0, &mesh, &err), SB_OK);
        sb_spring_mesh_def d = stretch_only();
        sb_model* model = build_springs(&mesh, &d);
        assert_int_equal(sb_model_vertex_count(model), mesh.vertex_count);
        assert_int_equal(sb_model_bond_count(model), 3 * mesh.vertex_count - 6);
        sb_model_destroy(model);
        /* with bend springs: one per edge (each edge has two triangles), none of
         * which duplicates an edge from subdivision 1 on */
        d = sb_default_spring_mesh_def();
        model = build_springs(&mesh, &d);
        uint32_t edges = 3 * mesh.vertex_count - 6;
        if (s > 0) assert_int_equal(sb_model_bond_count(model), 2 * edges);
        sb_model_destroy(model);
        sb_mesh_free(&mesh);
    }
}

static void sheet(uint32_t nx, uint32_t ny, double jitter, sb_mesh* mesh) {
    sb_error err;
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = nx;
    def.ny = ny;
    def.jitter = jitter;
    assert_int_equal(sb_mesh_generate_sheet(&def, mesh, &err), SB_OK);
}

/* A sheet with every quad split along the same diagonal: no two interior
 * edges share their pair of opposite vertices, so a bend spring per
 * interior edge. */
static void uniform_sheet(uint32_t nx, uint32_t ny, sb_mesh* mesh) {
    mesh->vertex_count = nx * ny;
    mesh->positions = malloc(3 * nx * ny * sizeof(double));
    mesh->triangle_count = 2 * (nx - 1) * (ny - 1);
    mesh->triangles = malloc(3 * mesh->triangle_count * sizeof(uint32_t));
    for (uint32_t y = 0; y < ny; y++)
        for (uint32_t x = 0; x < nx; x++) {
            double* p = mesh->positions + 3 * (y * nx + x);
            p[0] = x + 0.1 * sin(x * 7.0 + y);
            p[1] = y + 0.1 * cos(x + y * 3.0);
            p[2] = 0.0;
        }
    uint32_t* t = mesh->triangles;
    for (uint32_t y = 0; y + 1 < ny; y++)
        for (uint32_t x = 0; x + 1 < nx; x++) {
            uint32_t ll = y * nx + x, lr = ll + 1, ul = ll + nx, ur = ul + 1;
            uint32_t quad[6] = {ll, lr, ur, ll, ur, ul};
            memcpy(t, quad, sizeof quad);
            t += 6;
        }
}

static void test_sheet_bend_count(void** state) {
    (void)state;
    const uint32_t nx = 7, ny = 5;
    sb_mesh mesh = {0};
    uniform_sheet(nx, ny, &mesh);
    uint32_t edges = (nx - 1) * ny + nx * (ny - 1) + (nx - 1) * (ny - 1);
    uint32_t interior = edges - 2 * (nx - 1) - 2 * (ny - 1);
    sb_spring_mesh_def d = sb_default_spring_mesh_def();
    d.stretch_k = 7.0;
    d.stretch_damping = 0.5;
    d.bend_k = 3.0;
    d.bend_damping = 0.25;
    sb_model* model = build_springs(&mesh, &d);
    assert_int_equal(sb_model_bond_count(model), edges + interior);
    /* every spring has the constants of its kind and its current length as rest */
    uint32_t stretch = 0, bend = 0;
    for (uint32_t e = 0; e < sb_model_bond_count(model); e++) {
        sb_bond_info info = sb_model_bond(model, e);
        assert_true(info.k == 0.0);
        if (info.spring_k == 7.0 && info.spring_damping == 0.5) stretch++;
        if (info.spring_k == 3.0 && info.spring_damping == 0.25) bend++;
        double r = tu_dist(mesh.positions + 3 * info.i, mesh.positions + 3 * info.j);
        TU_ASSERT_NEAR(info.rest_length, r, 1e-15);
    }
    assert_int_equal(stretch, edges);
    assert_int_equal(bend, interior);
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* The generator's sheet alternates its diagonals: at a vertex where four
 * diagonals meet, the two edges along a row have the same opposite pair.
 * The bend springs are the distinct opposite pairs, counted here by brute
 * force, fewer than the interior edges. */
static void test_sheet_bend_duplicates_dropped(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sheet(7, 5, 0.2, &mesh);
    /* brute force: every pair of triangles sharing an edge gives its opposite pair */
    uint32_t pairs[512][2], count = 0, interior = 0;
    for (uint32_t s = 0; s < mesh.triangle_count; s++)
        for (uint32_t t = s + 1; t < mesh.triangle_count; t++) {
            const uint32_t *a = mesh.triangles + 3 * s, *b = mesh.triangles + 3 * t;
            uint32_t shared = 0, oa = 0, ob = 0;
            for (int i = 0; i < 3; i++) {
                bool in_b = a[i] == b[0] || a[i] == b[1] || a[i] == b[2];
                bool in_a = b[i] == a[0] || b[i] == a[1] || b[i] == a[2];
                shared += in_b;
                if (!in_b) oa = a[i];
                if (!in_a) ob = b[i];
            }
            if (shared != 2) continue;
            interior++;
            uint32_t lo = oa < ob ? oa : ob, hi = oa ^ ob ^ lo;
            bool seen = false;
            for (uint32_t k = 0; k < count && !seen; k++) seen = pairs[k][0] == lo && pairs[k][1] == hi;
            if (!seen) {
                pairs[count][0] = lo;
                pairs[count++][1] = hi;
            }
        }
    assert_true(count < interior);
    sb_spring_mesh_def d = sb_default_spring_mesh_def();
    d.stretch_k = d.stretch_damping = 0.0;
    sb_model* model = build_springs(&mesh, &d);
    assert_int_equal(sb_model_bond_count(model), count);
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* On a regular 1 m-spaced sheet the vicinity 1.5 m reaches the diagonals
 * that are not edges and the vertices two apart along a row or column that
 * are not bend pairs; the total is the brute-force count of pairs nearer
 * than 1.5, every pair joined once. */
static void test_sheet_vicinity_no_duplicates(void** state) {
    (void)state;
    const uint32_t nx = 9, ny = 6;
    sb_mesh mesh = {0};
    sheet(nx, ny, 0.0, &mesh);
    sb_spring_mesh_def d = sb_default_spring_mesh_def();
    double spacing = 1.0 / (nx - 1);
    assert_true(fabs(spacing - 1.0 / (ny - 1)) > 1e-3); /* not square: only the x spacing matters */
    d.vicinity = 2.01 * (1.0 / (nx - 1));
    d.vicinity_k = 1.0;
    sb_model* model = build_springs(&mesh, &d);
    uint32_t near = 0;
    for (uint32_t i = 0; i < mesh.vertex_count; i++)
        for (uint32_t j = i + 1; j < mesh.vertex_count; j++)
            near += tu_dist(mesh.positions + 3 * i, mesh.positions + 3 * j) < d.vicinity;
    /* every near pair is joined once; edges and bend pairs further than the
     * vicinity come on top */
    uint32_t far = 0;
    for (uint32_t e = 0; e < sb_model_bond_count(model); e++) {
        sb_bond_info info = sb_model_bond(model, e);
        far += info.rest_length >= d.vicinity;
    }
    assert_int_equal(sb_model_bond_count(model), near + far);
    assert_true(near > 0 && far > 0);
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

static int compare_pair(const void* a, const void* b) {
    const uint32_t *x = a, *y = b;
    if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
    return (x[1] > y[1]) - (x[1] < y[1]);
}

static void check_against_brute_force(const double* p, uint32_t n, double radius) {
    sb_error err;
    uint32_t* pairs;
    size_t count;
    assert_int_equal(sb_vicinity_pairs(p, n, radius, &pairs, &count, &err), SB_OK);
    uint32_t* expected = malloc(2 * (size_t)n * n * sizeof *expected + 8);
    size_t expected_count = 0;
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t j = i + 1; j < n; j++) {
            double d = tu_dist(p + 3 * i, p + 3 * j);
            if (d < radius && d > 0.0) {
                expected[2 * expected_count] = i;
                expected[2 * expected_count++ + 1] = j;
            }
        }
    assert_int_equal(count, expected_count);
    for (size_t k = 0; k < count; k++) assert_true(pairs[2 * k] < pairs[2 * k + 1]);
    qsort(pairs, count, 2 * sizeof *pairs, compare_pair);
    if (count) assert_memory_equal(pairs, expected, 2 * count * sizeof *pairs);
    free(expected);
    free(pairs);
}

static void test_vicinity_matches_brute_force(void** state) {
    (void)state;
    tu_rng rng = {42};
    const uint32_t n = 2000;
    double* p = malloc(3 * n * sizeof *p);
    for (uint32_t i = 0; i < 3 * n; i++) p[i] = tu_uniform(&rng, -1.0, 1.0);
    /* a flat cluster and duplicated points too */
    for (uint32_t i = 0; i < 200; i++) p[3 * i + 2] = 0.25;
    memcpy(p + 3 * 300, p + 3 * 301, 3 * sizeof *p);
    for (int r = 0; r < 4; r++) check_against_brute_force(p, n, (double[]){0.05, 0.12, 0.3, 5.0}[r]);
    /* points along one axis only */
    for (uint32_t i = 0; i < n; i++) p[3 * i] = p[3 * i + 1] = 0.0;
    check_against_brute_force(p, n, 0.002);
    free(p);
}

static void test_vicinity_bad_input(void** state) {
    (void)state;
    sb_error err;
    uint32_t* pairs;
    size_t count;
    double p[6] = {0, 0, 0, 1, 0, 0};
    assert_int_equal(sb_vicinity_pairs(p, 2, -1.0, &pairs, &count, &err), SB_ERR_INVALID);
    assert_int_equal(sb_vicinity_pairs(p, 2, 0.0, &pairs, &count, &err), SB_OK);
    assert_int_equal(count, 0);
    p[4] = NAN;
    assert_int_equal(sb_vicinity_pairs(p, 2, 1.0, &pairs, &count, &err), SB_ERR_INVALID);
    TU_ASSERT_CONTAINS(err.message, "point 1");
    p[4] = 1e300;
    assert_int_equal(sb_vicinity_pairs(p, 2, 1e-300, &pairs, &count, &err), SB_ERR_INVALID);
}

static void test_spring_mass_from_density(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sheet(4, 4, 0.1, &mesh);
    sb_spring_mesh_def d = sb_default_spring_mesh_def();
    d.density = 2.0; /* kg/m², on a 1 m² sheet */
    sb_model* model = build_springs(&mesh, &d);
    double total = 0.0;
    for (uint32_t v = 0; v < sb_model_vertex_count(model); v++) total += sb_model_mass(model, v);
    TU_ASSERT_NEAR(total, 2.0, 1e-12);
    sb_model_destroy(model);
    sb_error err;
    d.stretch_k = -1.0;
    sb_builder* b = sb_builder_create();
    assert_int_equal(sb_builder_add_spring_mesh(b, &mesh, &d, &err), SB_ERR_INVALID);
    sb_builder_destroy(b);
    sb_mesh_free(&mesh);
}

/* Appended after a vertex already in the builder: indices are offset. A
 * fin of three triangles on one edge gets no bend spring across it; the
 * other edges have one triangle each. */
static void test_offset_and_fin(void** state) {
    (void)state;
    double positions[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
    uint32_t triangles[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    sb_mesh fin = {5, positions, 3, triangles};
    sb_error err;
    sb_builder* b = sb_builder_create();
    assert_true(tu_vertex(b, 9, 9, 9, 1.0, false) == 0);
    sb_spring_mesh_def d = sb_default_spring_mesh_def();
    assert_int_equal(sb_builder_add_spring_mesh(b, &fin, &d, &err), SB_OK);
    sb_model* model = tu_compile(b);
    assert_int_equal(sb_model_vertex_count(model), 6);
    assert_int_equal(sb_model_bond_count(model), 7); /* 7 edges, no bend */
    for (uint32_t e = 0; e < 7; e++) {
        sb_bond_info info = sb_model_bond(model, e);
        assert_true(info.i >= 1 && info.j >= 1);
        TU_ASSERT_NEAR(info.rest_length, tu_dist(positions + 3 * (info.i - 1), positions + 3 * (info.j - 1)), 1e-15);
    }
    sb_model_destroy(model);
    sb_builder_destroy(b);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_icosphere_edges),
        cmocka_unit_test(test_sheet_bend_count),
        cmocka_unit_test(test_sheet_bend_duplicates_dropped),
        cmocka_unit_test(test_sheet_vicinity_no_duplicates),
        cmocka_unit_test(test_vicinity_matches_brute_force),
        cmocka_unit_test(test_vicinity_bad_input),
        cmocka_unit_test(test_spring_mass_from_density),
        cmocka_unit_test(test_offset_and_fin),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
