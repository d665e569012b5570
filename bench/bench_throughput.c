/* sb_bench: step throughput of the fast kernels (1 and 2 threads) and the
 * scalar reference on sheets and icospheres of ~10k, ~100k and ~1M vertices,
 * with all molecular-mechanics terms, gravity and Verlet.
 *
 * Method. For each case and each configuration a solver is created, run
 * until it has taken at least a warm-up time (which also calibrates the step
 * count N so that one measurement takes about --target seconds; --steps
 * fixes N instead), then reset to the rest state (untimed) and timed over N
 * steps of sb_solver_advance, --repeats times; the best time counts. Every
 * measurement starts from the same state, so each does the same work. In the
 * same run a STREAM triad (bench_stream.c) gives the memory-bandwidth ceiling
 * for 1 and 2 threads, and the byte and flop models of bench_model.c turn
 * step times into GB/s and GFLOP/s.
 *
 * Output: a table on stdout, a CSV (machine and models in '#' lines at the
 * top) and machine.txt beside it. */
#include "bench/bench_cases.h"
#include "common/clock.h"
#include "bench/bench_model.h"
#include "bench/bench_stream.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define SB_MAX_THREAD_COUNTS 8
#define SB_MAX_ROWS 64

typedef struct sb_options {
    bool small_only;
    const char* case_list; /* comma-separated names, or NULL */
    uint64_t steps;        /* 0 = calibrate */
    int threads[SB_MAX_THREAD_COUNTS];
    int thread_count;
    bool quick, reference, all_terms;
    bool cpu_clock; /* time the steps on the process's CPU clock */
    double target, jitter;
    int repeats;
    const char* csv;
} sb_options;

/* One measured configuration of one case. */
typedef struct sb_row {
    const sb_bench_case* bcase;
    sb_bench_counts counts;
    double dt;
    const char* kernels; /* "fast" or "reference" */
    int threads;
    bool ok;
    char note[160];
    uint64_t steps;
    double seconds;             /* best of the repeats, N steps */
    double triad;               /* GB/s with the same thread count */
    double speedup, efficiency; /* NAN where not applicable */
} sb_row;

/* ---- options ------------------------------------------------------------- */

static void sb_usage(FILE* out) {
    fprintf(out,
            "usage: sb_bench [options]\n"
            "  --cases small|all|NAME[,NAME]  small: the ~10k cases (default all)\n"
            "  --steps N            time N steps per measurement (default: calibrated to\n"
            "                       --target; the reference takes at most the calibrated count)\n"
            "  --threads-list 1,2   thread counts for the fast kernels (default 1,2)\n"
            "  --quick              shorter measurements, 1 repeat, smaller triad arrays\n"
            "  --all-terms          add the damped spring and the hinge bend\n"
            "  --no-reference       skip the scalar reference\n"
            "  --target S           seconds per measurement (default 0.8; quick 0.25)\n"
            "  --repeats N          measurements per configuration, best kept (default 3)\n"
            "  --cpu-clock          time the steps in the process's CPU time, not the wall\n"
            "                       clock: on a shared machine it leaves out the time other\n"
            "                       programs held the cores (1 thread; spinning waits count)\n"
            "  --jitter J           sheet jitter, fraction of the spacing (default %.2g)\n"
            "  --csv FILE           CSV output (default %s/bench/results/throughput.csv)\n"
            "  --list               print the cases and exit\n",
            SB_BENCH_DEFAULT_JITTER, SB_BENCH_SOURCE_DIR);
}

static bool sb_parse_threads(const char* text, sb_options* o) {
    o->thread_count = 0;
    for (const char* p = text; *p;) {
        char* end;
        long t = strtol(p, &end, 10);
        if (end == p || t < 1 || t > 1024 || o->thread_count == SB_MAX_THREAD_COUNTS) return false;
        o->threads[o->thread_count++] = (int)t;
        p = *end == ',' ? end + 1 : end;
        if (*end && *end != ',') return false;
    }
    return o->thread_count > 0;
}

