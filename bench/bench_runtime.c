/* sb_bench_runtime: what the solver's thread team does to a host that
 * shares its cores, and what publishing a snapshot costs.
 *
 * 1. Wait policies and a competing thread. The 100k sheet of sb_bench (fast
 *    kernels, Verlet, bond + angle + stretch-bend) on a team of 2 threads,
 *    for each wait policy (spin, yield, passive) with pinning on and off,
 *    is stepped for --seconds after a --warmup: (a) alone, (b) beside a
 *    competing thread, a plain pthread (default scheduling, every core
 *    allowed) that wakes every 1 ms on absolute deadlines
 *    (clock_nanosleep, TIMER_ABSTIME, CLOCK_MONOTONIC), busy-works 50 µs
 *    and records its wake-up lateness (wake time − deadline) each tick;
 *    the deadlines stay on their 1 ms grid, so a tick delayed past the next
 *    deadline makes the following ticks late too, as in a servo loop that
 *    catches up. The competing thread also runs alone (no solver): the
 *    baseline lateness of the machine. A team of 1 (no worker thread; the
 *    wait policy does not apply) is measured the same way.
 * 2. Publish cost. For the 10k and 100k sheets (2 threads, pinned, passive
 *    and spin), --publish-steps steps each followed by sb_solver_publish
 *    into a state buffer; both are timed with clock_gettime and the mean
 *    of each, and their ratio, reported. The byte counts (publish: the
 *    packed x y z w positions and velocities read, 3n interleaved written;
 *    step: bench_model.c's byte model) give what bounds the ratio when both
 *    run at memory bandwidth.
 *
 * Every configuration runs --runs times, interleaved: run 1 of all of them,
 * then run 2, so that drift of a shared machine shows as a difference
 * between the runs rather than between configurations.
 *
 * Output: bench/results/runtime.csv (one row per configuration and run) and
 * bench/results/runtime.md (tables; the "## Conclusions" section of an
 * existing runtime.md is kept, since a person writes it from the numbers).
 *
 * The team pins its creating thread (thread 0) when pin is on and leaves it
 * pinned after the solver is destroyed, so this program restores the main
 * thread's affinity after every solver and gives the competing thread the
 * process's original affinity explicitly (a thread inherits its creator's). */
#include "bench/bench_cases.h"
#include "common/clock.h"
#include "bench/bench_model.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define SB_TICK_NS 1000000L /* the competing thread's period */
#define SB_WORK_NS 50000L   /* and its busy work per tick */
#define SB_MISS_US 1000.0   /* a tick later than this missed its deadline */
#define SB_MAX_RUNS 8

typedef struct sb_options {
    double seconds, warmup;
    int runs;
    int publish_steps;
    double quiet;  /* a measurement waits for other processes to use at most this many cores, and is */
    int retries;   /* repeated at most this many times when they used more meanwhile, */
    double budget; /* within this many seconds for the whole program */
    const char* csv;
    const char* md;
} sb_options;

static cpu_set_t sb_all_cpus; /* the process's affinity at start */

static int64_t sb_now_ns(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (int64_t)t.tv_sec * 1000000000 + t.tv_nsec;
}

/* Busy CPU seconds of the whole machine (/proc/stat) and of this process:
 * their difference over a window is what other processes took meanwhile. */
typedef struct sb_cpu_sample {
    double wall, machine_busy, self;
} sb_cpu_sample;

static sb_cpu_sample sb_cpu_now(void) {
    sb_cpu_sample c = {sb_wall_seconds(), NAN, NAN};
    FILE* f = fopen("/proc/stat", "r");
    unsigned long long v[8] = {0};
    if (f && fscanf(f, "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6],
                    &v[7]) == 8)
        c.machine_busy = (double)(v[0] + v[1] + v[2] + v[5] + v[6] + v[7]) / (double)sysconf(_SC_CLK_TCK);
    if (f) fclose(f);
    struct timespec t;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) == 0) c.self = (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
    return c;
}

/* Cores other processes kept busy, on average, since `start`. */
static double sb_others_since(sb_cpu_sample start) {
    sb_cpu_sample end = sb_cpu_now();
    double others = (end.machine_busy - start.machine_busy) - (end.self - start.self);
    return fmax(0.0, others / (end.wall - start.wall));
}

/* The time the program may spend beyond its measurements: budget less the
 * time gone less the nominal time of the measurements still to do (the
 * current one included). */
typedef struct sb_schedule {
    double started, budget, remaining;
    double waited; /* seconds spent waiting for quiet */
    int retried;   /* measurements repeated */
} sb_schedule;

static double sb_spare(const sb_schedule* s) { return s->budget - (sb_wall_seconds() - s->started) - s->remaining; }

/* Waits, while there is spare time, for a half second in which other
 * processes kept at most `quiet` cores busy. */
static void sb_wait_for_quiet(sb_schedule* s, double quiet) {
    while (sb_spare(s) > 0.5) {
        sb_cpu_sample c = sb_cpu_now();
        struct timespec pause = {0, 500000000};
        nanosleep(&pause, NULL);
        if (sb_others_since(c) <= quiet) return;
        s->waited += 0.5;
    }
}

static void sb_restore_affinity(void) { pthread_setaffinity_np(pthread_self(), sizeof sb_all_cpus, &sb_all_cpus); }

/* ---- the competing thread ------------------------------------------------ */

typedef struct sb_competitor {
    pthread_t thread;
    atomic_int stop;
    double* lateness_us; /* one per tick */
    size_t capacity, count;
} sb_competitor;

