/* Sudhamani & Merriliance's three tables (their Tables 2.2.1-2.2.3) redone
 * with softbond, their numbers beside ours: paper_tables.csv (one row per
 * cell) and paper_tables.md (the tables, how each was measured, and a
 * sentence on each difference).
 *
 * The paper gives neither its stiffness, masses, damping, step nor the
 * duration it timed, so every table here states its own. All three use the
 * study's sheet (study_sheet.h: 1 m², left edge fixed, 0.01 kg per vertex,
 * bond stretch k = 100 N/m, angle bend 0.1 J on 12 x 12 vertices, scaled
 * as h² on Table 2.2.1's finer sheets) in a viscous medium: drag
 * TABLE_DRAG (each free vertex feels −drag·m·v). Undamped, explicit Euler
 * gains energy at any step (stability.csv), so the paper's finite limit for
 * it says its model was damped; with drag c, forward Euler on a mode of
 * angular frequency ω is stable for dt < c/ω² (while c < 2ω), which the
 * table prints beside the measurement.
 *
 * Table 2.2.2 comes first: its explicit-Euler limit sets the common step
 * dt_c = ½ × that limit at which Tables 2.2.1 and 2.2.3 run Euler and
 * Verlet side by side ("Euler" is explicit Euler, "Verlet" the position
 * form, Eq. 12). Timing runs use the fast kernels on one thread, best of
 * three; stability and accuracy runs use the double reference. */
#include "study.h"
#include "study_sheet.h"

#include <math.h>
#include <stdlib.h>

#define TABLE_K 100.0   /* N/m */
#define TABLE_DRAG 20.0 /* 1/s */
#define TABLE_SIDE 12   /* vertices per side, Tables 2.2.2 and 2.2.3 */
#define COST_TIME 1.0   /* s simulated by the timing runs */
#define COST_FORCE 0.5  /* N at the middle, out of plane, in the timing runs */
#define ERROR_TIME 0.2  /* s: the deformation error's end time */
/* A stable run lasts 1 s and starts perturbed in plane too, so that the
 * in-plane modes that limit the step start with some energy. */
static const study_trial table_trial = {.duration = 1.0, .in_plane = true};

static const double paper_points[] = {200, 500, 1000, 2000, 4000};
static const double paper_time_euler[] = {0.5, 1.7, 2.78, 3.14, 3.96};
static const double paper_time_verlet[] = {0.3, 1.2, 2, 2.67, 3.12};
static const uint32_t table_sides[] = {14, 22, 32, 45, 63}; /* side² nearest the paper's counts */
static const sb_integrator step_methods[] = {SB_INTEGRATOR_EXPLICIT_EULER, SB_INTEGRATOR_IMPLICIT_EULER,
                                             SB_INTEGRATOR_VERLET};
static const double paper_step_ms[] = {0.5, 49.0, 11.5};
static const double paper_cost_ms[] = {9.3, 172.0, 8.5};
static const double forces[] = {0, 2, 4, 6, 8, 10};
static const double paper_error_euler[] = {0, 1.583356, 3.248017, 4.183456, 9.492629, 12.423452};
static const double paper_error_verlet[] = {0, 1.298453, 1.972952, 2.7839, 6.93582, 8.1674};

/* The study's material with the angle term scaled as h² (h the spacing):
 * 0.1 J on the 12 x 12 sheet, and the same stiffness against a corner's
 * displacement at every resolution, so that ω_max does not grow with the
 * points (with angle_k fixed it would, as 1/h). */
static study_sheet table_sheet(uint32_t side) {
    sb_material_def material = study_material(TABLE_K);
    double scale = (TABLE_SIDE - 1.0) / (side - 1.0);
    material.angle_k *= scale * scale;
    return study_sheet_make(side, &material);
}

static sb_solver_def damped_def(sb_integrator integrator, sb_kernels kernels) {
    sb_solver_def def = study_solver_def(integrator);
    def.drag = TABLE_DRAG;
    def.kernels = kernels;
    return def;
}

/* CPU seconds of COST_TIME s under the middle push at dt, best of `repeats`
 * (fast kernels, one thread); negative when the run failed. */
static double cost(const study_sheet* s, sb_integrator integrator, double dt, int repeats) {
    sb_solver_def def = damped_def(integrator, SB_KERNELS_FAST);
    study_load push = {.vertices = &s->middle, .count = 1, .force = {0.0, 0.0, COST_FORCE}};
    double *x = malloc(3 * s->mesh.vertex_count * sizeof *x), best = INFINITY;
    for (int r = 0; r < repeats; r++) {
        double seconds = study_load_run(s, &def, &push, dt, COST_TIME, x);
        best = seconds < 0 ? seconds : fmin(best, seconds);
        if (seconds < 0) break;
    }
    free(x);
    return best;
}

