/* Cutting through triangles (sb_solver_def.cut_through,
 * kernels/interaction/cut_mesh.c): a blade's edge, square to a jittered
 * sheet at rest, carried straight across it, leaves exactly two pieces,
 * one on each side of its line, whose cut edges (the pieces' border edges
 * off the sheet's outline) lie within 5 % of a cell of that line — at
 * three mesh resolutions and with the line along the mesh's columns and
 * at 30 degrees to them — and run the sheet's whole width along it on
 * each side. The oracle is the blade's line itself (cutting along the
 * mesh's edges leaves them up to a cell off it). A cut through a moving,
 * spinning sheet keeps its mass and momentum to rounding at every step;
 * the same cut with 1, 2 and 3 threads is the same bitwise, and a
 * checkpoint taken half way restarts bitwise — each on the reference
 * kernels and on the fast ones; what it cannot run with is refused naming
 * what it needs. */
#define _POSIX_C_SOURCE 200809L
#include "pulled_sheet.h"
#include "cut_setups.h"

#define WIDTH 0.1 /* ps_sheet_model's sheet: 0.1 m square, in the xy plane */

/* The blade's line: through (0.0503, 0.05) at `degrees` from the y axis. */
typedef struct cut_line {
    double c[2], d[2];
} cut_line;

static cut_line line_at(double degrees) {
    double a = degrees * M_PI / 180.0;
    return (cut_line){{0.0503, 0.05}, {sin(a), cos(a)}};
}

/* Signed distance of (x, y) from the line. */
static double off_line(const cut_line* l, double x, double y) {
    return (x - l->c[0]) * l->d[1] - (y - l->c[1]) * l->d[0];
}

/* A vertical edge from 0.1 m before the sheet's centre along the line to
 * 0.1 m past it, in 0.05 s. */
static sb_blade_def line_blade(const cut_line* l, sb_keyframe path[2]) {
    sb_blade_def blade = {.a = {l->c[0] - 0.1 * l->d[0], l->c[1] - 0.1 * l->d[1], -0.01},
                          .b = {l->c[0] - 0.1 * l->d[0], l->c[1] - 0.1 * l->d[1], 0.01},
                          .path = path,
                          .path_count = 2};
    path[0] = (sb_keyframe){0.0, {0, 0, 0}, {0, 0, 0}};
    path[1] = (sb_keyframe){0.05, {0.2 * l->d[0], 0.2 * l->d[1], 0}, {0, 0, 0}};
    return blade;
}

static sb_solver_def cut_def(const sb_blade_def* blade, int threads, int k) {
    return cut_setup_def(blade, threads, k, 2000);
}

static bool on_outline(double x, double y) {
    const double tol = 1e-6 * WIDTH;
    return fabs(x) < tol || fabs(y) < tol || fabs(x - WIDTH) < tol || fabs(y - WIDTH) < tol;
}

