/* The integrator study (issue 4): how far each integrator's step can go,
 * and what accuracy each buys for its CPU time, on the square sheet of
 * Sudhamani & Merriliance (2019): fixed along its left edge, a force at its
 * middle.
 *
 *   sb_study [--quick] [--out DIR]      (DIR defaults to bench/results)
 *
 * Writes DIR/stability.csv and DIR/work_precision.csv; bench/study.gp
 * draws them. Every run uses the double scalar reference for the forces,
 * so the comparison is between integrators, not kernels.
 *
 * Stability: for bond stiffness k over four decades, the largest step at
 * which a run of 400 steps from a perturbed state neither stops
 * (SB_ERR_UNSTABLE) nor multiplies its total energy by more than 10, found
 * by bisection on log dt between 1e-3 and 100 times 2/ω_max. ω_max, the
 * sheet's highest angular frequency, comes from power iteration on
 * M^-1/2 K M^-1/2 with K p the central directional difference of the
 * reference forces: Verlet's limit is dt = 2/ω_max.
 *
 * Work-precision: a force of 0.5 N pushes the middle vertex out of plane
 * for 0.2 s; the error is the largest distance of any vertex from a
 * velocity-Verlet run with a step 512 times smaller than 2/ω_max, against
 * the CPU time of the run, for steps from 20 down to 0.0125 times 2/ω_max,
 * each integrator only up to the largest stable step the stability part
 * measured for it at this stiffness (a run beyond it is not a point of
 * accuracy, it is a blow-up that 0.2 s is too short to catch). */
#include "softbond/softbond.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define SHEET_N 12        /* vertices per side */
#define SHEET_MASS 0.01   /* kg per vertex */
#define PUSH_FORCE 0.5    /* N, at the middle vertex */
#define PUSH_TIME 0.2     /* s */
#define STABLE_STEPS 400  /* steps a stable run must survive */

typedef struct study_sheet {
    sb_mesh mesh;
    sb_model* model;
    uint32_t middle;
} study_sheet;

/* The sheet with bond stretch k and angle bend scaled with it, left edge fixed. */
static study_sheet make_sheet(double k) {
    study_sheet s = {0};
    sb_error err;
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = def.ny = SHEET_N;
    if (sb_mesh_generate_sheet(&def, &s.mesh, &err) != SB_OK) exit(fprintf(stderr, "sb_study: %s\n", err.message));
    sb_material_def material = sb_default_material_def();
    material.bond_k = k;
    material.angle_k = 1e-3 * k;
    material.spring_damping = 0.0;
    material.mass = SHEET_MASS;
    sb_builder* builder = sb_builder_create();
    if (sb_builder_add_mesh(builder, &s.mesh, &material, &err) != SB_OK)
        exit(fprintf(stderr, "sb_study: %s\n", err.message));
    for (uint32_t row = 0; row < SHEET_N; row++) sb_builder_vertex(builder, row * SHEET_N)->fixed = true;
    s.model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    if (!s.model) exit(fprintf(stderr, "sb_study: %s\n", err.message));
    s.middle = (SHEET_N / 2) * SHEET_N + SHEET_N / 2;
    return s;
}

static void free_sheet(study_sheet* s) {
    sb_model_destroy(s->model);
    sb_mesh_free(&s->mesh);
}

/* K p by central differences of the reference forces at the rest shape,
 * free vertices only. */
static void stiffness_product(const study_sheet* s, const double* p, double* out, double* work) {
    uint32_t n3 = 3 * s->mesh.vertex_count;
    double *plus = work, *minus = work + n3, *x = work + 2 * n3, eps = 1e-7;
    sb_energies e;
    sb_error err;
    for (int sign = 0; sign < 2; sign++) {
        for (uint32_t i = 0; i < n3; i++) x[i] = s->mesh.positions[i] + (sign ? -eps : eps) * p[i];
        sb_reference_forces(s->model, x, NULL, sign ? minus : plus, &e, &err);
    }
    for (uint32_t i = 0; i < n3; i++)
        out[i] = sb_model_is_fixed(s->model, i / 3) ? 0.0 : -(plus[i] - minus[i]) / (2 * eps);
}

/* The largest ω: power iteration on M^-1/2 K M^-1/2 (K is positive
 * semidefinite at rest, so the dominant eigenvalue is the largest ω²). */