typedef struct sb_lateness {
    size_t ticks;
    double median_us, p99_us, max_us;
    size_t misses; /* ticks later than SB_MISS_US */
} sb_lateness;

static void* sb_competitor_main(void* arg) {
    sb_competitor* c = arg;
    pthread_setaffinity_np(pthread_self(), sizeof sb_all_cpus, &sb_all_cpus);
    struct timespec deadline;
    clock_gettime(CLOCK_MONOTONIC, &deadline);
    while (!atomic_load_explicit(&c->stop, memory_order_relaxed) && c->count < c->capacity) {
        deadline.tv_nsec += SB_TICK_NS;
        if (deadline.tv_nsec >= 1000000000) {
            deadline.tv_nsec -= 1000000000;
            deadline.tv_sec++;
        }
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, NULL) == EINTR) {
        }
        int64_t woke = sb_now_ns(), due = (int64_t)deadline.tv_sec * 1000000000 + deadline.tv_nsec;
        c->lateness_us[c->count++] = 1e-3 * (double)(woke - due);
        while (sb_now_ns() - woke < SB_WORK_NS) {
        }
    }
    return NULL;
}

static bool sb_competitor_start(sb_competitor* c, double seconds) {
    c->capacity = (size_t)(seconds * 1e9 / SB_TICK_NS) * 2 + 1000;
    c->count = 0;
    atomic_init(&c->stop, 0);
    c->lateness_us = malloc(c->capacity * sizeof *c->lateness_us);
    if (!c->lateness_us) return false;
    if (pthread_create(&c->thread, NULL, sb_competitor_main, c) != 0) {
        free(c->lateness_us);
        c->lateness_us = NULL;
        return false;
    }
    return true;
}

static int sb_compare(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static sb_lateness sb_competitor_stop(sb_competitor* c) {
    atomic_store(&c->stop, 1);
    pthread_join(c->thread, NULL);
    sb_lateness l = {.ticks = c->count, .median_us = NAN, .p99_us = NAN, .max_us = NAN};
    if (c->count > 0) {
        qsort(c->lateness_us, c->count, sizeof *c->lateness_us, sb_compare);
        size_t p99 = (size_t)ceil(0.99 * (double)c->count);
        l.median_us = c->lateness_us[c->count / 2];
        l.p99_us = c->lateness_us[(p99 ? p99 : 1) - 1];
        l.max_us = c->lateness_us[c->count - 1];
        for (size_t i = 0; i < c->count; i++) l.misses += c->lateness_us[i] > SB_MISS_US;
    }
    free(c->lateness_us);
    c->lateness_us = NULL;
    return l;
}

/* ---- part 1: wait policies beside a competing thread --------------------- */

typedef struct sb_config {
    bool solver; /* false: the competing thread alone */
    int threads; /* the team's size */
    sb_wait_policy wait;
    bool pin;
    bool competitor;
} sb_config;

typedef struct sb_result {
    bool ok;
    char note[160];
    uint64_t steps;
    double seconds;
    sb_lateness lateness;
    double others; /* cores other processes used meanwhile */
    int tries;
} sb_result;

static sb_solver_def sb_bench_solver_def(const sb_runtime_def* runtime) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_VERLET;
    def.gravity[0] = def.gravity[1] = 0.0;
    def.gravity[2] = -SB_BENCH_GRAVITY;
    def.kernels = SB_KERNELS_FAST;
    def.runtime = *runtime;
    return def;
}

static const char* sb_wait_label(const sb_config* c) {
    return !c->solver || c->threads == 1 ? "-" : sb_wait_policy_name(c->wait);
}

static void sb_run_config(const sb_bench_setup* setup, const sb_config* c, const sb_options* o, sb_result* r) {
    memset(r, 0, sizeof *r);
    r->lateness = (sb_lateness){.median_us = NAN, .p99_us = NAN, .max_us = NAN};
    sb_restore_affinity();
    sb_competitor comp;
    if (!c->solver) {
        if (!sb_competitor_start(&comp, o->seconds)) {
            snprintf(r->note, sizeof r->note, "could not start the competing thread");
            return;
        }
        sb_cpu_sample cpu = sb_cpu_now();
        double t0 = sb_wall_seconds();
        while (sb_wall_seconds() - t0 < o->seconds) {
            struct timespec pause = {0, 10000000};
            nanosleep(&pause, NULL);
        }
        r->seconds = sb_wall_seconds() - t0;
        r->lateness = sb_competitor_stop(&comp);
        r->others = sb_others_since(cpu);
        r->ok = true;
        return;
    }
    sb_runtime_def runtime = {.threads = c->threads, .pin = c->pin, .wait = c->wait};
    sb_solver_def def = sb_bench_solver_def(&runtime);
    sb_error err = {{0}};
    sb_solver* s = sb_solver_create(setup->model, &def, &err);
    if (!s) {
        snprintf(r->note, sizeof r->note, "unavailable: %.120s", err.message);
        sb_restore_affinity();
        return;
    }
    r->ok = true;
    for (double t0 = sb_wall_seconds(); r->ok && sb_wall_seconds() - t0 < o->warmup;)
        r->ok = sb_solver_advance(s, setup->dt) == SB_OK;
    bool competing = false;
    if (r->ok && c->competitor) {
        competing = sb_competitor_start(&comp, o->seconds);
        if (!competing) {
            snprintf(r->note, sizeof r->note, "could not start the competing thread");
            r->ok = false;
        }
    }
    sb_cpu_sample cpu = sb_cpu_now();
    if (r->ok) {
        double t0 = sb_wall_seconds(), t = t0;
        while (t - t0 < o->seconds) {
            if (sb_solver_advance(s, setup->dt) != SB_OK) {
                r->ok = false;
                break;
            }
            r->steps++;
            t = sb_wall_seconds();
        }
        r->seconds = t - t0;
    }
    if (competing) r->lateness = sb_competitor_stop(&comp);
    r->others = sb_others_since(cpu);
    if (!r->ok && !r->note[0]) snprintf(r->note, sizeof r->note, "step failed: %.120s", sb_solver_error(s));
    sb_solver_destroy(s);
    sb_restore_affinity();
}