/* A table cell: the value, or "failed" where the run stopped (negative). */
static const char* cell(char text[32], double value, double scale) {
    if (value < 0) return "failed";
    snprintf(text, 32, "%.3g", scale * value);
    return text;
}

static void csv_row(FILE* csv, const char* table, double key, const char* method, const char* quantity,
                    const char* unit, double paper, double ours) {
    fprintf(csv, "%s,%g,%s,%s,%s,%g,%.6g\n", table, key, method, quantity, unit, paper, ours);
}

/* What the tables share: the sheet's limit and the steps Table 2.2.2 found. */
typedef struct table_context {
    FILE *csv, *md;
    bool quick;
    double omega, limit; /* of the 12 x 12 sheet */
    double stable[3];    /* s, step_methods' largest stable steps */
    double common_dt;    /* s, ½ of explicit Euler's */
} table_context;

/* The steps of a ladder (1 to 100 times 2/ω_max) at which implicit Euler
 * does not survive, as text ("none" when it survives all). */
static void implicit_failures(const study_sheet* s, double limit, char* text, size_t size) {
    static const double ladder[] = {1, 2, 5, 10, 20, 40, 60, 80, 100};
    sb_solver_def def = damped_def(SB_INTEGRATOR_IMPLICIT_EULER, SB_KERNELS_REFERENCE);
    size_t used = 0;
    for (size_t i = 0; i < sizeof ladder / sizeof *ladder; i++)
        if (!study_survives(s, &def, ladder[i] * limit, &table_trial) && used < size)
            used += snprintf(text + used, size - used, "%s%.0f ms", used ? ", " : "", 1e3 * ladder[i] * limit);
    if (!used) snprintf(text, size, "none of them");
}

static void step_table(table_context* t) {
    study_sheet s = table_sheet(TABLE_SIDE);
    t->omega = study_omega_max(&s);
    t->limit = 2.0 / t->omega;
    double cap = 100.0 * t->limit, costs[3];
    for (int m = 0; m < 3; m++) {
        sb_solver_def def = damped_def(step_methods[m], SB_KERNELS_REFERENCE);
        t->stable[m] = study_largest_stable_step(&s, &def, 1e-3 * t->limit, cap, &table_trial);
        costs[m] = cost(&s, step_methods[m], study_dividing_step(COST_TIME, t->stable[m]), t->quick ? 1 : 3);
        csv_row(t->csv, "2.2.2", 0, sb_integrator_name(step_methods[m]), "largest_stable_step", "ms", paper_step_ms[m],
                1e3 * t->stable[m]);
        csv_row(t->csv, "2.2.2", 0, sb_integrator_name(step_methods[m]), "computation_time", "ms", paper_cost_ms[m],
                1e3 * costs[m]);
    }
    t->common_dt = study_dividing_step(COST_TIME, 0.5 * t->stable[0]);
    fprintf(t->md,
            "## Table 2.2.2: largest stable step and computation time\n\n"
            "%u x %u sheet, bond k = %g N/m, drag %g /s, no load. *Largest stable step*: the largest dt at which "
            "a run of %g s from a slightly perturbed state (every coordinate moved by up to 1 mm) "
            "neither stops nor multiplies the total energy by more than 10 (bisection on log dt, tried up to "
            "100 x 2/ω_max = %.0f ms). *Computation time*: CPU time to simulate "
            "%g s under a %g N push at the middle at that step (divided evenly into %g s), fast kernels, one "
            "thread, best of 3. ω_max = %.1f rad/s, so 2/ω_max = %.3f ms and forward Euler's damped bound "
            "c/ω_max² = %.3f ms.\n\n"
            "| method | paper step [ms] | our step [ms] | paper time [ms] | our time [ms] |\n|---|---|---|---|---|\n",
            TABLE_SIDE, TABLE_SIDE, TABLE_K, TABLE_DRAG, table_trial.duration, 1e3 * cap, COST_TIME, COST_FORCE,
            COST_TIME, t->omega, 1e3 * t->limit, 1e3 * TABLE_DRAG / (t->omega * t->omega));
    for (int m = 0; m < 3; m++) {
        char a[32];
        fprintf(t->md, "| %s | %g | %s%.3g | %g | %s |\n", sb_integrator_name(step_methods[m]), paper_step_ms[m],
                t->stable[m] >= cap ? "≥ " : "", 1e3 * t->stable[m], paper_cost_ms[m], cell(a, costs[m], 1e3));
    }
    char failures[256] = "";
    implicit_failures(&s, t->limit, failures, sizeof failures);
    fprintf(t->md,
            "\n- explicit_euler: %.3g ms against the paper's 0.5 ms; with drag c its limit is about c/ω_max² = %.3g "
            "ms (the bisection, which asks only that the energy not grow tenfold in 1 s, lets it go a little "
            "beyond), so it depends on the drag and the stiffness per unit mass, and the paper gives neither.\n"
            "- implicit_euler: %s%.3g ms, against 49 ms, but this is no stability limit: backward Euler is "
            "unconditionally stable, and what can fail is its Newton solve (exact Jacobian, at most 20 "
            "iterations, a halving line search): on a ladder of steps from 1 to 100 x 2/ω_max it failed at %s; "
            "the paper's 49 ms is presumably the limit of its solver. It costs %.3g ms for %g s in %.0f steps, "
            "against the paper's 172 ms.\n"
            "- verlet: %.3g ms = %.3f x 2/ω_max, against 11.5 ms; 2/ω_max scales as √(m/k), so the two agree for "
            "a sheet about %.2g times as stiff per unit mass as ours. Euler's step over Verlet's: ours %.3f, the "
            "paper's %.3f. Verlet needs %.0f times fewer steps than explicit Euler and so is %.0f times cheaper, "
            "where the paper found it only 1.1 times cheaper (its Euler time cannot have been for the same "
            "simulated duration).\n\n",
            1e3 * t->stable[0], 1e3 * TABLE_DRAG / (t->omega * t->omega), t->stable[1] >= cap ? "≥ " : "",
            1e3 * t->stable[1], failures, 1e3 * costs[1], COST_TIME,
            COST_TIME / study_dividing_step(COST_TIME, t->stable[1]), 1e3 * t->stable[2], t->stable[2] / t->limit,
            pow(t->stable[2] / 11.5e-3, 2), t->stable[0] / t->stable[2], 0.5 / 11.5, t->stable[2] / t->stable[0],
            costs[0] / costs[2]);
    study_sheet_free(&s);
}

