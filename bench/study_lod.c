/* Level of detail against accuracy ("model no more than a scene needs"):
 * what the coarser models `--budget-ms` chooses from give up, beside what
 * they save, in lod_accuracy.csv (bench/study.gp draws lod_accuracy.png).
 *
 * The default scene's sheet (scenes/default.yaml: 1 m², bond 1000 N/m,
 * angle 0.5 J, damped springs 100 N/m and 0.05 N s/m, bend 5e-4 J/rad²,
 * 0.2 kg/m² by area, top corners fixed, gravity, drag 1/s) at 60 × 60
 * vertices, and the levels `--budget-ms` calibrates from it: each half the
 * last by sb_mesh_simplify, down to where the locked boundary stops it.
 * Each level falls and swings for 1 s with Verlet at dt = 25 µs (the full
 * model's corners, a sixth of an interior vertex's mass, need less than
 * the default scene's 0.1 ms) on the fast kernels, one thread. Simplification removes vertices and never moves
 * one, so every vertex of a coarse level is a vertex of the full model; a
 * level's error is the RMS distance of its vertices from the same vertices
 * of the full model at the end, relative to the RMS distance those moved
 * in the full model (and the largest distance). A bond's stiffness per
 * bond is kept at every level: in a 2-D triangle lattice that keeps the
 * membrane's stretching modulus (it does not depend on the bond length), so
 * the levels model the same sheet, coarser. Cost: CPU ms per step. */
#include "study.h"
#include "study_sheet.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define LOD_SIDE 60
#define LOD_DT 2.5e-5
#define LOD_DURATION 1.0
#define LOD_MAX_LEVELS 6
#define LOD_SMALLEST 64 /* as --budget-ms: no level below about this many vertices */

static _Noreturn void lod_fail(const char* message) {
    fprintf(stderr, "sb_study: level of detail: %s\n", message);
    exit(1);
}

/* A level: its mesh and, per vertex, the full model's vertex it is. */
typedef struct lod_level {
    sb_mesh mesh;
    uint32_t* full_index;
} lod_level;

static sb_material_def lod_material(void) {
    sb_material_def m = sb_default_material_def();
    m.bond_k = 1000.0;
    m.angle_k = 0.5;
    m.stretch_bend_k = 0.0;
    m.spring_k = 100.0;
    m.spring_damping = 0.05;
    m.bend_k = 0.0005;
    m.density = 0.2;
    return m;
}

/* The two vertices at the top (largest y) corners. */
static void top_corners(const sb_mesh* mesh, uint32_t corners[2]) {
    double best[2] = {-INFINITY, -INFINITY};
    for (uint32_t i = 0; i < mesh->vertex_count; i++) {
        const double* p = mesh->positions + 3 * i;
        double score[2] = {p[1] - p[0], p[1] + p[0]}; /* top left, top right */
        for (int c = 0; c < 2; c++)
            if (score[c] > best[c]) best[c] = score[c], corners[c] = i;
    }
}

/* The next level: half the vertices of `from`, the top corners locked. */
static bool lod_simplify(const lod_level* from, lod_level* to) {
    sb_error err;
    uint32_t n = from->mesh.vertex_count, corners[2] = {0, 0};
    to->mesh = (sb_mesh){n, malloc(3 * (size_t)n * sizeof(double)), from->mesh.triangle_count,
                         malloc(3 * (size_t)from->mesh.triangle_count * sizeof(uint32_t))};
    uint32_t* origin = malloc((size_t)n * sizeof *origin);
    to->full_index = malloc((size_t)n * sizeof *to->full_index);
    if (!to->mesh.positions || !to->mesh.triangles || !origin || !to->full_index) lod_fail("out of memory");
    memcpy(to->mesh.positions, from->mesh.positions, 3 * (size_t)n * sizeof(double));
    memcpy(to->mesh.triangles, from->mesh.triangles, 3 * (size_t)from->mesh.triangle_count * sizeof(uint32_t));
    top_corners(&from->mesh, corners);
    sb_simplify_def def = sb_default_simplify_def();
    def.target_vertices = n / 2;
    def.locked = corners;
    def.locked_count = 2;
    if (sb_mesh_simplify(&to->mesh, &def, origin, NULL, &err) != SB_OK) lod_fail(err.message);
    for (uint32_t i = 0; i < to->mesh.vertex_count; i++) to->full_index[i] = from->full_index[origin[i]];
    free(origin);
    /* stuck, as --budget-ms decides: the locked vertices are most of it */
    return (uint64_t)to->mesh.vertex_count * 10 <= (uint64_t)n * 9;
}

