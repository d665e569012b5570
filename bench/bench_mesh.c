/* sb_bench_mesh: how long a large mesh takes to become a model (issue 5's
 * performance targets), written to bench/results/mesh_load.csv by
 * bench/mesh.sh.
 *
 *   sb_bench_mesh [--csv FILE] [--trials N] [--cold] [--keep DIR]
 *
 * Load and compile: a 708 × 708 jittered sheet (501 264 vertices, 999 698
 * triangles) is written as an OBJ file (35 MB of text), then each trial
 * times, separately, sb_mesh_load of that file, sb_builder_add_mesh (the
 * molecular-mechanics factory: bonds, every corner's angle and
 * stretch-bend) with sb_builder_compile, and sb_builder_add_spring_mesh
 * (stretch and bend springs) with sb_builder_compile. The target is load +
 * add + compile < 2 s. With --cold (root only) the page cache is dropped
 * before the first trial, so its load reads the disk; the other trials find
 * the file in memory. The first and the best trial are both reported.
 *
 * Vicinity: sb_vicinity_pairs on the 1000 × 1000 sheet with a radius of
 * 1.5 spacings, and on 10^6 uniform random points in a unit cube with a
 * radius of 0.01; target < 1 s each. */
#include "softbond/softbond.h"
#include "common/clock.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define SHEET_SIDE 708 /* 2 · 707² = 999 698 triangles */
#define CLOUD_SIZE 1000000

typedef struct phase_times {
    double first, best;
} phase_times;

static void fail(const char* what, const sb_error* err) {
    fprintf(stderr, "sb_bench_mesh: %s: %s\n", what, err ? err->message : "failed");
    exit(1);
}

static void record(phase_times* p, int trial, double seconds) {
    if (trial == 0) p->first = p->best = seconds;
    if (seconds < p->best) p->best = seconds;
}

static sb_mesh make_sheet(uint32_t side) {
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = def.ny = side;
    sb_mesh mesh;
    sb_error err;
    if (sb_mesh_generate_sheet(&def, &mesh, &err) != SB_OK) fail("sheet", &err);
    return mesh;
}

static void write_obj(const char* path, const sb_mesh* mesh) {
    FILE* f = fopen(path, "w");
    if (!f) fail(path, NULL);
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        fprintf(f, "v %.9g %.9g %.9g\n", mesh->positions[3 * v], mesh->positions[3 * v + 1],
                mesh->positions[3 * v + 2]);
    for (uint32_t t = 0; t < mesh->triangle_count; t++)
        fprintf(f, "f %u %u %u\n", mesh->triangles[3 * t] + 1, mesh->triangles[3 * t + 1] + 1,
                mesh->triangles[3 * t + 2] + 1);
    if (fclose(f) != 0) fail(path, NULL);
}

/* Drops the page cache so that the next read comes from the disk (root). */
static int drop_page_cache(void) {
    sync();
    FILE* f = fopen("/proc/sys/vm/drop_caches", "w");
    if (!f) return 0;
    int ok = fputs("3\n", f) >= 0;
    return fclose(f) == 0 && ok;
}

/* Adds a mesh with one of the two factories and compiles it; seconds taken. */
static double add_and_compile(const sb_mesh* mesh, int springs) {
    sb_error err;
    double start = sb_wall_seconds();
    sb_builder* builder = sb_builder_create();
    sb_material_def material = sb_default_material_def();
    sb_spring_mesh_def spring = sb_default_spring_mesh_def();
    sb_status status = springs ? sb_builder_add_spring_mesh(builder, mesh, &spring, &err)
                               : sb_builder_add_mesh(builder, mesh, &material, &err);
    if (status != SB_OK) fail("factory", &err);
    sb_model* model = sb_builder_compile(builder, &err);
    if (!model) fail("compile", &err);
    double seconds = sb_wall_seconds() - start;
    sb_builder_destroy(builder);
    sb_model_destroy(model);
    return seconds;
}

static double time_vicinity(const double* positions, uint32_t count, double radius, size_t* pairs_out) {
    uint32_t* pairs;
    sb_error err;
    double start = sb_wall_seconds();
    if (sb_vicinity_pairs(positions, count, radius, &pairs, pairs_out, &err) != SB_OK) fail("vicinity", &err);
    double seconds = sb_wall_seconds() - start;
    free(pairs);
    return seconds;
}

static double* random_cloud(uint32_t count) {
    double* p = malloc(3 * (size_t)count * sizeof *p);
    uint64_t state = 0x9E3779B97F4A7C15ull;
    for (size_t i = 0; i < 3 * (size_t)count; i++) {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        p[i] = (double)(state >> 11) / 9007199254740992.0;
    }
    return p;
}