static void points_table(table_context* t) {
    fprintf(t->md,
            "## Table 2.2.1: computation time against number of points\n\n"
            "A side x side sheet (side² nearest the paper's count), bond k = %g N/m, angle bend scaled as h² "
            "so that ω_max stays put (column ω_max), drag %g /s, a %g N push at the middle vertex out of plane; "
            "CPU time to simulate %g s at the common step dt_c = %.4g ms (half explicit Euler's largest stable "
            "step from Table 2.2.2), fast kernels, one thread, best of 3.\n\n"
            "| points (paper) | points (ours) | ω_max [rad/s] | paper Euler [s] | our Euler [s] | paper Verlet [s] "
            "| our Verlet [s] |\n|---|---|---|---|---|---|---|\n",
            TABLE_K, TABLE_DRAG, COST_FORCE, COST_TIME, 1e3 * t->common_dt);
    int rows = t->quick ? 3 : 5;
    double first[2] = {0}, last[2] = {0}, ratio_min = INFINITY, ratio_max = 0.0, faster_min = INFINITY,
           faster_max = 0.0;
    for (int r = 0; r < rows; r++) {
        study_sheet s = table_sheet(table_sides[r]);
        double omega = study_omega_max(&s);
        double euler = cost(&s, SB_INTEGRATOR_EXPLICIT_EULER, t->common_dt, t->quick ? 1 : 3);
        double verlet = cost(&s, SB_INTEGRATOR_VERLET, t->common_dt, t->quick ? 1 : 3);
        uint32_t points = s.mesh.vertex_count;
        csv_row(t->csv, "2.2.1", paper_points[r], "explicit_euler", "computation_time", "s", paper_time_euler[r],
                euler);
        csv_row(t->csv, "2.2.1", paper_points[r], "verlet", "computation_time", "s", paper_time_verlet[r], verlet);
        char a[32], b[32];
        fprintf(t->md, "| %g | %u | %.1f | %g | %s | %g | %s |\n", paper_points[r], points, omega, paper_time_euler[r],
                cell(a, euler, 1), paper_time_verlet[r], cell(b, verlet, 1));
        if (r == 0) first[0] = euler, first[1] = verlet;
        last[0] = euler, last[1] = verlet;
        ratio_min = fmin(ratio_min, euler / verlet), ratio_max = fmax(ratio_max, euler / verlet);
        double faster[2] = {paper_time_euler[r] / euler, paper_time_verlet[r] / verlet};
        faster_min = fmin(faster_min, fmin(faster[0], faster[1]));
        faster_max = fmax(faster_max, fmax(faster[0], faster[1]));
        study_sheet_free(&s);
    }
    double points_ratio = (double)(table_sides[rows - 1] * table_sides[rows - 1]) / (table_sides[0] * table_sides[0]);
    char ratio[64];
    if (ratio_max - ratio_min < 0.005)
        snprintf(ratio, sizeof ratio, "%.2f times", ratio_min);
    else
        snprintf(ratio, sizeof ratio, "%.2f to %.2f times", ratio_min, ratio_max);
    fprintf(t->md,
            "\nFrom %u to %u points (x %.1f) our time grows x %.1f for Euler and x %.1f for Verlet, the paper's "
            "x 7.9 and x 10.4 for x 20 the points, less than in proportion; ours %s. Our times are %.1f to %.1f "
            "times smaller than the paper's, "
            "which says neither the duration nor the step it timed, so only the growth compares. Our Euler costs "
            "%s our Verlet, not the paper's 1.3 to 1.7 times: both evaluate the forces once per step, and the "
            "rest is a few multiply-adds per vertex.\n\n",
            table_sides[0] * table_sides[0], table_sides[rows - 1] * table_sides[rows - 1], points_ratio,
            last[0] / first[0], last[1] / first[1],
            fmax(last[0] / first[0], last[1] / first[1]) < points_ratio
                ? "less than in proportion too, because a fixed cost per step still counts on the small sheets"
                : "more than in proportion (the timings are CPU times on a shared machine; a small sheet's fits "
                  "in cache)",
            faster_min, faster_max, ratio);
}

