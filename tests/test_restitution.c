/* Restitution a body obeys (kernels/contact/body_restitution.c): a stiff,
 * undamped soft ball dropped from h onto a collider of restitution e
 * rebounds to e² h (Newton's law for its centre of mass: it leaves with e
 * times the speed it came in with, √(2 g h), and rises (e √(2 g h))² / 2 g).
 * The oracle is that closed form. Before the body-level treatment the same
 * ball rebounded to 72–77 % of h whatever e, its springs giving the impact
 * back.
 *
 * The ball: an icosphere (2 subdivisions, 162 vertices, radius 0.2 m) with
 * a spring between every two vertices nearer than 0.3 m (through its
 * inside, so that it keeps its shape), 1500 N/m, no damping, 0.05 kg a
 * vertex, no drag, no friction. The rebound is measured on the centre of
 * mass: its highest point after it left the collider, over its height at
 * the first touch. */
#include "tests/test_util.h"

#define G 9.81
#define RADIUS 0.2   /* m */
#define REACH 0.3    /* m: the springs' reach */
#define SPRING 1500. /* N/m */
#define MASS 0.05    /* kg a vertex */
#define DROP 0.5     /* m: h, the lowest point's height over the collider */
#define DT 2e-4      /* s */

/* The ball with its centre at `center`. */
static sb_model* stiff_ball(const double center[3]) {
    sb_mesh mesh = {0};
    sb_error err;
    if (sb_mesh_generate_icosphere(2, RADIUS, &mesh, &err) != SB_OK) fail_msg("%s", err.message);
    sb_builder* b = sb_builder_create();
    const double* p = mesh.positions;
    for (uint32_t i = 0; i < mesh.vertex_count; i++)
        tu_vertex(b, center[0] + p[3 * i], center[1] + p[3 * i + 1], center[2] + p[3 * i + 2], MASS, false);
    for (uint32_t i = 0; i < mesh.vertex_count; i++)
        for (uint32_t j = i + 1; j < mesh.vertex_count; j++) {
            double d[3] = {p[3 * j] - p[3 * i], p[3 * j + 1] - p[3 * i + 1], p[3 * j + 2] - p[3 * i + 2]};
            if (sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) < REACH) tu_bond(b, i, j, -1, 0.0, SPRING, 0.0);
        }
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    sb_mesh_free(&mesh);
    return m;
}

static sb_collider* collider(sb_collider_shape shape, double restitution, const double center[3]) {
    sb_collider_def def = sb_default_collider_def();
    def.shape = shape;
    def.name = "ground";
    def.restitution = restitution;
    def.friction = def.static_friction = 0.0;
    memcpy(def.center, center, sizeof def.center);
    def.radius = 2.0;
    sb_error err;
    sb_collider* c = sb_collider_create(&def, &err);
    if (!c) fail_msg("%s", err.message);
    return c;
}

/* The centre of mass's height along `up` from `base`. */
static double center_height(const sb_solver* s, double* x, const double base[3], const double up[3]) {
    uint32_t n = sb_solver_vertex_count(s);
    sb_solver_get_positions(s, x);
    double c[3] = {0, 0, 0};
    for (uint32_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) c[k] += x[3 * i + k] / n;
    return (c[0] - base[0]) * up[0] + (c[1] - base[1]) * up[1] + (c[2] - base[2]) * up[2];
}

/* The rebound over the drop: the centre's highest point after its lowest,
 * over its height at the first touch (the drop from the start to there is
 * h); the run stops once the centre falls again clear of the collider. */
static double rebound_ratio(const sb_model* m, sb_collider* ground, sb_integrator integrator, sb_kernels kernels,
                            const double base[3], const double up[3]) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.kernels = kernels;
    def.gravity[2] = -G;
    def.colliders = &ground;
    def.collider_count = 1;
    def.runtime.threads = 1;
    sb_solver* s = tu_solver(m, &def);
    double* x = malloc(3 * (size_t)sb_solver_vertex_count(s) * sizeof *x);
    assert_non_null(x);
    double start = center_height(s, x, base, up), touch = NAN, lowest = INFINITY, apex = -INFINITY;
    int clear = 0;                            /* steps since the last contact */
    for (int step = 0; step < 5000; step++) { /* 1 s: the fall takes 0.32 s, the highest rise as long */
        tu_advance(s, DT, 1);
        double height = center_height(s, x, base, up);
        clear = sb_solver_last_step(s).contacts > 0 ? 0 : clear + 1;
        if (clear == 0 && isnan(touch)) touch = height;
        if (isnan(touch)) continue;
        if (height < lowest) lowest = height, apex = height;
        apex = fmax(apex, height);
        if (clear > 100 && height < apex - 1e-3) break; /* falling again */
    }
    free(x);
    sb_solver_destroy(s);
    assert_false(isnan(touch));
    return (apex - touch) / (start - touch);
}

/* Within 15 % of e² (for e = 0: below 0.15 × 0.25, the tolerance of e = 0.5). */
static void expect_rebound(double ratio, double e, const char* what) {
    print_message("%s, e = %.1f: rebound %.3f of the drop, e² = %.3f\n", what, e, ratio, e * e);
    TU_ASSERT_LE(fabs(ratio - e * e), 0.15 * fmax(e * e, 0.25));
}