/* Checks the cut of a side × side sheet along the line at `degrees`. */
static void check_line_cut(uint32_t side, double degrees, int k) {
    sb_model* m = ps_sheet_model(side, 0.2, 0.0);
    cut_line l = line_at(degrees);
    sb_keyframe path[2];
    sb_blade_def blade = line_blade(&l, path);
    sb_solver_def def = cut_def(&blade, 1, k);
    sb_solver* s = tu_solver(m, &def);
    int steps = 600 * (int)(side - 1) / 23; /* 0.06 s, the step in proportion to the cell (a CFL bound) */
    tu_advance(s, 0.06 / steps, (uint64_t)steps);
    uint32_t n = sb_solver_vertex_count(s), triangles = sb_solver_triangle_count(s);
    double* x = malloc(3 * (size_t)sb_solver_vertex_capacity(s) * sizeof *x);
    sb_solver_get_positions(s, x);
    uint32_t* parent = ps_components(s); /* the pieces: the triangles' vertices joined */
    uint32_t first_piece = UINT32_MAX, second_piece = UINT32_MAX;
    double worst = 0.0, length[2] = {0.0, 0.0};
    for (uint32_t t = 0; t < triangles; t++) {
        uint32_t v[3];
        sb_solver_triangle(s, t, v);
        uint32_t piece = ps_find(parent, v[0]);
        if (first_piece == UINT32_MAX) first_piece = piece;
        if (piece != first_piece && second_piece == UINT32_MAX) second_piece = piece;
        if (!(piece == first_piece || piece == second_piece)) {
            print_message("triangle %u (%u %u %u) in a third piece\n", t, v[0], v[1], v[2]);
            for (int c = 0; c < 3; c++)
                print_message("  %u at %g %g (%g cells off)\n", v[c], x[3 * v[c]], x[3 * v[c] + 1],
                              off_line(&l, x[3 * v[c]], x[3 * v[c] + 1]) / (WIDTH / (side - 1)));
        }
        assert_true(piece == first_piece || piece == second_piece); /* two pieces, no more */
        for (int c = 0; c < 3; c++) {
            uint32_t i = v[c], j = v[(c + 1) % 3], shared = 0;
            for (uint32_t u = 0; u < triangles && !shared; u++) {
                uint32_t w[3];
                sb_solver_triangle(s, u, w);
                for (int k = 0; k < 3; k++) shared |= u != t && w[k] == j && w[(k + 1) % 3] == i;
            }
            const double *p = x + 3 * (size_t)i, *q = x + 3 * (size_t)j;
            if (shared || (on_outline(p[0], p[1]) && on_outline(q[0], q[1]) &&
                           on_outline(0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]))))
                continue;
            /* a cut edge: both ends on the line, on this piece's side */
            worst = fmax(worst, fmax(fabs(off_line(&l, p[0], p[1])), fabs(off_line(&l, q[0], q[1]))));
            length[piece != first_piece] += hypot(q[0] - p[0], q[1] - p[1]);
        }
    }
    /* every vertex of a piece on its side of the line */
    double side_of[2] = {0.0, 0.0};
    for (uint32_t i = 0; i < n; i++) {
        uint32_t piece = ps_find(parent, i);
        if (piece != first_piece && piece != second_piece) continue;
        double d = off_line(&l, x[3 * i], x[3 * i + 1]);
        side_of[piece != first_piece] += d;
    }
    double cell = WIDTH / (side - 1), through = WIDTH / cos(degrees * M_PI / 180.0);
    print_message("%s, %u x %u sheet, line at %g degrees: %u vertices, %u triangles; cut edges at most %.3g "
                  "cells off the "
                  "line, %.4g and %.4g m long (the line crosses %.4g m)\n",
                  setups[k].name, side, side, degrees, n, triangles, worst / cell, length[0], length[1], through);
    assert_true(second_piece != UINT32_MAX);
    assert_true(worst <= 0.05 * cell);
    assert_true(side_of[0] * side_of[1] < 0.0);
    for (int k = 0; k < 2; k++) assert_true(fabs(length[k] - through) < 1e-3 * through);
    for (uint32_t i = 0; i < n; i++) { /* each piece wholly on its side (within the tolerance) */
        uint32_t piece = ps_find(parent, i);
        if (piece != first_piece && piece != second_piece) continue;
        double d = off_line(&l, x[3 * i], x[3 * i + 1]) * (side_of[piece != first_piece] > 0.0 ? 1.0 : -1.0);
        assert_true(d >= -0.05 * cell);
    }
    assert_int_equal(sb_solver_broken_count(s), 0);
    free(parent);
    free(x);
    sb_solver_destroy(s);
    sb_model_destroy(m);
}

static void test_straight_cut_follows_the_line(void** state) {
    (void)state;
    const uint32_t sides[3] = {12, 24, 48};
    for (int k = 0; k < SETUPS; k++)
        for (int r = 0; r < 3; r++) {
            bool explicit_step = setups[k].integrator != SB_INTEGRATOR_IMPLICIT_EULER;
            if (!explicit_step && r != 1) continue; /* implicit Euler's steps cost more: 24 × 24 at 30 degrees */
            if (explicit_step) check_line_cut(sides[r], 0.0, k);
            check_line_cut(sides[r], 30.0, k);
        }
}

static void check_mass_and_momentum(int k) {
    sb_model* m = ps_sheet_model(24, 0.2, 0.0);
    cut_line l = line_at(30.0);
    sb_keyframe path[2];
    sb_blade_def blade = line_blade(&l, path);
    sb_solver_def def = cut_def(&blade, 2, k);
    sb_solver* s = tu_solver(m, &def);
    tu_set_spin(s, 0.05, 0.05, 0.3, 0.1, 60.0);
    double mass0, p0[3], scale = 0.0;
    tu_mass_momentum(s, &mass0, p0);
    scale = mass0 * 0.4; /* kg m/s: the mass times the fastest speed */
    uint32_t made = 0;
    double worst_mass = 0.0, worst_momentum = 0.0;
    for (int step = 0; step < 600; step++) {
        double mass, p[3];
        tu_advance(s, 1e-4, 1);
        tu_mass_momentum(s, &mass, p);
        made = sb_solver_vertex_count(s) - sb_model_vertex_count(m);
        worst_mass = fmax(worst_mass, fabs(mass - mass0) / mass0);
        for (int a = 0; a < 3; a++) worst_momentum = fmax(worst_momentum, fabs(p[a] - p0[a]) / scale);
    }
    print_message("%s: %u vertices made by the cut; mass off by at most %.3g of itself, momentum by %.3g of m v_max\n",
                  setups[k].name, made, worst_mass, worst_momentum);
    assert_true(made > 40);
    assert_true(worst_mass < 1e-12);
    /* implicit Euler's Newton stops at a residual of 1e-8 of its first (or
     * at rounding level), and what is left of it is momentum the step did
     * not balance. */
    bool implicit = setups[k].integrator == SB_INTEGRATOR_IMPLICIT_EULER, single = sizeof(sb_real) == 4;
    assert_true(worst_momentum < (single ? (implicit ? 1e-4 : 1e-5) : (implicit ? 1e-9 : 1e-12)));
    sb_solver_destroy(s);
    sb_model_destroy(m);
}