/* ---- part 2: publish cost ------------------------------------------------ */

typedef struct sb_publish_config {
    const char* case_name;
    sb_wait_policy wait;
} sb_publish_config;

typedef struct sb_publish_result {
    bool ok;
    char note[160];
    uint32_t vertices;
    int steps;
    double step_s, publish_s; /* means over the steps followed by sb_solver_publish */
    double fused_s;           /* mean of sb_solver_advance_published (every other step) */
    double publish_bytes, step_bytes;
    double memcpy_gb_per_s; /* one thread, publish-sized buffers, reads + writes counted */
    double others;
    int tries;
} sb_publish_result;

/* A ceiling for the publish's copy: memcpy, one thread, of the bytes one
 * publish writes (2 × 3n reals) into three destinations in turn, as the
 * state buffer's slots rotate; the best of 30 copies, read + write bytes. */
static double sb_memcpy_gb_per_s(uint32_t n) {
    size_t bytes = 6 * sizeof(sb_real) * (size_t)n;
    char *src = malloc(bytes), *dst = malloc(3 * bytes);
    double best = INFINITY;
    if (src && dst) {
        memset(src, 1, bytes);
        memset(dst, 2, 3 * bytes);
        for (int k = 0; k < 30; k++) {
            double t0 = sb_wall_seconds();
            memcpy(dst + (size_t)(k % 3) * bytes, src, bytes);
            best = fmin(best, sb_wall_seconds() - t0);
        }
        volatile char sink = dst[bytes / 2];
        (void)sink;
    }
    free(src);
    free(dst);
    return isfinite(best) ? 2e-9 * (double)bytes / best : NAN;
}

static void sb_run_publish(const sb_bench_setup* setup, const sb_publish_config* c, const sb_options* o,
                           sb_publish_result* r) {
    memset(r, 0, sizeof *r);
    sb_restore_affinity();
    uint32_t n = sb_model_vertex_count(setup->model);
    r->vertices = n;
    r->publish_bytes = 14.0 * sizeof(sb_real) * n; /* read 2 × 4n, write 2 × 3n reals */
    r->step_bytes = sb_bench_count(setup->model, false).bytes_per_step;
    r->memcpy_gb_per_s = sb_memcpy_gb_per_s(n);
    sb_runtime_def runtime = {.threads = 2, .pin = true, .wait = c->wait};
    sb_solver_def def = sb_bench_solver_def(&runtime);
    sb_error err = {{0}};
    sb_solver* s = sb_solver_create(setup->model, &def, &err);
    sb_state_buffer* buffer = s ? sb_state_buffer_create(n, 1, &err) : NULL;
    if (!s || !buffer) {
        snprintf(r->note, sizeof r->note, "unavailable: %.120s", err.message);
        sb_solver_destroy(s);
        sb_restore_affinity();
        return;
    }
    r->ok = true;
    for (double t0 = sb_wall_seconds(); r->ok && sb_wall_seconds() - t0 < fmin(o->warmup, 0.3);)
        r->ok = sb_solver_advance(s, setup->dt) == SB_OK && sb_solver_publish(s, buffer) == SB_OK;
    double step = 0.0, publish = 0.0, fused = 0.0, start = sb_wall_seconds();
    int separate = 0, together = 0;
    sb_cpu_sample cpu = sb_cpu_now();
    for (int k = 0; r->ok && k < o->publish_steps && (k < 100 || sb_wall_seconds() - start < o->seconds); k++) {
        r->steps = k + 1;
        if (k % 2) { /* every other step: the step that publishes itself */
            double t0 = sb_wall_seconds();
            r->ok = sb_solver_advance_published(s, setup->dt, buffer) == SB_OK;
            fused += sb_wall_seconds() - t0;
            together++;
            continue;
        }
        double t0 = sb_wall_seconds();
        r->ok = sb_solver_advance(s, setup->dt) == SB_OK;
        double t1 = sb_wall_seconds();
        sb_status status = sb_solver_publish(s, buffer);
        double t2 = sb_wall_seconds();
        if (status != SB_OK) {
            snprintf(r->note, sizeof r->note, "publish failed (%d)", (int)status);
            r->ok = false;
        }
        step += t1 - t0;
        publish += t2 - t1;
        separate++;
    }
    r->others = sb_others_since(cpu);
    if (!r->ok && !r->note[0]) snprintf(r->note, sizeof r->note, "step failed: %.120s", sb_solver_error(s));
    if (separate > 0 && together > 0) {
        r->step_s = step / separate;
        r->publish_s = publish / separate;
        r->fused_s = fused / together;
    } else {
        r->ok = false;
    }
    sb_state_buffer_destroy(buffer);
    sb_solver_destroy(s);
    sb_restore_affinity();
}

