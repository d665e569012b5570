/* sb_bench_materials: the speed–accuracy chart of the tissue models
 * (issue 29), written to materials_chart.csv in the folder given (bench/
 * materials_chart.sh runs it and draws materials_chart.png).
 *
 * For each model (tissue.model springs, corotated, corotated_quadratic),
 * two cases at three resolutions each:
 *   - the cantilever of bench/fem_static.h (100 × 20 × 20 mm clamped at
 *     x = 0, E 3.5 kPa, ν 0.45, a shear traction on the tip face) at 1, 2
 *     and 3 cells across its thickness; the error: softbond's static
 *     deflection of the tip's lower edge against CalculiX's C3D10 at 4
 *     cells across (ccx run here, through bench/fem_oracle.h, on the same
 *     box meshes), in per cent;
 *   - the indentation of bench/fem_indent.h (a block 20 × 20 × 10 mm
 *     clamped on its bottom, a rigid sphere of radius 5 mm pressed 1 mm
 *     deep, E 3.5 kPa, ν 0.45) at 2, 3 and 4 cells across its thickness
 *     for the quadratic element and 4, 6 and 8 for the others (the same
 *     vertex counts: 405, about 1 200, 2 601); the error: the force on
 *     softbond's sphere collider at rest against ccx's C3D10 with the
 *     contact's active set on the quarter block at 10 cells across;
 *   - the cost: the wall time of a Verlet step on the fast kernels with 2
 *     threads at the model's stable step (stable_step: the largest of
 *     0.9 × 0.7^k × 2/ω_max that runs, ω_max by power iteration on M⁻¹K,
 *     K's products from central differences of the reference forces),
 *     best of RUNS runs of STEPS steps, in µs; with the step it also gives
 *     the cost of a simulated second.
 * The design choice: a C program rather than a script over `softbond run`,
 * so that the meshes, clamps and loads are the oracle's very arrays and
 * the static answer is the one tests/test_fem.c checks. */
#define _GNU_SOURCE
#include "bench/fem_indent.h"

#include <stdio.h>
#include <time.h>

#define STEPS 300
#define RUNS 3
#define REFERENCE_CELLS 4
#define INDENT_REFERENCE_CELLS 10
#define THREADS 2
#define PERTURBATION 1e-4 /* m: the free vertices' random start, exciting every mode */

static const sb_tissue_model models[] = {SB_TISSUE_SPRINGS, SB_TISSUE_COROTATED, SB_TISSUE_COROTATED_QUADRATIC};
static const char* const model_names[] = {"springs", "corotated", "corotated_quadratic"};

/* ω_max of M⁻¹K at rest on the free vertices, by power iteration on the
 * symmetric M^-½ K M^-½. */
static double omega_max(const fem_body* body, double scale) {
    size_t n3 = 3 * (size_t)body->count;
    double *p = malloc(n3 * 8), *q = malloc(n3 * 8), *w = malloc(n3 * 8);
    fem_static s = {.model = body->model, .load = body->load, .held = body->held, .n3 = n3};
    s.fp = malloc(n3 * 8), s.fm = malloc(n3 * 8), s.xp = malloc(n3 * 8);
    unsigned seed = 7;
    for (size_t k = 0; k < n3; k++) p[k] = body->held[k / 3] ? 0.0 : (double)rand_r(&seed) / RAND_MAX - 0.5;
    double lambda = 0.0;
    for (int it = 0; it < 5000; it++) {
        double norm = sqrt(fem_dot(p, p, n3));
        for (size_t k = 0; k < n3; k++) w[k] = p[k] / norm / sqrt(sb_model_mass(body->model, (uint32_t)(k / 3)));
        fem_product(&s, body->rest, w, q, scale);
        for (size_t k = 0; k < n3; k++) q[k] /= sqrt(sb_model_mass(body->model, (uint32_t)(k / 3)));
        double rayleigh = fem_dot(p, q, n3) / norm;
        bool converged = fabs(rayleigh - lambda) <= 1e-8 * rayleigh;
        lambda = rayleigh;
        memcpy(p, q, n3 * 8);
        if (converged) break;
    }
    free(p), free(q), free(w), free(s.fp), free(s.fm), free(s.xp);
    return sqrt(lambda);
}

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The best wall time of a Verlet step (fast kernels, THREADS threads, no
 * gravity, the free vertices started PERTURBATION off rest at random) in
 * µs over RUNS runs of STEPS steps, or NAN when a step fails (a run away:
 * dt beyond the model's stable step). */
static double step_cost(const fem_body* body, double dt) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_VERLET;
    def.kernels = SB_KERNELS_FAST;
    def.runtime.threads = THREADS;
    def.gravity[2] = 0.0;
    sb_error err = {0};
    sb_solver* solver = sb_solver_create(body->model, &def, &err);
    if (!solver) {
        fprintf(stderr, "sb_bench_materials: %s\n", err.message);
        return NAN;
    }
    size_t n3 = 3 * (size_t)body->count;
    double *x = malloc(n3 * 8), *v = calloc(n3, 8);
    unsigned seed = 11;
    for (size_t k = 0; k < n3; k++)
        x[k] = body->rest[k] + (body->held[k / 3] ? 0.0 : PERTURBATION * ((double)rand_r(&seed) / RAND_MAX - 0.5));
    bool failed = sb_solver_set_state(solver, x, v) != SB_OK;
    free(x), free(v);
    double best = INFINITY;
    for (int run = 0; run < RUNS && !failed; run++) {
        double start = now();
        for (int k = 0; k < STEPS && !failed; k++) failed = sb_solver_advance(solver, dt) != SB_OK;
        best = fmin(best, (now() - start) / STEPS);
    }
    sb_solver_destroy(solver);
    return failed ? NAN : 1e6 * best;
}