static const char* sb_value(int argc, char** argv, int* i) {
    if (*i + 1 >= argc) {
        fprintf(stderr, "sb_bench: %s needs a value\n", argv[*i]);
        exit(2);
    }
    return argv[++*i];
}

static void sb_list_cases(void) {
    for (size_t i = 0; i < sb_bench_case_count; i++)
        printf("%s%s\n", sb_bench_cases[i].name, sb_bench_cases[i].small ? " (small)" : "");
}

static sb_options sb_parse(int argc, char** argv) {
    static char default_csv[4096];
    snprintf(default_csv, sizeof default_csv, "%s/bench/results/throughput.csv", SB_BENCH_SOURCE_DIR);
    sb_options o = {.threads = {1, 2},
                    .thread_count = 2,
                    .reference = true,
                    .target = -1.0,
                    .jitter = SB_BENCH_DEFAULT_JITTER,
                    .repeats = -1,
                    .csv = default_csv};
    for (int i = 1; i < argc; i++) {
        const char* a = argv[i];
        if (!strcmp(a, "--cases")) {
            const char* v = sb_value(argc, argv, &i);
            o.small_only = !strcmp(v, "small");
            o.case_list = strcmp(v, "small") && strcmp(v, "all") ? v : NULL;
        } else if (!strcmp(a, "--steps"))
            o.steps = strtoull(sb_value(argc, argv, &i), NULL, 10);
        else if (!strcmp(a, "--threads-list")) {
            if (!sb_parse_threads(sb_value(argc, argv, &i), &o)) {
                fprintf(stderr, "sb_bench: --threads-list wants positive integers like 1,2\n");
                exit(2);
            }
        } else if (!strcmp(a, "--quick"))
            o.quick = true;
        else if (!strcmp(a, "--cpu-clock"))
            o.cpu_clock = true;
        else if (!strcmp(a, "--all-terms"))
            o.all_terms = true;
        else if (!strcmp(a, "--no-reference"))
            o.reference = false;
        else if (!strcmp(a, "--target"))
            o.target = atof(sb_value(argc, argv, &i));
        else if (!strcmp(a, "--repeats"))
            o.repeats = atoi(sb_value(argc, argv, &i));
        else if (!strcmp(a, "--jitter"))
            o.jitter = atof(sb_value(argc, argv, &i));
        else if (!strcmp(a, "--csv"))
            o.csv = sb_value(argc, argv, &i);
        else if (!strcmp(a, "--list")) {
            sb_list_cases();
            exit(0);
        } else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            sb_usage(stdout);
            exit(0);
        } else {
            fprintf(stderr, "sb_bench: unknown option '%s'\n", a);
            sb_usage(stderr);
            exit(2);
        }
    }
    if (o.target <= 0.0) o.target = o.quick ? 0.25 : 0.8;
    if (o.repeats <= 0) o.repeats = o.quick ? 1 : 3;
    return o;
}

static bool sb_case_selected(const sb_bench_case* c, const sb_options* o) {
    if (o->small_only) return c->small;
    if (!o->case_list) return true;
    size_t n = strlen(c->name);
    for (const char* p = o->case_list; (p = strstr(p, c->name)) != NULL; p += n)
        if ((p == o->case_list || p[-1] == ',') && (p[n] == '\0' || p[n] == ',')) return true;
    return false;
}

/* ---- the machine ----------------------------------------------------------- */

static const char* sb_simd_level(void) {
#if defined(__AVX512F__)
    return "avx512";
#elif defined(__AVX2__)
    return "avx2";
#elif defined(__SSE2__)
    return "sse2";
#else
    return "scalar";
#endif
}

static void sb_cpu_model(char* out, size_t size) {
    snprintf(out, size, "unknown");
    FILE* f = fopen("/proc/cpuinfo", "r");
    if (!f) return;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        char* colon = strchr(line, ':');
        if (strncmp(line, "model name", 10) != 0 || !colon) continue;
        colon += strspn(colon + 1, " \t") + 1;
        colon[strcspn(colon, "\n")] = '\0';
        snprintf(out, size, "%s", colon);
        break;
    }
    fclose(f);
}

