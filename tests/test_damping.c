/* Rayleigh's stiffness-proportional damping (tissue.stiffness_damping β)
 * against its closed-form law: with D = β K every mode of angular frequency
 * ω is a damped oscillator of damping ratio ζ = β ω / 2, whatever the mesh.
 *
 * A 20 mm cube of tissue, its bottom face held, starts at rest shape with a
 * sideways velocity growing with height (the sway mode's shape, roughly)
 * and no gravity. The mass-weighted mean sideways displacement then rings
 * in the lowest sway mode (the higher ones, excited a little, die faster:
 * their ζ grows with ω). From its peaks the test measures the damped
 * period and the decrement per period, hence ω and ζ, and holds ζ to
 * β ω / 2 — both measured from the run, so the law is the oracle — for the
 * corotated elements, linear and quadratic, and for the springs (c = β k
 * per spring), on two meshes: the settle time 1/(ζ ω) and the frequency
 * must stay put when the mesh is refined. A strip of a sheet's membrane
 * (sheet.stiffness_damping) rings likewise in its first stretching mode,
 * whose frequency is also held to the bar's closed form. */
#include "tests/test_util.h"
#include "bench/fem_oracle.h"
#include "softbond/volume.h"
#include "kernels/forces/hessian.h"

#define CUBE 0.02 /* m */
#define YOUNG 3500.0
#define DENSITY 1060.0
#define SWAY 0.01 /* m/s at the top */

typedef struct ring {
    double omega, zeta; /* the measured lowest mode: natural angular frequency, damping ratio */
} ring;

typedef struct ring_case {
    sb_tissue_model model;
    int cells;         /* across the cube */
    double beta, rule; /* tissue.stiffness_damping, tissue.damping */
    sb_integrator integrator;
    sb_kernels kernels;
} ring_case;

static sb_model* ring_model(const ring_case* c) {
    fem_mesh m = fem_box(CUBE, CUBE / 2, CUBE, 2 * c->cells, c->cells, 2 * c->cells);
    sb_tet_mesh tm = {.vertex_count = m.nodes, .positions = m.x, .tet_count = m.tets, .tets = m.tet};
    sb_tissue_def tissue = sb_default_tissue_def();
    tissue.young_modulus = YOUNG;
    tissue.density = DENSITY;
    tissue.poisson_ratio = 0.3;
    tissue.model = c->model;
    tissue.damping = c->rule;
    tissue.stiffness_damping = c->beta;
    sb_builder* b = sb_builder_create();
    sb_error err = {0};
    assert_int_equal(sb_builder_add_tet_mesh(b, &tm, &tissue, &err), SB_OK);
    for (uint32_t i = 0; i < m.nodes; i++) {
        sb_vertex_def* v = sb_builder_vertex(b, i);
        v->fixed = m.x[3 * i + 2] < 1e-9;
        v->velocity[1] = v->fixed ? 0.0 : SWAY * m.x[3 * i + 2] / CUBE;
    }
    sb_model* model = tu_compile(b);
    sb_builder_destroy(b);
    fem_mesh_free(&m);
    return model;
}

/* The mass-weighted mean displacement along `axis`. */
static double ring_sway(const sb_solver* s, const sb_model* m, int axis, double* x) {
    uint32_t n = sb_model_vertex_count(m);
    sb_solver_get_positions(s, x);
    double sum = 0.0, mass = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        double rest[3];
        sb_model_rest_position(m, i, rest);
        sum += sb_model_mass(m, i) * (x[3 * i + axis] - rest[axis]);
        mass += sb_model_mass(m, i);
    }
    return sum / mass;
}

/* The parabola's vertex through three samples a step apart: its time
 * offset from the middle one (in steps) and its height. */
static void ring_vertex(const double y[3], double* offset, double* height) {
    double curvature = y[0] - 2.0 * y[1] + y[2];
    *offset = 0.5 * (y[0] - y[2]) / curvature;
    *height = y[1] - 0.25 * (y[0] - y[2]) * *offset;
}

/* The first maxima, where the higher modes still ring, are skipped. */
#define SKIP 2

/* A damped oscillator's ζ and ω from its decrement δ per damped period T_d
 * (time-continuous: ζ = δ / √(4π² + δ²), ω = 2π / (T_d √(1 − ζ²))). */