static double omega_max(const study_sheet* s) {
    uint32_t n3 = 3 * s->mesh.vertex_count;
    double *p = malloc(n3 * sizeof *p), *q = malloc(n3 * sizeof *q), *work = malloc(3 * n3 * sizeof *work);
    unsigned seed = 7;
    for (uint32_t i = 0; i < n3; i++) p[i] = sb_model_is_fixed(s->model, i / 3) ? 0.0 : (double)rand_r(&seed) / RAND_MAX - 0.5;
    double lambda = 0.0, scale = 1.0 / sqrt(SHEET_MASS);
    for (int it = 0; it < 2000; it++) {
        double norm = 0.0;
        for (uint32_t i = 0; i < n3; i++) norm += p[i] * p[i];
        for (uint32_t i = 0; i < n3; i++) p[i] /= sqrt(norm);
        for (uint32_t i = 0; i < n3; i++) q[i] = p[i] * scale;
        stiffness_product(s, q, q, work);
        double rayleigh = 0.0;
        for (uint32_t i = 0; i < n3; i++) {
            q[i] *= scale;
            rayleigh += p[i] * q[i];
        }
        bool converged = fabs(rayleigh - lambda) <= 1e-10 * rayleigh;
        lambda = rayleigh;
        memcpy(p, q, n3 * sizeof *p);
        if (converged) break;
    }
    free(p);
    free(q);
    free(work);
    return sqrt(lambda);
}

static sb_solver* make_solver(const study_sheet* s, sb_integrator integrator, sb_external_force_fn push, void* user) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.gravity[2] = 0.0;
    def.kernels = SB_KERNELS_REFERENCE;
    def.threads = 1;
    def.external_force = push;
    def.external_user = user;
    sb_error err;
    sb_solver* solver = sb_solver_create(s->model, &def, &err);
    if (!solver) exit(fprintf(stderr, "sb_study: %s\n", err.message));
    return solver;
}

/* Every free vertex displaced a little out of plane, deterministically. */
static void perturb(const study_sheet* s, sb_solver* solver) {
    uint32_t n = s->mesh.vertex_count;
    double* x = malloc(3 * n * sizeof *x);
    memcpy(x, s->mesh.positions, 3 * n * sizeof *x);
    for (uint32_t i = 0; i < n; i++) x[3 * i + 2] += 1e-3 * sin(12.9898 * i);
    sb_solver_set_state(solver, x, NULL);
    free(x);
}

static bool survives(const study_sheet* s, sb_integrator integrator, double dt) {
    sb_solver* solver = make_solver(s, integrator, NULL, NULL);
    perturb(s, solver);
    sb_energies e = sb_solver_energies(solver);
    double e0 = sb_energies_total(&e);
    bool ok = true;
    for (int step = 0; step < STABLE_STEPS && ok; step++) {
        ok = sb_solver_advance(solver, dt) == SB_OK;
        if (ok) {
            e = sb_solver_energies(solver);
            ok = sb_energies_total(&e) <= 10.0 * e0;
        }
    }
    sb_solver_destroy(solver);
    return ok;
}

/* Bisection on log dt; returns hi when even that survives. */
static double largest_stable_step(const study_sheet* s, sb_integrator integrator, double lo, double hi) {
    if (survives(s, integrator, hi)) return hi;
    if (!survives(s, integrator, lo)) return 0.0;
    for (int it = 0; it < 14; it++) {
        double mid = sqrt(lo * hi);
        if (survives(s, integrator, mid)) lo = mid;
        else hi = mid;
    }
    return lo;
}

/* The largest stable step of each integrator at the work-precision
 * stiffness (k = 100 N/m), filled by stability(). */
static double stable_at_100[SB_INTEGRATOR_COUNT];

static void stability(FILE* csv, bool quick) {
    fprintf(csv, "# largest stable step of each integrator (bench/study.c): %u x %u sheet, left edge fixed, "
                 "bond k, angle 1e-3 k, %g kg per vertex; %d steps from a perturbed state, energy growth <= 10x\n",
            SHEET_N, SHEET_N, SHEET_MASS, STABLE_STEPS);
    fprintf(csv, "k,omega_max,verlet_limit,integrator,stable_dt,ratio_to_limit\n");
    double ks[] = {1, 10, 100, 1000, 10000};
    int count = quick ? 3 : 5;
    for (int c = 0; c < count; c++) {
        study_sheet s = make_sheet(ks[c]);
        double omega = omega_max(&s), limit = 2.0 / omega;
        for (int i = 0; i < SB_INTEGRATOR_COUNT; i++) {
            double dt = largest_stable_step(&s, (sb_integrator)i, 1e-3 * limit, 100.0 * limit);
            if (ks[c] == 100.0) stable_at_100[i] = dt;
            fprintf(csv, "%g,%.9g,%.9g,%s,%.6g,%.4f\n", ks[c], omega, limit, sb_integrator_name((sb_integrator)i), dt,
                    dt / limit);
            printf("k %-6g %-17s stable dt %.4g s = %.3f x 2/omega_max\n", ks[c], sb_integrator_name((sb_integrator)i),
                   dt, dt / limit);
        }
        free_sheet(&s);
    }
}

