/* Meshes: the sheet and icosphere generators, the OBJ and OFF readers, the
 * assimp path of sb_mesh_load and its errors. Input files are written by the
 * tests into a fresh temporary directory. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tests/test_util.h"

/* ---- temporary files ----------------------------------------------------- */

static char tmp_dir[256];
static char tmp_files[64][512];
static int tmp_count;

static int setup_dir(void** state) {
    (void)state;
    const char* base = getenv("TMPDIR");
    snprintf(tmp_dir, sizeof tmp_dir, "%s/sb_test_mesh_XXXXXX", base && *base ? base : "/tmp");
    return mkdtemp(tmp_dir) != NULL ? 0 : -1;
}

static int teardown_dir(void** state) {
    (void)state;
    for (int i = 0; i < tmp_count; i++) {
        remove(tmp_files[i]);
    }
    return rmdir(tmp_dir);
}

/* Writes text to tmp_dir/name and returns the path (valid until teardown). */
static const char* write_file(const char* name, const char* text) {
    assert_true(tmp_count < 64);
    char* path = tmp_files[tmp_count++];
    snprintf(path, sizeof tmp_files[0], "%s/%s", tmp_dir, name);
    FILE* f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fputs(text, f) >= 0, 1);
    assert_int_equal(fclose(f), 0);
    return path;
}

/* Makes a directory that teardown removes. */
static int mkdir_for_test(const char* path) {
    assert_true(tmp_count < 64);
    snprintf(tmp_files[tmp_count++], sizeof tmp_files[0], "%s", path);
    return mkdir(path, 0700);
}

static bool mesh_is_zeroed(const sb_mesh* m) {
    return m->vertex_count == 0 && m->positions == NULL && m->triangle_count == 0 && m->triangles == NULL;
}

static void triangle_normal(const sb_mesh* m, uint32_t t, double n[3]) {
    const uint32_t* v = m->triangles + 3 * (size_t)t;
    const double *a = m->positions + 3 * (size_t)v[0], *b = m->positions + 3 * (size_t)v[1],
                 *c = m->positions + 3 * (size_t)v[2];
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    tu_cross(u, w, n);
}

static void assert_indices_in_range(const sb_mesh* m) {
    for (size_t i = 0; i < 3 * (size_t)m->triangle_count; i++) {
        assert_true(m->triangles[i] < m->vertex_count);
    }
}

static void assert_triangle(const sb_mesh* m, uint32_t t, uint32_t a, uint32_t b, uint32_t c) {
    const uint32_t* v = m->triangles + 3 * (size_t)t;
    if (v[0] != a || v[1] != b || v[2] != c) {
        fail_msg("triangle %u is (%u %u %u), expected (%u %u %u)", t, v[0], v[1], v[2], a, b, c);
    }
}

/* ---- sheet --------------------------------------------------------------- */

static void test_sheet_default_def(void** state) {
    (void)state;
    sb_sheet_def def = sb_default_sheet_def();
    assert_int_equal(def.nx, 10);
    assert_int_equal(def.ny, 10);
    assert_true(def.width == 1.0 && def.height == 1.0 && def.jitter == 0.0);
    assert_int_equal(def.seed, 1);
}

static void test_sheet_counts(void** state) {
    (void)state;
    const uint32_t sizes[][2] = {{2, 2}, {3, 5}, {7, 2}, {10, 10}, {33, 17}};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        sb_sheet_def def = sb_default_sheet_def();
        def.nx = sizes[s][0];
        def.ny = sizes[s][1];
        sb_mesh m;
        sb_error err;
        assert_int_equal(sb_mesh_generate_sheet(&def, &m, &err), SB_OK);
        assert_int_equal(m.vertex_count, def.nx * def.ny);
        assert_int_equal(m.triangle_count, 2 * (def.nx - 1) * (def.ny - 1));
        assert_indices_in_range(&m);
        sb_mesh_free(&m);
        assert_true(mesh_is_zeroed(&m));
    }
}