/* The largest vertex distance (m) after ERROR_TIME s of a force at the
 * middle, between the integrator at dt and `reference`; negative when the
 * run failed. */
static double deformation_error(const study_sheet* s, sb_integrator integrator, double dt, const study_load* load,
                                const double* reference, double* x) {
    sb_solver_def def = damped_def(integrator, SB_KERNELS_REFERENCE);
    if (study_load_run(s, &def, load, dt, ERROR_TIME, x) < 0) return -1.0;
    return study_max_distance(x, reference, s->mesh.vertex_count);
}

static void error_table(table_context* t) {
    study_sheet s = table_sheet(TABLE_SIDE);
    uint32_t n = s.mesh.vertex_count;
    double *reference = malloc(3 * n * sizeof *reference), *x = malloc(3 * n * sizeof *x);
    double fine = study_dividing_step(ERROR_TIME, t->limit / 512),
           own = study_dividing_step(ERROR_TIME, 0.5 * t->stable[2]);
    double common = study_dividing_step(ERROR_TIME, t->common_dt);
    fprintf(t->md,
            "## Table 2.2.3: deformation error against applied force\n\n"
            "*Deformation error*: the largest distance, over all vertices, between where the integrator puts a "
            "vertex and where a converged reference puts it, %g s after a constant force F starts pushing the "
            "middle vertex of the %u x %u sheet out of plane (bond k = %g N/m, drag %g /s). The reference is "
            "velocity Verlet at 2/ω_max / 512 = %.4g ms. Euler and Verlet run at the common step dt_c = %.4g ms "
            "(half explicit Euler's largest stable step); the last column is Verlet at half its own largest "
            "stable step, %.4g ms. The paper's column heading says N/m, but the values are forces in N.\n\n"
            "| F [N] | paper Euler [mm] | our Euler [mm] | paper Verlet [mm] | our Verlet [mm] | our Verlet at "
            "%.3g ms [mm] |\n|---|---|---|---|---|---|\n",
            ERROR_TIME, TABLE_SIDE, TABLE_SIDE, TABLE_K, TABLE_DRAG, 1e3 * fine, 1e3 * common, 1e3 * own, 1e3 * own);
    int count = sizeof forces / sizeof *forces;
    double euler_max = 0.0, verlet_max = 0.0, own_max = 0.0;
    bool own_below = true; /* Verlet at its own step below the paper's Verlet at every force > 0 */
    bool steady = true;    /* every error column grows with the force */
    double previous[3] = {0};
    for (int f = 0; f < count; f += t->quick ? 2 : 1) {
        study_load push = {.vertices = &s.middle, .count = 1, .force = {0.0, 0.0, forces[f]}};
        sb_solver_def def = damped_def(SB_INTEGRATOR_VELOCITY_VERLET, SB_KERNELS_REFERENCE);
        study_load_run(&s, &def, &push, fine, ERROR_TIME, reference);
        double euler = deformation_error(&s, SB_INTEGRATOR_EXPLICIT_EULER, common, &push, reference, x);
        double verlet = deformation_error(&s, SB_INTEGRATOR_VERLET, common, &push, reference, x);
        double verlet_own = deformation_error(&s, SB_INTEGRATOR_VERLET, own, &push, reference, x);
        csv_row(t->csv, "2.2.3", forces[f], "explicit_euler", "deformation_error", "mm", paper_error_euler[f],
                1e3 * euler);
        csv_row(t->csv, "2.2.3", forces[f], "verlet", "deformation_error", "mm", paper_error_verlet[f], 1e3 * verlet);
        csv_row(t->csv, "2.2.3", forces[f], "verlet_own_step", "deformation_error", "mm", NAN, 1e3 * verlet_own);
        char a[32], b[32], c[32];
        fprintf(t->md, "| %g | %g | %s | %g | %s | %s |\n", forces[f], paper_error_euler[f], cell(a, euler, 1e3),
                paper_error_verlet[f], cell(b, verlet, 1e3), cell(c, verlet_own, 1e3));
        euler_max = fmax(euler_max, euler), verlet_max = fmax(verlet_max, verlet), own_max = fmax(own_max, verlet_own);
        own_below &= forces[f] == 0 || (verlet_own >= 0 && 1e3 * verlet_own < paper_error_verlet[f]);
        steady &= euler >= previous[0] && verlet >= previous[1] && verlet_own >= previous[2];
        previous[0] = euler, previous[1] = verlet, previous[2] = verlet_own;
    }
    fprintf(t->md,
            "\nAt the same step Verlet's error is at most %.3g mm against Euler's %.3g mm (%.0f times smaller), "
            "where the paper's is only 1.5 times smaller than its Euler's: Euler is first order and Verlet "
            "second, so at a step small enough for Euler to be stable Verlet is nearly exact, and the paper's "
            "Verlet must have run at a larger step than its Euler, or been measured otherwise. At half its own "
            "stable step, %.0f times dt_c, Verlet's error is at most %.3g mm, %s the paper's at every force but "
            "zero. %s; with no force the sheet stays at rest under every method (error at rounding level).\n",
            1e3 * verlet_max, 1e3 * euler_max, euler_max / verlet_max, own / common, 1e3 * own_max,
            own_below ? "below" : "not always below",
            steady ? "All errors grow steadily with the force, as the paper's do"
                   : "Our errors grow with the force but not steadily, where the paper's do: an error taken at one "
                     "end time depends on where in its oscillation the pushed sheet is then");
    free(reference);
    free(x);
    study_sheet_free(&s);
}