/* The model's stable step: the largest of 0.9, 0.63, 0.44 … (× 0.7^k)
 * × 2/ω_max (the undamped limit; the springs' damping, the papers' rule,
 * lowers it many times) at which the
 * perturbed body runs RUNS x STEPS steps; its cost in *us (NAN when none does). */
static double stable_step(const fem_body* body, double scale, double* us) {
    double dt = 0.9 * 2.0 / omega_max(body, scale);
    for (int tries = 0; tries < 30; tries++, dt *= 0.7) {
        *us = step_cost(body, dt);
        if (!isnan(*us)) return dt;
    }
    return dt;
}

/* One row of the chart: the model's answer and error, its stable step and cost. */
static int write_row(FILE* csv, const char* name, size_t m, int n, fem_body* body, double mine, double reference,
                     double scale) {
    if (isnan(mine)) {
        fprintf(stderr, "sb_bench_materials: %s, %s at %d cells across failed\n", name, model_names[m], n);
        return 1;
    }
    double us, dt = stable_step(body, scale, &us);
    double error = 100.0 * (mine / reference - 1.0);
    fprintf(csv, "%s,%s,%d,%u,%.6g,%.3f,%.4g,%.4g,%.4g\n", name, model_names[m], n, body->count, mine, error, dt, us,
            1e-3 * us / dt);
    printf("%-12s %-20s %d across %5u vertices: error %+7.2f %%, dt %.3g s, %.3g us a step\n", name, model_names[m], n,
           body->count, error, dt, us);
    fflush(stdout);
    return isnan(us);
}

/* The cantilever's rows: the static deflection at 1, 2, 3 cells across. */
static int cantilever_rows(FILE* csv, const fem_problem* pb, double reference) {
    int status = 0;
    for (size_t m = 0; m < sizeof models / sizeof *models; m++)
        for (int n = 1; n <= 3; n++) {
            fem_body body = fem_body_build(pb, n, models[m]);
            double mine = fem_body_static(&body, pb);
            status |= write_row(csv, "cantilever", m, n, &body, mine, reference, pb->lz);
            fem_body_free(&body);
        }
    return status;
}

/* The indentation's rows: the sphere's force at rest, at the same vertex
 * counts for every model. */
static int indentation_rows(FILE* csv, const fem_indent* in, double reference) {
    int status = 0;
    fem_problem pb = fem_indent_problem(in);
    pb.undamped = false; /* the cost with the papers' damping rule, as the cantilever's */
    for (size_t m = 0; m < sizeof models / sizeof *models; m++)
        for (int k = 2; k <= 4; k++) {
            int n = models[m] == SB_TISSUE_COROTATED_QUADRATIC ? k : 2 * k;
            double mine = fem_indent_softbond(in, n, models[m], NULL);
            fem_body body = fem_body_build(&pb, n, models[m]);
            status |= write_row(csv, "indentation", m, n, &body, mine, reference, in->lz);
            fem_body_free(&body);
        }
    return status;
}

int main(int argc, char** argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: sb_bench_materials RESULTS_DIR\n");
        return 2;
    }
    char work[] = "/tmp/sb_bench_materials_XXXXXX", dir[600], path[1200];
    if (!mkdtemp(work)) {
        perror("sb_bench_materials: mkdtemp");
        return 1;
    }
    fem_problem pb = fem_cantilever_of(FEM_E, 0.45, false);
    fem_indent in = fem_indent_case(FEM_E, 0.45, 1e-3);
    snprintf(dir, sizeof dir, "%s/reference", work);
    double reference = fem_oracle_probe(&pb, REFERENCE_CELLS, true, dir);
    snprintf(dir, sizeof dir, "%s/indentation", work);
    double indent_reference = fem_indent_oracle(&in, INDENT_REFERENCE_CELLS, true, dir, NULL);
    if (isnan(reference) || isnan(indent_reference)) {
        fprintf(stderr, "sb_bench_materials: ccx failed in %s (see ccx.log there)\n", work);
        return 1;
    }
    snprintf(path, sizeof path, "%s/materials_chart.csv", argv[1]);
    FILE* csv = fopen(path, "w");
    if (!csv) {
        perror(path);
        return 1;
    }
    fprintf(csv,
            "# speed-accuracy of the tissue models (bench/bench_materials.c): cantilever 100 x 20 x 20 mm, E %g Pa, nu "
            "%g, tip shear traction %g Pa, the error of the tip's lower edge deflection against ccx C3D10 at %d cells "
            "across (%.6g m); indentation of a block 20 x 20 x 10 mm clamped below by a rigid sphere of radius %g mm "
            "%g mm deep, E %g Pa, nu %g, the error of the force at rest against ccx C3D10 with the contact's active "
            "set at %d cells across (%.6g N); cost: Verlet, fast kernels, %d threads, best of %d x %d steps at the "
            "largest 0.9 x 0.7^k x 2/omega_max that runs\n",
            pb.c.young_modulus, pb.c.poisson_ratio, -pb.c.traction[2], REFERENCE_CELLS, reference, 1e3 * in.radius,
            1e3 * in.depth, in.young_modulus, in.poisson_ratio, INDENT_REFERENCE_CELLS, indent_reference, THREADS, RUNS,
            STEPS);
    fprintf(csv, "case,model,cells_across,vertices,answer,error_percent,dt_s,us_per_step,ms_per_simulated_s\n");
    int status = cantilever_rows(csv, &pb, reference) | indentation_rows(csv, &in, indent_reference);
    fclose(csv);
    snprintf(path, sizeof path, "rm -rf '%s'", work);
    if (system(path) != 0) fprintf(stderr, "sb_bench_materials: could not remove %s\n", work);
    return status;
}
