/* The integrator study (issue 4): how far each integrator's step can go,
 * and what accuracy each buys for its CPU time, on the square sheet of
 * Sudhamani & Merriliance (2019) (study_sheet.h); then the paper's tables
 * (study_tables.c) and the model-accuracy chart (study_accuracy.c).
 *
 *   sb_study [--quick] [--out DIR]      (DIR defaults to bench/results)
 *
 * Writes DIR/stability.csv, work_precision.csv, work_precision_corner.csv,
 * work_precision_large.csv,
 * paper_tables.csv, paper_tables.md, model_accuracy.csv and
 * lod_accuracy.csv; bench/study.gp
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
 * accuracy, it is a blow-up that 0.2 s is too short to catch). The third
 * chart does the same at scale: a 48 × 48 sheet on the fast kernels, five
 * steps from 20 to 0.1 times its 2/ω_max, against velocity Verlet at
 * 2/ω_max / 64 (each integrator up to the stable ratio measured on the
 * 12 × 12 sheet). */
#include "study.h"
#include "study_sheet.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SHEET_N 12       /* vertices per side */
#define PUSH_FORCE 0.5   /* N, out of plane */
#define PUSH_TIME 0.2    /* s */
#define LARGE_SHEET_N 48 /* the large work-precision chart's sheet: 2304 vertices */

static void stability(FILE* csv, bool quick, double stable_ratio[SB_INTEGRATOR_COUNT]) {
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
            if (ks[c] == 100.0) stable_ratio[i] = dt / limit;
            fprintf(csv, "%g,%.9g,%.9g,%s,%.6g,%.4f\n", ks[c], omega, limit, sb_integrator_name((sb_integrator)i), dt,
                    dt / limit);
            printf("k %-6g %-17s stable dt %.4g s = %.3f x 2/omega_max\n", ks[c], sb_integrator_name((sb_integrator)i),
                   dt, dt / limit);
        }
        study_sheet_free(&s);
    }
}

/* One work-precision chart: the sheet's size, where the push is, the
 * kernels, the steps tried (fractions of 2/ω_max) and the reference's. */
typedef struct precision_setup {
    const char* file;
    uint32_t side;
    bool corner, fast;
    const double* fractions;
    int count;
    double reference_fraction;
} precision_setup;

static void work_precision(const char* out, const precision_setup* p, const double stable_ratio[SB_INTEGRATOR_COUNT]) {
    FILE* csv = study_open(out, p->file);
    sb_material_def material = study_material(100.0);
    study_sheet s = study_sheet_make(p->side, &material);
    double limit = 2.0 / study_omega_max(&s);
    uint32_t n = s.mesh.vertex_count, vertex = p->corner ? s.corner : s.middle;
    study_load push = {.vertices = &vertex, .count = 1, .force = {0.0, 0.0, PUSH_FORCE}};
    double *reference = malloc(3 * n * sizeof *reference), *x = malloc(3 * n * sizeof *x);
    sb_solver_def def = study_solver_def(SB_INTEGRATOR_VELOCITY_VERLET);
    if (p->fast) def.kernels = SB_KERNELS_FAST;
    study_load_run(&s, &def, &push, study_dividing_step(PUSH_TIME, p->reference_fraction * limit), PUSH_TIME,
                   reference);
    fprintf(csv,
            "# error after %g s of a %g N push at the %s of the %u x %u sheet (bond k 100 N/m) against "
            "velocity Verlet at 2/omega_max x %g; CPU seconds of the run, %s kernels, 1 thread (bench/study.c)\n",
            PUSH_TIME, PUSH_FORCE, p->corner ? "free corner (x = 1 m, y = 0)" : "middle", p->side, p->side,
            p->reference_fraction, p->fast ? "fast" : "reference");
    fprintf(csv, "integrator,dt,dt_over_limit,steps,cpu_seconds,max_error_m\n");
    for (int i = 0; i < SB_INTEGRATOR_COUNT; i++)
        for (int f = 0; f < p->count; f++) {
            double dt = study_dividing_step(PUSH_TIME, p->fractions[f] * limit);
            if (dt / limit > stable_ratio[i]) continue; /* beyond its measured stability limit */
            def = study_solver_def((sb_integrator)i);
            if (p->fast) def.kernels = SB_KERNELS_FAST;
            double seconds = study_load_run(&s, &def, &push, dt, PUSH_TIME, x);
            if (seconds < 0) continue; /* unstable at this step: no point on the curve */
            fprintf(csv, "%s,%.6g,%.4f,%ld,%.6g,%.6g\n", sb_integrator_name((sb_integrator)i), dt, dt / limit,
                    lround(PUSH_TIME / dt), seconds, study_max_distance(x, reference, n));
            printf("%s: %-17s dt %.3g x 2/omega_max: %.3g s, error %.3g m\n", p->file,
                   sb_integrator_name((sb_integrator)i), dt / limit, seconds, study_max_distance(x, reference, n));
        }
    free(reference);
    free(x);
    study_sheet_free(&s);
    fclose(csv);
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
    double stable_ratio[SB_INTEGRATOR_COUNT];
    FILE* csv = study_open(out, "stability.csv");
    stability(csv, quick, stable_ratio);
    fclose(csv);
    static const double fractions[] = {20, 10, 5, 2, 0.8, 0.4, 0.2, 0.1, 0.05, 0.025, 0.0125};
    static const double large_fractions[] = {20, 5, 1, 0.4, 0.1};
    int skip = quick ? 4 : 0, drop = quick ? 3 : 0;
    const precision_setup setups[] = {
        {"work_precision.csv", SHEET_N, false, false, fractions + skip, 11 - skip - drop, 1.0 / 512},
        {"work_precision_corner.csv", SHEET_N, true, false, fractions + skip, 11 - skip - drop, 1.0 / 512},
        {"work_precision_large.csv", quick ? 24 : LARGE_SHEET_N, false, true, large_fractions, 5, 1.0 / 64},
    };
    for (size_t k = 0; k < sizeof setups / sizeof *setups; k++) work_precision(out, &setups[k], stable_ratio);
    study_paper_tables(out, quick);
    study_model_accuracy(out, quick);
    study_lod_accuracy(out, quick);
    printf("wrote the study's files to %s\n", out);
    return 0;
}