static ring ring_continuous(double period, double delta) {
    ring r;
    r.zeta = delta / sqrt(4.0 * M_PI * M_PI + delta * delta);
    r.omega = 2.0 * M_PI / (period * sqrt(1.0 - r.zeta * r.zeta));
    return r;
}

/* The same oscillator as backward Euler steps it: each step multiplies the
 * mode by z, a root of (1 + 2ζω dt + ω² dt²) z² − (2 + 2ζω dt) z + 1 = 0,
 * so from the measured z = e^(−δ dt / T_d + i 2π dt / T_d): a = 1 / |z|²,
 * b = 2 a |z| cos(arg z), ω dt = √(a − b + 1), ζ = (b − 2) / (2 ω dt). */
static ring ring_backward_euler(double period, double delta, double dt) {
    double modulus = exp(-delta * dt / period), angle = 2.0 * M_PI * dt / period;
    double a = 1.0 / (modulus * modulus), b = 2.0 * a * modulus * cos(angle);
    double omega_dt = sqrt(a - b + 1.0);
    return (ring){omega_dt / dt, (b - 2.0) / (2.0 * omega_dt)};
}

/* Steps model m until `peaks` maxima of its mean displacement along `axis`
 * past the skipped are seen; from the first and the last the damped period
 * and the decrement per period, then the oscillator's ζ and ω (backward
 * Euler's own law for it). Destroys m. */
static ring ring_run(sb_model* m, sb_integrator integrator, sb_kernels kernels, int axis, double dt, int peaks) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.kernels = kernels;
    def.gravity[2] = 0.0;
    sb_solver* s = tu_solver(m, &def);
    double* x = malloc(3 * sizeof(double) * sb_model_vertex_count(m));
    double y[3] = {0.0, 0.0, 0.0}, first_t = 0.0, first_a = 0.0, last_t = 0.0, last_a = 0.0;
    int seen = 0;
    for (uint64_t step = 1; seen < SKIP + peaks && step < 2000000; step++) {
        tu_advance(s, dt, 1);
        y[0] = y[1], y[1] = y[2], y[2] = ring_sway(s, m, axis, x);
        if (step < 3 || !(y[1] > y[0] && y[1] >= y[2] && y[1] > 0.0)) continue;
        double offset, height;
        ring_vertex(y, &offset, &height);
        double t = ((double)step - 1.0 + offset) * dt;
        if (++seen <= SKIP) continue;
        if (seen == SKIP + 1)
            first_t = t, first_a = height;
        else
            last_t = t, last_a = height;
    }
    assert_int_equal(seen, SKIP + peaks);
    double period = (last_t - first_t) / (peaks - 1), delta = log(first_a / last_a) / (peaks - 1);
    free(x);
    sb_solver_destroy(s);
    sb_model_destroy(m);
    return integrator == SB_INTEGRATOR_IMPLICIT_EULER || integrator == SB_INTEGRATOR_VBD
               ? ring_backward_euler(period, delta, dt)
               : ring_continuous(period, delta);
}

static ring ring_measure(const ring_case* c, double dt, int peaks) {
    return ring_run(ring_model(c), c->integrator, c->kernels, 1, dt, peaks);
}

/* The lowest sway mode of the cube: about 90 rad/s for ν 0.3 (a period of
 * 70 ms). β = 1.2 ms gives it ζ ≈ 0.05. The step: 0.1 ms, well inside the
 * explicit limit 2 / (β ω_max²) of the highest, overdamped modes of the
 * finer mesh. */
#define BETA 1.2e-3
#define STEP 1e-4

/* Peaks measured: the springs' sway carries more of the other modes. */
static int ring_peaks(sb_tissue_model model) { return model == SB_TISSUE_SPRINGS ? 6 : 4; }

static const char* ring_model_name(sb_tissue_model model) {
    return model == SB_TISSUE_COROTATED             ? "corotated"
           : model == SB_TISSUE_COROTATED_QUADRATIC ? "corotated quadratic"
                                                    : "springs";
}