/* Onto the plane z = 0, for e = 0, 0.5, 0.9, with each integrator that
 * answers contact by the contact pass. */
static void test_ball_on_a_plane(void** state) {
    (void)state;
    const double center[3] = {0, 0, RADIUS + DROP}, base[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    const double restitution[3] = {0.0, 0.5, 0.9};
    const struct {
        sb_integrator integrator;
        sb_kernels kernels;
        const char* name;
    } runs[] = {
        {SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, "verlet (fast)"},
        {SB_INTEGRATOR_VERLET, SB_KERNELS_REFERENCE, "verlet (reference)"},
        {SB_INTEGRATOR_VELOCITY_VERLET, SB_KERNELS_FAST, "velocity verlet (fast)"},
        {SB_INTEGRATOR_SYMPLECTIC_EULER, SB_KERNELS_FAST, "symplectic euler"},
        {SB_INTEGRATOR_IMPLICIT_EULER, SB_KERNELS_FAST, "implicit euler"},
        {SB_INTEGRATOR_VBD, SB_KERNELS_FAST, "vbd"},
        {SB_INTEGRATOR_PBD, SB_KERNELS_FAST, "pbd"},
        {SB_INTEGRATOR_XPBD, SB_KERNELS_FAST, "xpbd"},
    };
    sb_model* m = stiff_ball(center);
    for (size_t r = 0; r < sizeof runs / sizeof runs[0]; r++)
        for (int k = 0; k < 3; k++) {
            sb_collider* plane = collider(SB_COLLIDER_PLANE, restitution[k], base);
            expect_rebound(rebound_ratio(m, plane, runs[r].integrator, runs[r].kernels, base, up), restitution[k],
                           runs[r].name);
            sb_collider_destroy(plane);
        }
    sb_model_destroy(m);
}

/* Onto the top of a sphere of radius 2 m: the episode's normal is the mean
 * of the sphere's at the touching vertices. */
static void test_ball_on_a_sphere(void** state) {
    (void)state;
    const double sphere[3] = {0, 0, -2.0}, center[3] = {0, 0, RADIUS + DROP}, up[3] = {0, 0, 1};
    sb_model* m = stiff_ball(center);
    sb_collider* ground = collider(SB_COLLIDER_SPHERE, 0.5, sphere);
    const double base[3] = {0, 0, 0};
    expect_rebound(rebound_ratio(m, ground, SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, base, up), 0.5, "sphere");
    sb_collider_destroy(ground);
    sb_model_destroy(m);
}

/* A solver for the ball onto the plane of e = 0.5 (fast Verlet). */
static sb_solver* ball_solver(const sb_model* m, sb_collider** plane, int threads) {
    sb_solver_def def = sb_default_solver_def();
    def.gravity[2] = -G;
    def.colliders = plane;
    def.collider_count = 1;
    def.runtime.threads = threads;
    return tu_solver(m, &def);
}

/* Through the bounce (the first touch at step 1597, the ball clear by
 * 1760) the state is bitwise the same on 1 and 3 threads, and a run saved
 * mid-contact (step 1650, its episode open) and resumed in a new solver
 * ends bitwise where the uninterrupted one does. */
static void test_deterministic_and_resumed(void** state) {
    (void)state;
    const double center[3] = {0, 0, RADIUS + DROP}, base[3] = {0, 0, 0};
    sb_model* m = stiff_ball(center);
    sb_collider* plane = collider(SB_COLLIDER_PLANE, 0.5, base);
    uint64_t hashes[2];
    for (int t = 0; t < 2; t++) {
        sb_solver* s = ball_solver(m, &plane, 1 + 2 * t);
        tu_advance(s, DT, 1800);
        hashes[t] = tu_state_hash(s);
        sb_solver_destroy(s);
    }
    assert_true(hashes[0] == hashes[1]);
    sb_collider_destroy(plane);

    plane = collider(SB_COLLIDER_PLANE, 0.5, base);
    sb_solver* s = ball_solver(m, &plane, 1);
    tu_advance(s, DT, 1650);
    assert_true(sb_solver_last_step(s).contacts > 0);
    size_t size = sb_solver_state_size(s);
    void* saved = malloc(size);
    assert_non_null(saved);
    sb_error err;
    assert_int_equal(sb_solver_save_state(s, saved, size, &err), SB_OK);
    tu_advance(s, DT, 150);
    uint64_t uninterrupted = tu_state_hash(s);
    sb_solver_destroy(s);
    sb_collider_destroy(plane);

    plane = collider(SB_COLLIDER_PLANE, 0.5, base);
    s = ball_solver(m, &plane, 1);
    assert_int_equal(sb_solver_load_state(s, saved, size, &err), SB_OK);
    tu_advance(s, DT, 150);
    assert_true(tu_state_hash(s) == uninterrupted);
    sb_solver_destroy(s);
    sb_collider_destroy(plane);
    free(saved);
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ball_on_a_plane),
        cmocka_unit_test(test_ball_on_a_sphere),
        cmocka_unit_test(test_deterministic_and_resumed),
    };
    return TU_RUN_TESTS(tests);
}
