/* sb_bench_tearing: what tearing costs a step (issue 12).
 *
 * The 100k-vertex sheet of sb_bench (sheet_100k: bond, angle and
 * stretch-bend terms, fast kernels, Verlet, its dt), without gravity,
 * pulled apart by two hard handles on its bottom and top rows moving at
 * --speed m/s each, twice: once with its bonds breaking beyond r0 (1 +
 * --strain), which tears it (the default max_splits: spare vertices
 * reserved), and once without limits, which only stretches. The two
 * solvers advance in interleaved chunks of --chunk steps through the same
 * simulated times, every step timed on its own. Reported:
 *   - steps per second of each while the first tears (from the first step
 *     that broke a bond to the last), their ratio (target >= 0.8), and the
 *     same before any break (what the breakable model costs by itself:
 *     its break-limit test, its spare vertices' memory);
 *   - the cost of one topology update: the time of a step that split
 *     vertices minus the median time of the tearing solver's quiet steps
 *     (no break, no split) of the same run, median and max in ms, and the
 *     same for steps that only broke bonds (the forces evaluated again).
 * Prints a table and writes CSV and markdown.
 *
 *   sb_bench_tearing [--size N] [--steps N] [--chunk N] [--speed V] [--strain S]
 *                    [--threads N] [--csv FILE] [--md FILE] */
#include "bench/bench_cases.h"
#include "common/clock.h"
#include "softbond/handle.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct tearing_options {
    uint32_t size;
    int steps, chunk, threads;
    double speed, strain;
    const char *csv, *md;
} tearing_options;

/* One solver's run: the sheet's model, its two handles and every step's time. */
typedef struct pulled {
    sb_model* model;
    sb_handle* handles[2];
    uint32_t* rows;
    sb_keyframe paths[2][2];
    sb_solver* solver;
    double* seconds;    /* per step */
    uint32_t* broke;    /* bonds broken by each step */
    uint32_t* vertices; /* vertices after each step */
} pulled;

static void fail(const char* what, const char* message) {
    fprintf(stderr, "sb_bench_tearing: %s: %s\n", what, message);
    exit(1);
}

static sb_model* build_model(const sb_bench_setup* setup, double strain) {
    sb_material_def material = setup->material;
    material.break_strain = strain;
    sb_error err;
    sb_builder* b = sb_builder_create();
    if (!b || sb_builder_add_mesh(b, &setup->mesh, &material, &err) != SB_OK) fail("model", err.message);
    sb_model* m = sb_builder_compile(b, &err);
    if (!m) fail("model", err.message);
    sb_builder_destroy(b);
    return m;
}

/* Row 0 moves −y and the last row +y at `speed`. */
static void make_handles(pulled* p, uint32_t side, double speed, double duration) {
    p->rows = malloc(2 * (size_t)side * sizeof *p->rows);
    for (int h = 0; h < 2; h++) {
        uint32_t row = h ? side - 1 : 0;
        for (uint32_t i = 0; i < side; i++) p->rows[h * side + i] = row * side + i;
        p->paths[h][0] = (sb_keyframe){0.0, {0, 0, 0}, {0, 0, 0}};
        p->paths[h][1] = (sb_keyframe){duration, {0, (h ? 1 : -1) * speed * duration, 0}, {0, 0, 0}};
        sb_handle_def def = sb_default_handle_def();
        def.vertices = p->rows + h * side;
        def.vertex_count = side;
        def.path = p->paths[h];
        def.path_count = 2;
        sb_error err;
        if (!(p->handles[h] = sb_handle_create(&def, &err))) fail("handle", err.message);
    }
}

static void start(pulled* p, const sb_bench_setup* setup, const tearing_options* o, double strain) {
    memset(p, 0, sizeof *p);
    p->model = build_model(setup, strain);
    make_handles(p, o->size, o->speed, o->steps * setup->dt);
    sb_solver_def def = sb_default_solver_def();
    def.gravity[2] = 0.0;
    def.handles = p->handles;
    def.handle_count = 2;
    def.runtime = (sb_runtime_def){.threads = o->threads, .pin = o->threads > 1, .wait = SB_WAIT_SPIN};
    sb_error err;
    if (!(p->solver = sb_solver_create(p->model, &def, &err))) fail("solver", err.message);
    p->seconds = calloc(o->steps, sizeof *p->seconds);
    p->broke = calloc(o->steps, sizeof *p->broke);
    p->vertices = calloc(o->steps, sizeof *p->vertices);
}

static void finish(pulled* p) {
    sb_solver_destroy(p->solver);
    for (int h = 0; h < 2; h++) sb_handle_destroy(p->handles[h]);
    sb_model_destroy(p->model);
    free(p->rows);
    free(p->seconds);
    free(p->broke);
    free(p->vertices);
}

