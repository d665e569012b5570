/* Cutting (kernels/interaction/cutting.c, softbond/blade.h): a blade, an edge across a
 * sheet at rest (no gravity, no limits: nothing moves but the blade),
 * moved along y by its keyframes, severs exactly the bonds whose segment
 * crosses the rectangle its edge swept — counted here from the model's rest
 * positions, each bond once, through the breakage callback — with both
 * kernels and 1 or 2 threads; carried through the sheet it leaves two
 * pieces (union-find over the live triangles); a static blade cuts
 * nothing; bad blades are refused naming the blade. */
#define _POSIX_C_SOURCE 200809L
#include "pulled_sheet.h"

#define SIDE 20
#define BLADE_X 0.05   /* the edge's x: between columns 9 and 10 */
#define BLADE_Y0 -0.02 /* its y at time 0 */

typedef struct cut_log {
    uint32_t count;
    uint8_t cut[4 * SIDE * SIDE];
} cut_log;

static void record_cut(void* user, uint32_t bond, uint32_t i, uint32_t j, double time) {
    (void)i, (void)j, (void)time;
    cut_log* log = user;
    assert_int_equal(log->cut[bond], 0); /* once */
    log->cut[bond] = 1;
    log->count++;
}

/* The blade's edge, vertical through the sheet's plane, moving +y by
 * `travel` m in 0.05 s. */
static sb_blade_def vertical_blade(sb_keyframe path[2], double travel) {
    sb_blade_def blade = {
        .a = {BLADE_X, BLADE_Y0, -0.01}, .b = {BLADE_X, BLADE_Y0, 0.01}, .path = path, .path_count = 2};
    path[0] = (sb_keyframe){0.0, {0, 0, 0}, {0, 0, 0}};
    path[1] = (sb_keyframe){0.05, {0, travel, 0}, {0, 0, 0}};
    return blade;
}

/* Whether bond e crosses x = BLADE_X at a y in [BLADE_Y0, y_end] (rest
 * positions); *margin gets the nearest such crossing's distance to y_end. */
static bool crosses(const sb_model* m, uint32_t e, double y_end, double* margin) {
    sb_bond_info bond = sb_model_bond(m, e);
    double p[3], q[3];
    sb_model_rest_position(m, bond.i, p);
    sb_model_rest_position(m, bond.j, q);
    if ((p[0] - BLADE_X) * (q[0] - BLADE_X) >= 0.0) return false;
    double s = (BLADE_X - p[0]) / (q[0] - p[0]), y = p[1] + s * (q[1] - p[1]);
    *margin = fmin(*margin, fabs(y - y_end));
    return y >= BLADE_Y0 && y <= y_end;
}

/* A run of check_cut: the blade's travel over its 0.05 s path, the
 * sheet's speed along -y (rigid: it starts at rest shape), the steps. */
typedef struct cut_run {
    double travel, sheet_speed, dt;
    int steps;
} cut_run;

/* The sheet moves at -sheet_speed along y, rigidly (no force acts on it). */
static void set_sheet_speed(sb_solver* s, const sb_model* m, double speed) {
    uint32_t n = sb_solver_vertex_capacity(s);
    double* x = calloc(3 * (size_t)n, sizeof *x);
    double* v = calloc(3 * (size_t)n, sizeof *v);
    sb_solver_get_positions(s, x);
    for (uint32_t i = 0; i < sb_model_vertex_count(m); i++) v[3 * i + 1] = -speed;
    assert_int_equal(sb_solver_set_state(s, x, v), SB_OK);
    free(x);
    free(v);
}