static sb_model* lod_model(const sb_mesh* mesh) {
    sb_error err;
    sb_material_def material = lod_material();
    sb_builder* builder = sb_builder_create();
    if (!builder || sb_builder_add_mesh(builder, mesh, &material, &err) != SB_OK) lod_fail("the sheet's model");
    uint32_t corners[2] = {0, 0};
    top_corners(mesh, corners);
    for (int c = 0; c < 2; c++) sb_builder_vertex(builder, corners[c])->fixed = true;
    sb_model* model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    if (!model) lod_fail(err.message);
    return model;
}

/* The level's run: end positions into out (3n), CPU ms per step returned. */
static double lod_run(const lod_level* level, double* out) {
    sb_error err;
    sb_model* model = lod_model(&level->mesh);
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_VERLET;
    def.kernels = SB_KERNELS_FAST;
    def.runtime.threads = 1;
    def.gravity[2] = -9.81;
    def.drag = 1.0;
    sb_solver* solver = sb_solver_create(model, &def, &err);
    if (!solver) lod_fail(err.message);
    int steps = (int)lround(LOD_DURATION / LOD_DT);
    clock_t start = clock();
    for (int k = 0; k < steps; k++)
        if (sb_solver_advance(solver, LOD_DT) != SB_OK) lod_fail(sb_solver_error(solver));
    double ms = 1e3 * (double)(clock() - start) / CLOCKS_PER_SEC / steps;
    sb_solver_get_positions(solver, out);
    sb_solver_destroy(solver);
    sb_model_destroy(model);
    return ms;
}

void study_lod_accuracy(const char* out, bool quick) {
    sb_error err;
    lod_level levels[LOD_MAX_LEVELS];
    memset(levels, 0, sizeof levels);
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = quick ? LOD_SIDE / 2 : LOD_SIDE;
    if (sb_mesh_generate_sheet(&sheet, &levels[0].mesh, &err) != SB_OK) lod_fail(err.message);
    uint32_t full_count = levels[0].mesh.vertex_count;
    levels[0].full_index = malloc((size_t)full_count * sizeof *levels[0].full_index);
    if (!levels[0].full_index) lod_fail("out of memory");
    for (uint32_t i = 0; i < full_count; i++) levels[0].full_index[i] = i;
    int count = 1;
    while (count < LOD_MAX_LEVELS && levels[count - 1].mesh.vertex_count / 2 >= LOD_SMALLEST) {
        if (!lod_simplify(&levels[count - 1], &levels[count])) {
            sb_mesh_free(&levels[count].mesh), free(levels[count].full_index);
            break;
        }
        count++;
    }
    FILE* csv = study_open(out, "lod_accuracy.csv");
    fprintf(csv,
            "# level of detail against accuracy (bench/study_lod.c): the default scene's sheet at %u vertices and "
            "its simplified levels, %g s of Verlet at dt = %g s, fast kernels, 1 thread; error at the end against "
            "the full model's same vertices\n",
            full_count, LOD_DURATION, LOD_DT);
    fprintf(csv, "vertices,triangles,ms_per_step,rms_error_m,max_error_m,relative_rms_error\n");
    double* full = malloc(3 * (size_t)full_count * sizeof *full);
    double* here = malloc(3 * (size_t)full_count * sizeof *here);
    if (!full || !here) lod_fail("out of memory");
    for (int l = 0; l < count; l++) {
        double ms = lod_run(&levels[l], l == 0 ? full : here);
        const double* end = l == 0 ? full : here;
        double error2 = 0.0, moved2 = 0.0, largest = 0.0;
        for (uint32_t i = 0; i < levels[l].mesh.vertex_count; i++) {
            uint32_t f = levels[l].full_index[i];
            double d2 = 0.0, m2 = 0.0;
            for (int c = 0; c < 3; c++) {
                double d = end[3 * i + c] - full[3 * f + c], m = full[3 * f + c] - levels[0].mesh.positions[3 * f + c];
                d2 += d * d, m2 += m * m;
            }
            error2 += d2, moved2 += m2, largest = fmax(largest, sqrt(d2));
        }
        double n = levels[l].mesh.vertex_count;
        fprintf(csv, "%u,%u,%.6g,%.6g,%.6g,%.6g\n", levels[l].mesh.vertex_count, levels[l].mesh.triangle_count, ms,
                sqrt(error2 / n), largest, sqrt(error2 / moved2));
        fflush(csv);
    }
    fclose(csv);
    free(full), free(here);
    for (int l = 0; l < count; l++) sb_mesh_free(&levels[l].mesh), free(levels[l].full_index);
}