static void advance(pulled* p, double dt, int first, int count) {
    for (int k = first; k < first + count; k++) {
        uint32_t broken = sb_solver_broken_count(p->solver);
        double t0 = sb_wall_seconds();
        sb_status status = sb_solver_advance(p->solver, dt);
        p->seconds[k] = sb_wall_seconds() - t0;
        if (status != SB_OK) fail("advance", sb_solver_error(p->solver));
        p->broke[k] = sb_solver_broken_count(p->solver) - broken;
        p->vertices[k] = sb_solver_vertex_count(p->solver);
    }
}

static int compare(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static double median(double* values, int count) {
    if (count == 0) return NAN;
    qsort(values, count, sizeof *values, compare);
    return count % 2 ? values[count / 2] : 0.5 * (values[count / 2 - 1] + values[count / 2]);
}

/* The median of seconds[first, last). */
static double median_of(const double* seconds, int first, int last) {
    double* copy = malloc((size_t)(last - first) * sizeof *copy);
    memcpy(copy, seconds + first, (size_t)(last - first) * sizeof *copy);
    double m = median(copy, last - first);
    free(copy);
    return m;
}

static double sum(const double* seconds, int first, int last) {
    double total = 0.0;
    for (int k = first; k < last; k++) total += seconds[k];
    return total;
}

/* Extra cost over a quiet step of the steps `pick` selects: median and max, ms. */
typedef struct extra_cost {
    int steps;
    double median_ms, max_ms;
} extra_cost;

static extra_cost extra(const pulled* p, int steps, double quiet, bool splits) {
    double* costs = malloc(steps * sizeof *costs);
    extra_cost c = {0, NAN, NAN};
    for (int k = 0; k < steps; k++) {
        uint32_t before = k ? p->vertices[k - 1] : sb_model_vertex_count(p->model);
        bool split = p->vertices[k] > before;
        if (split == splits && (split || p->broke[k] > 0)) costs[c.steps++] = 1e3 * (p->seconds[k] - quiet);
    }
    if (c.steps) {
        c.median_ms = median(costs, c.steps);
        c.max_ms = costs[c.steps - 1];
    }
    free(costs);
    return c;
}

static tearing_options parse(int argc, char** argv) {
    tearing_options o = {.size = 316, .steps = 3000, .chunk = 50, .threads = 1, .speed = 2.0, .strain = 0.05};
    for (int i = 1; i + 1 < argc; i += 2) {
        const char *key = argv[i], *value = argv[i + 1];
        if (!strcmp(key, "--size"))
            o.size = (uint32_t)atoi(value);
        else if (!strcmp(key, "--steps"))
            o.steps = atoi(value);
        else if (!strcmp(key, "--chunk"))
            o.chunk = atoi(value);
        else if (!strcmp(key, "--threads"))
            o.threads = atoi(value);
        else if (!strcmp(key, "--speed"))
            o.speed = atof(value);
        else if (!strcmp(key, "--strain"))
            o.strain = atof(value);
        else if (!strcmp(key, "--csv"))
            o.csv = value;
        else if (!strcmp(key, "--md"))
            o.md = value;
        else
            fail("usage", "sb_bench_tearing [--size N] [--steps N] [--chunk N] [--speed V] [--strain S] "
                          "[--threads N] [--csv FILE] [--md FILE]");
    }
    if (o.size < 4 || o.steps < 1 || o.chunk < 1 || o.threads < 1 || !(o.speed > 0) || !(o.strain > 0))
        fail("usage", "sizes, counts, speed and strain must be positive");
    return o;
}

int main(int argc, char** argv) {
    tearing_options o = parse(argc, argv);
    sb_bench_case c = {"sheet", SB_BENCH_SHEET, o.size, false, SB_BENCH_GENERATED};
    sb_bench_options options = {.all_terms = false, .jitter = SB_BENCH_DEFAULT_JITTER};
    sb_bench_setup setup;
    sb_error err;
    if (sb_bench_prepare(&c, &options, &setup, &err) != SB_OK) fail("mesh", err.message);
    pulled tearing, whole;
    start(&tearing, &setup, &o, o.strain);
    start(&whole, &setup, &o, 0.0);
    for (int k = 0; k < o.steps; k += o.chunk) { /* interleaved: the same simulated times, the same machine state */
        int count = k + o.chunk <= o.steps ? o.chunk : o.steps - k;
        advance(&tearing, setup.dt, k, count);
        advance(&whole, setup.dt, k, count);
    }
    int first = -1, last = -1;
    for (int k = 0; k < o.steps; k++)
        if (tearing.broke[k]) last = k, first = first < 0 ? k : first;
    double* quiet = malloc(o.steps * sizeof *quiet);
    int quiet_count = 0;
    for (int k = 0; k < o.steps; k++)
        if (!tearing.broke[k] && (k == 0 || tearing.vertices[k] == tearing.vertices[k - 1]))
            quiet[quiet_count++] = tearing.seconds[k];
    double quiet_median = median(quiet, quiet_count);
    free(quiet);
    int window = first >= 0 ? last + 1 - first : 0, before = first >= 0 ? first : o.steps;
    double tear_s = window ? sum(tearing.seconds, first, last + 1) : NAN;
    double whole_s = window ? sum(whole.seconds, first, last + 1) : NAN;
    double tear_before = sum(tearing.seconds, 0, before), whole_before = sum(whole.seconds, 0, before);
    double tear_median = window ? 1e3 * median_of(tearing.seconds, first, last + 1) : NAN;
    double whole_median = window ? 1e3 * median_of(whole.seconds, first, last + 1) : NAN;
    extra_cost split = extra(&tearing, o.steps, quiet_median, true),
               breaks = extra(&tearing, o.steps, quiet_median, false);
    uint32_t n = sb_model_vertex_count(tearing.model), made = sb_solver_vertex_count(tearing.solver) - n;
    printf("sheet %u x %u (%u vertices, %u bonds), dt %.3g s, %d steps in chunks of %d, %d thread(s)\n", o.size, o.size,
           n, sb_model_bond_count(tearing.model), setup.dt, o.steps, o.chunk, o.threads);
    printf("tearing: %u bonds broken, %u vertices split off (capacity %u), steps %d to %d\n",
           sb_solver_broken_count(tearing.solver), made, sb_solver_vertex_capacity(tearing.solver), first, last);
    printf("before any break (%d steps): tearing model %.1f steps/s, whole %.1f steps/s, ratio %.3f\n", before,
           before / tear_before, before / whole_before, whole_before / tear_before);
    printf("while tearing (%d steps):    tearing %.1f steps/s, whole %.1f steps/s, ratio %.3f (target >= 0.8)\n",
           window, window / tear_s, window / whole_s, whole_s / tear_s);
    printf("while tearing, median step: tearing %.3f ms, whole %.3f ms, ratio %.3f\n", tear_median, whole_median,
           whole_median / tear_median);
    printf("quiet step %.3f ms; a step that split vertices costs %.3f ms more (median of %d, max %.3f); one that "
           "only broke bonds %.3f ms more (median of %d, max %.3f)\n",
           1e3 * quiet_median, split.median_ms, split.steps, split.max_ms, breaks.median_ms, breaks.steps,
           breaks.max_ms);
    if (o.csv) {
        FILE* f = fopen(o.csv, "w");
        if (!f) fail(o.csv, "cannot write");
        fprintf(f, "vertices,bonds,threads,steps,first_break,last_break,broken,split_off,"
                   "before_tearing_sps,before_whole_sps,while_tearing_sps,while_whole_sps,ratio,median_tearing_ms,"
                   "median_whole_ms,median_ratio,quiet_ms,"
                   "split_steps,split_extra_median_ms,split_extra_max_ms,break_steps,break_extra_median_ms,"
                   "break_extra_max_ms\n");
        fprintf(f, "%u,%u,%d,%d,%d,%d,%u,%u,%.2f,%.2f,%.2f,%.2f,%.4f,%.4f,%.4f,%.4f,%.4f,%d,%.4f,%.4f,%d,%.4f,%.4f\n",
                n, sb_model_bond_count(tearing.model), o.threads, o.steps, first, last,
                sb_solver_broken_count(tearing.solver), made, before / tear_before, before / whole_before,
                window / tear_s, window / whole_s, whole_s / tear_s, tear_median, whole_median,
                whole_median / tear_median, 1e3 * quiet_median, split.steps, split.median_ms, split.max_ms,
                breaks.steps, breaks.median_ms, breaks.max_ms);
        fclose(f);
    }
    if (o.md) {
        FILE* f = fopen(o.md, "w");
        if (!f) fail(o.md, "cannot write");
        fprintf(f, "| | tearing sheet | same sheet, no limits | ratio |\n|---|---|---|---|\n");
        fprintf(f, "| steps/s before any break (%d steps) | %.1f | %.1f | %.3f |\n", before, before / tear_before,
                before / whole_before, whole_before / tear_before);
        fprintf(f, "| steps/s while tearing (%d steps) | %.1f | %.1f | %.3f |\n", window, window / tear_s,
                window / whole_s, whole_s / tear_s);
        fprintf(f, "| median step while tearing | %.3f ms | %.3f ms | %.3f |\n\n", tear_median, whole_median,
                whole_median / tear_median);
        fprintf(f, "| step | count | extra over a quiet step (%.3f ms): median | max |\n|---|---|---|---|\n",
                1e3 * quiet_median);
        fprintf(f, "| splits vertices (a topology update) | %d | %.3f ms | %.3f ms |\n", split.steps, split.median_ms,
                split.max_ms);
        fprintf(f, "| only breaks bonds | %d | %.3f ms | %.3f ms |\n", breaks.steps, breaks.median_ms, breaks.max_ms);
        fclose(f);
    }
    finish(&tearing);
    finish(&whole);
    sb_bench_setup_free(&setup);
    return 0;
}