int main(int argc, char** argv) {
    const char* csv_path = "mesh_load.csv";
    const char* dir = NULL;
    int trials = 5, cold = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--csv") == 0 && i + 1 < argc)
            csv_path = argv[++i];
        else if (strcmp(argv[i], "--trials") == 0 && i + 1 < argc)
            trials = atoi(argv[++i]);
        else if (strcmp(argv[i], "--keep") == 0 && i + 1 < argc)
            dir = argv[++i];
        else if (strcmp(argv[i], "--cold") == 0)
            cold = 1;
        else
            return fprintf(stderr, "usage: sb_bench_mesh [--csv FILE] [--trials N] [--cold] [--keep DIR]\n"), 2;
    }
    if (trials < 1) return fprintf(stderr, "sb_bench_mesh: --trials must be at least 1\n"), 2;
    char obj[4096];
    snprintf(obj, sizeof obj, "%s/sb_bench_mesh_%ld.obj", dir ? dir : "/tmp", (long)getpid());
    sb_mesh sheet = make_sheet(SHEET_SIDE);
    write_obj(obj, &sheet);
    uint32_t vertices = sheet.vertex_count, triangles = sheet.triangle_count;
    sb_mesh_free(&sheet);
    int cold_done = cold && drop_page_cache();
    if (cold && !cold_done) fprintf(stderr, "sb_bench_mesh: could not drop the page cache (not root?)\n");

    phase_times load = {0}, mm = {0}, springs = {0}, total = {0};
    for (int trial = 0; trial < trials; trial++) {
        sb_mesh mesh;
        sb_error err;
        double start = sb_wall_seconds();
        if (sb_mesh_load(obj, &mesh, &err) != SB_OK) fail("load", &err);
        double t_load = sb_wall_seconds() - start;
        double t_mm = add_and_compile(&mesh, 0);
        double t_springs = add_and_compile(&mesh, 1);
        record(&load, trial, t_load);
        record(&mm, trial, t_mm);
        record(&springs, trial, t_springs);
        record(&total, trial, t_load + t_mm);
        sb_mesh_free(&mesh);
    }
    if (!dir) remove(obj);

    sb_mesh grid = make_sheet(1000);
    double spacing = 1.0 / 999.0;
    phase_times grid_t = {0}, cloud_t = {0};
    size_t grid_pairs = 0, cloud_pairs = 0;
    double* cloud = random_cloud(CLOUD_SIZE);
    for (int trial = 0; trial < trials; trial++) {
        record(&grid_t, trial, time_vicinity(grid.positions, grid.vertex_count, 1.5 * spacing, &grid_pairs));
        record(&cloud_t, trial, time_vicinity(cloud, CLOUD_SIZE, 0.01, &cloud_pairs));
    }

    FILE* csv = fopen(csv_path, "w");
    if (!csv) fail(csv_path, NULL);
    double load_avg[3] = {0};
    getloadavg(load_avg, 3);
    fprintf(csv, "# sb_bench_mesh, %d trials, first trial %s, load average at the end %.2f\n", trials,
            cold_done ? "after dropping the page cache" : "with the file in the page cache", load_avg[0]);
    fprintf(csv, "case,vertices,triangles_or_pairs,phase,first_s,best_s,target_s\n");
    const char* sheet_case = "sheet_708_obj";
    fprintf(csv, "%s,%u,%u,load,%.4f,%.4f,\n", sheet_case, vertices, triangles, load.first, load.best);
    fprintf(csv, "%s,%u,%u,mm_factory_compile,%.4f,%.4f,\n", sheet_case, vertices, triangles, mm.first, mm.best);
    fprintf(csv, "%s,%u,%u,load_mm_factory_compile,%.4f,%.4f,2\n", sheet_case, vertices, triangles, total.first,
            total.best);
    fprintf(csv, "%s,%u,%u,spring_factory_compile,%.4f,%.4f,\n", sheet_case, vertices, triangles, springs.first,
            springs.best);
    fprintf(csv, "sheet_1000_vicinity_1.5h,%u,%zu,vicinity,%.4f,%.4f,1\n", grid.vertex_count, grid_pairs, grid_t.first,
            grid_t.best);
    fprintf(csv, "cloud_1m_vicinity_0.01,%u,%zu,vicinity,%.4f,%.4f,1\n", CLOUD_SIZE, cloud_pairs, cloud_t.first,
            cloud_t.best);
    fclose(csv);
    free(cloud);
    sb_mesh_free(&grid);
    printf("load %.3f s, MM factory + compile %.3f s, total %.3f s (first %.3f s); spring factory + compile "
           "%.3f s; vicinity sheet %.3f s, cloud %.3f s\n",
           load.best, mm.best, total.best, total.first, springs.best, grid_t.best, cloud_t.best);
    return 0;
}