static void sb_git_commit(char* out, size_t size) {
    snprintf(out, size, "unknown");
    char command[4200];
    snprintf(command, sizeof command, "git -C '%s' rev-parse --short HEAD 2>/dev/null", SB_BENCH_SOURCE_DIR);
    FILE* p = popen(command, "r");
    if (!p) return;
    if (fgets(out, (int)size, p))
        out[strcspn(out, "\n")] = '\0';
    else
        snprintf(out, size, "unknown");
    pclose(p);
}

/* The machine as "key: value" lines, each after `prefix`. */
static void sb_print_machine(FILE* out, const char* prefix, const sb_triad_result* triads, int triad_count) {
    char cpu[256], commit[64], date[64];
    time_t now = time(NULL);
    sb_cpu_model(cpu, sizeof cpu);
    sb_git_commit(commit, sizeof commit);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S %Z", localtime(&now));
    fprintf(out, "%sdate: %s\n%scommit: %s\n", prefix, date, prefix, commit);
    fprintf(out, "%scpu: %s\n%slogical cores online: %ld\n", prefix, cpu, prefix, sysconf(_SC_NPROCESSORS_ONLN));
    size_t llc = sb_bench_llc_bytes();
    if (llc)
        fprintf(out, "%slast-level cache: %.1f MiB\n", prefix, llc / 1048576.0);
    else
        fprintf(out, "%slast-level cache: not reported by the OS (cpuid's L3: %.1f MiB, may be a whole package's)\n",
                prefix, sb_bench_cpuid_l3_bytes() / 1048576.0);
    double load[3];
    if (getloadavg(load, 3) == 3)
        fprintf(out, "%sload average (1, 5, 15 min; above 0.5 means others shared the cores): %.2f %.2f %.2f\n", prefix,
                load[0], load[1], load[2]);
    fprintf(out, "%ssimd: %s (SB_SIMD=%s)\n%sprecision: %s (SB_DOUBLE=%d)\n", prefix, sb_simd_level(),
            SB_BENCH_SIMD_OPTION, prefix, SB_DOUBLE ? "double" : "float", SB_DOUBLE);
    fprintf(out, "%sbuild: %s, %s\n", prefix, SB_BENCH_BUILD_TYPE, SB_BENCH_COMPILER);
    for (int t = 0; t < triad_count; t++)
        fprintf(out, "%sstream triad, %d thread%s: %.2f GB/s (3 arrays of %.0f MiB)\n", prefix, triads[t].threads,
                triads[t].threads == 1 ? "" : "s", triads[t].gb_per_s, triads[t].array_bytes / 1048576.0);
    fprintf(out, "%sbyte model: %s\n%sflop model: %s\n", prefix, sb_bench_byte_model_text(), prefix,
            sb_bench_flop_model_text());
}

/* ---- measuring ----------------------------------------------------------- */

static bool sb_advance(sb_solver* s, double dt, uint64_t steps, sb_row* row) {
    for (uint64_t k = 0; k < steps; k++)
        if (sb_solver_advance(s, dt) != SB_OK) {
            snprintf(row->note, sizeof row->note, "step failed: %s", sb_solver_error(s));
            return false;
        }
    return true;
}

static bool sb_reset(sb_solver* s, sb_row* row) {
    if (sb_solver_set_state(s, NULL, NULL) == SB_OK) return true;
    snprintf(row->note, sizeof row->note, "reset failed: %s", sb_solver_error(s));
    return false;
}

/* Warm-up: doubles the step count until warmup seconds have passed; returns
 * the seconds per step it saw (negative on failure). */
static double sb_warm_up(sb_solver* s, double dt, double warmup, sb_row* row) {
    uint64_t chunk = 1, done = 0;
    double t0 = sb_wall_seconds(), elapsed = 0.0;
    while (elapsed < warmup) {
        if (!sb_advance(s, dt, chunk, row)) return -1.0;
        done += chunk;
        chunk *= 2;
        elapsed = sb_wall_seconds() - t0;
    }
    return elapsed / (double)done;
}

