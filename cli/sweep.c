/* `softbond sweep SWEEP.yaml`: runs a scene over a design of varied keys
 * and writes one row per case to DIR/sweep.csv, with charts beside it
 * (docs/sweep.md). The file is read and the base scene checked before any
 * case runs; then a farm runs the cases — worker processes on this machine
 * (sweep_farm.c), or the ranks of mpirun (sweep_mpi.c) — and the charts are
 * drawn from the finished table (sweep_charts.c). */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli.h"
#include "cli/output_dir.h"
#include "cli/sweep_charts.h"
#include "cli/sweep_job.h"
#include "cli/sweep_row.h"
#include "common/error.h"
#include "scenes/scene.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void sb_cli_sweep_usage(FILE* stream) {
    fprintf(stream, "usage: softbond sweep SWEEP.yaml [--set key=value]... [--output DIR] [--workers N] [--threads N]\n"
                    "       softbond sweep SWEEP.yaml [--set key=value]... --resume DIR [--workers N] [--threads N]\n"
                    "       mpirun -np N softbond sweep SWEEP.yaml ...\n"
                    "Runs a base scene once per case of a design (keys varied as lists, linear or log\n"
                    "ranges, random or Latin hypercube samples; combined as a grid or zipped) and writes\n"
                    "DIR/sweep.csv (default out/<sweep name>): one row per case, as cases finish, with\n"
                    "the varied values, the metrics (a log.csv column's end, max or min; a collider's or\n"
                    "handle's force; a vertex's end position; the blow-up step; the wall time), the\n"
                    "run's exit status and its message. A failed case is a row, not the end. Charts\n"
                    "(gnuplot): DIR/<metric>.png against the first key and, with two keys or more,\n"
                    "DIR/stability.png (which cases failed). See docs/sweep.md.\n"
                    "--set overrides a key of every case (after the file's set:, before the case's values).\n"
                    "--workers N runs N cases at once on this machine (default 1).\n"
                    "--threads N gives each run N solver threads (default: the scene's).\n"
                    "--resume DIR goes on with the sweep in DIR: the cases in its sweep.csv are skipped.\n"
                    "Under mpirun (a build with SB_MPI), rank 0 hands out the cases and writes the\n"
                    "table, the other ranks run them; a rank that dies ends the job (Open MPI), and\n"
                    "--resume DIR runs the cases it lost.\n");
}

typedef struct sweep_command {
    sb_cli_args args;
    sb_sweep_job job;
    int rank, size;
} sweep_command;

static int finish(sweep_command* s, int code) {
    sb_sweep_table_free(&s->job.table);
    sb_sweep_design_free(&s->job.design);
    sb_sweep_spec_free(&s->job.spec);
    free(s->job.dir);
    sb_cli_args_free(&s->args);
    return code;
}

/* The base scene (the file's sets and the command line's) as a run reads it. */
static sb_status check_scene(const sb_sweep_job* job, sb_error* err) {
    size_t count = job->spec.set_count + job->set_count;
    const char** sets = calloc(count ? count : 1, sizeof *sets);
    if (!sets) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    for (size_t i = 0; i < job->spec.set_count; i++) sets[i] = job->spec.sets[i]; /* either may be NULL when empty */
    for (size_t i = 0; i < job->set_count; i++) sets[job->spec.set_count + i] = job->sets[i];
    sb_scene scene;
    sb_status status = sb_scene_read(&scene, job->spec.scene, sets, count, err);
    if (status == SB_OK) sb_scene_free(&scene);
    free(sets);
    char prefix[600];
    snprintf(prefix, sizeof prefix, "%s: the base scene", job->spec.yaml.path);
    return status == SB_OK ? SB_OK : sb_error_prefix(err, status, prefix);
}

static sb_status parse_options(sweep_command* s, sb_error* err) {
    sb_sweep_job* job = &s->job;
    job->workers = 1;
    if (s->args.workers) {
        char* end;
        job->workers = strtol(s->args.workers, &end, 10);
        if (end == s->args.workers || *end != '\0' || job->workers < 1 || job->workers > 1024)
            return sb_error_set(err, SB_ERR_INVALID, "--workers: expected 1 to 1024, got '%s'", s->args.workers);
    }
    if (s->args.threads) {
        char* end;
        long threads = strtol(s->args.threads, &end, 10);
        if (end == s->args.threads || *end != '\0' || threads < 1 || threads > 4096)
            return sb_error_set(err, SB_ERR_INVALID, "--threads: expected 1 to 4096, got '%s'", s->args.threads);
    }
    if (s->args.resume && s->args.output)
        return sb_error_set(err, SB_ERR_INVALID, "--resume DIR writes into DIR: leave out --output");
    job->sets = s->args.sets;
    job->set_count = (size_t)s->args.set_count;
    job->threads = s->args.threads;
    return SB_OK;
}

/* The sweep's name: the file's name without folder and extension. */
static void sweep_name(const char* path, char* out, size_t size) {
    const char* slash = strrchr(path, '/');
    const char* name = slash ? slash + 1 : path;
    snprintf(out, size, "%.*s", (int)strcspn(name, "."), name);
}

