/* sb_bench_contact: what contact costs a step.
 *
 * The 100k-vertex sheet of sb_bench (bond, angle and stretch-bend terms,
 * fast kernels, Verlet, its dt, two corners pinned) falls for 0.05 s onto a
 * sphere of radius 0.1 m whose top touches the sheet's middle, above a
 * floor, in two scenes:
 *   draped  the floor 0.5 m down, out of reach: the vertices over the
 *           sphere touch it, the rest of the sheet is culled by the bounds;
 *   floor   the floor 2 mm down: after the warm-up every vertex lies on it
 *           (the worst case: the whole sheet answered every step).
 * From the warmed-up state, steps are timed without colliders, with the
 * plane and the sphere, and with them and self-contact (thickness 1 mm, a
 * third of the sheet's spacing), interleaved, on 1 and 2 threads
 * (spinning, pinned: the machine is the benchmark's); the contact passes'
 * cost is the difference. Prints a table and writes CSV and markdown.
 *
 *   sb_bench_contact [--steps N] [--runs N] [--csv FILE] [--md FILE] */
#include "bench/bench_cases.h"
#include "common/clock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct contact_options {
    int steps, runs;
    const char *csv, *md;
} contact_options;

static sb_collider* make_collider(sb_collider_shape shape, double floor) {
    sb_collider_def def = sb_default_collider_def();
    def.shape = shape;
    def.friction = def.static_friction = 0.3;
    if (shape == SB_COLLIDER_PLANE) {
        def.name = "floor";
        def.point[2] = floor;
    } else {
        def.name = "ball";
        def.center[0] = def.center[1] = 0.5;
        def.center[2] = -0.1;
        def.radius = 0.1;
    }
    sb_error err;
    sb_collider* c = sb_collider_create(&def, &err);
    if (!c) {
        fprintf(stderr, "sb_bench_contact: %s\n", err.message);
        exit(1);
    }
    return c;
}

#define SB_BENCH_SELF_THICKNESS 1e-3

static sb_solver* make_solver(const sb_bench_setup* setup, int threads, sb_collider** colliders, uint32_t count,
                              bool self) {
    sb_solver_def def = sb_default_solver_def();
    def.gravity[2] = -SB_BENCH_GRAVITY;
    def.runtime = (sb_runtime_def){.threads = threads, .pin = threads > 1, .wait = SB_WAIT_SPIN};
    def.colliders = colliders;
    def.collider_count = count;
    def.self_collision = self;
    def.contact_thickness = self ? SB_BENCH_SELF_THICKNESS : 0.0;
    sb_error err;
    sb_solver* s = sb_solver_create(setup->model, &def, &err);
    if (!s) {
        fprintf(stderr, "sb_bench_contact: %s\n", err.message);
        exit(1);
    }
    return s;
}

static void advance(sb_solver* s, double dt, int steps, uint64_t* contacts, uint64_t* self_contacts) {
    for (int i = 0; i < steps; i++) {
        if (sb_solver_advance(s, dt) != SB_OK) {
            fprintf(stderr, "sb_bench_contact: %s\n", sb_solver_error(s));
            exit(1);
        }
        if (contacts) *contacts += sb_solver_last_step(s).contacts;
        if (self_contacts) *self_contacts += sb_solver_last_step(s).self_contacts;
    }
}

/* Seconds per step from the warmed-up state, with or without colliders
 * and self-contact; the contacts answered per step (vertices, pairs). */
static double time_steps(const sb_bench_setup* setup, int threads, sb_collider** colliders, uint32_t count, bool self,
                         const double* x, const double* v, int steps, double per_step[2]) {
    sb_solver* s = make_solver(setup, threads, colliders, count, self);
    sb_solver_set_state(s, x, v);
    advance(s, setup->dt, 20, NULL, NULL); /* caches and the team warm */
    uint64_t contacts = 0, self_contacts = 0;
    double t0 = sb_wall_seconds();
    advance(s, setup->dt, steps, &contacts, &self_contacts);
    double seconds = (sb_wall_seconds() - t0) / steps;
    per_step[0] = (double)contacts / steps;
    per_step[1] = (double)self_contacts / steps;
    sb_solver_destroy(s);
    return seconds;
}

static void parse(int argc, char** argv, contact_options* o) {
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
        if (i + 1 < argc && !strcmp(a, "--steps"))
            o->steps = atoi(argv[++i]);
        else if (i + 1 < argc && !strcmp(a, "--runs"))
            o->runs = atoi(argv[++i]);
        else if (i + 1 < argc && !strcmp(a, "--csv"))
            o->csv = argv[++i];
        else if (i + 1 < argc && !strcmp(a, "--md"))
            o->md = argv[++i];
        else {
            fprintf(stderr, "usage: sb_bench_contact [--steps N] [--runs N] [--csv FILE] [--md FILE]\n");
            exit(2);
        }
    }
    if (o->steps < 1 || o->runs < 1) {
        fprintf(stderr, "sb_bench_contact: --steps and --runs must be positive\n");
        exit(2);
    }
}