static ring ring_law(sb_tissue_model model, int cells, sb_integrator integrator, sb_kernels kernels, double dt) {
    ring_case c = {model, cells, BETA, 0.0, integrator, kernels};
    ring r = ring_measure(&c, dt, ring_peaks(model));
    double law = BETA * r.omega / 2.0;
    print_message("%s, %d cells, %s, %s: omega %.3f rad/s, zeta %.5f, beta omega / 2 %.5f (%+.2f %%), settle 1/(zeta "
                  "omega) %.4f s\n",
                  ring_model_name(model), cells, kernels == SB_KERNELS_FAST ? "fast" : "reference",
                  sb_integrator_name(integrator), r.omega, r.zeta, law, 100.0 * (r.zeta / law - 1.0),
                  1.0 / (r.zeta * r.omega));
    assert_true(fabs(r.zeta / law - 1.0) < 0.05);
    return r;
}

/* Refining the mesh: the settle time 1/(ζ ω) = 2/(β ω²) moves only as the
 * element's own stiffness converges (ω², which the damping does not
 * touch): within `settle` of the coarse mesh's, ω within `stiffness`. */
static void ring_same(ring coarse, ring fine, double settle, double stiffness) {
    double settle_change = (coarse.zeta * coarse.omega) / (fine.zeta * fine.omega) - 1.0;
    double omega = fine.omega / coarse.omega - 1.0;
    print_message("refined: settle time %+.2f %%, omega %+.2f %%\n", 100.0 * settle_change, 100.0 * omega);
    assert_true(fabs(settle_change) < settle);
    assert_true(fabs(omega) < stiffness);
}

static void test_corotated_rayleigh(void** state) {
    (void)state;
    ring coarse = ring_law(SB_TISSUE_COROTATED, 3, SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, STEP);
    ring fine = ring_law(SB_TISSUE_COROTATED, 6, SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, STEP);
    ring_same(coarse, fine, 0.25, 0.12); /* linear tetrahedra stiff in bending: ω −9 % */
    ring reference = ring_law(SB_TISSUE_COROTATED, 3, SB_INTEGRATOR_VERLET, SB_KERNELS_REFERENCE, STEP);
    assert_true(fabs(reference.zeta / coarse.zeta - 1.0) < 1e-3);
}

/* Backward Euler with the damping in its residual and D = β K in its
 * Jacobian (its own discrete law, ring_backward_euler), and vbd's
 * per-vertex share of it. */
static void test_corotated_rayleigh_implicit(void** state) {
    (void)state;
    ring_law(SB_TISSUE_COROTATED, 2, SB_INTEGRATOR_IMPLICIT_EULER, SB_KERNELS_FAST, 30 * STEP);
    ring_law(SB_TISSUE_COROTATED, 2, SB_INTEGRATOR_VBD, SB_KERNELS_REFERENCE, 30 * STEP);
}

/* The quadratic elements: −β R K0 Rᵀ v with their own K0, in the
 * reference and fast passes, implicit Euler's Jacobian and vbd. */
static void test_quadratic_rayleigh(void** state) {
    (void)state;
    ring fast = ring_law(SB_TISSUE_COROTATED_QUADRATIC, 1, SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, STEP);
    ring reference = ring_law(SB_TISSUE_COROTATED_QUADRATIC, 1, SB_INTEGRATOR_VERLET, SB_KERNELS_REFERENCE, STEP);
    assert_true(fabs(reference.zeta / fast.zeta - 1.0) < 1e-3);
}

/* Refined under implicit Euler (the finer mesh's middle nodes need a
 * smaller explicit step); vbd's share on the coarse one. */
static void test_quadratic_rayleigh_implicit(void** state) {
    (void)state;
    ring coarse = ring_law(SB_TISSUE_COROTATED_QUADRATIC, 1, SB_INTEGRATOR_IMPLICIT_EULER, SB_KERNELS_FAST, 30 * STEP);
    ring fine = ring_law(SB_TISSUE_COROTATED_QUADRATIC, 2, SB_INTEGRATOR_IMPLICIT_EULER, SB_KERNELS_FAST, 30 * STEP);
    ring_same(coarse, fine, 0.15, 0.08); /* measured: settle +11 %, ω −5.3 % */
    ring_law(SB_TISSUE_COROTATED_QUADRATIC, 1, SB_INTEGRATOR_VBD, SB_KERNELS_REFERENCE, 30 * STEP);
}

