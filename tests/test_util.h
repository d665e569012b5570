/* Shared helpers for the cmocka tests: small models built by hand through
 * the public builder API, a deterministic random generator, vector helpers
 * and assertions on doubles that print both sides when they fail. */
#ifndef SB_TEST_UTIL_H
#define SB_TEST_UTIL_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>

#include "softbond/softbond.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* cmocka's run of the group `tests`, only its cases whose names match
 * SB_TEST_FILTER (cmocka's pattern: * and ?) when that is set:
 * tests/CMakeLists.txt gives the thread sanitizer only a program's cases
 * that run threads. */
#define TU_RUN_TESTS(tests)                                                                                            \
    (getenv("SB_TEST_FILTER") ? cmocka_set_test_filter(getenv("SB_TEST_FILTER")) : (void)0,                            \
     cmocka_run_group_tests(tests, NULL, NULL))

/* 1 in the builds with a sanitizer (tests/CMakeLists.txt): a test may
 * leave out there a repeat that only needs checking once (it says which). */
#ifndef SB_TEST_SANITIZED
#define SB_TEST_SANITIZED 0
#endif

/* The rounding unit of the solver's state (float by default). */
#define TU_REAL_EPS ((double)(sizeof(sb_real) == sizeof(float) ? FLT_EPSILON : DBL_EPSILON))

/* a <= b, printing both values (cmocka's float asserts round to float). */
#define TU_ASSERT_LE(a, b)                                                                                             \
    do {                                                                                                               \
        double tu_a_ = (a), tu_b_ = (b);                                                                               \
        if (!(tu_a_ <= tu_b_)) fail_msg("expected %s <= %s, got %.17g > %.17g", #a, #b, tu_a_, tu_b_);                 \
    } while (0)

/* |a - b| <= tol, printing the values. */
#define TU_ASSERT_NEAR(a, b, tol)                                                                                      \
    do {                                                                                                               \
        double tu_a_ = (a), tu_b_ = (b), tu_t_ = (tol);                                                                \
        if (!(fabs(tu_a_ - tu_b_) <= tu_t_))                                                                           \
            fail_msg("expected %s ~= %s within %.3g, got %.17g vs %.17g (diff %.3g)", #a, #b, tu_t_, tu_a_, tu_b_,     \
                     fabs(tu_a_ - tu_b_));                                                                             \
    } while (0)

/* The message contains the substring. */
#define TU_ASSERT_CONTAINS(message, needle)                                                                            \
    do {                                                                                                               \
        const char* tu_m_ = (message);                                                                                 \
        if (!tu_m_ || !strstr(tu_m_, (needle)))                                                                        \
            fail_msg("expected message to contain \"%s\", got \"%s\"", (needle), tu_m_ ? tu_m_ : "(null)");            \
    } while (0)

/* ---- random numbers: splitmix64, deterministic across platforms ---------- */

typedef struct tu_rng {
    uint64_t s;
} tu_rng;

static inline uint64_t tu_next(tu_rng* r) {
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Uniform in [lo, hi). */
static inline double tu_uniform(tu_rng* r, double lo, double hi) {
    return lo + (hi - lo) * (double)(tu_next(r) >> 11) * (1.0 / 9007199254740992.0);
}

/* ---- vectors -------------------------------------------------------------- */

static inline double tu_dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline double tu_norm(const double a[3]) { return sqrt(tu_dot(a, a)); }
static inline void tu_cross(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}
static inline double tu_dist(const double* a, const double* b) {
    double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    return tu_norm(d);
}
static inline double tu_max_abs(const double* v, size_t n) {
    double m = 0.0;
    for (size_t i = 0; i < n; ++i)
        if (fabs(v[i]) > m) m = fabs(v[i]);
    return m;
}
static inline bool tu_all_finite(const double* v, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(v[i])) return false;
    return true;
}

/* ---- building models by hand --------------------------------------------- */

static inline int64_t tu_vertex(sb_builder* b, double x, double y, double z, double mass, bool fixed) {
    sb_vertex_def v = sb_default_vertex_def();
    v.position[0] = x;
    v.position[1] = y;
    v.position[2] = z;
    v.velocity[0] = v.velocity[1] = v.velocity[2] = 0.0;
    v.mass = mass;
    v.fixed = fixed;
    return sb_builder_add_vertex(b, &v);
}

/* rest_length < 0: the current distance. */
static inline int64_t tu_bond(sb_builder* b, uint32_t i, uint32_t j, double rest_length, double k, double spring_k,
                              double spring_damping) {
    sb_bond_def d = sb_default_bond_def();
    d.i = i;
    d.j = j;
    d.rest_length = rest_length;
    d.k = k;
    d.spring_k = spring_k;
    d.spring_damping = spring_damping;
    return sb_builder_add_bond(b, &d);
}

static inline int64_t tu_triangle(sb_builder* b, uint32_t i, uint32_t j, uint32_t k, double angle_k,
                                  double stretch_bend_k) {
    sb_triangle_def d = sb_default_triangle_def();
    d.i = i;
    d.j = j;
    d.k = k;
    d.angle_k = angle_k;
    d.stretch_bend_k = stretch_bend_k;
    return sb_builder_add_triangle(b, &d);
}

static inline int64_t tu_hinge(sb_builder* b, uint32_t e0, uint32_t e1, uint32_t o0, uint32_t o1, double k) {
    sb_hinge_def d;
    memset(&d, 0, sizeof d);
    d.e0 = e0;
    d.e1 = e1;
    d.o0 = o0;
    d.o1 = o1;
    d.k = k;
    return sb_builder_add_hinge(b, &d);
}

/* Compiles and fails the test (with the library's message) on error. */
static inline sb_model* tu_compile(const sb_builder* b) {
    sb_error err;
    memset(&err, 0, sizeof err);
    sb_model* m = sb_builder_compile(b, &err);
    if (!m) fail_msg("sb_builder_compile failed: %s", err.message);
    return m;
}

/* Expects the compile to fail and returns the message (static storage). */
static inline const char* tu_compile_fails(const sb_builder* b) {
    static sb_error err;
    memset(&err, 0, sizeof err);
    sb_model* m = sb_builder_compile(b, &err);
    if (m) {
        sb_model_destroy(m);
        fail_msg("sb_builder_compile succeeded where it should have failed");
    }
    if (err.message[0] == '\0') fail_msg("sb_builder_compile failed with an empty message");
    return err.message;
}

/* The model of a mesh with one material, failing the test with the
 * library's message when it cannot be built. */
static inline sb_model* tu_mesh_model(const sb_mesh* mesh, const sb_material_def* material) {
    sb_error err;
    sb_builder* b = sb_builder_create();
    if (sb_builder_add_mesh(b, mesh, material, &err) != SB_OK) fail_msg("sb_builder_add_mesh: %s", err.message);
    sb_model* m = sb_builder_compile(b, &err);
    sb_builder_destroy(b);
    if (!m) fail_msg("sb_builder_compile: %s", err.message);
    return m;
}

/* A jittered side × side sheet with every term (stretch-bend included) and
 * damped springs, vertex 0 fixed and, with `two_pins`, vertex side − 1 too
 * (the two corners of its first row): vbd's tests' sheet. */
static inline sb_model* tu_every_term_sheet(uint32_t side, bool two_pins) {
    sb_mesh mesh = {0};
    sb_error err;
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = side;
    sheet.jitter = 0.15;
    if (sb_mesh_generate_sheet(&sheet, &mesh, &err) != SB_OK) fail_msg("sb_mesh_generate_sheet: %s", err.message);
    sb_material_def material = sb_default_material_def();
    material.bond_k = 50.0;
    material.angle_k = 0.3;
    material.stretch_bend_k = 1.0;
    material.spring_k = 20.0;
    material.spring_damping = 0.05;
    material.bend_k = 0.01;
    sb_builder* b = sb_builder_create();
    if (sb_builder_add_mesh(b, &mesh, &material, &err) != SB_OK) fail_msg("sb_builder_add_mesh: %s", err.message);
    sb_builder_vertex(b, 0)->fixed = true;
    if (two_pins) sb_builder_vertex(b, side - 1)->fixed = true;
    sb_model* m = sb_builder_compile(b, &err);
    sb_builder_destroy(b);
    sb_mesh_free(&mesh);
    if (!m) fail_msg("sb_builder_compile: %s", err.message);
    return m;
}

/* An nx × ny × nz block of cubes of side h from the origin, each cut into
 * six co-rotated tetrahedra around its diagonal (Kuhn's, conforming), E and
 * ν, each vertex a mass of ρ h³ (ρ = 1060 kg/m³), the rest positions
 * jittered by up to `jitter` h (seeded); the vertices at x = 0 fixed when
 * `clamped`. */
static inline sb_model* tu_tet_block(int nx, int ny, int nz, double h, double young, double poisson, double jitter,
                                     uint64_t seed, bool clamped) {
    static const int kuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
    tu_rng rng = {seed * 6364136223846793005ull + 1442695040888963407ull};
    sb_builder* b = sb_builder_create();
    for (int k = 0; k <= nz; k++)
        for (int j = 0; j <= ny; j++)
            for (int i = 0; i <= nx; i++) {
                double d[3];
                for (int a = 0; a < 3; a++) d[a] = jitter * h * tu_uniform(&rng, -1, 1);
                tu_vertex(b, i * h + d[0], j * h + d[1], k * h + d[2], 1060.0 * h * h * h, clamped && i == 0);
            }
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++)
                for (int t = 0; t < 6; t++) {
                    sb_tet_def d;
                    memset(&d, 0, sizeof d);
                    for (int c = 0; c < 4; c++) {
                        int corner = kuhn[t][c];
                        int ci = i + (corner & 1), cj = j + (corner >> 1 & 1), ck = k + (corner >> 2 & 1);
                        d.v[c] = (uint32_t)((ck * (ny + 1) + cj) * (nx + 1) + ci);
                    }
                    d.young_modulus = young;
                    d.poisson_ratio = poisson;
                    if (sb_builder_add_tet(b, &d) < 0) fail_msg("sb_builder_add_tet failed");
                }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

/* Rest positions of a model as 3n interleaved doubles (caller frees). */
static inline double* tu_rest_positions(const sb_model* m) {
    uint32_t n = sb_model_vertex_count(m);
    double* p = (double*)malloc(sizeof(double) * 3 * (n ? n : 1));
    for (uint32_t v = 0; v < n; ++v) sb_model_rest_position(m, v, p + 3 * v);
    return p;
}

/* tu_tet_block's block (the same jittered vertices and tetrahedra) as a
 * tissue of the given model (sb_builder_add_tet_mesh: for
 * SB_TISSUE_COROTATED_QUADRATIC a vertex at each edge's middle, HRZ masses
 * of ρ = 1060 kg/m³), undamped; when `clamped`, the vertices at x = 0 (and the
 * middles between them) fixed (jitter at most 0.2). */
static inline sb_model* tu_tissue_tet_block(int nx, int ny, int nz, double h, double young, double poisson,
                                            double jitter, uint64_t seed, bool clamped, sb_tissue_model model) {
    sb_model* linear = tu_tet_block(nx, ny, nz, h, young, poisson, jitter, seed, false);
    static const int kuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
    uint32_t corners = sb_model_vertex_count(linear);
    sb_tet_mesh mesh = {corners, tu_rest_positions(linear), (uint32_t)(6 * nx * ny * nz), NULL};
    sb_model_destroy(linear);
    mesh.tets = (uint32_t*)malloc(4 * sizeof(uint32_t) * mesh.tet_count);
    uint32_t* v = mesh.tets;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++)
                for (int t = 0; t < 6; t++)
                    for (int c = 0; c < 4; c++) {
                        int corner = kuhn[t][c];
                        int ci = i + (corner & 1), cj = j + (corner >> 1 & 1), ck = k + (corner >> 2 & 1);
                        *v++ = (uint32_t)((ck * (ny + 1) + cj) * (nx + 1) + ci);
                    }
    for (uint32_t t = 0; t < mesh.tet_count; t++) { /* Kuhn's six alternate in orientation: all positive */
        uint32_t* c = mesh.tets + 4 * t;
        const double* p = mesh.positions;
        if (sb_tet_volume(p + 3 * c[0], p + 3 * c[1], p + 3 * c[2], p + 3 * c[3]) < 0.0) {
            uint32_t swap = c[2];
            c[2] = c[3];
            c[3] = swap;
        }
    }
    sb_tissue_def tissue = sb_default_tissue_def();
    tissue.young_modulus = young;
    tissue.poisson_ratio = poisson;
    tissue.model = model;
    tissue.damping = 0.0; /* the springs' damping rule off: it needs a far smaller step */
    sb_builder* b = sb_builder_create();
    sb_error err;
    memset(&err, 0, sizeof err);
    if (sb_builder_add_tet_mesh(b, &mesh, &tissue, &err) != SB_OK) fail_msg("sb_builder_add_tet_mesh: %s", err.message);
    for (uint32_t i = 0; clamped && i < sb_builder_vertex_count(b); i++)
        sb_builder_vertex(b, i)->fixed = sb_builder_vertex(b, i)->position[0] < 0.3 * h;
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    sb_tet_mesh_free(&mesh);
    return m;
}

/* tu_tissue_tet_block's quadratic tissue. */
static inline sb_model* tu_quadratic_tet_block(int nx, int ny, int nz, double h, double young, double poisson,
                                               double jitter, uint64_t seed, bool clamped) {
    return tu_tissue_tet_block(nx, ny, nz, h, young, poisson, jitter, seed, clamped, SB_TISSUE_COROTATED_QUADRATIC);
}

/* ---- solvers -------------------------------------------------------------- */

/* A solver, failing the test (with the library's message) when it cannot be made. */
static inline sb_solver* tu_solver(const sb_model* m, const sb_solver_def* def) {
    sb_error err;
    memset(&err, 0, sizeof err);
    sb_solver* s = sb_solver_create(m, def, &err);
    if (!s) fail_msg("sb_solver_create failed: %s", err.message);
    return s;
}

/* `steps` steps of dt, failing the test at the first that does not succeed. */
static inline void tu_advance(sb_solver* s, double dt, uint64_t steps) {
    for (uint64_t i = 0; i < steps; ++i) {
        sb_status st = sb_solver_advance(s, dt);
        if (st != SB_OK)
            fail_msg("step %llu failed (%s): %s", (unsigned long long)i, sb_status_name(st), sb_solver_error(s));
    }
}

/* FNV-1a over the bytes of the positions and velocities (3n doubles each,
 * exact copies of the solver's sb_real values): equal hashes, bitwise equal
 * states. */
static inline uint64_t tu_state_hash(const sb_solver* solver) {
    size_t n = 3 * (size_t)sb_solver_vertex_count(solver); /* a tearing solver's copies included */
    double* values = malloc(2 * (n ? n : 1) * sizeof *values);
    assert_non_null(values);
    sb_solver_get_positions(solver, values);
    sb_solver_get_velocities(solver, values + n);
    uint64_t h = 1469598103934665603ull;
    const unsigned char* bytes = (const unsigned char*)values;
    for (size_t b = 0; b < 2 * n * sizeof *values; b++) h = (h ^ bytes[b]) * 1099511628211ull;
    free(values);
    return h;
}

/* The total mass and momentum of a solver's vertices in use. */
static inline void tu_mass_momentum(const sb_solver* s, double* mass, double momentum[3]) {
    uint32_t n = sb_solver_vertex_count(s);
    double* v = malloc(3 * (size_t)sb_solver_vertex_capacity(s) * sizeof *v);
    double* w = malloc((size_t)sb_solver_vertex_capacity(s) * sizeof *w);
    sb_solver_get_velocities(s, v);
    sb_solver_get_masses(s, w);
    *mass = momentum[0] = momentum[1] = momentum[2] = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        *mass += w[i];
        for (int a = 0; a < 3; a++) momentum[a] += w[i] * v[3 * i + a];
    }
    free(v);
    free(w);
}

/* Sets every vertex in use moving: a drift along x, a spin of 2 rad/s
 * about the vertical through (cx, cy), and a vertical wobble of amplitude
 * `wobble` (m/s) and wavenumber k (1/m) along x. */
static inline void tu_set_spin(sb_solver* s, double cx, double cy, double drift, double wobble, double k) {
    uint32_t n = sb_solver_vertex_capacity(s);
    double* x = calloc(3 * (size_t)n, sizeof *x);
    double* v = calloc(3 * (size_t)n, sizeof *v);
    sb_solver_get_positions(s, x);
    for (uint32_t i = 0; i < sb_solver_vertex_count(s); i++) {
        v[3 * i] = drift - 2.0 * (x[3 * i + 1] - cy);
        v[3 * i + 1] = 2.0 * (x[3 * i] - cx);
        v[3 * i + 2] = wobble * sin(k * x[3 * i]);
    }
    assert_int_equal(sb_solver_set_state(s, x, v), SB_OK);
    free(x);
    free(v);
}

#endif
