/* Model accuracy: what the molecular-mechanics corner terms buy over bonds
 * alone, in model_accuracy.csv (bench/study.gp draws model_accuracy.png).
 *
 * The study's sheet (study_sheet.h, 12 x 12 vertices over 1 m², left edge
 * fixed) in two models: "springs", bond stretch alone (k = 100 N/m on every
 * mesh edge, the classic mass-spring sheet without bend springs), and
 * "springs+angle", the same bonds plus angle bend 0.5 k h² and stretch-bend
 * 0.1 k h on every triangle corner (h the edge spacing, the constants of
 * bench/bench_cases.c). A total force F, shared equally by the right edge's
 * vertices, pulls the edge along +x (stretch) or along +y (shear, in plane).
 * Each case is brought to static equilibrium by velocity Verlet with drag
 * until the largest residual force on a free vertex (internal forces plus
 * load) is below 1e-9 of a vertex's share of the load; the CSV records the
 * residual and the time it took, so convergence can be checked. At
 * equilibrium it measures how the sheet kept its shape: the RMS of each
 * triangle's relative area change, the total area's relative change, the RMS
 * deviation of every triangle corner's angle from rest, and the mean
 * displacement of the loaded edge along the load. */
#include "study.h"
#include "study_sheet.h"

#include <math.h>
#include <stdlib.h>

#define ACCURACY_SIDE 12
#define ACCURACY_K 100.0     /* N/m */
#define ACCURACY_DRAG 10.0   /* 1/s */
#define ACCURACY_MAX_TIME 60 /* s simulated before giving up on equilibrium */
#define ACCURACY_TOLERANCE 1e-9

typedef struct shape_measure {
    double area_rms, area_total, angle_rms_deg, displacement;
} shape_measure;

