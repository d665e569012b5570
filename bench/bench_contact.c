/* sb_bench_contact: what contact costs a step.
 *
 * The 100k-vertex sheet of sb_bench (bond, angle and stretch-bend terms,
 * fast kernels, Verlet, its dt, two corners pinned, spacing 3.2 mm) falls
 * for 0.05 s onto a sphere whose top touches the sheet's middle, above a
 * floor, in three scenes:
 *   draped  a sphere of radius 0.1 m, the floor 0.5 m down, out of reach:
 *           the vertices over the sphere touch it, the rest of the sheet
 *           is culled by the bounds;
 *   floor   the same sphere, the floor 2 mm down: after the warm-up every
 *           vertex lies on it (the worst case: the whole sheet answered
 *           every step);
 *   face    a sphere of radius 1 mm under the centre of a cell, between
 *           four vertices, the floor out of reach: the sheet rests on it
 *           by face contact alone (kernels/contact/surface.c).
 * From the warmed-up state, steps are timed without colliders, with the
 * plane and the sphere, with them answering vertices only (the solver's
 * vertex_contact_only: no face-contact pass; the difference is that
 * pass's share of the step), and with the plane, the sphere and self-contact
 * (thickness 1 mm, a third of the sheet's spacing), interleaved, on 1 and
 * 2 threads (spinning, pinned: the machine is the benchmark's); the contact
 * passes' cost is the difference. Prints a table and writes CSV and
 * markdown, with the load average at the start and at the end.
 *
 *   sb_bench_contact [--steps N] [--runs N] [--scene NAME] [--cpu] [--csv FILE] [--md FILE]
 *
 * --scene times one scene only (draped, floor or face): a before/after pair
 * of binaries run interleaved on it. --cpu times by the process's CPU time
 * instead of the wall clock: on 1 thread it does not count the time spent
 * waiting for a core on a loaded machine (on 2 it counts the workers'
 * spinning too). */
#include "bench/bench_cases.h"
#include "common/clock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct contact_options {
    int steps, runs;
    const char *csv, *md, *scene; /* scene: NULL for every scene */
    bool cpu;                     /* time by the process's CPU time */
} contact_options;

/* The process's CPU time, s. */
static double cpu_seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The clock the steps are timed by (sb_wall_seconds, or cpu_seconds with --cpu). */
static double (*timer)(void) = sb_wall_seconds;

/* A scene: where the floor lies, the sphere's center height and radius. */
typedef struct contact_scene {
    const char* name;
    double floor, radius;
} contact_scene;

static const contact_scene scenes[] = {{"draped", -0.5, 0.1}, {"floor", -0.002, 0.1}, {"face", -0.5, 0.001}};

static sb_collider* checked(sb_collider* c, const sb_error* err) {
    if (!c) {
        fprintf(stderr, "sb_bench_contact: %s\n", err->message);
        exit(1);
    }
    return c;
}

/* The scene's floor or sphere (its top at the sheet's middle, the centre
 * of a cell: the sheet's vertices lie at multiples of 1/315 m). */
static sb_collider* make_collider(sb_collider_shape shape, const contact_scene* scene) {
    sb_collider_def def = sb_default_collider_def();
    def.shape = shape;
    def.friction = def.static_friction = 0.3;
    if (shape == SB_COLLIDER_PLANE) {
        def.name = "floor";
        def.point[2] = scene->floor;
    } else {
        def.name = "ball";
        def.center[0] = def.center[1] = 0.5;
        def.center[2] = -scene->radius;
        def.radius = scene->radius;
    }
    sb_error err;
    return checked(sb_collider_create(&def, &err), &err);
}

/* The 1-minute load average, or -1. */
static double load_average(void) {
    FILE* f = fopen("/proc/loadavg", "r");
    double load = -1.0;
    if (f) {
        if (fscanf(f, "%lf", &load) != 1) load = -1.0;
        fclose(f);
    }
    return load;
}

#define SB_BENCH_SELF_THICKNESS 1e-3

/* What a timing's solver answers besides its colliders' vertices. */
typedef enum contact_mode { FACES, VERTICES_ONLY, SELF } contact_mode;