static void test_sheet_positions(void** state) {
    (void)state;
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = 4;
    def.ny = 3;
    def.width = 2.0;
    def.height = 1.5;
    sb_mesh m;
    assert_int_equal(sb_mesh_generate_sheet(&def, &m, NULL), SB_OK);
    for (uint32_t row = 0; row < 3; row++) {
        for (uint32_t col = 0; col < 4; col++) {
            const double* p = m.positions + 3 * (row * 4 + col);
            TU_ASSERT_NEAR(p[0], col * 2.0 / 3.0, 1e-15);
            TU_ASSERT_NEAR(p[1], row * 0.75, 1e-15);
            assert_true(p[2] == 0.0);
        }
    }
    /* The far corner is exactly (width, height). */
    assert_true(m.positions[3 * 11] == 2.0 && m.positions[3 * 11 + 1] == 1.5);
    sb_mesh_free(&m);
}

/* Every triangle faces +z and the triangles tile the rectangle exactly. */
static void assert_sheet_tiles(const sb_sheet_def* def) {
    sb_mesh m;
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(def, &m, &err), SB_OK);
    double area = 0.0;
    for (uint32_t t = 0; t < m.triangle_count; t++) {
        double n[3];
        triangle_normal(&m, t, n);
        if (!(n[2] > 0.0)) {
            fail_msg("triangle %u faces -z (normal z %g)", t, n[2]);
        }
        TU_ASSERT_NEAR(n[0], 0.0, 0.0);
        TU_ASSERT_NEAR(n[1], 0.0, 0.0);
        area += 0.5 * n[2];
    }
    TU_ASSERT_NEAR(area, def->width * def->height, 1e-12 * def->width * def->height);
    sb_mesh_free(&m);
}

static void test_sheet_normals_up(void** state) {
    (void)state;
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = 9;
    def.ny = 6;
    def.width = 3.0;
    def.height = 0.5;
    assert_sheet_tiles(&def);
    def.jitter = 0.16; /* below 1/6: no triangle can fold over */
    def.seed = 12345;
    assert_sheet_tiles(&def);
}

static bool triangle_has_edge(const sb_mesh* m, uint32_t t, uint32_t a, uint32_t b) {
    const uint32_t* v = m->triangles + 3 * (size_t)t;
    bool has_a = v[0] == a || v[1] == a || v[2] == a;
    bool has_b = v[0] == b || v[1] == b || v[2] == b;
    return has_a && has_b;
}

static void test_sheet_checkerboard(void** state) {
    (void)state;
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = 4;
    def.ny = 3;
    sb_mesh m;
    assert_int_equal(sb_mesh_generate_sheet(&def, &m, NULL), SB_OK);
    /* Quads in row-major order, two triangles each. */
    for (uint32_t row = 0; row < 2; row++) {
        for (uint32_t col = 0; col < 3; col++) {
            uint32_t q = row * 3 + col;
            uint32_t a = row * 4 + col, b = a + 1, c = a + 4, d = c + 1;
            bool even = (row + col) % 2 == 0;
            uint32_t e0 = even ? a : b, e1 = even ? d : c;
            assert_true(triangle_has_edge(&m, 2 * q, e0, e1));
            assert_true(triangle_has_edge(&m, 2 * q + 1, e0, e1));
            assert_false(triangle_has_edge(&m, 2 * q, even ? b : a, even ? c : d));
        }
    }
    sb_mesh_free(&m);
}

static void test_sheet_jitter(void** state) {
    (void)state;
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = 12;
    def.ny = 8;
    def.width = 2.2;
    def.height = 0.7;
    def.jitter = 0.45;
    def.seed = 99;
    sb_mesh plain, a, b, c;
    sb_sheet_def flat = def;
    flat.jitter = 0.0;
    assert_int_equal(sb_mesh_generate_sheet(&flat, &plain, NULL), SB_OK);
    assert_int_equal(sb_mesh_generate_sheet(&def, &a, NULL), SB_OK);
    assert_int_equal(sb_mesh_generate_sheet(&def, &b, NULL), SB_OK);
    def.seed = 100;
    assert_int_equal(sb_mesh_generate_sheet(&def, &c, NULL), SB_OK);

    double dx = 2.2 / 11, dy = 0.7 / 7;
    double largest[2] = {0, 0};
    for (uint32_t row = 0; row < 8; row++) {
        for (uint32_t col = 0; col < 12; col++) {
            size_t v = row * 12 + col;
            const double *p = a.positions + 3 * v, *q = plain.positions + 3 * v;
            double ox = fabs(p[0] - q[0]), oy = fabs(p[1] - q[1]);
            assert_true(p[2] == 0.0);
            if (row == 0 || row == 7 || col == 0 || col == 11) {
                assert_true(ox == 0.0 && oy == 0.0); /* the boundary stays put */
            } else {
                TU_ASSERT_LE(ox, 0.45 * dx);
                TU_ASSERT_LE(oy, 0.45 * dy);
                largest[0] = fmax(largest[0], ox / dx);
                largest[1] = fmax(largest[1], oy / dy);
            }
        }
    }
    /* 60 interior vertices: the offsets use most of the allowed range. */
    assert_true(largest[0] > 0.3 && largest[1] > 0.3);
    /* Same seed, same bits; another seed, another mesh; same topology. */
    assert_memory_equal(a.positions, b.positions, 3 * a.vertex_count * sizeof(double));
    assert_memory_equal(a.triangles, plain.triangles, 3 * a.triangle_count * sizeof(uint32_t));
    assert_memory_not_equal(a.positions, c.positions, 3 * a.vertex_count * sizeof(double));
    sb_mesh_free(&plain);
    sb_mesh_free(&a);
    sb_mesh_free(&b);
    sb_mesh_free(&c);
}