static void test_springs_rayleigh(void** state) {
    (void)state;
    ring coarse = ring_law(SB_TISSUE_SPRINGS, 3, SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, STEP);
    ring fine = ring_law(SB_TISSUE_SPRINGS, 6, SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, STEP);
    ring_same(coarse, fine, 0.15, 0.06);
}

/* A strip of membrane (the sheet factory, E 30 kPa, ν 0.45, 1 mm thick),
 * 100 mm by 20 mm, its end x = 0 held, rings in its first stretching mode
 * along x: started at rest shape with the velocity V sin(π x / 2L) along
 * x, the mode's shape; the higher modes it excites a little die faster.
 * Its frequency: the bar's ω = (π / 2L) √(E / ρ) (83.8 rad/s; the narrow
 * strip's Poisson contraction is free), held within 3 %; ζ to β ω / 2 as
 * above, on two meshes. The motion stays in the sheet's plane, so its
 * hinges (undamped) never bend. */
#define STRIP_LENGTH 0.1
#define STRIP_WIDTH 0.02
#define STRIP_YOUNG 30e3
#define STRIP_BETA 1.2e-3

static sb_model* strip_model(uint32_t columns) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = columns + 1;
    sheet.ny = columns / 5 + 1;
    sheet.width = STRIP_LENGTH;
    sheet.height = STRIP_WIDTH;
    sb_mesh mesh;
    sb_error err = {0};
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    sb_sheet_material_def material = sb_default_sheet_material_def();
    material.young_modulus = STRIP_YOUNG;
    material.density = DENSITY;
    material.stiffness_damping = STRIP_BETA;
    sb_builder* b = sb_builder_create();
    assert_int_equal(sb_builder_add_sheet(b, &mesh, &material, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) {
        sb_vertex_def* v = sb_builder_vertex(b, i);
        double x = mesh.positions[3 * i];
        v->fixed = x < 1e-9;
        v->velocity[0] = v->fixed ? 0.0 : SWAY * sin(M_PI * x / (2.0 * STRIP_LENGTH));
    }
    sb_model* model = tu_compile(b);
    sb_builder_destroy(b);
    sb_mesh_free(&mesh);
    return model;
}

static ring strip_law(uint32_t columns, sb_integrator integrator, sb_kernels kernels, double dt) {
    ring r = ring_run(strip_model(columns), integrator, kernels, 0, dt, 4);
    double law = STRIP_BETA * r.omega / 2.0, bar = M_PI / (2.0 * STRIP_LENGTH) * sqrt(STRIP_YOUNG / DENSITY);
    print_message("membrane strip, %u columns, %s, %s: omega %.3f rad/s (bar %.3f, %+.2f %%), zeta %.5f, beta omega / "
                  "2 %.5f (%+.2f %%)\n",
                  columns, kernels == SB_KERNELS_FAST ? "fast" : "reference", sb_integrator_name(integrator), r.omega,
                  bar, 100.0 * (r.omega / bar - 1.0), r.zeta, law, 100.0 * (r.zeta / law - 1.0));
    assert_true(fabs(r.zeta / law - 1.0) < 0.05);
    assert_true(fabs(r.omega / bar - 1.0) < 0.03);
    return r;
}

static void test_membrane_rayleigh(void** state) {
    (void)state;
    ring coarse = strip_law(10, SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, STEP);
    ring fine = strip_law(20, SB_INTEGRATOR_VERLET, SB_KERNELS_FAST, STEP);
    ring_same(coarse, fine, 0.05, 0.02);
    ring reference = strip_law(10, SB_INTEGRATOR_VERLET, SB_KERNELS_REFERENCE, STEP);
    assert_true(fabs(reference.zeta / coarse.zeta - 1.0) < 1e-3);
    strip_law(10, SB_INTEGRATOR_IMPLICIT_EULER, SB_KERNELS_FAST, 10 * STEP);
    strip_law(10, SB_INTEGRATOR_VBD, SB_KERNELS_REFERENCE, 10 * STEP);
}

/* The damping force itself, at a strained and turned state: the forces at
 * (x, v) less those at x alone against −β K v, K the elements' co-rotated
 * stiffness assembled from their matrices (kernels/forces/hessian.h; the
 * passes compute K v matrix-free, as a viscous stress), for the quadratic
 * tetrahedra and the membranes; and nothing for a rigid spin of the
 * unstrained, turned body. Relative to the largest Σ |β K_rc v_c|. */