static sb_solver* make_solver(const sb_bench_setup* setup, int threads, sb_collider** colliders, uint32_t count,
                              contact_mode mode) {
    bool self = mode == SELF;
    sb_solver_def def = sb_default_solver_def();
    def.gravity[2] = -SB_BENCH_GRAVITY;
    def.runtime = (sb_runtime_def){.threads = threads, .pin = threads > 1, .wait = SB_WAIT_SPIN};
    def.colliders = colliders;
    def.collider_count = count;
    def.self_collision = self;
    def.contact_thickness = self ? SB_BENCH_SELF_THICKNESS : 0.0;
    def.vertex_contact_only = mode == VERTICES_ONLY;
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

/* Seconds per step from the warmed-up state, with or without colliders,
 * face contact and self-contact; the contacts answered per step (vertices,
 * pairs). */
static double time_steps(const sb_bench_setup* setup, int threads, sb_collider** colliders, uint32_t count,
                         contact_mode mode, const double* x, const double* v, int steps, double per_step[2]) {
    sb_solver* s = make_solver(setup, threads, colliders, count, mode);
    sb_solver_set_state(s, x, v);
    advance(s, setup->dt, 20, NULL, NULL); /* caches and the team warm */
    uint64_t contacts = 0, self_contacts = 0;
    double t0 = timer();
    advance(s, setup->dt, steps, &contacts, &self_contacts);
    double seconds = (timer() - t0) / steps;
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
        else if (i + 1 < argc && !strcmp(a, "--scene"))
            o->scene = argv[++i];
        else if (!strcmp(a, "--cpu"))
            o->cpu = true;
        else {
            fprintf(stderr,
                    "usage: sb_bench_contact [--steps N] [--runs N] [--scene NAME] [--cpu] [--csv FILE] [--md FILE]\n");
            exit(2);
        }
    }
    bool known = o->scene == NULL;
    for (size_t k = 0; k < sizeof scenes / sizeof *scenes; k++) known |= o->scene && !strcmp(o->scene, scenes[k].name);
    if (!known) {
        fprintf(stderr, "sb_bench_contact: --scene %s: not a scene (draped, floor or face)\n", o->scene);
        exit(2);
    }
    if (o->cpu) timer = cpu_seconds;
    if (o->steps < 1 || o->runs < 1) {
        fprintf(stderr, "sb_bench_contact: --steps and --runs must be positive\n");
        exit(2);
    }
}