static double triangle_area(const double* x, const uint32_t* t) {
    const double *p = x + 3 * t[0], *q = x + 3 * t[1], *r = x + 3 * t[2];
    double a[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, b[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

/* The angle at corner t[0] of triangle t. */
static double corner_angle(const double* x, const uint32_t* t) {
    const double *p = x + 3 * t[0], *q = x + 3 * t[1], *r = x + 3 * t[2];
    double dot = 0.0, aa = 0.0, bb = 0.0;
    for (int c = 0; c < 3; c++) {
        double a = q[c] - p[c], b = r[c] - p[c];
        dot += a * b, aa += a * a, bb += b * b;
    }
    return acos(fmax(-1.0, fmin(1.0, dot / sqrt(aa * bb))));
}

static shape_measure measure(const study_sheet* s, const double* x, const study_load* load) {
    const double* x0 = s->mesh.positions;
    shape_measure m = {0};
    double area = 0.0, area0 = 0.0;
    uint32_t count = s->mesh.triangle_count;
    for (uint32_t t = 0; t < count; t++) {
        const uint32_t* v = s->mesh.triangles + 3 * t;
        double a = triangle_area(x, v), a0 = triangle_area(x0, v);
        area += a, area0 += a0;
        m.area_rms += (a / a0 - 1) * (a / a0 - 1);
        for (int c = 0; c < 3; c++) {
            uint32_t corner[3] = {v[c], v[(c + 1) % 3], v[(c + 2) % 3]};
            double d = corner_angle(x, corner) - corner_angle(x0, corner);
            m.angle_rms_deg += d * d;
        }
    }
    m.area_rms = sqrt(m.area_rms / count);
    m.area_total = area / area0 - 1;
    m.angle_rms_deg = sqrt(m.angle_rms_deg / (3.0 * count)) * 180.0 / M_PI;
    double norm = sqrt(load->force[0] * load->force[0] + load->force[1] * load->force[1]);
    for (uint32_t i = 0; i < load->count && norm > 0; i++)
        for (int c = 0; c < 2; c++)
            m.displacement += (x[3 * load->vertices[i] + c] - x0[3 * load->vertices[i] + c]) * load->force[c] / norm;
    m.displacement /= load->count;
    return m;
}

/* The largest force left on a free vertex: internal forces plus the load. */
static double residual(const study_sheet* s, const double* x, const study_load* load, double* f) {
    sb_energies e;
    sb_error err;
    sb_reference_forces(s->model, x, NULL, f, &e, &err);
    for (uint32_t i = 0; i < load->count; i++)
        for (int c = 0; c < 3; c++) f[3 * load->vertices[i] + c] += load->force[c];
    double largest = 0.0;
    for (uint32_t v = 0; v < s->mesh.vertex_count; v++)
        if (!sb_model_is_fixed(s->model, v))
            largest =
                fmax(largest, sqrt(f[3 * v] * f[3 * v] + f[3 * v + 1] * f[3 * v + 1] + f[3 * v + 2] * f[3 * v + 2]));
    return largest;
}

/* Damped velocity Verlet from rest until the residual is below tolerance
 * (checked every 0.1 s, up to ACCURACY_MAX_TIME); x receives the end
 * positions, *time the simulated seconds; returns the residual (N), or
 * infinity when the solver stopped. */
static double settle(const study_sheet* s, const study_load* load, double dt, double* x, double* time) {
    sb_solver_def def = study_solver_def(SB_INTEGRATOR_VELOCITY_VERLET);
    def.drag = ACCURACY_DRAG;
    sb_solver* solver = study_loaded_solver(s, &def, load);
    double share = sqrt(load->force[0] * load->force[0] + load->force[1] * load->force[1]), left = INFINITY;
    double* f = malloc(3 * s->mesh.vertex_count * sizeof *f);
    long chunk = lround(0.1 / dt);
    bool ok = true;
    for (*time = 0.0; ok && *time < ACCURACY_MAX_TIME && !(left <= ACCURACY_TOLERANCE * share); *time += chunk * dt) {
        for (long i = 0; i < chunk && ok; i++) ok = sb_solver_advance(solver, dt) == SB_OK;
        sb_solver_get_positions(solver, x);
        left = ok ? residual(s, x, load, f) : INFINITY;
    }
    free(f);
    sb_solver_destroy(solver);
    return left;
}

void study_model_accuracy(const char* out, bool quick) {
    FILE* csv = study_open(out, "model_accuracy.csv");
    fprintf(csv,
            "# shape kept at static equilibrium (bench/study_accuracy.c): %u x %u sheet, 1 m^2, left edge fixed, "
            "bond k %g N/m; springs+angle adds angle 0.5 k h^2 and stretch-bend 0.1 k h; total force on the right "
            "edge along +x (stretch) or +y (shear); drag %g /s until the residual < %g of a vertex's load\n",
            ACCURACY_SIDE, ACCURACY_SIDE, ACCURACY_K, ACCURACY_DRAG, ACCURACY_TOLERANCE);
    fprintf(csv, "model,load,force_n,edge_displacement_m,area_rms,area_total_change,angle_rms_deg,settle_time_s,"
                 "residual_n\n");
    uint32_t edge[ACCURACY_SIDE];
    for (uint32_t row = 0; row < ACCURACY_SIDE; row++) edge[row] = row * ACCURACY_SIDE + ACCURACY_SIDE - 1;
    double h = 1.0 / (ACCURACY_SIDE - 1);
    const char* models[] = {"springs", "springs+angle"};
    const char* loads[] = {"stretch", "shear"};
    for (int model = 0; model < 2; model++) {
        sb_material_def material = study_material(ACCURACY_K);
        material.angle_k = model ? 0.5 * ACCURACY_K * h * h : 0.0;
        material.stretch_bend_k = model ? 0.1 * ACCURACY_K * h : 0.0;
        study_sheet s = study_sheet_make(ACCURACY_SIDE, &material);
        double dt = 0.5 * 2.0 / study_omega_max(&s);
        double* x = malloc(3 * s.mesh.vertex_count * sizeof *x);
        for (int load = 0; load < 2; load++)
            for (double force = 1.0; force <= 10.0; force += quick ? 3.0 : 1.0) {
                study_load pull = {.vertices = edge, .count = ACCURACY_SIDE, .force = {0}};
                pull.force[load] = force / ACCURACY_SIDE;
                double time, left = settle(&s, &pull, dt, x, &time);
                shape_measure m = measure(&s, x, &pull);
                fprintf(csv, "%s,%s,%g,%.6g,%.6g,%.6g,%.6g,%.3g,%.3g\n", models[model], loads[load], force,
                        m.displacement, m.area_rms, m.area_total, m.angle_rms_deg, time, left);
                printf("%-13s %-7s %4g N: edge moved %.4g m, area rms %.3g, angle rms %.3g deg (settled in %.3g s, "
                       "residual %.2g N)\n",
                       models[model], loads[load], force, m.displacement, m.area_rms, m.angle_rms_deg, time, left);
            }
        free(x);
        study_sheet_free(&s);
    }
    fclose(csv);
}