void study_paper_tables(const char* out, bool quick) {
    table_context t = {
        .csv = study_open(out, "paper_tables.csv"), .md = study_open(out, "paper_tables.md"), .quick = quick};
    fprintf(t.csv, "# Sudhamani & Merriliance (2019) Tables 2.2.1-2.2.3, the paper's numbers and ours "
                   "(bench/study_tables.c; paper_tables.md says how each was measured)\n");
    fprintf(t.csv, "table,key,method,quantity,unit,paper,ours\n");
    fprintf(t.md,
            "# The paper's tables redone\n\n"
            "Sudhamani & Merriliance (2019), Tables 2.2.1-2.2.3, with softbond on the study's sheet "
            "(1 m², left edge fixed, 0.01 kg per vertex, bond stretch k = %g N/m, angle bend %g J on 12 x 12 vertices) "
            "in a "
            "viscous medium, drag %g /s: undamped, explicit Euler is never stable (stability.csv), so the "
            "paper's model must have been damped. \"Euler\" is explicit Euler, \"Verlet\" the position "
            "form (Eq. 12). Written by `sb_study` (bench/study_tables.c)%s; the numbers are in "
            "paper_tables.csv.\n\n",
            TABLE_K, 1e-3 * TABLE_K, TABLE_DRAG, quick ? " with --quick" : "");
    step_table(&t);
    points_table(&t);
    error_table(&t);
    fclose(t.csv);
    fclose(t.md);
}