static void expect_sheet_invalid(sb_sheet_def def, const char* needle) {
    sb_mesh m;
    memset(&m, 0xab, sizeof m);
    sb_error err;
    memset(&err, 0, sizeof err);
    assert_int_equal(sb_mesh_generate_sheet(&def, &m, &err), SB_ERR_INVALID);
    assert_true(mesh_is_zeroed(&m));
    TU_ASSERT_CONTAINS(err.message, needle);
    assert_int_equal(sb_mesh_generate_sheet(&def, &m, NULL), SB_ERR_INVALID);
}

static void test_sheet_invalid(void** state) {
    (void)state;
    sb_sheet_def d = sb_default_sheet_def();
    d.nx = 1;
    expect_sheet_invalid(d, "nx and ny");
    d = sb_default_sheet_def();
    d.ny = 0;
    expect_sheet_invalid(d, "nx and ny");
    d = sb_default_sheet_def();
    d.width = 0.0;
    expect_sheet_invalid(d, "width and height");
    d = sb_default_sheet_def();
    d.height = NAN;
    expect_sheet_invalid(d, "width and height");
    d = sb_default_sheet_def();
    d.width = INFINITY;
    expect_sheet_invalid(d, "width and height");
    d = sb_default_sheet_def();
    d.jitter = 0.5;
    expect_sheet_invalid(d, "jitter");
    d = sb_default_sheet_def();
    d.jitter = -0.01;
    expect_sheet_invalid(d, "jitter");
    d = sb_default_sheet_def();
    d.jitter = NAN;
    expect_sheet_invalid(d, "jitter");
    d = sb_default_sheet_def();
    d.nx = 70000;
    d.ny = 70000;
    expect_sheet_invalid(d, "2^32-1");
}

/* ---- icosphere ----------------------------------------------------------- */

typedef struct directed_edge {
    uint32_t a, b;
} directed_edge;

static int compare_edges(const void* x, const void* y) {
    const directed_edge *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    return 0;
}

static bool edge_present(const directed_edge* edges, size_t n, uint32_t a, uint32_t b) {
    directed_edge key = {a, b};
    return bsearch(&key, edges, n, sizeof key, compare_edges) != NULL;
}

/* Closed and consistently oriented: each directed edge once, and its
 * reverse once, so every undirected edge lies in exactly two triangles.
 * Returns the number of undirected edges. */
static size_t assert_closed(const sb_mesh* m) {
    size_t n = 3 * (size_t)m->triangle_count;
    directed_edge* edges = malloc(n * sizeof *edges);
    assert_non_null(edges);
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        for (int c = 0; c < 3; c++) {
            edges[3 * t + c].a = m->triangles[3 * t + c];
            edges[3 * t + c].b = m->triangles[3 * t + (c + 1) % 3];
        }
    }
    qsort(edges, n, sizeof *edges, compare_edges);
    for (size_t i = 0; i < n; i++) {
        if (i > 0 && compare_edges(&edges[i - 1], &edges[i]) == 0) {
            fail_msg("directed edge %u->%u appears twice", edges[i].a, edges[i].b);
        }
        if (!edge_present(edges, n, edges[i].b, edges[i].a)) {
            fail_msg("edge %u-%u is on the boundary", edges[i].a, edges[i].b);
        }
    }
    free(edges);
    return n / 2;
}