static double damping_force_error(sb_model* m, double beta, bool spin) {
    uint32_t n = sb_model_vertex_count(m);
    size_t n3 = 3 * (size_t)n;
    double *x = malloc(n3 * sizeof *x), *v = malloc(n3 * sizeof *v), *f = malloc(n3 * sizeof *f);
    double *elastic = malloc(n3 * sizeof *f), *expected = calloc(n3, sizeof *f), *size_of = calloc(n3, sizeof *f);
    double k[SB_ELEMENT_MATRIX], c = cos(0.4), s = sin(0.4); /* a turn of 0.4 rad about z */
    tu_rng rng = {7};
    for (uint32_t i = 0; i < n; i++) {
        double p[3];
        sb_model_rest_position(m, i, p);
        double turned[3] = {c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]};
        for (int a = 0; a < 3; a++) x[3 * i + a] = turned[a] + (spin ? 0.0 : tu_uniform(&rng, -5e-4, 5e-4));
        double whirl[3] = {-3.0 * x[3 * i + 1], 3.0 * x[3 * i], 0.0}; /* 3 rad/s about z */
        for (int a = 0; a < 3; a++) v[3 * i + a] = spin ? whirl[a] : tu_uniform(&rng, -0.01, 0.01);
    }
    sb_energies e;
    sb_error err;
    assert_int_equal(sb_reference_forces(m, x, v, f, &e, &err), SB_OK);
    assert_int_equal(sb_reference_forces(m, x, NULL, elastic, &e, &err), SB_OK);
    for (uint64_t id = 0; id < sb_element_count(m); id++) {
        sb_element el = sb_element_at(m, id);
        if (el.kind != SB_ELEMENT_TET && el.kind != SB_ELEMENT_MEMBRANE) continue;
        assert_true(sb_element_stiffness(m, &el, x, k));
        int size = 3 * el.count;
        for (int r = 0; r < size; r++)
            for (int q = 0; q < size; q++) {
                size_t row = 3 * (size_t)el.vertex[r / 3] + r % 3, col = 3 * (size_t)el.vertex[q / 3] + q % 3;
                expected[row] -= beta * k[r * size + q] * v[col];
                size_of[row] += fabs(beta * k[r * size + q] * v[col]);
            }
    }
    double error = 0.0, scale = 0.0;
    for (size_t q = 0; q < n3; q++) {
        error = fmax(error, fabs(f[q] - elastic[q] - (spin ? 0.0 : expected[q])));
        scale = fmax(scale, size_of[q]);
    }
    free(x), free(v), free(f), free(elastic), free(expected), free(size_of);
    sb_model_destroy(m);
    return error / scale;
}

static void test_damping_force_is_beta_k_v(void** state) {
    (void)state;
    ring_case quadratic = {SB_TISSUE_COROTATED_QUADRATIC, 1, BETA, 0.0, SB_INTEGRATOR_VERLET, SB_KERNELS_REFERENCE};
    double tet = damping_force_error(ring_model(&quadratic), BETA, false);
    double membrane = damping_force_error(strip_model(10), STRIP_BETA, false);
    double tet_spin = damping_force_error(ring_model(&quadratic), BETA, true);
    double membrane_spin = damping_force_error(strip_model(10), STRIP_BETA, true);
    print_message("damping force against -beta K v: quadratic tetrahedra %.3g, membranes %.3g; under a rigid spin "
                  "%.3g, %.3g\n",
                  tet, membrane, tet_spin, membrane_spin);
    TU_ASSERT_LE(tet, 1e-12);
    TU_ASSERT_LE(membrane, 1e-12);
    TU_ASSERT_LE(tet_spin, 1e-12);
    TU_ASSERT_LE(membrane_spin, 1e-12);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_corotated_rayleigh),        cmocka_unit_test(test_corotated_rayleigh_implicit),
        cmocka_unit_test(test_quadratic_rayleigh),        cmocka_unit_test(test_quadratic_rayleigh_implicit),
        cmocka_unit_test(test_springs_rayleigh),          cmocka_unit_test(test_membrane_rayleigh),
        cmocka_unit_test(test_damping_force_is_beta_k_v),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