static sb_status prepare(sweep_command* s, sb_error* err) {
    sb_sweep_job* job = &s->job;
    sb_status status = parse_options(s, err);
    if (status == SB_OK) status = sb_sweep_spec_load(&job->spec, s->args.input, err);
    if (status == SB_OK) status = check_scene(job, err);
    if (status == SB_OK) status = sb_sweep_design_make(&job->spec, &job->design, err);
    if (status != SB_OK) return status;
    char name[256];
    sweep_name(s->args.input, name, sizeof name);
    if (s->args.resume) { /* the folder as the stopped sweep left it: its table is read, nothing made */
        job->dir = strdup(s->args.resume);
        return job->dir ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    }
    sb_output_dir out = {0};
    status = sb_output_dir_create(&out, s->args.output, name, err);
    job->dir = out.dir;
    return status;
}

static sb_status open_table(sb_sweep_job* job, bool resume, sb_error* err) {
    char* header = sb_sweep_header(&job->spec);
    if (!header) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    char path[4096];
    snprintf(path, sizeof path, "%s/sweep.csv", job->dir);
    sb_status status = sb_sweep_table_open(&job->table, path, header, job->design.case_count, resume, err);
    free(header);
    if (status == SB_OK && resume)
        printf("softbond: resuming %s: %zu of %zu cases done\n", path, job->table.done, job->design.case_count);
    return status;
}

/* Field k of a row (0 the case), or "" (in a buffer). */
static const char* row_field(const char* row, size_t k, char* buffer, size_t size) {
    snprintf(buffer, size, "%s", row);
    char* fields[1024];
    size_t n = sb_csv_split(buffer, fields, 1024);
    return k < n ? fields[k] : "";
}

static void report(const sb_sweep_job* job, int size) {
    size_t failed = 0, status_field = 1 + job->spec.axis_count + job->spec.metric_count;
    for (size_t c = 0; c < job->design.case_count; c++) {
        char buffer[8192];
        failed +=
            job->table.rows[c] && strcmp(row_field(job->table.rows[c], status_field, buffer, sizeof buffer), "0") != 0;
    }
    printf("softbond: %zu cases (%zu failed) in %s/sweep.csv, %s\n", job->table.done, failed, job->dir,
           size > 1 ? "over MPI ranks" : "on this machine");
}

/* A log.csv column that no run that ended well had (a misspelt column, a
 * collider's name): said once, naming the metric's line. */
static void check_columns(const sb_sweep_job* job) {
    const sb_sweep_spec* spec = &job->spec;
    size_t status_field = 1 + spec->axis_count + spec->metric_count;
    for (size_t m = 0; m < spec->metric_count; m++) {
        if (spec->metrics[m].kind != SB_METRIC_COLUMN) continue;
        bool ran = false, found = false;
        for (size_t c = 0; c < job->design.case_count && !found; c++) {
            const char* row = job->table.rows[c];
            char buffer[8192];
            if (!row || strcmp(row_field(row, status_field, buffer, sizeof buffer), "0") != 0) continue;
            ran = true;
            found = row_field(row, 1 + spec->axis_count + m, buffer, sizeof buffer)[0] != '\0';
        }
        if (ran && !found)
            fprintf(stderr,
                    "softbond: %s:%zu: metric '%s': no run's log.csv has a column '%s' (its fields are empty)\n",
                    spec->yaml.path, spec->metrics[m].line, spec->metrics[m].name, spec->metrics[m].column);
    }
}

/* DIR/cases, when no case's folder is kept in it. */
static void remove_cases_dir(const sb_sweep_job* job) {
    char path[4096];
    snprintf(path, sizeof path, "%s/cases", job->dir);
    rmdir(path);
}

int sb_cli_sweep(int argc, char** argv) {
    static const char* const accepted[] = {"--output", "--resume", "--workers", "--threads", NULL};
    sweep_command s = {0};
    sb_error err;
    if (sb_cli_parse(argc, argv, accepted, &s.args, &err) != SB_OK) return finish(&s, sb_cli_fail(SB_EXIT_INPUT, &err));
    if (s.args.help) {
        sb_cli_sweep_usage(stdout);
        return finish(&s, SB_EXIT_OK);
    }
    if (sb_study_mpi_begin(&s.rank, &s.size, &err) != SB_OK) return finish(&s, sb_cli_fail(SB_EXIT_INPUT, &err));
    int code = SB_EXIT_OK;
    if (prepare(&s, &err) != SB_OK) code = SB_EXIT_INPUT;
    sb_status opened = code == SB_EXIT_OK && s.rank == 0 ? open_table(&s.job, s.args.resume != NULL, &err) : SB_OK;
    if (opened != SB_OK) code = s.args.resume || opened == SB_ERR_PARSE ? SB_EXIT_INPUT : SB_EXIT_FAILURE;
    if (code != SB_EXIT_OK) {
        if (s.rank == 0) sb_cli_fail(code, &err);
        sb_study_mpi_end(code);
        return finish(&s, code);
    }
    sb_status status = s.size > 1 ? sb_sweep_farm_mpi(&s.job, s.rank, s.size, &err) : sb_sweep_farm_local(&s.job, &err);
    if (status == SB_OK && s.rank == 0) status = sb_sweep_charts(&s.job.spec, s.job.dir, &err);
    if (s.rank == 0) remove_cases_dir(&s.job);
    if (status != SB_OK) code = sb_cli_fail(SB_EXIT_FAILURE, &err);
    if (code == SB_EXIT_OK && s.rank == 0) {
        check_columns(&s.job);
        report(&s.job, s.size);
    }
    sb_study_mpi_end(code); /* a rank that failed ends the job: the others may wait on it */
    return finish(&s, code);
}