/* The clock a measurement reads (--cpu-clock): seconds. */
static double sb_measure_clock(const sb_options* o) {
    if (!o->cpu_clock) return sb_wall_seconds();
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void sb_measure(const sb_bench_setup* setup, const sb_options* o, sb_row* row) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_VERLET;
    def.gravity[0] = def.gravity[1] = 0.0;
    def.gravity[2] = -SB_BENCH_GRAVITY;
    def.kernels = strcmp(row->kernels, "fast") == 0 ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
    /* a dedicated machine: spinning waits; a team of two or more pinned one
     * thread per core, a single thread left to the scheduler */
    def.runtime = (sb_runtime_def){.threads = row->threads, .pin = row->threads > 1, .wait = SB_WAIT_SPIN};
    sb_error err = {{0}};
    sb_solver* s = sb_solver_create(setup->model, &def, &err);
    if (!s) {
        snprintf(row->note, sizeof row->note, "unavailable: %.120s", err.message); /* a note is short */
        return;
    }
    double per_step = sb_warm_up(s, setup->dt, fmin(0.3, 0.25 * o->target), row);
    if (per_step > 0.0) {
        /* --steps fixes N, except that the slow reference never runs past the
         * target time (it would take minutes at 1M vertices). */
        uint64_t calibrated = (uint64_t)fmax(2.0, ceil(o->target / per_step));
        row->steps = o->steps ? o->steps : calibrated;
        if (def.kernels == SB_KERNELS_REFERENCE && calibrated < row->steps) row->steps = calibrated;
        row->seconds = INFINITY;
        row->ok = true;
        for (int r = 0; r < o->repeats && row->ok; r++) {
            row->ok = sb_reset(s, row);
            double t0 = sb_measure_clock(o);
            row->ok = row->ok && sb_advance(s, setup->dt, row->steps, row);
            row->seconds = fmin(row->seconds, sb_measure_clock(o) - t0);
        }
    }
    sb_solver_destroy(s);
}

/* ---- reporting ----------------------------------------------------------- */

static double sb_ns_per_step(const sb_row* r) { return r->ok ? 1e9 * r->seconds / (double)r->steps : NAN; }
static double sb_steps_per_s(const sb_row* r) { return r->ok ? (double)r->steps / r->seconds : NAN; }

static void sb_derive(sb_row* rows, int first, int count) {
    const sb_row *ref = NULL, *one = NULL;
    for (int i = first; i < first + count; i++) {
        if (!strcmp(rows[i].kernels, "reference") && rows[i].ok) ref = &rows[i];
        if (!strcmp(rows[i].kernels, "fast") && rows[i].threads == 1 && rows[i].ok) one = &rows[i];
    }
    for (int i = first; i < first + count; i++) {
        sb_row* r = &rows[i];
        r->speedup = r->efficiency = NAN;
        if (!r->ok || strcmp(r->kernels, "fast") != 0) continue;
        if (ref) r->speedup = sb_ns_per_step(ref) / sb_ns_per_step(r);
        if (one && r->threads > 1) r->efficiency = sb_ns_per_step(one) / (r->threads * sb_ns_per_step(r));
    }
}

static void sb_print_header(void) {
    printf("%-15s %9s %9s %-9s %3s %7s %12s %10s %9s %7s %7s %6s %7s %7s %6s\n", "case", "vertices", "elements",
           "kernels", "thr", "steps", "ns/step", "steps/s", "Melem/s", "GB/s", "triad", "%bw", "GFLOP/s", "speedup",
           "eff");
}

static void sb_print_row(const sb_row* r) {
    printf("%-15s %9llu %9llu %-9s %3d ", r->bcase->name, (unsigned long long)r->counts.vertices,
           (unsigned long long)r->counts.elements, r->kernels, r->threads);
    if (!r->ok) {
        printf("%s\n", r->note);
        return;
    }
    double sps = sb_steps_per_s(r), gbs = r->counts.bytes_per_step * sps * 1e-9;
    printf("%7llu %12.0f %10.1f %9.1f %7.2f %7.2f %5.0f%% %7.2f ", (unsigned long long)r->steps, sb_ns_per_step(r), sps,
           r->counts.elements * sps * 1e-6, gbs, r->triad, 100.0 * gbs / r->triad,
           r->counts.flops_per_step * sps * 1e-9);
    if (isnan(r->speedup))
        printf("%7s ", "-");
    else
        printf("%6.2fx ", r->speedup);
    if (isnan(r->efficiency))
        printf("%6s\n", "-");
    else
        printf("%6.2f\n", r->efficiency);
}