static void test_icosphere_counts(void** state) {
    (void)state;
    for (uint32_t s = 0; s <= 5; s++) {
        sb_mesh m;
        sb_error err;
        assert_int_equal(sb_mesh_generate_icosphere(s, 1.0, &m, &err), SB_OK);
        uint32_t p = 1u << (2 * s);
        assert_int_equal(m.vertex_count, 10 * p + 2);
        assert_int_equal(m.triangle_count, 20 * p);
        assert_indices_in_range(&m);
        sb_mesh_free(&m);
    }
}

static void test_icosphere_geometry(void** state) {
    (void)state;
    const double radius = 2.5;
    for (uint32_t s = 0; s <= 3; s++) {
        sb_mesh m;
        assert_int_equal(sb_mesh_generate_icosphere(s, radius, &m, NULL), SB_OK);
        for (uint32_t v = 0; v < m.vertex_count; v++) {
            TU_ASSERT_NEAR(tu_norm(m.positions + 3 * v), radius, 1e-13 * radius);
        }
        for (uint32_t t = 0; t < m.triangle_count; t++) {
            double n[3], centroid[3] = {0, 0, 0};
            triangle_normal(&m, t, n);
            for (int c = 0; c < 3; c++) {
                for (int k = 0; k < 3; k++) {
                    centroid[k] += m.positions[3 * m.triangles[3 * t + c] + k] / 3.0;
                }
            }
            /* Outward and nearly radial: the cosine is close to 1. */
            double cosine = tu_dot(n, centroid) / (tu_norm(n) * tu_norm(centroid));
            if (!(cosine > 0.9)) {
                fail_msg("s=%u triangle %u: normal . centroid cosine %g", s, t, cosine);
            }
        }
        size_t edges = assert_closed(&m);
        assert_int_equal(edges, 3 * (size_t)m.triangle_count / 2);
        long euler = (long)m.vertex_count - (long)edges + (long)m.triangle_count;
        assert_int_equal(euler, 2);
        /* No two vertices coincide. */
        double shortest = INFINITY;
        for (size_t e = 0; e < 3 * (size_t)m.triangle_count; e++) {
            uint32_t a = m.triangles[e], b = m.triangles[e % 3 == 2 ? e - 2 : e + 1];
            shortest = fmin(shortest, tu_dist(m.positions + 3 * a, m.positions + 3 * b));
        }
        assert_true(shortest > 0.5 * radius / (1 << s));
        sb_mesh_free(&m);
    }
}

static void test_icosphere_large(void** state) {
    (void)state;
    sb_mesh m;
    assert_int_equal(sb_mesh_generate_icosphere(8, 1.0, &m, NULL), SB_OK);
    assert_int_equal(m.vertex_count, 655362);
    assert_int_equal(m.triangle_count, 1310720);
    sb_mesh_free(&m);
}

static void test_icosphere_invalid(void** state) {
    (void)state;
    sb_mesh m;
    sb_error err;
    assert_int_equal(sb_mesh_generate_icosphere(11, 1.0, &m, &err), SB_ERR_INVALID);
    TU_ASSERT_CONTAINS(err.message, "subdivisions");
    assert_true(mesh_is_zeroed(&m));
    const double radii[] = {0.0, -1.0, NAN, INFINITY};
    for (size_t i = 0; i < 4; i++) {
        assert_int_equal(sb_mesh_generate_icosphere(1, radii[i], &m, &err), SB_ERR_INVALID);
        TU_ASSERT_CONTAINS(err.message, "radius");
        assert_true(mesh_is_zeroed(&m));
    }
    assert_int_equal(sb_mesh_generate_icosphere(1, 0.0, &m, NULL), SB_ERR_INVALID);
}

/* ---- OBJ ----------------------------------------------------------------- */