/* ---- options ------------------------------------------------------------- */

static void sb_usage(FILE* out) {
    fprintf(out, "usage: sb_bench_runtime [options]\n"
                 "  --seconds S        stepping time per configuration (default 3)\n"
                 "  --warmup S         warm-up per configuration (default 0.5)\n"
                 "  --runs N           runs of every configuration, interleaved (default 2)\n"
                 "  --publish-steps N  steps of the publish measurement (default 2000; stops after --seconds)\n"
                 "  --quiet C          wait before each measurement for other processes to keep at most C\n"
                 "                     cores busy (default 0.1); repeat one during which they kept more,\n"
                 "  --retries N        at most N times (default 3), keeping the quietest try;\n"
                 "  --budget S         wait and repeat only as long as the program can still finish\n"
                 "                     within S seconds (default 220)\n"
                 "  --quick            0.5 s, 0.2 s warm-up, 1 run, 200 publish steps, no waiting (a smoke test)\n"
                 "  --csv FILE         default bench/results/runtime.csv\n"
                 "  --md FILE          default bench/results/runtime.md\n");
}

static const char* sb_value(int argc, char** argv, int* i) {
    if (*i + 1 >= argc) {
        fprintf(stderr, "sb_bench_runtime: %s needs a value\n", argv[*i]);
        exit(2);
    }
    return argv[++*i];
}

static sb_options sb_parse(int argc, char** argv) {
    sb_options o = {.seconds = 3.0,
                    .warmup = 0.5,
                    .runs = 2,
                    .publish_steps = 2000,
                    .quiet = 0.1,
                    .retries = 3,
                    .budget = 220.0,
                    .csv = SB_BENCH_SOURCE_DIR "/bench/results/runtime.csv",
                    .md = SB_BENCH_SOURCE_DIR "/bench/results/runtime.md"};
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
        if (!strcmp(a, "--seconds"))
            o.seconds = atof(sb_value(argc, argv, &i));
        else if (!strcmp(a, "--warmup"))
            o.warmup = atof(sb_value(argc, argv, &i));
        else if (!strcmp(a, "--runs"))
            o.runs = atoi(sb_value(argc, argv, &i));
        else if (!strcmp(a, "--publish-steps"))
            o.publish_steps = atoi(sb_value(argc, argv, &i));
        else if (!strcmp(a, "--quiet"))
            o.quiet = atof(sb_value(argc, argv, &i));
        else if (!strcmp(a, "--retries"))
            o.retries = atoi(sb_value(argc, argv, &i));
        else if (!strcmp(a, "--budget"))
            o.budget = atof(sb_value(argc, argv, &i));
        else if (!strcmp(a, "--quick")) {
            o.seconds = 0.5;
            o.warmup = 0.2;
            o.runs = 1;
            o.publish_steps = 200;
            o.retries = 0;
            o.budget = 0.0;
        } else if (!strcmp(a, "--csv"))
            o.csv = sb_value(argc, argv, &i);
        else if (!strcmp(a, "--md"))
            o.md = sb_value(argc, argv, &i);
        else if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            sb_usage(stdout);
            exit(0);
        } else {
            fprintf(stderr, "sb_bench_runtime: unknown option %s\n", a);
            sb_usage(stderr);
            exit(2);
        }
    }
    if (o.seconds <= 0.0 || o.warmup < 0.0 || o.runs < 1 || o.runs > SB_MAX_RUNS || o.publish_steps < 1 ||
        o.retries < 0) {
        fprintf(stderr, "sb_bench_runtime: bad option value\n");
        exit(2);
    }
    return o;
}

/* ---- reporting ----------------------------------------------------------- */

static void sb_git_commit(char* out, size_t size) {
    snprintf(out, size, "unknown");
    FILE* p = popen("git -C '" SB_BENCH_SOURCE_DIR "' rev-parse --short HEAD 2>/dev/null", "r");
    if (!p) return;
    if (fgets(out, (int)size, p)) out[strcspn(out, "\n")] = '\0';
    pclose(p);
}

static void sb_cpu_model(char* out, size_t size) {
    snprintf(out, size, "unknown");
    FILE* f = fopen("/proc/cpuinfo", "r");
    if (!f) return;
    char line[512];
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, "model name", 10)) {
            const char* colon = strchr(line, ':');
            if (colon) snprintf(out, size, "%s", colon + 2);
            out[strcspn(out, "\n")] = '\0';
            break;
        }
    fclose(f);
}

static double sb_steps_per_s(const sb_result* r) { return r->ok && r->seconds > 0.0 ? r->steps / r->seconds : NAN; }

/* "a / b" of one number over the runs, or "-" when none is finite. */
static void sb_cell(char* out, size_t size, const double* values, int runs, const char* format) {
    size_t used = 0;
    bool any = false;
    out[0] = '\0';
    for (int k = 0; k < runs; k++) any = any || isfinite(values[k]);
    if (!any) {
        snprintf(out, size, "-");
        return;
    }
    for (int k = 0; k < runs && used < size; k++) {
        if (k) used += (size_t)snprintf(out + used, size - used, " / ");
        if (used >= size) break;
        if (isfinite(values[k]))
            used += (size_t)snprintf(out + used, size - used, format, values[k]);
        else
            used += (size_t)snprintf(out + used, size - used, "-");
    }
}

