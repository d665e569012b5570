/* Breakage (kernels/interaction/breakage.c): a spring pulled past break_max (pushed
 * below break_min) breaks at the step whose end length first crosses the
 * limit — the step found in a recorded run of the same model without
 * limits, and within a step of the analytic crossing of its harmonic
 * motion — with one callback naming the bond, its vertices and that time;
 * afterwards it pulls nothing (both kernels); a sheet pulled apart by two
 * handles breaks, and its energies are then those of a model holding only
 * the bonds, triangles and hinges left whole (built independently from the
 * broken set); 1 and 2 threads break the same bonds at the same times and
 * end bitwise equal; a breakable sheet's fast model folds its constants
 * and break limits as a plain one's; bad limits are refused. The program: the committed
 * scenes/tearing_sheet.yaml and scenes/blade_cut.yaml break bonds
 * (log.csv's broken column counts up, the same for 1 and 2 threads), and
 * bad break strains, tearing caps and blades exit 2 naming the line. */
#define _POSIX_C_SOURCE 200809L
#include "pulled_sheet.h"
#include "tests/test_files.h"
#include "kernels/forces/fast_model.h"

/* What the breakage callback saw. */
typedef struct break_log {
    uint32_t count;
    uint32_t bond[4096], i[4096], j[4096];
    double time[4096];
} break_log;

static void record_break(void* user, uint32_t bond, uint32_t i, uint32_t j, double time) {
    break_log* log = user;
    if (log->count < 4096) {
        log->bond[log->count] = bond;
        log->i[log->count] = i;
        log->j[log->count] = j;
        log->time[log->count] = time;
    }
    log->count++;
}

/* Vertex 0 fixed at the origin, vertex 1 (1 kg) at x = 1 m moving at vx
 * m/s, one spring k = 100 N/m (ω = 10 rad/s, amplitude |vx|/10) with the
 * given break lengths. */
