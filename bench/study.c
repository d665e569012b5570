/* The integrator study (issue 4): how far each integrator's step can go,
 * and what accuracy each buys for its CPU time, on the square sheet of
 * Sudhamani & Merriliance (2019) (study_sheet.h); then the paper's tables
 * (study_tables.c) and the model-accuracy chart (study_accuracy.c).
 *
 *   sb_study [--quick] [--out DIR]      (DIR defaults to bench/results)
 *
 * Writes DIR/stability.csv, work_precision.csv, work_precision_corner.csv,
 * paper_tables.csv, paper_tables.md and model_accuracy.csv; bench/study.gp
 * draws the charts. Every run uses the double scalar reference for the
 * forces unless a part says otherwise, so the comparison is between
 * integrators, not kernels.
 *
 * Stability: for bond stiffness k over four decades, the largest step at
 * which a run of 400 steps from a perturbed state (every free vertex moved
 * by up to 1 mm out of plane) neither stops (SB_ERR_UNSTABLE) nor multiplies its total
 * energy by more than 10, found by bisection on log dt between 1e-3 and 100 times 2/ω_max. ω_max, the
 * sheet's highest angular frequency, comes from power iteration on
 * M^-1/2 K M^-1/2 with K p the central directional difference of the
 * reference forces: Verlet's limit is dt = 2/ω_max.
 *
 * Work-precision: a force of 0.5 N pushes one vertex out of plane for
 * 0.2 s — the middle vertex, then a free corner (the paper's Fig. 2(b) and
 * 2(c)); the error is the largest distance of any vertex from a
 * velocity-Verlet run with a step 512 times smaller than 2/ω_max, against
 * the CPU time of the run, for steps from 20 down to 0.0125 times 2/ω_max,
 * each integrator only up to the largest stable step the stability part
 * measured for it at this stiffness (a run beyond it is not a point of
 * accuracy, it is a blow-up that 0.2 s is too short to catch). */
#include "study.h"
#include "study_sheet.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SHEET_N 12     /* vertices per side */
#define PUSH_FORCE 0.5 /* N, out of plane */
#define PUSH_TIME 0.2  /* s */

static void stability(FILE* csv, bool quick, double stable_at_100[SB_INTEGRATOR_COUNT]) {
    fprintf(csv,
            "# largest stable step of each integrator (bench/study.c): %u x %u sheet, left edge fixed, "
            "bond k, angle 1e-3 k, %g kg per vertex; %d steps from a perturbed state, energy growth <= 10x\n",
            SHEET_N, SHEET_N, STUDY_MASS, STUDY_STABLE_STEPS);
    fprintf(csv, "k,omega_max,verlet_limit,integrator,stable_dt,ratio_to_limit\n");
    double ks[] = {1, 10, 100, 1000, 10000};
    study_trial trial = {0}; /* 400 steps, out of plane */
    int count = quick ? 3 : 5;
    for (int c = 0; c < count; c++) {
        sb_material_def material = study_material(ks[c]);
        study_sheet s = study_sheet_make(SHEET_N, &material);
        double omega = study_omega_max(&s), limit = 2.0 / omega;
        for (int i = 0; i < SB_INTEGRATOR_COUNT; i++) {
            sb_solver_def def = study_solver_def((sb_integrator)i);
            double dt = study_largest_stable_step(&s, &def, 1e-3 * limit, 100.0 * limit, &trial);
            if (ks[c] == 100.0) stable_at_100[i] = dt;
            fprintf(csv, "%g,%.9g,%.9g,%s,%.6g,%.4f\n", ks[c], omega, limit, sb_integrator_name((sb_integrator)i), dt,
                    dt / limit);
            printf("k %-6g %-17s stable dt %.4g s = %.3f x 2/omega_max\n", ks[c], sb_integrator_name((sb_integrator)i),
                   dt, dt / limit);
        }
        study_sheet_free(&s);
    }
}

/* The work-precision chart for a push on the middle vertex or on the free corner. */
static void work_precision(FILE* csv, bool quick, const double stable_at_100[SB_INTEGRATOR_COUNT], bool corner) {
    sb_material_def material = study_material(100.0);
    study_sheet s = study_sheet_make(SHEET_N, &material);
    double limit = 2.0 / study_omega_max(&s);
    uint32_t n = s.mesh.vertex_count, vertex = corner ? s.corner : s.middle;
    study_load push = {.vertices = &vertex, .count = 1, .force = {0.0, 0.0, PUSH_FORCE}};
    double *reference = malloc(3 * n * sizeof *reference), *x = malloc(3 * n * sizeof *x);
    sb_solver_def def = study_solver_def(SB_INTEGRATOR_VELOCITY_VERLET);
    study_load_run(&s, &def, &push, study_dividing_step(PUSH_TIME, limit / 512), PUSH_TIME, reference);
    fprintf(csv,
            "# error after %g s of a %g N push at the %s of the %u x %u sheet (bond k 100 N/m) against "
            "velocity Verlet at 2/omega_max / 512; CPU seconds of the run (bench/study.c)\n",
            PUSH_TIME, PUSH_FORCE, corner ? "free corner (x = 1 m, y = 0)" : "middle", SHEET_N, SHEET_N);
    fprintf(csv, "integrator,dt,dt_over_limit,steps,cpu_seconds,max_error_m\n");
    double fractions[] = {20, 10, 5, 2, 0.8, 0.4, 0.2, 0.1, 0.05, 0.025, 0.0125};
    int count = sizeof fractions / sizeof *fractions;
    for (int i = 0; i < SB_INTEGRATOR_COUNT; i++)
        for (int f = quick ? 4 : 0; f < count - (quick ? 3 : 0); f++) {
            double dt = study_dividing_step(PUSH_TIME, fractions[f] * limit);
            if (dt > stable_at_100[i]) continue; /* beyond its measured stability limit */
            def = study_solver_def((sb_integrator)i);
            double seconds = study_load_run(&s, &def, &push, dt, PUSH_TIME, x);
            if (seconds < 0) continue; /* unstable at this step: no point on the curve */
            fprintf(csv, "%s,%.6g,%.4f,%ld,%.6g,%.6g\n", sb_integrator_name((sb_integrator)i), dt, dt / limit,
                    lround(PUSH_TIME / dt), seconds, study_max_distance(x, reference, n));
        }
    free(reference);
    free(x);
    study_sheet_free(&s);
}

int main(int argc, char** argv) {
    bool quick = false;
    const char* out = SB_STUDY_RESULTS;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--quick") == 0)
            quick = true;
        else if (strcmp(argv[i], "--out") == 0 && i + 1 < argc)
            out = argv[++i];
        else
            return fprintf(stderr, "usage: sb_study [--quick] [--out DIR]\n"), 2;
    }
    double stable_at_100[SB_INTEGRATOR_COUNT];
    FILE* csv = study_open(out, "stability.csv");
    stability(csv, quick, stable_at_100);
    fclose(csv);
    const char* names[] = {"work_precision.csv", "work_precision_corner.csv"};
    for (int corner = 0; corner < 2; corner++) {
        csv = study_open(out, names[corner]);
        work_precision(csv, quick, stable_at_100, corner);
        fclose(csv);
    }
    study_paper_tables(out, quick);
    study_model_accuracy(out, quick);
    printf("wrote the study's files to %s\n", out);
    return 0;
}
