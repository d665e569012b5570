/* sb_bench_haptics: the servo thread beside a running simulation.
 *
 *   sb_bench_haptics [--seconds S] [--threads N]
 *
 * For sheets of about 3 200, 10 000 and 100 000 vertices (57², 100², 317²,
 * 1 m wide, held on two sides, no gravity, a 5 cm sphere tool 1 mm into
 * the middle, held still by the "none" device), runs the simulation S
 * seconds (default 60) as fast as it goes, first
 * alone, then with the 1 kHz servo thread coupled to the tool (the
 * simulation drives and senses the tool every step, as `softbond run`
 * does), and prints a CSV row per sheet: the steps per second without and
 * with the servo, the servo's period (median, 99th percentile, maximum),
 * its worst lateness, and the age of the contact model it used (median,
 * 99th percentile), with whether SCHED_FIFO was granted. bench/haptics.sh
 * builds it and writes bench/results/haptics.csv and haptics.md. */
#define _GNU_SOURCE
#include "softbond/softbond.h"
#include "common/clock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct bench_case {
    sb_mesh mesh;
    sb_model* model;
    sb_collider* tool;
    sb_solver* solver;
} bench_case;

static int bench_open(bench_case* b, uint32_t side, int threads) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = side;
    sb_error err;
    if (sb_mesh_generate_sheet(&sheet, &b->mesh, &err) != SB_OK) return fprintf(stderr, "%s\n", err.message), 1;
    sb_material_def material = sb_default_material_def();
    material.bond_k = 50;
    material.angle_k = 0.3;
    sb_builder* builder = sb_builder_create();
    if (sb_builder_add_mesh(builder, &b->mesh, &material, &err) != SB_OK)
        return fprintf(stderr, "%s\n", err.message), 1;
    for (uint32_t i = 0; i < side; i++) {
        sb_builder_vertex(builder, i)->fixed = true;
        sb_builder_vertex(builder, (side - 1) * side + i)->fixed = true;
    }
    b->model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    if (!b->model) return fprintf(stderr, "%s\n", err.message), 1;
    sb_collider_def c = sb_default_collider_def();
    c.shape = SB_COLLIDER_SPHERE;
    c.center[0] = c.center[1] = 0.5;
    c.center[2] = -0.049; /* 1 mm into the sheet: the tool is in contact throughout */
    c.radius = 0.05;
    b->tool = sb_collider_create(&c, &err);
    sb_solver_def def = sb_default_solver_def();
    def.kernels = SB_KERNELS_FAST;
    def.gravity[2] = 0;
    def.drag = 5;
    def.colliders = &b->tool;
    def.collider_count = 1;
    def.runtime.threads = threads;
    b->solver = sb_solver_create(b->model, &def, &err);
    return b->solver ? 0 : (fprintf(stderr, "%s\n", err.message), 1);
}

static void bench_close(bench_case* b) {
    sb_solver_destroy(b->solver);
    sb_collider_destroy(b->tool);
    sb_model_destroy(b->model);
    sb_mesh_free(&b->mesh);
}

/* Steps per second over `seconds`, with the servo coupled when h is not NULL. */
static double steps_per_second(bench_case* b, sb_haptics* h, double seconds) {
    sb_haptic_tick ticks[256];
    double start = sb_wall_seconds();
    uint64_t steps = 0;
    while (sb_wall_seconds() - start < seconds) {
        if (h) sb_haptics_drive(h);
        if (sb_solver_advance(b->solver, 1e-4) != SB_OK) {
            fprintf(stderr, "sb_bench_haptics: %s\n", sb_solver_error(b->solver));
            exit(1);
        }
        if (h) {
            sb_haptics_sense(h, b->solver, sb_haptics_clock(h));
            while (sb_haptics_drain(h, ticks, 256) > 0) {
            }
        }
        steps++;
    }
    return (double)steps / (sb_wall_seconds() - start);
}

int main(int argc, char** argv) {
    double seconds = 60;
    int threads = 1;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--seconds") == 0 && i + 1 < argc)
            seconds = atof(argv[++i]);
        else if (strcmp(argv[i], "--threads") == 0 && i + 1 < argc)
            threads = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: sb_bench_haptics [--seconds S] [--threads N]\n");
            return 2;
        }
    }
    static const uint32_t sides[] = {57, 100, 317};
    printf("vertices,threads,seconds,steps_per_s_alone,steps_per_s_with_servo,ratio,ticks,period_median_ms,"
           "period_p99_ms,period_max_ms,late_max_ms,age_median_ms,age_p99_ms,sched_fifo\n");
    for (size_t s = 0; s < sizeof sides / sizeof sides[0]; s++) {
        bench_case b = {0};
        if (bench_open(&b, sides[s], threads) != 0) return 1;
        double alone = steps_per_second(&b, NULL, seconds);
        sb_error err;
        sb_haptic_device* device = sb_haptic_device_open(&(sb_haptic_device_def){.kind = "none"}, &err);
        sb_haptics_def def = sb_default_haptics_def();
        def.stall_time = 1; /* a 100k step may take longer than 50 ms on a loaded machine; measured, not judged */
        sb_haptics* h = sb_haptics_create(&def, device, b.tool, 0, &err);
        bool fifo = false;
        if (!h || sb_haptics_start(h, &fifo, &err) != SB_OK) return fprintf(stderr, "%s\n", err.message), 1;
        double with = steps_per_second(&b, h, seconds);
        sb_haptics_stop(h);
        sb_haptics_stats st = sb_haptics_statistics(h);
        printf("%u,%d,%g,%.1f,%.1f,%.3f,%llu,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%s\n", sides[s] * sides[s], threads, seconds,
               alone, with, with / alone, (unsigned long long)st.ticks, 1e3 * st.period_median, 1e3 * st.period_p99,
               1e3 * st.period_max, 1e3 * st.late_max, 1e3 * st.age_median, 1e3 * st.age_p99, fifo ? "yes" : "no");
        fflush(stdout);
        sb_haptics_destroy(h);
        sb_haptic_device_close(device);
        bench_close(&b);
    }
    return 0;
}