static void test_obj_read(void** state) {
    (void)state;
    const char* path = write_file("shapes.obj", "# a comment\n"
                                                "mtllib shapes.mtl\n"
                                                "o square\n"
                                                "v 0 0 0\n"
                                                "v 1 0 0 1.0\n"
                                                "v 1 1 0\r\n"
                                                "v 0 1 0 # trailing comment\n"
                                                "vt 0 0\nvt 1 0\nvt 1 1\n"
                                                "vn 0 0 1\n"
                                                "g quad\ns off\nusemtl red\n"
                                                "\n"
                                                "f 1 2 3 4\n"
                                                "v 0.5 0.5 -2.25e-1\n"
                                                "v 7 8 9\n"
                                                "f -4 -3 -2\n"
                                                "f 1/1 2/2 5/3\n"
                                                "f 2//1 3//1 5//1\n"
                                                "f\t3/3/1 4/1/1 5/2/1 6/1/1 1/1/1\n"
                                                "l 1 2\n");
    sb_mesh m;
    sb_error err;
    sb_status status = sb_mesh_load(path, &m, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    /* Vertex order and count kept, the unreferenced vertex 6 too. */
    assert_int_equal(m.vertex_count, 6);
    const double expected[6][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, -0.225}, {7, 8, 9}};
    for (int v = 0; v < 6; v++) {
        for (int k = 0; k < 3; k++) {
            assert_true(m.positions[3 * v + k] == expected[v][k]);
        }
    }
    assert_int_equal(m.triangle_count, 2 + 1 + 1 + 1 + 3);
    assert_triangle(&m, 0, 0, 1, 2); /* the quad, fanned from its first corner */
    assert_triangle(&m, 1, 0, 2, 3);
    assert_triangle(&m, 2, 2, 3, 4); /* -4 -3 -2 with 6 vertices defined */
    assert_triangle(&m, 3, 0, 1, 4);
    assert_triangle(&m, 4, 1, 2, 4);
    assert_triangle(&m, 5, 2, 3, 4); /* a pentagon: three triangles */
    assert_triangle(&m, 6, 2, 4, 5);
    assert_triangle(&m, 7, 2, 5, 0);
    sb_mesh_free(&m);
}