typedef struct push_target {
    uint32_t vertex;
} push_target;

static void push_middle(void* user, uint32_t vertex, double time, const double position[3], const double velocity[3],
                        double force[3]) {
    (void)time, (void)position, (void)velocity;
    if (vertex == ((const push_target*)user)->vertex) force[2] += PUSH_FORCE;
}

/* Positions after PUSH_TIME with steps of dt; returns the CPU seconds, or
 * a negative number when the run failed. */
static double push_run(const study_sheet* s, sb_integrator integrator, double dt, double* out) {
    push_target target = {s->middle};
    sb_solver* solver = make_solver(s, integrator, push_middle, &target);
    long steps = lround(PUSH_TIME / dt);
    clock_t start = clock();
    bool ok = true;
    for (long i = 0; i < steps && ok; i++) ok = sb_solver_advance(solver, dt) == SB_OK;
    double seconds = (double)(clock() - start) / CLOCKS_PER_SEC;
    sb_solver_get_positions(solver, out);
    sb_solver_destroy(solver);
    return ok ? seconds : -1.0;
}

static void work_precision(FILE* csv, bool quick) {
    study_sheet s = make_sheet(100.0);
    double limit = 2.0 / omega_max(&s);
    uint32_t n3 = 3 * s.mesh.vertex_count;
    double *reference = malloc(n3 * sizeof *reference), *x = malloc(n3 * sizeof *x);
    push_run(&s, SB_INTEGRATOR_VELOCITY_VERLET, PUSH_TIME / ceil(PUSH_TIME / (limit / 512)), reference);
    fprintf(csv, "# error after %g s of a %g N push at the middle of the %u x %u sheet (bond k 100 N/m) against "
                 "velocity Verlet at 2/omega_max / 512; CPU seconds of the run (bench/study.c)\n",
            PUSH_TIME, PUSH_FORCE, SHEET_N, SHEET_N);
    fprintf(csv, "integrator,dt,dt_over_limit,steps,cpu_seconds,max_error_m\n");
    double fractions[] = {20, 10, 5, 2, 0.8, 0.4, 0.2, 0.1, 0.05, 0.025, 0.0125};
    int count = sizeof fractions / sizeof *fractions;
    for (int i = 0; i < SB_INTEGRATOR_COUNT; i++)
        for (int f = quick ? 4 : 0; f < count - (quick ? 3 : 0); f++) {
            double dt = PUSH_TIME / ceil(PUSH_TIME / (fractions[f] * limit));
            if (dt > stable_at_100[i]) continue; /* beyond its measured stability limit */
            double seconds = push_run(&s, (sb_integrator)i, dt, x);
            if (seconds < 0) continue; /* unstable at this step: no point on the curve */
            double error = 0.0;
            for (uint32_t k = 0; k < n3; k++) error = fmax(error, fabs(x[k] - reference[k]));
            fprintf(csv, "%s,%.6g,%.4f,%ld,%.6g,%.6g\n", sb_integrator_name((sb_integrator)i), dt, dt / limit,
                    lround(PUSH_TIME / dt), seconds, error);
        }
    free(reference);
    free(x);
    free_sheet(&s);
}

static FILE* open_csv(const char* dir, const char* name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE* f = fopen(path, "w");
    if (!f) exit(fprintf(stderr, "sb_study: cannot write %s\n", path));
    return f;
}

int main(int argc, char** argv) {
    bool quick = false;
    const char* out = SB_STUDY_RESULTS;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--quick") == 0) quick = true;
        else if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) out = argv[++i];
        else return fprintf(stderr, "usage: sb_study [--quick] [--out DIR]\n"), 2;
    }
    FILE* csv = open_csv(out, "stability.csv");
    stability(csv, quick);
    fclose(csv);
    csv = open_csv(out, "work_precision.csv");
    work_precision(csv, quick);
    fclose(csv);
    printf("wrote %s/stability.csv and %s/work_precision.csv\n", out, out);
    return 0;
}