int main(int argc, char** argv) {
    contact_options o = {.steps = 400, .runs = 3, .csv = "bench/results/contact.csv", .md = "bench/results/contact.md"};
    parse(argc, argv, &o);
    sb_bench_setup setup;
    sb_error err;
    sb_bench_options bo = {.jitter = SB_BENCH_DEFAULT_JITTER};
    if (sb_bench_build(sb_bench_find_case("sheet_100k"), &bo, &setup, &err) != SB_OK) {
        fprintf(stderr, "sb_bench_contact: %s\n", err.message);
        return 1;
    }
    const char* scenes[2] = {"draped", "floor"};
    const double floors[2] = {-0.5, -0.002};
    uint32_t n = setup.mesh.vertex_count;
    double *x = malloc(3 * (size_t)n * sizeof *x), *v = malloc(3 * (size_t)n * sizeof *v);
    char machine[256];
    sb_runtime_describe(machine, sizeof machine);
    FILE *csv = fopen(o.csv, "w"), *md = fopen(o.md, "w");
    if (!csv || !md) {
        fprintf(stderr, "sb_bench_contact: cannot write %s or %s\n", o.csv, o.md);
        return 1;
    }
    fprintf(csv, "scene,threads,run,ms_without,ms_with,ratio,contacts_per_step,ms_self,ratio_self,self_per_step\n");
    fprintf(md, "# Contact: the cost of a plane, a sphere and self-contact on the 100k sheet\n\n");
    fprintf(md,
            "Machine: `%s`. Written by `bench/contact.sh` (`sb_bench_contact`; the scenes and the method are at the "
            "top of bench/bench_contact.c). %d steps per timing, dt %.3g s, %u vertices, self-contact thickness "
            "%g m; runs interleaved; the best of each configuration in bold.\n\n",
            machine, o.steps, setup.dt, n, SB_BENCH_SELF_THICKNESS);
    fprintf(md, "| scene | threads | run | ms/step without | with plane + sphere | ratio | contacts/step | "
                "with them + self-contact | ratio | self pairs/step |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    printf("scene   threads run  ms_without  ms_with  ratio  contacts  ms_self  ratio  self_pairs\n");
    for (int scene = 0; scene < 2; scene++) {
        sb_collider* colliders[2] = {make_collider(SB_COLLIDER_PLANE, floors[scene]),
                                     make_collider(SB_COLLIDER_SPHERE, floors[scene])};
        sb_solver* warm = make_solver(&setup, 2, colliders, 2, false); /* 0.05 s of falling onto the colliders */
        advance(warm, setup.dt, (int)(0.05 / setup.dt), NULL, NULL);
        sb_solver_get_positions(warm, x);
        sb_solver_get_velocities(warm, v);
        sb_solver_destroy(warm);
        for (int threads = 1; threads <= 2; threads++) {
            double best[3] = {INFINITY, INFINITY, INFINITY};
            for (int run = 1; run <= o.runs; run++) {
                double counts[2], self_counts[2], ignored[2];
                double without = time_steps(&setup, threads, NULL, 0, false, x, v, o.steps, ignored);
                double with = time_steps(&setup, threads, colliders, 2, false, x, v, o.steps, counts);
                double self = time_steps(&setup, threads, colliders, 2, true, x, v, o.steps, self_counts);
                best[0] = fmin(best[0], without);
                best[1] = fmin(best[1], with);
                best[2] = fmin(best[2], self);
                printf("%-7s %7d %3d  %10.3f  %7.3f  %5.3f  %8.0f  %7.3f  %5.3f  %.1f\n", scenes[scene], threads, run,
                       1e3 * without, 1e3 * with, with / without, counts[0], 1e3 * self, self / without,
                       self_counts[1]);
                fprintf(csv, "%s,%d,%d,%.6f,%.6f,%.4f,%.0f,%.6f,%.4f,%.1f\n", scenes[scene], threads, run,
                        1e3 * without, 1e3 * with, with / without, counts[0], 1e3 * self, self / without,
                        self_counts[1]);
                fprintf(md, "| %s | %d | %d | %.3f | %.3f | %.3f | %.0f | %.3f | %.3f | %.1f |\n", scenes[scene],
                        threads, run, 1e3 * without, 1e3 * with, with / without, counts[0], 1e3 * self, self / without,
                        self_counts[1]);
            }
            fprintf(md, "| %s | %d | best | %.3f | %.3f | **%.3f** | | %.3f | **%.3f** | |\n", scenes[scene], threads,
                    1e3 * best[0], 1e3 * best[1], best[1] / best[0], 1e3 * best[2], best[2] / best[0]);
        }
        for (int c = 0; c < 2; c++) sb_collider_destroy(colliders[c]);
    }
    fclose(csv);
    fclose(md);
    free(x);
    free(v);
    sb_bench_setup_free(&setup);
    return 0;
}