static void test_obj_extension_case(void** state) {
    (void)state;
    /* ".OBJ" is read by softbond's reader: the unused vertex stays. */
    const char* path = write_file("UPPER.OBJ", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nf 1 2 3\n");
    sb_mesh m;
    assert_int_equal(sb_mesh_load(path, &m, NULL), SB_OK);
    assert_int_equal(m.vertex_count, 4);
    assert_int_equal(m.triangle_count, 1);
    sb_mesh_free(&m);
}

typedef struct bad_file {
    const char* text;
    const char* where; /* ":LINE: " or ": " */
    const char* what;
} bad_file;

static void expect_parse_errors(const char* extension, const bad_file* cases, size_t count) {
    for (size_t i = 0; i < count; i++) {
        char name[64];
        snprintf(name, sizeof name, "bad%zu%s", i, extension);
        const char* path = write_file(name, cases[i].text);
        char prefix[400];
        snprintf(prefix, sizeof prefix, "%s%s", path, cases[i].where);
        sb_mesh m;
        memset(&m, 0xab, sizeof m);
        sb_error err;
        memset(&err, 0, sizeof err);
        sb_status status = sb_mesh_load(path, &m, &err);
        if (status != SB_ERR_PARSE) {
            fail_msg("case %zu (%s): status %d, message \"%s\"", i, cases[i].what, (int)status, err.message);
        }
        assert_true(mesh_is_zeroed(&m));
        if (strncmp(err.message, prefix, strlen(prefix)) != 0) {
            fail_msg("case %zu: expected \"%s...\", got \"%s\"", i, prefix, err.message);
        }
        TU_ASSERT_CONTAINS(err.message, cases[i].what);
        assert_null(strchr(err.message, '\n'));
        assert_int_equal(sb_mesh_load(path, &m, NULL), SB_ERR_PARSE);
    }
}

static void test_obj_errors(void** state) {
    (void)state;
    const char* tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    char texts[16][256];
    const char* bodies[] = {
        "v 0 0 zero\n", "f 1 2 7\n",    "f 0 1 2\n",       "f 1 2\n", "v 0 nan 0\n", "v 1e999 0 0\n",      "f -4 1 2\n",
        "f 1/ 2 3\n",   "f 1//x 2 3\n", "f 1/2/3/4 2 3\n", "v 1 2\n", "f a b c\n",   "# only a comment\n",
    };
    bad_file cases[] = {
        {NULL, ":4: ", "malformed number 'zero'"},
        {NULL, ":4: ", "vertex index 7 out of range (3 vertices"},
        {NULL, ":4: ", "vertex index 0 out of range"},
        {NULL, ":4: ", "face with 2 vertices"},
        {NULL, ":4: ", "non-finite coordinate 'nan'"},
        {NULL, ":4: ", "non-finite coordinate '1e999'"},
        {NULL, ":4: ", "vertex index -4 out of range"},
        {NULL, ":4: ", "malformed face vertex '1/'"},
        {NULL, ":4: ", "malformed face vertex '1//x'"},
        {NULL, ":4: ", "malformed face vertex '1/2/3/4'"},
        {NULL, ":4: ", "three coordinates"},
        {NULL, ":4: ", "malformed face vertex 'a'"},
        {NULL, ": ", "no triangles (3 vertices"},
    };
    size_t count = sizeof cases / sizeof cases[0];
    for (size_t i = 0; i < count; i++) {
        snprintf(texts[i], sizeof texts[i], "%s%s", tri, bodies[i]);
        cases[i].text = texts[i];
    }
    expect_parse_errors(".obj", cases, count);
    /* A face before the vertex it names (line 1), and an empty file. */
    const bad_file more[] = {
        {"f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", ":1: ", "out of range (0 vertices"},
        {"", ": ", "no triangles (0 vertices"},
    };
    expect_parse_errors("_more.obj", more, 2);
}

/* ---- OFF ----------------------------------------------------------------- */

static void test_off_read(void** state) {
    (void)state;
    const char* path = write_file("shapes.off", "OFF # a square pyramid\n"
                                                "# counts follow\n"
                                                "\n"
                                                "5 3 0\n"
                                                "0 0 0\n"
                                                "1 0 0 255 0 0\n"
                                                "1 1 0\n"
                                                "0 1 0\r\n"
                                                "0.5 0.5 1.5e0\n"
                                                "4 0 3 2 1 0.5 0.5 0.5\n"
                                                "3 0 1 4\n"
                                                "3 1 2 4\n");
    sb_mesh m;
    sb_error err;
    sb_status status = sb_mesh_load(path, &m, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(m.vertex_count, 5);
    assert_true(m.positions[3 * 4 + 2] == 1.5 && m.positions[3 * 1] == 1.0);
    assert_int_equal(m.triangle_count, 4);
    assert_triangle(&m, 0, 0, 3, 2);
    assert_triangle(&m, 1, 0, 2, 1);
    assert_triangle(&m, 2, 0, 1, 4);
    assert_triangle(&m, 3, 1, 2, 4);
    sb_mesh_free(&m);

    /* Counts on the header line, a COFF header, an uppercase extension. */
    path = write_file("TRI.OFF", "COFF 3 1 3\n0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n0 1 0 1 1 1 1\n"
                                 "3 2 1 0\n");
    assert_int_equal(sb_mesh_load(path, &m, NULL), SB_OK);
    assert_int_equal(m.vertex_count, 3);
    assert_int_equal(m.triangle_count, 1);
    assert_triangle(&m, 0, 2, 1, 0);
    sb_mesh_free(&m);
}

static void test_off_errors(void** state) {
    (void)state;
    const bad_file cases[] = {
        {"PLY\n3 1 0\n", ":1: ", "expected the OFF header, found 'PLY'"},
        {"OFF\n3 x 0\n", ":2: ", "malformed count 'x'"},
        {"OFF\n3\n", ":2: ", "expected the counts"},
        {"OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n", ":4: ", "malformed number 'zero'"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 inf 0\n3 0 1 2\n", ":5: ", "non-finite coordinate 'inf'"},
        {"OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", ":4: ", "three coordinates"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", ":6: ", "vertex index 3 out of range"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", ":6: ", "vertex index -1 out of range"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", ":6: ", "face with 2 vertices"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", ":6: ", "face lists 3 of its 4"},
        {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 b\n", ":6: ", "malformed vertex index 'b'"},
        {"OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n", ":5: ", "file ends after 3 of 4 vertices"},
        {"OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", ":6: ", "file ends after 1 of 2 faces"},
        {"OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", ": ", "no triangles"},
        {"# nothing\n", ": ", "empty file"},
        {"4OFF\n3 1 0\n", ":1: ", "only 3-dimensional"},
        {"OFF BINARY\n", ":1: ", "binary OFF"},
    };
    expect_parse_errors(".off", cases, sizeof cases / sizeof cases[0]);
}

/* ---- assimp formats and missing files ------------------------------------ */

static void test_assimp_stl(void** state) {
    (void)state;
    /* A tetrahedron: 4 facets of 3 corners each, 4 distinct points. */
    const char* path = write_file("tetra.stl", "solid tetra\n"
                                               "facet normal 0 0 -1\nouter loop\n"
                                               "vertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\n"
                                               "endloop\nendfacet\n"
                                               "facet normal 0 -1 0\nouter loop\n"
                                               "vertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\n"
                                               "endloop\nendfacet\n"
                                               "facet normal -1 0 0\nouter loop\n"
                                               "vertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\n"
                                               "endloop\nendfacet\n"
                                               "facet normal 1 1 1\nouter loop\n"
                                               "vertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\n"
                                               "endloop\nendfacet\n"
                                               "endsolid tetra\n");
    sb_mesh m;
    sb_error err;
    sb_status status = sb_mesh_load(path, &m, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(m.vertex_count, 4);
    assert_int_equal(m.triangle_count, 4);
    assert_indices_in_range(&m);
    size_t edges = assert_closed(&m);
    assert_int_equal(edges, 6);
    /* Outward: the normal points away from the centroid (0.25, 0.25, 0.25). */
    for (uint32_t t = 0; t < 4; t++) {
        double n[3], d[3];
        triangle_normal(&m, t, n);
        const double* a = m.positions + 3 * m.triangles[3 * t];
        for (int k = 0; k < 3; k++) d[k] = a[k] - 0.25;
        assert_true(tu_dot(n, d) > 0);
    }
    sb_mesh_free(&m);
}

/* An ASCII PLY's every token is checked before assimp
 * reads it, the message naming file:line. Before, a face index 'abc',
 * 'nan' or '1e3' dropped the face as degenerate (exit 0), '1,5' was read
 * as 1, NaN coordinates gave 'No meshes remaining'. */
static void assert_ply_refused(const char* vertices, const char* faces, const char* message) {
    char text[1024], name[32], expected[512];
    static int n = 0;
    snprintf(text, sizeof text,
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
             "element face 1\nproperty list uchar int vertex_indices\nend_header\n%s%s",
             vertices, faces);
    snprintf(name, sizeof name, "bad%d.ply", n++);
    const char* path = write_file(name, text);
    sb_mesh m;
    sb_error err;
    assert_int_equal(sb_mesh_load(path, &m, &err), SB_ERR_PARSE);
    snprintf(expected, sizeof expected, "%s:%s", path, message);
    if (strcmp(err.message, expected) != 0) fail_msg("expected '%s', got '%s'", expected, err.message);
}

static void test_ply_ascii_tokens_checked(void** state) {
    (void)state;
    const char* good = "0 0 0\n1 0 0\n0 1 0\n";
    assert_ply_refused(good, "3 0 1 abc\n", "13: face 0: 'abc' is not an integer (int)");
    assert_ply_refused(good, "3 0 1 nan\n", "13: face 0: 'nan' is not an integer (int)");
    assert_ply_refused(good, "3 0 1 1e3\n", "13: face 0: '1e3' is not an integer (int)");
    assert_ply_refused(good, "3 0 1 3\n", "13: face 0: vertex index 3, but there are 3 vertices");
    assert_ply_refused(good, "3 0 1\n", "13: face 0: too few values on the line");
    assert_ply_refused(good, "3 0 1 2 7\n", "13: face 0: more values on the line than its 1 properties");
    assert_ply_refused(good, "300 0 1 2\n", "13: face 0: 300 is out of uchar's range");
    assert_ply_refused("0 0 0\n1,5 0 0\n0 1 0\n", "3 0 1 2\n", "11: vertex 1: '1,5' is not a finite number (float)");
    assert_ply_refused("0 0 0\n1 0 0\nnan nan nan\n", "3 0 1 2\n", "12: vertex 2: 'nan' is not a finite number (float)");
    assert_ply_refused("0 0 0\n1 0 0\n0 1 0\n", "\n\n\n", "16: ends at face 0 of the 1 declared");
    assert_ply_refused(good, "3 0 1 2\n3 0 1 2\n", "14: a line after the 3 'vertex', 1 'face' the header declares");
    /* and a good one still loads */
    const char* path = write_file("good.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                              "property float y\nproperty float z\nelement face 1\n"
                                              "property list uchar int vertex_indices\nend_header\n"
                                              "0 0 0\n1.5e-1 0 0\n0 -1 0\n3 0 1 2\n");
    sb_mesh m;
    sb_error err;
    if (sb_mesh_load(path, &m, &err) != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(m.triangle_count, 1);
    sb_mesh_free(&m);
}

static void test_assimp_ply(void** state) {
    (void)state;
    /* A square of two quads sharing an edge, and a lone point face-less. */
    const char* path = write_file("strip.ply", "ply\nformat ascii 1.0\n"
                                               "element vertex 6\n"
                                               "property float x\nproperty float y\nproperty float z\n"
                                               "element face 2\n"
                                               "property list uchar int vertex_indices\n"
                                               "end_header\n"
                                               "0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n"
                                               "4 0 1 4 3\n"
                                               "4 1 2 5 4\n");
    sb_mesh m;
    sb_error err;
    sb_status status = sb_mesh_load(path, &m, &err);
    if (status != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(m.vertex_count, 6);
    assert_int_equal(m.triangle_count, 4);
    assert_indices_in_range(&m);
    double area = 0.0;
    for (uint32_t t = 0; t < 4; t++) {
        double n[3];
        triangle_normal(&m, t, n);
        assert_true(n[2] > 0);
        area += 0.5 * n[2];
    }
    TU_ASSERT_NEAR(area, 2.0, 1e-6);
    sb_mesh_free(&m);
}

static void test_assimp_errors(void** state) {
    (void)state;
    const char* path = write_file("garbage.stl", "this is not a mesh at all\n");
    sb_mesh m;
    memset(&m, 0xab, sizeof m);
    sb_error err;
    assert_int_equal(sb_mesh_load(path, &m, &err), SB_ERR_PARSE);
    assert_true(mesh_is_zeroed(&m));
    char prefix[400];
    snprintf(prefix, sizeof prefix, "%s: ", path);
    if (strncmp(err.message, prefix, strlen(prefix)) != 0 || strlen(err.message) <= strlen(prefix)) {
        fail_msg("expected \"%s<why>\", got \"%s\"", prefix, err.message);
    }
    assert_int_equal(sb_mesh_load(path, &m, NULL), SB_ERR_PARSE);
}

static void test_missing_file(void** state) {
    (void)state;
    const char* names[] = {"missing.obj", "missing.off", "missing.stl", "missing"};
    for (size_t i = 0; i < 4; i++) {
        char path[400];
        snprintf(path, sizeof path, "%s/%s", tmp_dir, names[i]);
        sb_mesh m;
        memset(&m, 0xab, sizeof m);
        sb_error err;
        assert_int_equal(sb_mesh_load(path, &m, &err), SB_ERR_IO);
        assert_true(mesh_is_zeroed(&m));
        char expected[512];
        snprintf(expected, sizeof expected, "%s: cannot open: %s", path, strerror(ENOENT));
        assert_string_equal(err.message, expected);
        assert_int_equal(sb_mesh_load(path, &m, NULL), SB_ERR_IO);
    }
    /* A directory cannot be read as a mesh either. */
    sb_mesh m;
    sb_error err;
    char dir_obj[400];
    snprintf(dir_obj, sizeof dir_obj, "%s/folder.obj", tmp_dir);
    assert_int_equal(mkdir_for_test(dir_obj), 0);
    assert_int_equal(sb_mesh_load(dir_obj, &m, &err), SB_ERR_IO);
    TU_ASSERT_CONTAINS(err.message, dir_obj);
    assert_true(mesh_is_zeroed(&m));
}

static void test_free_zeroed(void** state) {
    (void)state;
    sb_mesh m;
    memset(&m, 0, sizeof m);
    sb_mesh_free(&m);
    sb_mesh_free(NULL);
    assert_true(mesh_is_zeroed(&m));
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sheet_default_def),  cmocka_unit_test(test_sheet_counts),
        cmocka_unit_test(test_sheet_positions),    cmocka_unit_test(test_sheet_normals_up),
        cmocka_unit_test(test_sheet_checkerboard), cmocka_unit_test(test_sheet_jitter),
        cmocka_unit_test(test_sheet_invalid),      cmocka_unit_test(test_icosphere_counts),
        cmocka_unit_test(test_icosphere_geometry), cmocka_unit_test(test_icosphere_large),
        cmocka_unit_test(test_icosphere_invalid),  cmocka_unit_test(test_obj_read),
        cmocka_unit_test(test_obj_extension_case), cmocka_unit_test(test_obj_errors),
        cmocka_unit_test(test_off_read),           cmocka_unit_test(test_off_errors),
        cmocka_unit_test(test_assimp_stl),         cmocka_unit_test(test_assimp_ply),
        cmocka_unit_test(test_ply_ascii_tokens_checked),
        cmocka_unit_test(test_assimp_errors),      cmocka_unit_test(test_missing_file),
        cmocka_unit_test(test_free_zeroed),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