static void sb_csv_number(FILE* f, double v, const char* format) {
    if (isfinite(v)) fprintf(f, format, v);
    fputc(',', f);
}

static void sb_csv_row(FILE* f, const sb_row* r) {
    const sb_bench_counts* c = &r->counts;
    double sps = sb_steps_per_s(r), gbs = c->bytes_per_step * sps * 1e-9;
    fprintf(f, "%s,%s,%llu,%llu,%llu,%llu,%llu,%.6g,%s,%s,%d,%llu,", r->bcase->name,
            r->bcase->shape == SB_BENCH_SHEET ? "sheet" : "icosphere", (unsigned long long)c->vertices,
            (unsigned long long)c->bonds, (unsigned long long)c->triangles, (unsigned long long)c->hinges,
            (unsigned long long)c->elements, r->dt, SB_DOUBLE ? "double" : "float", r->kernels, r->threads,
            (unsigned long long)(r->ok ? r->steps : 0));
    sb_csv_number(f, r->ok ? r->seconds : NAN, "%.6g");
    sb_csv_number(f, sb_ns_per_step(r), "%.1f");
    sb_csv_number(f, sps, "%.2f");
    sb_csv_number(f, c->elements * sps, "%.4g");
    fprintf(f, "%.0f,", c->bytes_per_step);
    sb_csv_number(f, gbs, "%.3f");
    sb_csv_number(f, r->triad, "%.3f");
    sb_csv_number(f, gbs / r->triad, "%.3f");
    fprintf(f, "%.0f,", c->flops_per_step);
    sb_csv_number(f, c->flops_per_step * sps * 1e-9, "%.3f");
    sb_csv_number(f, r->speedup, "%.3f");
    sb_csv_number(f, r->efficiency, "%.3f");
    fprintf(f, "%s\n", r->ok ? "" : r->note);
}

static const char* sb_csv_columns =
    "case,mesh,vertices,bonds,triangles,hinges,elements,dt_s,precision,kernels,threads,steps,seconds,"
    "ns_per_step,steps_per_s,elements_per_s,bytes_per_step,gb_per_s,triad_gb_per_s,bandwidth_fraction,"
    "flops_per_step,gflop_per_s,speedup_vs_reference,parallel_efficiency,note";

/* Makes the directories above path (mkdir -p of its dirname). */
static void sb_make_parents(const char* path) {
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", path);
    for (char* p = dir + 1; *p; p++)
        if (*p == '/') {
            *p = '\0';
            if (mkdir(dir, 0777) != 0 && errno != EEXIST) return;
            *p = '/';
        }
}

static int sb_write_outputs(const sb_options* o, const sb_row* rows, int count, const sb_triad_result* triads,
                            int triad_count) {
    sb_make_parents(o->csv);
    FILE* f = fopen(o->csv, "w");
    if (!f) {
        fprintf(stderr, "sb_bench: cannot write %s: %s\n", o->csv, strerror(errno));
        return 1;
    }
    fprintf(f, "# softbond sb_bench throughput%s\n", o->all_terms ? " (--all-terms)" : "");
    sb_print_machine(f, "# ", triads, triad_count);
    fprintf(f, "%s\n", sb_csv_columns);
    for (int i = 0; i < count; i++) sb_csv_row(f, &rows[i]);
    fclose(f);
    struct stat written;
    if (stat(o->csv, &written) != 0 || !S_ISREG(written.st_mode)) { /* /dev/null: no machine.txt beside it in /dev */
        printf("\nwrote %s\n", o->csv);
        return 0;
    }
    char machine[4200];
    snprintf(machine, sizeof machine, "%s", o->csv);
    char* slash = strrchr(machine, '/');
    snprintf(slash ? slash + 1 : machine, sizeof machine - (size_t)(slash ? slash + 1 - machine : 0), "machine.txt");
    FILE* m = fopen(machine, "w");
    if (m) {
        sb_print_machine(m, "", triads, triad_count);
        fclose(m);
    }
    printf("\nwrote %s and %s\n", o->csv, machine);
    return 0;
}

