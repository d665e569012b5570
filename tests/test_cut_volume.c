/* Cutting through tetrahedra (sb_solver_def.cut_through on a body of
 * linear co-rotated tetrahedra, kernels/interaction/cut_volume.c): a
 * blade's edge, longer than a 6 × 6 × 3-cell block of Kuhn tetrahedra is
 * thick, carried straight across it sweeps a plane; it leaves exactly two
 * pieces, one on each side of that plane, every vertex of the cut faces
 * (the pieces' boundary faces off the block's outer surface) within 5 % of
 * a cell of the plane, and no tetrahedron of negative or near-zero volume —
 * at two mesh resolutions and with the plane along the mesh's planes and
 * at 30 degrees to them. The oracle is the blade's plane itself (a cut
 * along the mesh's faces would leave a staircase up to a cell off it). A
 * cut through a drifting, spinning block keeps its mass and momentum to
 * rounding at every step; the same cut with 1, 2 and 3 threads is the same
 * bitwise, and a checkpoint taken half way restarts bitwise — each on the
 * reference kernels and on the fast ones; the models it cannot cut
 * through are refused naming what it needs. */
#define _POSIX_C_SOURCE 200809L
#include "test_util.h"
#include "cut_setups.h"
#include "kernels/state/solver_data.h"
#include "kernels/interaction/breakage.h"
#include "kernels/interaction/cut_volume.h"
#include "mesh/model_internal.h"

#define SIZE_X 0.06 /* the block: 0.06 × 0.06 × 0.03 m from the origin */
#define SIZE_Z 0.03

/* The blade's plane: through (0.0303, 0.03, ·), its line in xy at `degrees` from the y axis. */
typedef struct cut_plane {
    double c[2], d[2];
} cut_plane;

static cut_plane plane_at(double degrees) {
    double a = degrees * M_PI / 180.0;
    return (cut_plane){{0.0303, 0.03}, {sin(a), cos(a)}};
}

/* Signed distance of x from the plane. */
static double off_plane(const cut_plane* l, const double* x) {
    return (x[0] - l->c[0]) * l->d[1] - (x[1] - l->c[1]) * l->d[0];
}

/* A vertical edge, 0.01 m past the block above and below, from 0.05 m
 * before the plane's centre along its line to 0.05 m past it in 0.02 s. */
static sb_blade_def plane_blade(const cut_plane* l, sb_keyframe path[2]) {
    sb_blade_def blade = {.a = {l->c[0] - 0.05 * l->d[0], l->c[1] - 0.05 * l->d[1], -0.01},
                          .b = {l->c[0] - 0.05 * l->d[0], l->c[1] - 0.05 * l->d[1], SIZE_Z + 0.01},
                          .path = path,
                          .path_count = 2};
    path[0] = (sb_keyframe){0.0, {0, 0, 0}, {0, 0, 0}};
    path[1] = (sb_keyframe){0.02, {0.1 * l->d[0], 0.1 * l->d[1], 0}, {0, 0, 0}};
    return blade;
}

static sb_solver_def cut_def(const sb_blade_def* blade, int threads, int k) {
    return cut_setup_def(blade, threads, k, 4000);
}

/* The block at `cells` per 0.03 m (3 or 6), liver-like (E 3500 Pa, ν 0.45). */
static sb_model* block(int cells, sb_tissue_model model) {
    double h = 0.03 / cells;
    return tu_tissue_tet_block(2 * cells, 2 * cells, cells, h, 3500.0, 0.45, 0.0, 1, false, model);
}

/* The step: a tenth of the element's explicit bound (h over the P wave's
 * 3.5 m/s), so that the thinnest elements the cut makes stay stable. */
static double step_for(int cells) { return 0.1 * (0.03 / cells) / 3.5 / 4.0; }