int main(int argc, char** argv) {
    contact_options o = {.steps = 400,
                         .runs = 3,
                         .csv = "bench/results/contact.csv",
                         .md = "bench/results/contact.md",
                         .scene = NULL,
                         .cpu = false};
    parse(argc, argv, &o);
    sb_bench_setup setup;
    sb_error err;
    sb_bench_options bo = {.jitter = SB_BENCH_DEFAULT_JITTER};
    if (sb_bench_build(sb_bench_find_case("sheet_100k"), &bo, &setup, &err) != SB_OK) {
        fprintf(stderr, "sb_bench_contact: %s\n", err.message);
        return 1;
    }
    uint32_t n = setup.mesh.vertex_count;
    double *x = malloc(3 * (size_t)n * sizeof *x), *v = malloc(3 * (size_t)n * sizeof *v);
    char machine[256];
    sb_runtime_describe(machine, sizeof machine);
    FILE *csv = fopen(o.csv, "w"), *md = fopen(o.md, "w");
    if (!csv || !md) {
        fprintf(stderr, "sb_bench_contact: cannot write %s or %s\n", o.csv, o.md);
        return 1;
    }
    double load_start = load_average();
    fprintf(csv, "scene,threads,run,ms_without,ms_with,ratio,contacts_per_step,ms_vertices_only,face_share,ms_self,"
                 "ratio_self,self_per_step\n");
    fprintf(md, "# Contact: the cost of a plane, a sphere and self-contact on the 100k sheet\n\n");
    fprintf(md,
            "Machine: `%s`. Written by `bench/contact.sh` (`sb_bench_contact`; the scenes and the method are at the "
            "top of bench/bench_contact.c). %s; %d steps per timing, dt %.3g s, %u vertices, self-contact thickness "
            "%g m; runs interleaved; the best of each configuration in bold. Face share: the part of the step with "
            "the plane and the sphere that the face-contact pass takes (1 − vertices only / with).\n\n",
            machine, o.cpu ? "Timed by the process's CPU time (--cpu)" : "Timed by the wall clock", o.steps, setup.dt,
            n, SB_BENCH_SELF_THICKNESS);
    fprintf(md, "| scene | threads | run | ms/step without | with plane + sphere | ratio | contacts/step | "
                "vertices only (no face pass) | face share | with them + self-contact | ratio | self pairs/step |\n"
                "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    printf("scene   threads run  ms_without  ms_with  ratio  contacts  ms_vertices  face_share  ms_self  ratio  "
           "self_pairs\n");
    for (size_t scene = 0; scene < sizeof scenes / sizeof *scenes; scene++) {
        const contact_scene* sc = &scenes[scene];
        if (o.scene && strcmp(o.scene, sc->name)) continue;
        sb_collider* colliders[2] = {make_collider(SB_COLLIDER_PLANE, sc), make_collider(SB_COLLIDER_SPHERE, sc)};
        sb_solver* warm = make_solver(&setup, 2, colliders, 2, FACES); /* 0.05 s of falling onto the colliders */
        advance(warm, setup.dt, (int)(0.05 / setup.dt), NULL, NULL);
        sb_solver_get_positions(warm, x);
        sb_solver_get_velocities(warm, v);
        sb_solver_destroy(warm);
        for (int threads = 1; threads <= 2; threads++) {
            double best[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
            for (int run = 1; run <= o.runs; run++) {
                double counts[2], self_counts[2], ignored[2];
                double without = time_steps(&setup, threads, NULL, 0, FACES, x, v, o.steps, ignored);
                double with = time_steps(&setup, threads, colliders, 2, FACES, x, v, o.steps, counts);
                double vertices = time_steps(&setup, threads, colliders, 2, VERTICES_ONLY, x, v, o.steps, ignored);
                double self = time_steps(&setup, threads, colliders, 2, SELF, x, v, o.steps, self_counts);
                double times[4] = {without, with, vertices, self};
                for (int k = 0; k < 4; k++) best[k] = fmin(best[k], times[k]);
                printf("%-7s %7d %3d  %10.3f  %7.3f  %5.3f  %8.0f  %11.3f  %10.3f  %7.3f  %5.3f  %.1f\n", sc->name,
                       threads, run, 1e3 * without, 1e3 * with, with / without, counts[0], 1e3 * vertices,
                       1.0 - vertices / with, 1e3 * self, self / without, self_counts[1]);
                fprintf(csv, "%s,%d,%d,%.6f,%.6f,%.4f,%.0f,%.6f,%.4f,%.6f,%.4f,%.1f\n", sc->name, threads, run,
                        1e3 * without, 1e3 * with, with / without, counts[0], 1e3 * vertices, 1.0 - vertices / with,
                        1e3 * self, self / without, self_counts[1]);
                fprintf(md, "| %s | %d | %d | %.3f | %.3f | %.3f | %.0f | %.3f | %.3f | %.3f | %.3f | %.1f |\n",
                        sc->name, threads, run, 1e3 * without, 1e3 * with, with / without, counts[0], 1e3 * vertices,
                        1.0 - vertices / with, 1e3 * self, self / without, self_counts[1]);
            }
            fprintf(md, "| %s | %d | best | %.3f | %.3f | **%.3f** | | %.3f | **%.3f** | %.3f | **%.3f** | |\n",
                    sc->name, threads, 1e3 * best[0], 1e3 * best[1], best[1] / best[0], 1e3 * best[2],
                    1.0 - best[2] / best[1], 1e3 * best[3], best[3] / best[0]);
        }
        for (int c = 0; c < 2; c++) sb_collider_destroy(colliders[c]);
    }
    fprintf(md, "\nLoad average (1 minute): %.2f at the start, %.2f at the end.\n", load_start, load_average());
    fclose(csv);
    fclose(md);
    free(x);
    free(v);
    sb_bench_setup_free(&setup);
    return 0;
}