static double sb_mean_finite(const double* values, int runs) {
    double sum = 0.0;
    int count = 0;
    for (int k = 0; k < runs; k++)
        if (isfinite(values[k])) sum += values[k], count++;
    return count ? sum / count : NAN;
}

/* The "## Conclusions" section of an existing file, or NULL. */
static char* sb_read_conclusions(const char* path) {
    FILE* f = fopen(path, "r");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char* text = size > 0 ? malloc((size_t)size + 1) : NULL;
    if (!text || fread(text, 1, (size_t)size, f) != (size_t)size) {
        free(text);
        fclose(f);
        return NULL;
    }
    fclose(f);
    text[size] = '\0';
    char* at = strstr(text, "\n## Conclusions");
    char* kept = at ? strdup(at + 1) : NULL;
    free(text);
    return kept;
}

static void sb_print_config(FILE* f, const sb_config* c) {
    if (!c->solver)
        fprintf(f, "%-9s %-7s %-3s %-5s", "none", "-", "-", "yes");
    else
        fprintf(f, "%-9d %-7s %-3s %-5s", c->threads, sb_wait_label(c), c->pin ? "on" : "off",
                c->competitor ? "yes" : "no");
}

int main(int argc, char** argv) {
    double started = sb_wall_seconds();
    sb_options o = sb_parse(argc, argv);
    setvbuf(stdout, NULL, _IOLBF, 0);
    if (sched_getaffinity(0, sizeof sb_all_cpus, &sb_all_cpus) != 0) {
        CPU_ZERO(&sb_all_cpus);
        for (int i = 0; i < CPU_SETSIZE; i++) CPU_SET(i, &sb_all_cpus);
    }
    char machine[512], cpu[256], commit[64], date[64];
    sb_runtime_describe(machine, sizeof machine);
    sb_cpu_model(cpu, sizeof cpu);
    sb_git_commit(commit, sizeof commit);
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S %Z", localtime(&now));
    double load_start[3] = {NAN, NAN, NAN}, load_end[3] = {NAN, NAN, NAN};
    getloadavg(load_start, 3);
    printf("machine: %s\ncpu: %s, %ld logical cores online\n", machine, cpu, sysconf(_SC_NPROCESSORS_ONLN));
    printf("load average at start: %.2f %.2f %.2f\n\n", load_start[0], load_start[1], load_start[2]);

    /* the cases */
    const char* names[2] = {"sheet_10k", "sheet_100k"};
    sb_bench_setup setups[2];
    sb_bench_options bo = {.all_terms = false, .jitter = SB_BENCH_DEFAULT_JITTER};
    for (int i = 0; i < 2; i++) {
        sb_error err = {{0}};
        if (sb_bench_build(sb_bench_find_case(names[i]), &bo, &setups[i], &err) != SB_OK) {
            fprintf(stderr, "sb_bench_runtime: %s: %s\n", names[i], err.message);
            return 1;
        }
    }
    const sb_bench_setup* big = &setups[1];

    /* part 1 */
    sb_config configs[32];
    int config_count = 0;
    configs[config_count++] = (sb_config){.solver = false, .competitor = true};
    for (int w = 0; w < SB_WAIT_COUNT; w++)
        for (int p = 1; p >= 0; p--)
            for (int comp = 0; comp < 2; comp++)
                configs[config_count++] =
                    (sb_config){.solver = true, .threads = 2, .wait = (sb_wait_policy)w, .pin = p, .competitor = comp};
    for (int p = 1; p >= 0; p--)
        for (int comp = 0; comp < 2; comp++)
            configs[config_count++] =
                (sb_config){.solver = true, .threads = 1, .wait = SB_WAIT_PASSIVE, .pin = p, .competitor = comp};
    static sb_result results[32][SB_MAX_RUNS];

    /* part 2 */
    const sb_publish_config publish_configs[] = {{"sheet_10k", SB_WAIT_PASSIVE},
                                                 {"sheet_10k", SB_WAIT_SPIN},
                                                 {"sheet_100k", SB_WAIT_PASSIVE},
                                                 {"sheet_100k", SB_WAIT_SPIN}};
    const int publish_count = (int)(sizeof publish_configs / sizeof *publish_configs);
    static sb_publish_result publish_results[8][SB_MAX_RUNS];

    printf("part 1: %s (%u vertices), %.1f s per configuration after %.1f s warm-up\n", names[1],
           sb_model_vertex_count(big->model), o.seconds, o.warmup);
    printf("%-3s %-9s %-7s %-3s %-5s %8s %10s %10s %10s %6s %6s %7s %s\n", "run", "solver", "wait", "pin", "comp",
           "steps/s", "late p50", "late p99", "late max", ">1ms", "ticks", "others", "tries");
    /* nominal times: warm-up, stepping, creation; publish stops after --seconds */
    const double nominal = o.warmup + o.seconds + 0.2, nominal_publish = fmin(o.warmup, 0.3) + o.seconds + 0.2;
    sb_schedule schedule = {.started = started,
                            .budget = o.budget,
                            .remaining = o.runs * (config_count * nominal + publish_count * nominal_publish)};
    for (int k = 0; k < o.runs; k++) {
        for (int i = 0; i < config_count; i++) {
            sb_result* r = &results[i][k];
            for (int t = 0;; t++) { /* keep the quietest try */
                sb_wait_for_quiet(&schedule, o.quiet);
                sb_result try;
                sb_run_config(big, &configs[i], &o, &try);
                if (t == 0 || (try.ok && try.others < r->others) || !r->ok) *r = try;
                r->tries = t + 1;
                if (r->others <= o.quiet || t >= o.retries || sb_spare(&schedule) <= 0.0) break;
                schedule.retried++;
            }
            schedule.remaining -= nominal;
            printf("%-3d ", k + 1);
            sb_print_config(stdout, &configs[i]);
            if (!r->ok) {
                printf(" %s\n", r->note);
                continue;
            }
            printf(" %8.1f %10.1f %10.1f %10.1f %6zu %6zu %7.2f %d\n", sb_steps_per_s(r), r->lateness.median_us,
                   r->lateness.p99_us, r->lateness.max_us, r->lateness.misses, r->lateness.ticks, r->others, r->tries);
        }
        for (int i = 0; i < publish_count; i++) {
            const sb_publish_config* c = &publish_configs[i];
            sb_publish_result* r = &publish_results[i][k];
            for (int t = 0;; t++) {
                sb_wait_for_quiet(&schedule, o.quiet);
                sb_publish_result try;
                sb_run_publish(&setups[strcmp(c->case_name, names[0]) == 0 ? 0 : 1], c, &o, &try);
                if (t == 0 || (try.ok && try.others < r->others) || !r->ok) *r = try;
                r->tries = t + 1;
                if (r->others <= o.quiet || t >= o.retries || sb_spare(&schedule) <= 0.0) break;
                schedule.retried++;
            }
            schedule.remaining -= nominal_publish;
            printf("%-3d publish %-10s %-7s", k + 1, c->case_name, sb_wait_policy_name(c->wait));
            if (!r->ok)
                printf(" %s\n", r->note);
            else
                printf(" %d steps: step %8.1f us, publish %7.1f us, %5.1f %%, advance_published %8.1f us (%+.1f %%), "
                       "memcpy "
                       "%.1f GB/s, others %.2f, tries %d\n",
                       r->steps, 1e6 * r->step_s, 1e6 * r->publish_s, 100.0 * r->publish_s / r->step_s,
                       1e6 * r->fused_s, 100.0 * (r->fused_s - r->step_s) / r->step_s, r->memcpy_gb_per_s, r->others,
                       r->tries);
        }
    }
    getloadavg(load_end, 3);

    /* CSV */
    FILE* f = fopen(o.csv, "w");
    if (!f) {
        fprintf(stderr, "sb_bench_runtime: cannot write %s: %s\n", o.csv, strerror(errno));
        return 1;
    }
    fprintf(f, "# softbond sb_bench_runtime, %s, commit %s\n# machine: %s\n# cpu: %s\n", date, commit, machine, cpu);
    fprintf(f, "# load average at start %.2f %.2f %.2f, at end %.2f %.2f %.2f\n", load_start[0], load_start[1],
            load_start[2], load_end[0], load_end[1], load_end[2]);
    fprintf(f, "# %.1f s waiting for quiet (others <= %.2f cores), %d measurements repeated\n", schedule.waited,
            o.quiet, schedule.retried);
    fprintf(f, "section,run,case,vertices,solver_threads,wait,pin,competitor,steps,seconds,steps_per_s,ticks,"
               "late_median_us,late_p99_us,late_max_us,ticks_late_over_1ms,step_mean_us,publish_mean_us,"
               "publish_pct_of_step,publish_bytes,step_model_bytes,memcpy_gb_per_s,others_cores,tries,note,"
               "advance_published_mean_us,advance_published_excess_pct\n");
    for (int k = 0; k < o.runs; k++)
        for (int i = 0; i < config_count; i++) {
            const sb_config* c = &configs[i];
            const sb_result* r = &results[i][k];
            fprintf(f, "wait,%d,%s,%u,%d,%s,%s,%s,%llu,%.4f,", k + 1, c->solver ? names[1] : "none",
                    c->solver ? sb_model_vertex_count(big->model) : 0, c->solver ? c->threads : 0, sb_wait_label(c),
                    !c->solver ? "-"
                    : c->pin   ? "on"
                               : "off",
                    c->competitor ? "yes" : "no", (unsigned long long)r->steps, r->seconds);
            if (c->solver && r->ok)
                fprintf(f, "%.2f,", sb_steps_per_s(r));
            else
                fprintf(f, ",");
            if (c->competitor && r->ok)
                fprintf(f, "%zu,%.1f,%.1f,%.1f,%zu,", r->lateness.ticks, r->lateness.median_us, r->lateness.p99_us,
                        r->lateness.max_us, r->lateness.misses);
            else
                fprintf(f, ",,,,,");
            fprintf(f, ",,,,,,%.2f,%d,%s,,\n", r->others, r->tries, r->ok ? "" : r->note);
        }
    for (int k = 0; k < o.runs; k++)
        for (int i = 0; i < publish_count; i++) {
            const sb_publish_config* c = &publish_configs[i];
            const sb_publish_result* r = &publish_results[i][k];
            fprintf(f, "publish,%d,%s,%u,2,%s,on,no,%d,,,,,,,,", k + 1, c->case_name, r->vertices,
                    sb_wait_policy_name(c->wait), r->steps);
            if (r->ok)
                fprintf(f, "%.2f,%.2f,%.2f,%.0f,%.0f,%.2f,%.2f,%d,,%.2f,%.2f\n", 1e6 * r->step_s, 1e6 * r->publish_s,
                        100.0 * r->publish_s / r->step_s, r->publish_bytes, r->step_bytes, r->memcpy_gb_per_s,
                        r->others, r->tries, 1e6 * r->fused_s, 100.0 * (r->fused_s - r->step_s) / r->step_s);
            else
                fprintf(f, ",,,,,,,%d,%s,,\n", r->tries, r->note);
        }
    fclose(f);

    /* markdown */
    char* conclusions = sb_read_conclusions(o.md);
    FILE* m = fopen(o.md, "w");
    if (!m) {
        fprintf(stderr, "sb_bench_runtime: cannot write %s: %s\n", o.md, strerror(errno));
        free(conclusions);
        return 1;
    }
    fprintf(m, "# Runtime: wait policies beside a 1 kHz thread, and the cost of publishing\n\n");
    fprintf(m, "Machine: `%s`  \n", machine);
    fprintf(m,
            "CPU: %s, %ld logical cores online; %s, commit %s; load average (1, 5, 15 min) %.2f %.2f %.2f at "
            "start, %.2f %.2f %.2f at the end (above 0.5: other work shared the cores).\n\n",
            cpu, sysconf(_SC_NPROCESSORS_ONLN), date, commit, load_start[0], load_start[1], load_start[2], load_end[0],
            load_end[1], load_end[2]);
    fprintf(m,
            "Written by `bench/runtime.sh` (`sb_bench_runtime`; the method is in bench/bench_runtime.c). Every "
            "configuration ran %d time%s, interleaved (run 1 of all of them, then run 2, ...); a cell shows the "
            "runs in order, `run 1 / run 2`, so that drift of the shared machine is visible.\n\n",
            o.runs, o.runs == 1 ? "" : "s");
    fprintf(m, "## 1. Wait policies beside a competing 1 kHz thread\n\n");
    fprintf(m,
            "%s (%u vertices; bond, angle and stretch-bend terms; fast kernels, Verlet, dt as in sb_bench): steps "
            "per second over %.1f s after a %.1f s warm-up. The competing thread is a plain pthread (default "
            "scheduling, every core allowed) that wakes every 1 ms on absolute deadlines (clock_nanosleep, "
            "TIMER_ABSTIME, CLOCK_MONOTONIC), busy-works 50 µs and records its lateness, wake-up time − deadline; "
            "its deadlines stay on the 1 ms grid. *late > 1 ms*: ticks that woke more than 1 ms after their "
            "deadline. *vs alone*: steps/s beside the competing thread over steps/s of the same configuration "
            "alone (means of the runs). *others*: cores that other processes kept busy during the measurement "
            "(/proc/stat less this process's CPU time), the noise of the shared machine. Each measurement first "
            "waited for a half second in which other processes kept at most %.2f cores busy, and one during which "
            "they kept more busy was repeated, up to %d more time%s, the quietest try shown (*tries*); both only "
            "while the program stayed within %.0f s (this run: %.1f s of waiting, %d repeated). A team of 1 starts no "
            "worker "
            "thread, so no wait policy applies.\n\n",
            names[1], sb_model_vertex_count(big->model), o.seconds, o.warmup, o.quiet, o.retries,
            o.retries == 1 ? "" : "s", o.budget, schedule.waited, schedule.retried);
    fprintf(m, "| solver threads | wait | pin | competing thread | steps/s | vs alone | lateness median µs | "
               "p99 µs | max µs | late > 1 ms | ticks | others | tries |\n");
    fprintf(m, "|---|---|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int i = 0; i < config_count; i++) {
        const sb_config* c = &configs[i];
        double sps[SB_MAX_RUNS], p50[SB_MAX_RUNS], p99[SB_MAX_RUNS], max[SB_MAX_RUNS], miss[SB_MAX_RUNS],
            ticks[SB_MAX_RUNS], others[SB_MAX_RUNS], tries[SB_MAX_RUNS];
        for (int k = 0; k < o.runs; k++) {
            const sb_result* r = &results[i][k];
            bool late = c->competitor && r->ok;
            sps[k] = c->solver ? sb_steps_per_s(r) : NAN;
            p50[k] = late ? r->lateness.median_us : NAN;
            p99[k] = late ? r->lateness.p99_us : NAN;
            max[k] = late ? r->lateness.max_us : NAN;
            miss[k] = late ? (double)r->lateness.misses : NAN;
            ticks[k] = late ? (double)r->lateness.ticks : NAN;
            others[k] = r->others;
            tries[k] = r->tries;
        }
        char vs[32] = "-";
        if (c->solver && c->competitor && i > 0) { /* the same configuration alone is the row before */
            double alone[SB_MAX_RUNS];
            for (int k = 0; k < o.runs; k++) alone[k] = sb_steps_per_s(&results[i - 1][k]);
            double ratio = sb_mean_finite(sps, o.runs) / sb_mean_finite(alone, o.runs);
            if (isfinite(ratio)) snprintf(vs, sizeof vs, "%.2f", ratio);
        }
        char a[96], b[96], d[96], e[96], g[96], h[96], x[96], y[96];
        sb_cell(a, sizeof a, sps, o.runs, "%.0f");
        sb_cell(b, sizeof b, p50, o.runs, "%.0f");
        sb_cell(d, sizeof d, p99, o.runs, "%.0f");
        sb_cell(e, sizeof e, max, o.runs, "%.0f");
        sb_cell(g, sizeof g, miss, o.runs, "%.0f");
        sb_cell(h, sizeof h, ticks, o.runs, "%.0f");
        sb_cell(x, sizeof x, others, o.runs, "%.2f");
        sb_cell(y, sizeof y, tries, o.runs, "%.0f");
        if (c->solver)
            fprintf(m, "| %d | %s | %s | %s |", c->threads, sb_wait_label(c), c->pin ? "on" : "off",
                    c->competitor ? "yes" : "no");
        else
            fprintf(m, "| none | - | - | alone (baseline) |");
        fprintf(m, " %s | %s | %s | %s | %s | %s | %s | %s | %s |\n", a, vs, b, d, e, g, h, x, y);
    }
    fprintf(m, "\n## 2. Publish cost\n\n");
    fprintf(m,
            "Up to %d steps (fewer when they take more than %.1f s): every other one followed by `sb_solver_publish` "
            "into a state buffer (1 reader slot, no reader), each timed with clock_gettime, and the others taken with "
            "`sb_solver_advance_published` (the fused Verlet step writes the snapshot in its kick pass), timed whole: "
            "*fused µs* is its mean and *fused − step* its excess over the plain step, the cost of publishing that "
            "way; 2 threads, pinned. *publish MB*: bytes one publish moves (the packed x y z w "
            "positions and velocities read, 3n interleaved written: 14 × %zu B per vertex, without the "
            "write-allocate reads). *step MB*: bench_model.c's byte model for one step. Were both bound by memory "
            "bandwidth, publish/step would be about publish MB / step MB (*bytes ratio*). *memcpy GB/s*: a ceiling "
            "for the copy, memcpy on one thread of the bytes one publish writes into three rotating "
            "destinations (the best of 30; reads + writes counted), measured just before. Target: publish < 5 %% "
            "of a step. *others* and *tries* as above.\n\n",
            o.publish_steps, o.seconds, sizeof(sb_real));
    fprintf(m, "| case | vertices | wait | step µs | publish µs | publish / step | fused µs | fused − step | publish "
               "MB | publish GB/s | memcpy GB/s | step MB | step GB/s | bytes ratio | steps | others | tries |\n");
    fprintf(m, "|---|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (int i = 0; i < publish_count; i++) {
        const sb_publish_config* c = &publish_configs[i];
        double fus[SB_MAX_RUNS], fpct[SB_MAX_RUNS];
        double step[SB_MAX_RUNS], pub[SB_MAX_RUNS], pct[SB_MAX_RUNS], pgb[SB_MAX_RUNS], sgb[SB_MAX_RUNS],
            steps[SB_MAX_RUNS], others[SB_MAX_RUNS], mgb[SB_MAX_RUNS], tries[SB_MAX_RUNS];
        const sb_publish_result* r0 = &publish_results[i][0];
        for (int k = 0; k < o.runs; k++) {
            const sb_publish_result* r = &publish_results[i][k];
            step[k] = r->ok ? 1e6 * r->step_s : NAN;
            pub[k] = r->ok ? 1e6 * r->publish_s : NAN;
            pct[k] = r->ok ? 100.0 * r->publish_s / r->step_s : NAN;
            fus[k] = r->ok ? 1e6 * r->fused_s : NAN;
            fpct[k] = r->ok ? 100.0 * (r->fused_s - r->step_s) / r->step_s : NAN;
            pgb[k] = r->ok ? 1e-9 * r->publish_bytes / r->publish_s : NAN;
            sgb[k] = r->ok ? 1e-9 * r->step_bytes / r->step_s : NAN;
            steps[k] = r->steps;
            others[k] = r->others;
            mgb[k] = r->memcpy_gb_per_s;
            tries[k] = r->tries;
        }
        char a[96], b[96], d[96], e[96], g[96], h[96], x[96], y[96], z[96], fa[96], fb[96];
        sb_cell(fa, sizeof fa, fus, o.runs, "%.0f");
        sb_cell(fb, sizeof fb, fpct, o.runs, "%+.1f %%");
        sb_cell(a, sizeof a, step, o.runs, "%.0f");
        sb_cell(b, sizeof b, pub, o.runs, "%.1f");
        sb_cell(d, sizeof d, pct, o.runs, "%.1f %%");
        sb_cell(e, sizeof e, pgb, o.runs, "%.1f");
        sb_cell(g, sizeof g, sgb, o.runs, "%.1f");
        sb_cell(h, sizeof h, steps, o.runs, "%.0f");
        sb_cell(x, sizeof x, others, o.runs, "%.2f");
        sb_cell(y, sizeof y, mgb, o.runs, "%.1f");
        sb_cell(z, sizeof z, tries, o.runs, "%.0f");
        fprintf(m, "| %s | %u | %s | %s | %s | %s | %s | %s | %.2f | %s | %s | %.1f | %s | %.1f %% | %s | %s | %s |\n",
                c->case_name, r0->vertices, sb_wait_policy_name(c->wait), a, b, d, fa, fb, 1e-6 * r0->publish_bytes, e,
                y, 1e-6 * r0->step_bytes, g, 100.0 * r0->publish_bytes / r0->step_bytes, h, x, z);
    }
    fprintf(m, "\n%s", conclusions ? conclusions : "## Conclusions\n\n(Written by hand from the numbers above.)\n");
    fclose(m);
    free(conclusions);
    printf("\n%.1f s waiting for quiet, %d measurements repeated, %.1f s in all\nwrote %s and %s\n", schedule.waited,
           schedule.retried, sb_wall_seconds() - started, o.csv, o.md);
    for (int i = 0; i < 2; i++) sb_bench_setup_free(&setups[i]);
    return 0;
}