static void test_cut_keeps_mass_and_momentum(void** state) {
    (void)state;
    for (int k = 0; k < SETUPS; k++) check_mass_and_momentum(k);
}

/* The positions and velocities after the cut with `threads` threads,
 * from a checkpoint taken at step `save_at` when it is positive. */
static double* cut_run(int threads, int save_at, int k) {
    sb_model* m = ps_sheet_model(24, 0.2, 0.0);
    cut_line l = line_at(30.0);
    sb_keyframe path[2];
    sb_blade_def blade = line_blade(&l, path);
    sb_solver_def def = cut_def(&blade, threads, k);
    sb_solver* s = tu_solver(m, &def);
    tu_set_spin(s, 0.05, 0.05, 0.3, 0.1, 60.0);
    if (save_at > 0) {
        tu_advance(s, 1e-4, (uint64_t)save_at);
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
    tu_advance(s, 1e-4, (uint64_t)(600 - (save_at > 0 ? save_at : 0)));
    size_t n = 3 * (size_t)sb_solver_vertex_capacity(s);
    double* out = calloc(2 * n + 1, sizeof *out);
    sb_solver_get_positions(s, out);
    sb_solver_get_velocities(s, out + n);
    out[2 * n] = sb_solver_vertex_count(s);
    sb_solver_destroy(s);
    sb_model_destroy(m);
    return out;
}

static void check_deterministic_and_restarts(int k) {
    double* one = cut_run(1, 0, k);
    size_t bytes = 0;
    {
        sb_model* m = ps_sheet_model(24, 0.2, 0.0);
        cut_line l = line_at(30.0);
        sb_keyframe path[2];
        sb_blade_def blade = line_blade(&l, path);
        sb_solver_def def = cut_def(&blade, 1, k);
        sb_solver* s = tu_solver(m, &def);
        bytes = (6 * (size_t)sb_solver_vertex_capacity(s) + 1) * sizeof(double);
        sb_solver_destroy(s);
        sb_model_destroy(m);
    }
    for (int threads = 2; threads <= 3; threads++) {
        double* other = cut_run(threads, 0, k);
        assert_memory_equal(one, other, bytes);
        free(other);
    }
    double* resumed = cut_run(2, 300, k); /* half way: the blade in the sheet */
    assert_memory_equal(one, resumed, bytes);
    print_message("%s: %g vertices after the cut: the same with 1, 2 and 3 threads and from a checkpoint at step 300\n",
                  setups[k].name, one[bytes / sizeof(double) - 1]);
    free(resumed);
    free(one);
}

static void test_cut_is_deterministic_and_restarts(void** state) {
    (void)state;
    for (int k = 0; k < SETUPS; k++) check_deterministic_and_restarts(k);
}

static void test_cut_through_refused(void** state) {
    (void)state;
    sb_model* m = ps_sheet_model(6, 0.0, 0.0);
    cut_line l = line_at(0.0);
    sb_keyframe path[2];
    sb_blade_def blade = line_blade(&l, path);
    for (int k = 0; k < 2; k++) {
        sb_solver_def def = cut_def(&blade, 1, k);
        def.integrator = SB_INTEGRATOR_PBD;
        sb_error err;
        assert_null(sb_solver_create(m, &def, &err));
        print_message("%s\n", err.message);
        assert_non_null(strstr(err.message, "needs an explicit integrator"));
    }
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_straight_cut_follows_the_line),
        cmocka_unit_test(test_cut_keeps_mass_and_momentum),
        cmocka_unit_test(test_cut_is_deterministic_and_restarts),
        cmocka_unit_test(test_cut_through_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