static void check_cut(sb_kernels kernels, int threads, cut_run run) {
    sb_model* m = ps_sheet_model(SIDE, 0.3, 0.0);
    sb_keyframe path[2];
    sb_blade_def blade = vertical_blade(path, run.travel);
    cut_log log = {0};
    sb_solver_def def = sb_default_solver_def();
    def.kernels = kernels;
    def.runtime.threads = threads;
    def.gravity[2] = 0.0;
    def.blades = &blade;
    def.blade_count = 1;
    def.on_break = record_cut;
    def.break_user = &log;
    sb_solver* s = tu_solver(m, &def);
    if (run.sheet_speed > 0.0) set_sheet_speed(s, m, run.sheet_speed);
    tu_advance(s, run.dt, (uint64_t)run.steps);
    /* where the blade's edge ends, in the sheet's frame */
    double time = run.dt * run.steps, y_end = BLADE_Y0 + run.travel * fmin(1.0, time / 0.05) + run.sheet_speed * time;
    uint32_t expected = 0;
    double margin = INFINITY;
    for (uint32_t e = 0; e < sb_model_bond_count(m); e++) {
        bool crossed = crosses(m, e, y_end, &margin);
        expected += crossed;
        assert_int_equal(log.cut[e], crossed);
        assert_int_equal(sb_solver_bond_broken(s, e), crossed);
    }
    print_message("kernels %d, %d threads, blade to y = %g: %u bonds cut (%u expected; nearest crossing %g m from "
                  "the blade's end)\n",
                  (int)kernels, threads, y_end, log.count, expected, margin);
    assert_true(margin > 1e-6); /* no crossing the float positions could put on the other side */
    assert_true(expected > 0);
    assert_int_equal(log.count, expected);
    if (y_end > 0.1) { /* through the sheet: a left and a right piece */
        uint32_t* parent = ps_components(s);
        uint32_t left = ps_find(parent, 0), right = ps_find(parent, SIDE - 1);
        for (uint32_t row = 0; row < SIDE; row++) {
            assert_int_equal(ps_find(parent, row * SIDE), left);
            assert_int_equal(ps_find(parent, row * SIDE + SIDE - 1), right);
        }
        assert_true(left != right);
        free(parent);
    }
    sb_solver_destroy(s);
    sb_model_destroy(m);
}

static void test_blade_cuts_what_it_crosses(void** state) {
    (void)state;
    for (int kernels = 0; kernels < 2; kernels++)
        for (int threads = 1; threads <= 2; threads++) {
            check_cut((sb_kernels)kernels, threads, (cut_run){0.0753, 0.0, 1e-4, 600}); /* half way up the sheet */
            check_cut((sb_kernels)kernels, threads, (cut_run){0.16, 0.0, 1e-4, 600});   /* through it */
        }
}

/* The sheet rushes down onto a slow blade, 1.3 cells a step against it:
 * tested at the step's end alone, most crossings would lie between two
 * steps' edges and slip past; the sweep continuous in time cuts each. */
static void test_fast_tissue_cannot_slip_past(void** state) {
    (void)state;
    for (int kernels = 0; kernels < 2; kernels++)
        for (int threads = 1; threads <= 3; threads++)
            check_cut((sb_kernels)kernels, threads, (cut_run){0.015, 6.6, 1e-3, 12});
}

/* A blade held still in a sheet at rest: nothing crosses it. */
static void test_static_blade_cuts_nothing(void** state) {
    (void)state;
    sb_model* m = ps_sheet_model(SIDE, 0.3, 0.0);
    sb_blade_def blade = {.a = {BLADE_X, -0.01, 0.0}, .b = {BLADE_X, 0.2, 0.0}};
    sb_solver_def def = sb_default_solver_def();
    def.gravity[2] = 0.0;
    def.blades = &blade;
    def.blade_count = 1;
    sb_solver* s = tu_solver(m, &def);
    tu_advance(s, 1e-4, 100);
    assert_int_equal(sb_solver_broken_count(s), 0);
    sb_solver_destroy(s);
    sb_model_destroy(m);
}

static void test_bad_blades_refused(void** state) {
    (void)state;
    sb_model* m = ps_sheet_model(4, 0.0, 0.0);
    sb_keyframe backwards[2] = {{1.0, {0, 0, 0}, {0, 0, 0}}, {0.5, {0, 0, 0}, {0, 0, 0}}};
    sb_blade_def blades[3] = {{.a = {0, 0, 0}, .b = {0, 0, 0}},
                              {.a = {0, 0, NAN}, .b = {0, 0, 1}},
                              {.a = {0, 0, 0}, .b = {0, 0, 1}, .path = backwards, .path_count = 2}};
    const char* expected[3] = {"blade 0: its ends a and b are the same point",
                               "blade 0: its ends a and b must be finite", "blade 0"};
    for (int k = 0; k < 3; k++) {
        sb_solver_def def = sb_default_solver_def();
        def.blades = &blades[k];
        def.blade_count = 1;
        sb_error err;
        assert_null(sb_solver_create(m, &def, &err));
        print_message("%s\n", err.message);
        assert_non_null(strstr(err.message, expected[k]));
    }
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blade_cuts_what_it_crosses),
        cmocka_unit_test(test_fast_tissue_cannot_slip_past),
        cmocka_unit_test(test_static_blade_cuts_nothing),
        cmocka_unit_test(test_bad_blades_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