/* ---- main ---------------------------------------------------------------- */

static int sb_triads(const sb_options* o, sb_triad_result* out) {
    /* 4x the larger of the OS's and cpuid's figures: past every cache either may mean */
    size_t llc = sb_bench_llc_bytes(), l3 = sb_bench_cpuid_l3_bytes();
    size_t bytes = 4 * (llc > l3 ? llc : l3 ? l3 : (size_t)32 << 20);
    size_t floor_bytes = (size_t)256 << 20;
    if (o->quick && bytes > floor_bytes) bytes = floor_bytes;
    if (bytes < floor_bytes / 4) bytes = floor_bytes / 4;
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && page > 0 && bytes > (size_t)pages * (size_t)page / 8) bytes = (size_t)pages * (size_t)page / 8;
    int n = 0;
    for (int t = 0; t < o->thread_count; t++) {
        out[n] = sb_bench_triad(bytes, o->threads[t], o->quick ? 3 : 6);
        fprintf(stderr, "stream triad, %d thread(s), 3 x %.0f MiB: %.2f GB/s\n", o->threads[t], bytes / 1048576.0,
                out[n].gb_per_s);
        n++;
    }
    return n;
}

static double sb_triad_for(const sb_triad_result* triads, int count, int threads) {
    for (int t = 0; t < count; t++)
        if (triads[t].threads == threads) return triads[t].gb_per_s;
    return NAN;
}

/* Measures every configuration of one case into rows[*count...]. */
static void sb_run_case(const sb_bench_case* c, const sb_options* o, const sb_triad_result* triads, int triad_count,
                        sb_row* rows, int* count) {
    sb_bench_options bo = {.all_terms = o->all_terms, .jitter = o->jitter};
    sb_bench_setup setup;
    sb_error err = {{0}};
    if (sb_bench_build(c, &bo, &setup, &err) != SB_OK) {
        fprintf(stderr, "sb_bench: %s: %s\n", c->name, err.message);
        sb_bench_setup_free(&setup);
        return;
    }
    sb_bench_counts counts = sb_bench_count(setup.model, o->all_terms);
    int first = *count;
    for (int t = 0; t <= o->thread_count && *count < SB_MAX_ROWS; t++) {
        bool ref = t == o->thread_count;
        if (ref && !o->reference) break;
        sb_row* r = &rows[(*count)++];
        *r = (sb_row){.bcase = c,
                      .counts = counts,
                      .dt = setup.dt,
                      .kernels = ref ? "reference" : "fast",
                      .threads = ref ? 1 : o->threads[t]};
        r->triad = sb_triad_for(triads, triad_count, r->threads);
        if (isnan(r->triad)) r->triad = sb_bench_triad(triads[0].array_bytes, r->threads, 3).gb_per_s;
        sb_measure(&setup, o, r);
    }
    sb_derive(rows, first, *count - first);
    for (int i = first; i < *count; i++) sb_print_row(&rows[i]);
    fflush(stdout);
    sb_bench_setup_free(&setup);
}

int main(int argc, char** argv) {
    sb_options o = sb_parse(argc, argv);
    static sb_row rows[SB_MAX_ROWS];
    sb_triad_result triads[SB_MAX_THREAD_COUNTS];
    int count = 0, triad_count = sb_triads(&o, triads);
    sb_print_machine(stdout, "", triads, triad_count);
    printf("\n");
    sb_print_header();
    for (size_t i = 0; i < sb_bench_case_count; i++)
        if (sb_case_selected(&sb_bench_cases[i], &o))
            sb_run_case(&sb_bench_cases[i], &o, triads, triad_count, rows, &count);
    if (count == 0) {
        fprintf(stderr, "sb_bench: no case selected (try --list)\n");
        return 2;
    }
    return sb_write_outputs(&o, rows, count, triads, triad_count);
}