static sb_model* one_spring(double vx, double break_min, double break_max) {
    sb_builder* b = sb_builder_create();
    tu_vertex(b, 0, 0, 0, 1.0, true);
    sb_vertex_def v = sb_default_vertex_def();
    v.position[0] = 1.0;
    v.velocity[0] = vx;
    v.mass = 1.0;
    sb_builder_add_vertex(b, &v);
    sb_bond_def d = sb_default_bond_def();
    d.i = 0;
    d.j = 1;
    d.spring_k = 100.0;
    d.break_min = break_min;
    d.break_max = break_max;
    sb_builder_add_bond(b, &d);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

static sb_solver_def spring_def(sb_kernels kernels, break_log* log) {
    sb_solver_def def = sb_default_solver_def();
    def.gravity[2] = 0.0;
    def.kernels = kernels;
    def.runtime.threads = 1;
    def.on_break = record_break;
    def.break_user = log;
    return def;
}

static double x1_of(const sb_solver* s) {
    double x[6];
    sb_solver_get_positions(s, x);
    return x[3];
}

#define DT 1e-4
#define STEPS 1000

/* The first step (1-based) of an unbreakable run whose end length is past the limit. */
static int crossing_step(sb_kernels kernels, double vx, double limit) {
    sb_model* m = one_spring(vx, 0.0, INFINITY);
    break_log log = {0};
    sb_solver_def def = spring_def(kernels, &log);
    sb_solver* s = tu_solver(m, &def);
    int found = 0;
    for (int n = 1; n <= STEPS && !found; n++) {
        tu_advance(s, DT, 1);
        double x = x1_of(s);
        if (vx > 0 ? x > limit : x < limit) found = n;
    }
    sb_solver_destroy(s);
    sb_model_destroy(m);
    return found;
}

/* Runs the spring with a limit and checks the break against the recorded
 * crossing and the analytic one: 1 + A sin(ω t) reaches the limit at
 * asin((limit − 1)/A)/ω. */
static void check_spring_break(sb_kernels kernels, double vx, double break_min, double break_max) {
    double limit = vx > 0 ? break_max : break_min;
    int expected = crossing_step(kernels, vx, limit);
    assert_true(expected > 0);
    double analytic = asin(fabs(limit - 1.0) / (fabs(vx) / 10.0)) / 10.0;
    TU_ASSERT_NEAR(expected * DT, analytic, 2 * DT);

    sb_model* m = one_spring(vx, break_min, break_max);
    break_log log = {0};
    sb_solver_def def = spring_def(kernels, &log);
    sb_solver* s = tu_solver(m, &def);
    for (int n = 1; n <= STEPS; n++) {
        tu_advance(s, DT, 1);
        assert_int_equal(log.count, n >= expected ? 1 : 0);
        assert_int_equal(sb_solver_broken_count(s), n >= expected ? 1 : 0);
        assert_int_equal(sb_solver_bond_broken(s, 0), n >= expected);
    }
    assert_int_equal(log.bond[0], 0);
    assert_int_equal(log.i[0], 0);
    assert_int_equal(log.j[0], 1);
    TU_ASSERT_NEAR(log.time[0], expected * DT, 1e-12);
    assert_false(sb_solver_bond_broken(s, 1)); /* out of range */

    /* broken: no force, no energy, and the vertex coasts at a constant velocity */
    double f[6], v0[6], v1[6], x0 = x1_of(s);
    sb_solver_get_forces(s, f);
    assert_true(f[3] == 0.0 && f[4] == 0.0 && f[5] == 0.0);
    assert_true(sb_solver_energies(s).term[SB_TERM_SPRING] == 0.0);
    sb_solver_get_velocities(s, v0);
    tu_advance(s, DT, 100);
    sb_solver_get_velocities(s, v1);
    TU_ASSERT_NEAR(v1[3], v0[3], 1e-5 * fabs(v0[3]));
    TU_ASSERT_NEAR(x1_of(s) - x0, 100 * DT * v0[3], 1e-9 + 100 * fabs(x0) * TU_REAL_EPS);
    assert_int_equal(log.count, 1);
    sb_solver_destroy(s);
    sb_model_destroy(m);
}

static void test_spring_breaks_past_max(void** state) {
    (void)state;
    for (int kernels = 0; kernels < 2; kernels++) check_spring_break((sb_kernels)kernels, 1.0, 0.0, 1.05);
}

static void test_spring_breaks_below_min(void** state) {
    (void)state;
    for (int kernels = 0; kernels < 2; kernels++) check_spring_break((sb_kernels)kernels, -1.0, 0.95, INFINITY);
}

/* Every integrator (but pbd, whose projection's stiffness is its own, far
 * stiffer here: kernels/integrators/pbd.c) and the adaptive stepper: the spring breaks
 * once, near the analytic time. */
static void test_every_integrator_breaks_once(void** state) {
    (void)state;
    double analytic = asin(0.5) / 10.0;
    for (int kernels = 0; kernels < 2; kernels++)
        for (int integrator = 0; integrator < SB_INTEGRATOR_COUNT; integrator++)
            for (int adaptive = 0; adaptive < 2 && integrator != SB_INTEGRATOR_PBD; adaptive++) {
                sb_model* m = one_spring(1.0, 0.0, 1.05);
                break_log log = {0};
                sb_solver_def def = spring_def((sb_kernels)kernels, &log);
                def.integrator = (sb_integrator)integrator;
                def.adaptive = adaptive;
                sb_solver* s = tu_solver(m, &def);
                print_message("%s kernels, %s%s\n", kernels ? "fast" : "reference",
                              sb_integrator_name((sb_integrator)integrator), adaptive ? ", adaptive" : "");
                tu_advance(s, 1e-3, 200);
                assert_int_equal(log.count, 1);
                TU_ASSERT_NEAR(log.time[0], analytic, 2e-3);
                sb_solver_destroy(s);
                sb_model_destroy(m);
            }
}

/* ---- a sheet pulled apart ----------------------------------------------- */

#define SIDE 8

typedef struct pulled_run {
    sb_model* model;
    sb_handle* handles[2];
    uint32_t rows[2][SIDE];
    sb_solver* solver;
    break_log log;
} pulled_run;

static void pulled_start(pulled_run* r, sb_kernels kernels, int threads) {
    r->model = ps_sheet_model(SIDE, 0.0, 0.3);
    ps_handles(SIDE, r->handles, r->rows[0]);
    sb_solver_def def = sb_default_solver_def();
    def.kernels = kernels;
    def.drag = 5.0;
    def.handles = r->handles;
    def.handle_count = 2;
    def.runtime.threads = threads;
    def.on_break = record_break;
    def.break_user = &r->log;
    def.max_splits = -1; /* the surface stays whole: its dead elements are compared (tests/test_tearing.c splits) */
    r->log.count = 0;
    r->solver = tu_solver(r->model, &def);
}

static void pulled_end(pulled_run* r) { ps_destroy(r->solver, r->handles, r->model); }

/* Whether the edge (a, b) is one of the broken bonds. */
static bool edge_broken(const sb_solver* s, const sb_model* m, uint32_t a, uint32_t b) {
    for (uint32_t e = 0; e < sb_model_bond_count(m); e++) {
        sb_bond_info info = sb_model_bond(m, e);
        if (((info.i == a && info.j == b) || (info.i == b && info.j == a)) && sb_solver_bond_broken(s, e)) return true;
    }
    return false;
}

/* The sheet's model rebuilt from scratch with only the elements no broken
 * bond touches: the same vertices, the same constants (ps_sheet_model's). */
static sb_model* survivors(const sb_solver* s, const sb_model* m, uint32_t* dead_triangles) {
    sb_builder* b = sb_builder_create();
    uint32_t n = sb_model_vertex_count(m);
    for (uint32_t v = 0; v < n; v++) {
        double p[3];
        sb_model_rest_position(m, v, p);
        tu_vertex(b, p[0], p[1], p[2], 0.01, false);
    }
    for (uint32_t e = 0; e < sb_model_bond_count(m); e++)
        if (!sb_solver_bond_broken(s, e)) tu_bond(b, sb_model_bond(m, e).i, sb_model_bond(m, e).j, -1.0, 200.0, 0, 0);
    *dead_triangles = 0;
    for (uint32_t t = 0; t < sb_model_triangle_count(m); t++) {
        uint32_t v[3];
        sb_model_triangle(m, t, v);
        bool dead = edge_broken(s, m, v[0], v[1]) || edge_broken(s, m, v[1], v[2]) || edge_broken(s, m, v[2], v[0]);
        *dead_triangles += dead;
        if (!dead) tu_triangle(b, v[0], v[1], v[2], 1e-3, 1e-2);
    }
    /* hinges: the factory's, one per interior edge, kept when neither wing is dead */
    for (uint32_t t = 0; t < sb_model_triangle_count(m); t++)
        for (uint32_t u = t + 1; u < sb_model_triangle_count(m); u++) {
            uint32_t a[3], c[3];
            sb_model_triangle(m, t, a);
            sb_model_triangle(m, u, c);
            for (int k = 0; k < 3; k++)
                for (int q = 0; q < 3; q++) {
                    if (a[k] != c[(q + 1) % 3] || a[(k + 1) % 3] != c[q]) continue; /* shared edge, opposite ways */
                    uint32_t o0 = a[(k + 2) % 3], o1 = c[(q + 2) % 3];
                    bool dead = edge_broken(s, m, a[k], a[(k + 1) % 3]) || edge_broken(s, m, a[k], o0) ||
                                edge_broken(s, m, a[(k + 1) % 3], o0) || edge_broken(s, m, a[k], o1) ||
                                edge_broken(s, m, a[(k + 1) % 3], o1);
                    if (!dead) tu_hinge(b, a[k], a[(k + 1) % 3], o0, o1, 1e-4);
                }
        }
    sb_model* out = tu_compile(b);
    sb_builder_destroy(b);
    return out;
}

static void test_sheet_tears_and_dead_elements_vanish(void** state) {
    (void)state;
    for (int kernels = 0; kernels < 2; kernels++) {
        pulled_run r;
        pulled_start(&r, (sb_kernels)kernels, 1);
        tu_advance(r.solver, 1e-4, 4000);
        uint32_t broken = sb_solver_broken_count(r.solver);
        assert_true(broken > 0);
        assert_int_equal(r.log.count, broken);
        for (uint32_t k = 1; k < r.log.count; k++) /* in bond order within a step, each once */
            assert_true(r.log.time[k] > r.log.time[k - 1] || r.log.bond[k] > r.log.bond[k - 1]);
        uint32_t dead;
        sb_model* alive = survivors(r.solver, r.model, &dead);
        assert_true(dead > 0);
        uint32_t n = sb_model_vertex_count(r.model);
        double* x = malloc(6 * n * sizeof *x);
        double* f = malloc(3 * n * sizeof *f);
        sb_solver_get_positions(r.solver, x);
        sb_solver_get_velocities(r.solver, x + 3 * n);
        sb_energies expected;
        sb_error err;
        assert_int_equal(sb_reference_forces(alive, x, x + 3 * n, f, &expected, &err), SB_OK);
        sb_energies got = sb_solver_energies(r.solver);
        /* the fast kernels sum in sb_real; the reference evaluates at the
         * positions with their drifts' carries, which a float build's
         * published positions round off (kernels/state/vertex_state.h) */
        double tol = (kernels ? 1e-3 : SB_DOUBLE ? 1e-9 : 1e-6) * sb_energies_internal(&expected) + 1e-15;
        assert_true(expected.term[SB_TERM_BOND] > 0 && expected.term[SB_TERM_ANGLE] > 0);
        for (int t = 0; t < SB_TERM_COUNT; t++) {
            print_message("kernels %d, %s: %g J (expected %g J)\n", kernels, sb_term_name((sb_term)t), got.term[t],
                          expected.term[t]);
            TU_ASSERT_NEAR(got.term[t], expected.term[t], tol);
        }
        free(x);
        free(f);
        sb_model_destroy(alive);
        pulled_end(&r);
    }
}

static void test_threads_break_the_same(void** state) {
    (void)state;
    pulled_run one, two;
    pulled_start(&one, SB_KERNELS_FAST, 1);
    pulled_start(&two, SB_KERNELS_FAST, 2);
    tu_advance(one.solver, 1e-4, 3000);
    tu_advance(two.solver, 1e-4, 3000);
    assert_true(one.log.count > 0);
    assert_int_equal(one.log.count, two.log.count);
    for (uint32_t k = 0; k < one.log.count; k++) {
        assert_int_equal(one.log.bond[k], two.log.bond[k]);
        assert_true(one.log.time[k] == two.log.time[k]);
    }
    assert_true(tu_state_hash(one.solver) == tu_state_hash(two.solver));
    pulled_end(&one);
    pulled_end(&two);
}

static void test_unbreakable_sheet_never_breaks(void** state) {
    (void)state;
    sb_model* m = ps_sheet_model(SIDE, 0.0, 0.0);
    break_log log = {0};
    sb_solver_def def = sb_default_solver_def();
    def.on_break = record_break;
    def.break_user = &log;
    sb_solver* s = tu_solver(m, &def);
    tu_advance(s, 1e-4, 100);
    assert_int_equal(log.count, 0);
    assert_int_equal(sb_solver_broken_count(s), 0);
    sb_solver_destroy(s);
    sb_model_destroy(m);
}

/* A breakable sheet's fast model reads what a plain one's does
 * (kernels/forces/fast_model.h): its triangles' and fused bonds' constants
 * folded to the plain model's values, the bonds' rest lengths the
 * triangles', and one break limit for all, the material's (1 + strain)²
 * relative to the squared rest length, less the margin (a jittered mesh:
 * the limit lengths differ from bond to bond); widened by the crack
 * rule's margin, that times its square. */
static void test_breakable_sheet_folds_like_a_plain_one(void** state) {
    (void)state;
    const double strain = 0.25, wider = 1.25;
    sb_model *plain = ps_sheet_model(SIDE, 0.2, 0.0), *breakable = ps_sheet_model(SIDE, 0.2, strain);
    sb_error err;
    sb_fast_model *p = sb_fast_model_create(plain, &err), *b = sb_fast_model_create(breakable, &err);
    assert_non_null(p);
    assert_non_null(b);
    assert_true(b->fused_bonds && b->mortal_triangles && b->fused_limits && b->bonds.count == 0);
    const sb_fast_constant* folded[][2] = {{&p->angle_k, &b->angle_k}, {&p->stretch_bend_k, &b->stretch_bend_k}};
    for (int k = 0; k < 2; k++) {
        assert_null(folded[k][1]->values);
        assert_true(folded[k][1]->uniform == folded[k][0]->uniform);
    }
    double limit = (1.0 + strain) * (1.0 + strain) * (1.0 - SB_LIMIT_MARGIN);
    for (int c = 0; c < 3; c++) {
        assert_null(b->tri_edge_r0[c]);
        assert_null(b->tri_edge_bond_k[c].values);
        assert_true(b->tri_edge_bond_k[c].uniform == p->tri_edge_bond_k[c].uniform);
        assert_null(b->tri_edge_max_ratio2[c].values);
        assert_null(b->tri_edge_min_ratio2[c].values);
        assert_true(b->tri_edge_min_ratio2[c].uniform == 0);
        TU_ASSERT_NEAR(b->tri_edge_max_ratio2[c].uniform, limit, 4 * FLT_EPSILON * limit);
    }
    sb_fast_widen_limits(b, wider);
    for (int c = 0; c < 3; c++)
        TU_ASSERT_NEAR(b->tri_edge_max_ratio2[c].uniform, limit * wider * wider, 8 * FLT_EPSILON * limit);
    sb_fast_model_destroy(p);
    sb_fast_model_destroy(b);
    sb_model_destroy(plain);
    sb_model_destroy(breakable);
}

static void test_bad_limits_refused(void** state) {
    (void)state;
    double limits[][2] = {{0.0, 0.9}, {1.1, INFINITY}, {-0.1, INFINITY}, {NAN, INFINITY}, {0.0, NAN}, {INFINITY, 0}};
    for (size_t c = 0; c < sizeof limits / sizeof *limits; c++) {
        sb_builder* b = sb_builder_create();
        tu_vertex(b, 0, 0, 0, 1.0, false);
        tu_vertex(b, 1, 0, 0, 1.0, false);
        sb_bond_def d = sb_default_bond_def();
        d.j = 1;
        d.k = 1.0;
        d.break_min = limits[c][0];
        d.break_max = limits[c][1];
        sb_builder_add_bond(b, &d);
        TU_ASSERT_CONTAINS(tu_compile_fails(b), "bond 0 (0, 1)");
        sb_builder_destroy(b);
    }
    sb_mesh mesh = {0};
    sb_sheet_def sheet = sb_default_sheet_def();
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    sb_material_def material = sb_default_material_def();
    material.break_strain = -0.5;
    sb_builder* b = sb_builder_create();
    assert_int_equal(sb_builder_add_mesh(b, &mesh, &material, &err), SB_ERR_INVALID);
    sb_spring_mesh_def springs = sb_default_spring_mesh_def();
    springs.break_strain = NAN;
    assert_int_equal(sb_builder_add_spring_mesh(b, &mesh, &springs, &err), SB_ERR_INVALID);
    sb_builder_destroy(b);
    sb_mesh_free(&mesh);
}

/* log.csv's last column in its last row, and the header's last name. */
static double last_broken(const char* log) {
    const char* header_end = strchr(log, '\n');
    assert_non_null(header_end);
    assert_int_equal(strncmp(header_end - 7, ",broken", 7), 0);
    const char* end = log + strlen(log) - 1; /* the last row's newline */
    const char* comma = end;
    while (comma > log && *comma != ',') comma--;
    return atof(comma + 1);
}

/* A committed scene's log.csv, shortened, run with 1 and 2 threads: the
 * same, and bonds broken by its end. */
static void check_scene_breaks(const char* scene, const char* duration) {
    char* logs[2];
    for (int threads = 1; threads <= 2; threads++) {
        char dir[16], count[4], path[400], scene_path[400];
        snprintf(dir, sizeof dir, "tear%d", threads);
        snprintf(count, sizeof count, "%d", threads);
        snprintf(scene_path, sizeof scene_path, SB_SOURCE_DIR "/scenes/%s", scene);
        /* cut_through off: the blade scene's blade severs the bonds it crosses (through the triangles none break) */
        tu_result r = tu_run((const char*[]){"run", scene_path, "--set", duration, "--set", "output.frames=false",
                                             "--set", "cut_through=false", "--threads", count, "--output", dir, NULL});
        if (r.code != 0) fail_msg("%s", r.err);
        tu_result_free(&r);
        snprintf(path, sizeof path, "%s/log.csv", tu_tmp_path(dir));
        logs[threads - 1] = tu_read_file(path);
        assert_non_null(logs[threads - 1]);
    }
    print_message("%s: %g bonds broken\n", scene, last_broken(logs[0]));
    assert_true(last_broken(logs[0]) > 0);
    assert_string_equal(logs[0], logs[1]);
    free(logs[0]);
    free(logs[1]);
}

static void test_tearing_scene(void** state) {
    (void)state;
    check_scene_breaks("tearing_sheet.yaml", "duration=0.5");
}

/* scenes/blade_cut.yaml, its blade severing bonds: the blade half way up the sheet. */
static void test_blade_scene(void** state) {
    (void)state;
    check_scene_breaks("blade_cut.yaml", "duration=0.4");
}

static void assert_scene_fails(const char* text, const char* message) {
    tu_write_file("bad.yaml", text);
    tu_result r = tu_run((const char*[]){"run", "bad.yaml", "--output", "never", NULL});
    if (r.code != 2 || !strstr(r.err, message))
        fail_msg("expected exit 2 and '%s', got %d: %s", message, r.code, r.err);
    tu_result_free(&r);
}

static void test_bad_scene_strains(void** state) {
    (void)state;
    assert_scene_fails("mesh: {nx: 3, ny: 3}\nbond: {k: 10, break_strain: -0.1}\n",
                       "bad.yaml:2: 'bond.break_strain' must be >= 0, got -0.1");
    assert_scene_fails("mesh: {nx: 3, ny: 3}\nfactory: springs\nsprings:\n  break_strain: many\n",
                       "bad.yaml:4: 'springs.break_strain' expects a number, got 'many'");
    assert_scene_fails("mesh: {nx: 3, ny: 3}\ntearing: {max_splits: -2}\n", "bad.yaml:2: 'tearing.max_splits' must be");
}

static void test_bad_scene_blades(void** state) {
    (void)state;
    assert_scene_fails("mesh: {nx: 3, ny: 3}\nblades:\n  - {a: [0, 0, 0], b: [0, 0, 0]}\n",
                       "bad.yaml:3: 'blades[0].b': the edge's ends a and b are the same point");
    assert_scene_fails("mesh: {nx: 3, ny: 3}\nblades:\n  - a: [0, 0, 0]\n", "bad.yaml:3: 'blades[0].b' is not set");
    assert_scene_fails("mesh: {nx: 3, ny: 3}\nblades:\n  - {a: [0, 0, 0], b: [0, 0, 1], pth: []}\n",
                       "bad.yaml:3: unknown key 'blades[0].pth' (did you mean 'blades[0].path'?)");
    assert_scene_fails(
        "mesh: {nx: 3, ny: 3}\nblades:\n  - {a: [0, 0, 0], b: [0, 0, 1]}\n  - {a: [0, 0], b: [0, 0, 1]}\n",
        "bad.yaml:4: 'blades[1].a' expects 3 numbers: [x, y, z] or x,y,z");
}

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_breakage");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spring_breaks_past_max),
        cmocka_unit_test(test_spring_breaks_below_min),
        cmocka_unit_test(test_every_integrator_breaks_once),
        cmocka_unit_test(test_sheet_tears_and_dead_elements_vanish),
        cmocka_unit_test(test_threads_break_the_same),
        cmocka_unit_test(test_unbreakable_sheet_never_breaks),
        cmocka_unit_test(test_breakable_sheet_folds_like_a_plain_one),
        cmocka_unit_test(test_bad_limits_refused),
        cmocka_unit_test(test_tearing_scene),
        cmocka_unit_test(test_bad_scene_strains),
        cmocka_unit_test(test_blade_scene),
        cmocka_unit_test(test_bad_scene_blades),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