static uint32_t find(uint32_t* parent, uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

/* parent[] of the vertices joined by the live tetrahedra. */
static uint32_t* pieces(const sb_model* live, uint32_t n) {
    uint32_t* parent = malloc(n * sizeof *parent);
    for (uint32_t i = 0; i < n; i++) parent[i] = i;
    for (uint32_t t = 0; t < live->tet_count; t++)
        for (int c = 1; c < 4; c++) parent[find(parent, live->tet_v[c][t])] = find(parent, live->tet_v[0][t]);
    return parent;
}

/* Whether face f lies on the block's outer surface (all three corners on one side's plane). */
static bool outer_face(const sb_model* live, uint32_t f, const double* x) {
    const double box[3] = {SIZE_X, SIZE_X, SIZE_Z}, tol = 1e-6 * SIZE_Z;
    for (int a = 0; a < 3; a++)
        for (int side = 0; side < 2; side++) {
            bool all = true;
            for (int k = 0; k < 3; k++) all &= fabs(x[3 * (size_t)live->face_v[k][f] + a] - side * box[a]) < tol;
            if (all) return true;
        }
    return false;
}

static double tet_volume_at(const sb_model* live, uint32_t t, const double* x) {
    const double* p[4];
    for (int c = 0; c < 4; c++) p[c] = x + 3 * (size_t)live->tet_v[c][t];
    return sb_tet_volume(p[0], p[1], p[2], p[3]);
}

/* Tetrahedron t's shape: its volume over its longest edge cubed, as a
 * fraction of a Kuhn tetrahedron's (h³/6 over (√3 h)³): 0 for a sliver. */
static double tet_shape_at(const sb_model* live, uint32_t t, const double* x) {
    double longest = 0.0;
    for (int a = 0; a < 4; a++)
        for (int b = a + 1; b < 4; b++) {
            const double *p = x + 3 * (size_t)live->tet_v[a][t], *q = x + 3 * (size_t)live->tet_v[b][t];
            longest = fmax(longest, sqrt((q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                                         (q[2] - p[2]) * (q[2] - p[2])));
        }
    return tet_volume_at(live, t, x) / (longest * longest * longest) * (6.0 * 3.0 * sqrt(3.0));
}

/* Checks the cut of the block at `cells` along the plane at `degrees`. */
static void check_plane_cut(int cells, double degrees, int k) {
    sb_model* m = block(cells, SB_TISSUE_COROTATED);
    cut_plane l = plane_at(degrees);
    sb_keyframe path[2];
    sb_blade_def blade = plane_blade(&l, path);
    sb_solver_def def = cut_def(&blade, 1, k);
    sb_solver* s = tu_solver(m, &def);
    double dt = step_for(cells), cell = 0.03 / cells;
    tu_advance(s, dt, (uint64_t)ceil(0.022 / dt));
    const sb_model* live = sb_breakage_model(s->breakage);
    uint32_t n = sb_solver_vertex_count(s);
    double* x = malloc(3 * (size_t)sb_solver_vertex_capacity(s) * sizeof *x);
    sb_solver_get_positions(s, x);
    uint32_t* parent = pieces(live, n);
    uint32_t first = find(parent, live->tet_v[0][0]), second = UINT32_MAX;
    double side_sum[2] = {0.0, 0.0}, smallest = INFINITY, flattest = INFINITY;
    for (uint32_t t = 0; t < live->tet_count; t++) {
        uint32_t piece = find(parent, live->tet_v[0][t]);
        if (piece != first && second == UINT32_MAX) second = piece;
        assert_true(piece == first || piece == second); /* two pieces, no more */
        double centre[3] = {0, 0, 0};
        for (int c = 0; c < 4; c++)
            for (int a = 0; a < 3; a++) centre[a] += 0.25 * x[3 * (size_t)live->tet_v[c][t] + a];
        side_sum[piece != first] += off_plane(&l, centre);
        smallest = fmin(smallest, tet_volume_at(live, t, x));
        flattest = fmin(flattest, tet_shape_at(live, t, x));
    }
    double worst = 0.0;
    uint32_t cut_faces = 0;
    for (uint32_t f = 0; f < live->face_count; f++) {
        if (outer_face(live, f, x)) continue;
        cut_faces++;
        for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(off_plane(&l, x + 3 * (size_t)live->face_v[k][f])));
    }
    double cell_tet = cell * cell * cell / 6.0, through = SIZE_X / cos(degrees * M_PI / 180.0) * SIZE_Z;
    double cut_area = 0.0;
    for (uint32_t f = 0; f < live->face_count; f++) {
        if (outer_face(live, f, x)) continue;
        const double *a = x + 3 * (size_t)live->face_v[0][f], *b = x + 3 * (size_t)live->face_v[1][f],
                     *c = x + 3 * (size_t)live->face_v[2][f];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double w[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        cut_area += 0.5 * sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    print_message(
        "%s, %d cells deep, plane at %g degrees: %u vertices, %u tetrahedra, %u cut faces of %.4g m² (the "
        "plane crosses %.4g m², each side); cut faces' vertices at most %.3g cells off the plane; smallest "
        "tetrahedron %.3g of a cell's sixth, the flattest %.3g of a Kuhn one's shape; %u not made for want of room\n",
        setups[k].name, cells, degrees, n, live->tet_count, cut_faces, cut_area, through, worst / cell,
        smallest / cell_tet, flattest, sb_cut_volume_refused(sb_breakage_cut_volume(s->breakage)));
    assert_true(second != UINT32_MAX);
    assert_true(side_sum[0] * side_sum[1] < 0.0); /* the pieces on either side */
    assert_true(worst <= 0.05 * cell);
    assert_true(fabs(cut_area - 2.0 * through) < 1e-3 * through); /* the cut runs the whole plane, both sides */
    /* the snap distance δ (2.5 % of a vertex's longest edge, the cube's
     * diagonal: 4.3 % of a cell) bounds what a cut makes: a corner cut off
     * δ from its vertex, about δ³ of a cell's sixth, and the needle on a
     * prism's cap δ across, of shape about δ² */
    assert_true(smallest > 0.5 * pow(0.04, 3) * cell_tet);
    assert_true(flattest > 0.5 * pow(0.04, 2));
    free(parent);
    free(x);
    sb_solver_destroy(s);
    sb_model_destroy(m);
}

static void test_cut_follows_the_blades_plane(void** state) {
    (void)state;
    for (int k = 0; k < SETUPS; k++)
        for (int cells = 3; cells <= 6; cells += 3) {
            bool explicit_step = setups[k].integrator != SB_INTEGRATOR_IMPLICIT_EULER;
            if (!explicit_step && cells != 3) continue; /* implicit Euler's steps cost more: the coarse block */
            check_plane_cut(cells, 0.0, k);
            check_plane_cut(cells, 30.0, k);
        }
}

static void check_mass_and_momentum(int k) {
    sb_model* m = block(3, SB_TISSUE_COROTATED);
    cut_plane l = plane_at(30.0);
    sb_keyframe path[2];
    sb_blade_def blade = plane_blade(&l, path);
    sb_solver_def def = cut_def(&blade, 2, k);
    sb_solver* s = tu_solver(m, &def);
    tu_set_spin(s, 0.03, 0.03, 0.2, 0.05, 100.0);
    double mass0, p0[3], dt = step_for(3);
    tu_mass_momentum(s, &mass0, p0);
    double scale = mass0 * 0.3; /* kg m/s: the mass times the fastest speed */
    double worst_mass = 0.0, worst_momentum = 0.0;
    int steps = (int)ceil(0.022 / dt);
    for (int step = 0; step < steps; step++) {
        double mass, p[3];
        tu_advance(s, dt, 1);
        tu_mass_momentum(s, &mass, p);
        worst_mass = fmax(worst_mass, fabs(mass - mass0) / mass0);
        for (int a = 0; a < 3; a++) worst_momentum = fmax(worst_momentum, fabs(p[a] - p0[a]) / scale);
    }
    uint32_t made = sb_solver_vertex_count(s) - sb_model_vertex_count(m);
    print_message("%s: %u vertices made by the cut; mass off by at most %.3g of itself, momentum by %.3g of m v_max\n",
                  setups[k].name, made, worst_mass, worst_momentum);
    assert_true(made > 40);
    assert_true(worst_mass < 1e-12);
    /* implicit Euler's Newton stops at a residual of 1e-8 of its first (or
     * at rounding level), and what is left of it is momentum the step did
     * not balance; in float the matrix-free CG on the fast kernels stops at
     * the rounding floor of the stiff small tetrahedra the cut makes (2.2e-5
     * of m v here, against 5.8e-12 in a double build) */
    bool implicit = setups[k].integrator == SB_INTEGRATOR_IMPLICIT_EULER, single = sizeof(sb_real) == 4;
    assert_true(worst_momentum < (single ? (implicit ? 1e-4 : 1e-5) : (implicit ? 1e-9 : 1e-12)));
    sb_solver_destroy(s);
    sb_model_destroy(m);
}

static void test_cut_keeps_mass_and_momentum(void** state) {
    (void)state;
    for (int k = 0; k < SETUPS; k++) check_mass_and_momentum(k);
}

/* The positions and velocities after the cut with `threads` threads, from
 * a checkpoint taken at step `save_at` when it is positive; the vertex
 * count last. */
static double* cut_run(int threads, int save_at, int k, size_t* bytes) {
    sb_model* m = block(3, SB_TISSUE_COROTATED);
    cut_plane l = plane_at(30.0);
    sb_keyframe path[2];
    sb_blade_def blade = plane_blade(&l, path);
    sb_solver_def def = cut_def(&blade, threads, k);
    sb_solver* s = tu_solver(m, &def);
    tu_set_spin(s, 0.03, 0.03, 0.2, 0.05, 100.0);
    double dt = step_for(3);
    int steps = (int)ceil(0.022 / dt);
    if (save_at > 0) {
        tu_advance(s, dt, (uint64_t)save_at);
        size_t size = sb_solver_state_size(s);
        void* buffer = malloc(size);
        sb_error err;
        assert_int_equal(sb_solver_save_state(s, buffer, size, &err), SB_OK);
        sb_solver_destroy(s);
        s = tu_solver(m, &def);
        sb_status loaded = sb_solver_load_state(s, buffer, size, &err);
        if (loaded != SB_OK) print_message("%s\n", err.message);
        assert_int_equal(loaded, SB_OK);
        free(buffer);
    }
    tu_advance(s, dt, (uint64_t)(steps - (save_at > 0 ? save_at : 0)));
    size_t n = 3 * (size_t)sb_solver_vertex_capacity(s);
    double* out = calloc(2 * n + 1, sizeof *out);
    sb_solver_get_positions(s, out);
    sb_solver_get_velocities(s, out + n);
    out[2 * n] = sb_solver_vertex_count(s);
    *bytes = (2 * n + 1) * sizeof *out;
    sb_solver_destroy(s);
    sb_model_destroy(m);
    return out;
}

static void check_deterministic_and_restarts(int k) {
    size_t bytes, other_bytes;
    double* one = cut_run(1, 0, k, &bytes);
    for (int threads = 2; threads <= 3; threads++) {
        double* other = cut_run(threads, 0, k, &other_bytes);
        assert_int_equal(other_bytes, bytes);
        assert_memory_equal(one, other, bytes);
        free(other);
    }
    int half = (int)ceil(0.022 / step_for(3)) / 2; /* the blade in the block */
    double* resumed = cut_run(2, half, k, &other_bytes);
    assert_memory_equal(one, resumed, bytes);
    print_message("%s: %g vertices after the cut: the same with 1, 2 and 3 threads and from a checkpoint at step %d\n",
                  setups[k].name, one[bytes / sizeof(double) - 1], half);
    free(resumed);
    free(one);
}

static void test_cut_is_deterministic_and_restarts(void** state) {
    (void)state;
    for (int k = 0; k < SETUPS; k++) check_deterministic_and_restarts(k);
}

/* The quadratic tetrahedra and a volume of springs are refused, naming what is needed. */
static void test_cut_through_refused(void** state) {
    (void)state;
    cut_plane l = plane_at(0.0);
    sb_keyframe path[2];
    sb_blade_def blade = plane_blade(&l, path);
    struct {
        sb_tissue_model model;
        const char* expected;
    } cases[2] = {{SB_TISSUE_COROTATED_QUADRATIC, "needs linear tetrahedra"},
                  {SB_TISSUE_SPRINGS, "use tissue.model: corotated"}};
    for (int k = 0; k < 2; k++) {
        sb_model* m = block(3, cases[k].model);
        sb_solver_def def = cut_def(&blade, 1, 1);
        sb_error err;
        assert_null(sb_solver_create(m, &def, &err));
        print_message("%s\n", err.message);
        assert_non_null(strstr(err.message, cases[k].expected));
        sb_model_destroy(m);
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cut_follows_the_blades_plane),
        cmocka_unit_test(test_cut_keeps_mass_and_momentum),
        cmocka_unit_test(test_cut_is_deterministic_and_restarts),
        cmocka_unit_test(test_cut_through_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
