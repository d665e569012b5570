/* `softbond fit FIT.yaml`: finds scene keys (within bounds) that make a
 * curve of the run's log.csv — one column against another — follow a
 * target curve given as a CSV, by least squares with a derivative-free
 * optimizer from NLopt (docs/sweep.md):
 *
 *     scene: probe.yaml
 *     set: [duration=0.05]
 *     parameters:
 *       - {key: bond.k, start: 300, min: 10, max: 3000}
 *       - {key: handles, format: "[{vertices: [0], stiffness: %g}]", start: 1, min: 0.1, max: 10}
 *     target: {file: measured.csv, x: time, y: probe_fz}   # file: a header, then x,y rows
 *     algorithm: bobyqa            # or neldermead
 *     max_evaluations: 200
 *     tolerance: 1e-6              # relative change of the keys that ends the search
 *
 * Each evaluation is one `softbond run` (study_case.h) in DIR/run; its
 * y column, linearly interpolated at the target's x, is compared with the
 * target's y: the objective is the sum of the squared differences. A run
 * that fails, or ends before the target's last x, scores 1e30. A key whose
 * bounds are both > 0 is searched in its logarithm (stiffnesses span
 * decades). Writes DIR/fit_evaluations.csv (every evaluation), DIR/fit.txt
 * (the fitted keys and the residual), DIR/fit_curve.csv and DIR/fit.png. */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli.h"
#include "cli/log_table.h"
#include "cli/output_dir.h"
#include "cli/study_case.h"
#include "cli/study_mpi.h"
#include "cli/sweep_spec.h"
#include "cli/sweep_table.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "scenes/scene.h"

#include <math.h>
#include <nlopt.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_PARAMETERS = 32, SET_SIZE = SB_SWEEP_VALUE_SIZE + 256 };
static const double FAILED_SCORE = 1e30;

void sb_cli_fit_usage(FILE* stream) {
    fprintf(stream, "usage: softbond fit FIT.yaml [--set key=value]... [--output DIR] [--threads N]\n"
                    "       mpirun -np N softbond fit FIT.yaml ...\n"
                    "Fits scene keys (parameters: key, start, min, max; format for a key inside a list)\n"
                    "so that a curve of log.csv (target: x and y, its column names) follows the target\n"
                    "CSV (target: file, a header then x,y rows): least squares, searched by NLopt's\n"
                    "BOBYQA (algorithm: bobyqa, the default) or Nelder-Mead (neldermead), derivative-free,\n"
                    "one softbond run per evaluation. Writes to DIR (default out/<fit name>):\n"
                    "fit.txt (the fitted keys, the RMS residual), fit_evaluations.csv, fit_curve.csv and\n"
                    "fit.png (gnuplot). Under mpirun (a build with SB_MPI) each rank searches from its\n"
                    "own start (rank 0 from the file's) and the best of them wins. See docs/sweep.md.\n");
}

typedef struct fit_parameter {
    const char* key;
    const char* format;
    double start, min, max;
    bool log; /* searched in its logarithm */
} fit_parameter;

typedef struct fit_spec {
    sb_study_yaml yaml;
    char* scene;
    char* target_path;
    const char** sets;
    size_t set_count;
    fit_parameter parameters[MAX_PARAMETERS];
    size_t parameter_count;
    const char *x_column, *y_column;
    int algorithm; /* 0 bobyqa, 1 neldermead */
    long max_evaluations;
    double tolerance;
} fit_spec;

typedef struct fit_job {
    sb_cli_args args;
    int rank, size; /* under mpirun: each rank searches from its own start */
    fit_spec spec;
    sb_log_table target;
    char* dir;
    char run_dir[4096];
    FILE* evaluations; /* fit_evaluations.csv, a row appended and flushed per evaluation */
    long evaluation;
    double best_score;
    double best[MAX_PARAMETERS];
    double* best_curve; /* the model's y at the target's x, of the best evaluation */
    double* curve;
} fit_job;

/* ---- the file ---- */

static sb_status read_parameter(fit_spec* spec, fit_parameter* p, const yaml_node_t* map) {
    sb_study_yaml* y = &spec->yaml;
    static const char* const known[] = {"key", "format", "start", "min", "max", NULL};
    sb_status status = sb_study_yaml_map(y, map, "parameter");
    if (status == SB_OK) status = sb_study_yaml_check_keys(y, map, known);
    yaml_node_t *key = NULL, *start = NULL, *min = NULL, *max = NULL;
    if (status == SB_OK) {
        key = sb_study_yaml_get(y, map, "key"), start = sb_study_yaml_get(y, map, "start");
        min = sb_study_yaml_get(y, map, "min"), max = sb_study_yaml_get(y, map, "max");
        if (!key || !start || !min || !max)
            return sb_study_yaml_fail(y, map, "parameter: needs key, start, min and max");
    }
    if (status == SB_OK) status = sb_study_read_key(y, key, &p->key);
    if (status == SB_OK) status = sb_study_read_format(y, map, &p->format);
    if (status == SB_OK) status = sb_study_yaml_number(y, start, "start", &p->start);
    if (status == SB_OK) status = sb_study_yaml_number(y, min, "min", &p->min);
    if (status == SB_OK) status = sb_study_yaml_number(y, max, "max", &p->max);
    if (status == SB_OK && !(p->min < p->max && p->min <= p->start && p->start <= p->max))
        return sb_study_yaml_fail(y, map, "parameter '%s': expected min < max and start within them", p->key);
    p->log = p->min > 0.0;
    return status;
}

static sb_status read_parameters(fit_spec* spec, const yaml_node_t* node) {
    sb_study_yaml* y = &spec->yaml;
    sb_status status = sb_study_yaml_sequence(y, node, "parameters");
    if (status == SB_OK && sb_study_yaml_count(node) > MAX_PARAMETERS)
        return sb_study_yaml_fail(y, node, "parameters: at most %d", MAX_PARAMETERS);
    spec->parameter_count = sb_study_yaml_count(node);
    for (size_t i = 0; i < spec->parameter_count && status == SB_OK; i++)
        status = read_parameter(spec, &spec->parameters[i], sb_study_yaml_item(y, node, i));
    return status;
}

static sb_status read_target(fit_spec* spec, const yaml_node_t* map) {
    sb_study_yaml* y = &spec->yaml;
    static const char* const known[] = {"file", "x", "y", NULL};
    sb_status status = sb_study_yaml_map(y, map, "target");
    if (status == SB_OK) status = sb_study_yaml_check_keys(y, map, known);
    yaml_node_t *file = NULL, *x = NULL, *yy = NULL;
    if (status == SB_OK) {
        file = sb_study_yaml_get(y, map, "file"), x = sb_study_yaml_get(y, map, "x"),
        yy = sb_study_yaml_get(y, map, "y");
        if (!file || !x || !yy) return sb_study_yaml_fail(y, map, "target: needs file, x and y");
    }
    const char* name;
    if (status == SB_OK) status = sb_study_yaml_text(y, file, "target.file", &name);
    if (status == SB_OK && !(spec->target_path = sb_study_yaml_relative(y, name)))
        return sb_error_set(y->err, SB_ERR_NOMEM, "out of memory");
    if (status == SB_OK) status = sb_study_yaml_text(y, x, "target.x", &spec->x_column);
    if (status == SB_OK) status = sb_study_yaml_text(y, yy, "target.y", &spec->y_column);
    return status;
}

static sb_status read_sets(fit_spec* spec, const yaml_node_t* node) {
    sb_study_yaml* y = &spec->yaml;
    sb_status status = sb_study_yaml_sequence(y, node, "set");
    spec->set_count = sb_study_yaml_count(node);
    spec->sets = calloc(spec->set_count + 1, sizeof *spec->sets);
    if (!spec->sets) return sb_error_set(y->err, SB_ERR_NOMEM, "out of memory");
    for (size_t i = 0; i < spec->set_count && status == SB_OK; i++)
        status = sb_study_yaml_text(y, sb_study_yaml_item(y, node, i), "set", &spec->sets[i]);
    return status;
}

static sb_status read_search(fit_spec* spec, const yaml_node_t* root) {
    sb_study_yaml* y = &spec->yaml;
    static const char* const algorithms[] = {"bobyqa", "neldermead", NULL};
    yaml_node_t *algorithm = sb_study_yaml_get(y, root, "algorithm"),
                *most = sb_study_yaml_get(y, root, "max_evaluations"),
                *tolerance = sb_study_yaml_get(y, root, "tolerance");
    spec->max_evaluations = 200;
    spec->tolerance = 1e-6;
    sb_status status =
        algorithm ? sb_study_yaml_choice(y, algorithm, "algorithm", algorithms, &spec->algorithm) : SB_OK;
    if (status == SB_OK && most)
        status = sb_study_yaml_whole(y, most, "max_evaluations", 1, 1000000, &spec->max_evaluations);
    if (status == SB_OK && tolerance) status = sb_study_yaml_number(y, tolerance, "tolerance", &spec->tolerance);
    if (status == SB_OK && !(spec->tolerance > 0.0))
        return sb_study_yaml_fail(y, tolerance, "tolerance: expected a number > 0");
    return status;
}

static sb_status fit_spec_load(fit_spec* spec, const char* path, sb_error* err) {
    sb_status status = sb_study_yaml_load(&spec->yaml, path, err);
    if (status != SB_OK) return status;
    sb_study_yaml* y = &spec->yaml;
    static const char* const known[] = {"scene",           "set",       "parameters", "target", "algorithm",
                                        "max_evaluations", "tolerance", NULL};
    yaml_node_t* root = sb_study_yaml_root(y);
    status = sb_study_yaml_check_keys(y, root, known);
    yaml_node_t *scene = sb_study_yaml_get(y, root, "scene"), *parameters = sb_study_yaml_get(y, root, "parameters"),
                *target = sb_study_yaml_get(y, root, "target"), *set = sb_study_yaml_get(y, root, "set");
    if (status == SB_OK && (!scene || !parameters || !target))
        return sb_study_yaml_fail(y, root, "needs scene, parameters and target");
    const char* name;
    if (status == SB_OK) status = sb_study_yaml_text(y, scene, "scene", &name);
    if (status == SB_OK && !(spec->scene = sb_study_yaml_relative(y, name)))
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    if (status == SB_OK && set) status = read_sets(spec, set);
    if (status == SB_OK) status = read_parameters(spec, parameters);
    if (status == SB_OK) status = read_target(spec, target);
    return status == SB_OK ? read_search(spec, root) : status;
}

static void fit_spec_free(fit_spec* spec) {
    free(spec->scene);
    free(spec->target_path);
    free(spec->sets);
    sb_study_yaml_free(&spec->yaml);
}

/* ---- the objective ---- */

static double key_value(const fit_parameter* p, double u) { return p->log ? exp(u) : u; }
static double search_value(const fit_parameter* p, double x) { return p->log ? log(x) : x; }

/* y of the log at x, linearly between its rows (x increasing); NaN outside. */
static double interpolate(const sb_log_table* log, size_t xc, size_t yc, double x) {
    for (size_t r = 1; r < log->row_count; r++) {
        double x0 = sb_log_table_at(log, r - 1, xc), x1 = sb_log_table_at(log, r, xc);
        if (x < x0 || x > x1 || !(x1 > x0)) continue;
        double w = (x - x0) / (x1 - x0);
        return (1.0 - w) * sb_log_table_at(log, r - 1, yc) + w * sb_log_table_at(log, r, yc);
    }
    return log->row_count == 1 && x == sb_log_table_at(log, 0, xc) ? sb_log_table_at(log, 0, yc) : NAN;
}

/* The model's curve at the target's x from the run's log.csv; false when it
 * lacks a column or a point. */
static bool model_curve(fit_job* job) {
    char path[4200];
    snprintf(path, sizeof path, "%s/log.csv", job->run_dir);
    sb_log_table log;
    sb_error ignored;
    bool ok = sb_log_table_read(path, &log, &ignored) == SB_OK;
    long xc = ok ? sb_log_table_column(&log, job->spec.x_column) : -1,
         yc = ok ? sb_log_table_column(&log, job->spec.y_column) : -1;
    ok = xc >= 0 && yc >= 0;
    for (size_t r = 0; r < job->target.row_count && ok; r++) {
        job->curve[r] = interpolate(&log, (size_t)xc, (size_t)yc, sb_log_table_at(&job->target, r, 0));
        ok = isfinite(job->curve[r]);
    }
    sb_log_table_free(&log);
    return ok;
}

static double evaluate(fit_job* job, const double* keys, sb_study_outcome* outcome) {
    const fit_spec* spec = &job->spec;
    size_t count = spec->set_count + (size_t)job->args.set_count + spec->parameter_count + 1;
    const char* sets[count];
    char texts[MAX_PARAMETERS][SET_SIZE];
    size_t n = 0;
    for (size_t i = 0; i < spec->set_count; i++) sets[n++] = spec->sets[i];
    for (int i = 0; i < job->args.set_count; i++) sets[n++] = job->args.sets[i];
    for (size_t i = 0; i < spec->parameter_count; i++) {
        char value[SB_SWEEP_VALUE_SIZE];
        sb_study_format_value(spec->parameters[i].format, keys[i], value, sizeof value);
        snprintf(texts[i], sizeof texts[i], "%s=%s", spec->parameters[i].key, value);
        sets[n++] = texts[i];
    }
    sets[n++] = "output.frames=false";
    sb_study_run run = {spec->scene, sets, n, job->run_dir, job->args.threads};
    sb_error err;
    if (sb_study_run_wait(&run, outcome, &err) != SB_OK) {
        outcome->status = 1;
        snprintf(outcome->message, sizeof outcome->message, "%s", err.message);
    }
    if (outcome->status != 0) return FAILED_SCORE;
    if (!model_curve(job)) {
        snprintf(outcome->message, sizeof outcome->message, "log.csv lacks %s or %s, or ends before the target",
                 spec->x_column, spec->y_column);
        return FAILED_SCORE;
    }
    double sum = 0.0;
    for (size_t r = 0; r < job->target.row_count; r++) {
        double d = job->curve[r] - sb_log_table_at(&job->target, r, 1);
        sum += d * d;
    }
    return sum;
}

static double objective(unsigned n, const double* u, double* gradient, void* data) {
    (void)gradient; /* derivative-free algorithms only */
    fit_job* job = data;
    double keys[MAX_PARAMETERS] = {0};
    for (unsigned i = 0; i < n; i++) keys[i] = key_value(&job->spec.parameters[i], u[i]);
    sb_study_outcome outcome;
    double score = evaluate(job, keys, &outcome);
    fprintf(job->evaluations, "%ld", job->evaluation++);
    for (unsigned i = 0; i < n; i++) fprintf(job->evaluations, ",%.17g", keys[i]);
    fprintf(job->evaluations, ",%.17g,%d\n", score, outcome.status);
    fflush(job->evaluations);
    if (score < job->best_score) {
        job->best_score = score;
        memcpy(job->best, keys, n * sizeof *keys);
        memcpy(job->best_curve, job->curve, job->target.row_count * sizeof *job->curve);
    }
    return score;
}

/* ---- the search and its outputs ---- */

/* Where rank r > 0 starts within key i's range, as a fraction: the
 * Kronecker sequence frac(r (phi - 1 + (sqrt 2 - 1) i)), spread evenly for
 * any number of ranks and keys. */
static double spread(int r, unsigned i) {
    double x = (double)r * (0.6180339887498949 + 0.41421356237309515 * (double)i);
    return x - floor(x);
}

static sb_status search(fit_job* job, sb_error* err) {
    const fit_spec* spec = &job->spec;
    unsigned n = (unsigned)spec->parameter_count;
    nlopt_opt opt = nlopt_create(spec->algorithm == 0 && n >= 2 ? NLOPT_LN_BOBYQA : NLOPT_LN_NELDERMEAD, n);
    if (!opt) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    double lower[MAX_PARAMETERS], upper[MAX_PARAMETERS], u[MAX_PARAMETERS], step[MAX_PARAMETERS];
    for (unsigned i = 0; i < n; i++) {
        const fit_parameter* p = &spec->parameters[i];
        lower[i] = search_value(p, p->min), upper[i] = search_value(p, p->max), u[i] = search_value(p, p->start);
        step[i] = (upper[i] - lower[i]) / 8.0;
        if (job->rank > 0) u[i] = lower[i] + spread(job->rank, i) * (upper[i] - lower[i]);
    }
    nlopt_set_lower_bounds(opt, lower);
    nlopt_set_upper_bounds(opt, upper);
    nlopt_set_initial_step(opt, step);
    nlopt_set_min_objective(opt, objective, job);
    nlopt_set_xtol_rel(opt, spec->tolerance);
    nlopt_set_maxeval(opt, (int)spec->max_evaluations);
    double score;
    nlopt_result result = nlopt_optimize(opt, u, &score);
    nlopt_destroy(opt);
    if (result < 0 && result != NLOPT_ROUNDOFF_LIMITED)
        return sb_error_set(err, SB_ERR_INVALID, "NLopt stopped: %s (code %d)", nlopt_result_to_string(result), result);
    return SB_OK;
}

/* Every rank's search done: the best of them (under mpirun), or fails when
 * no evaluation anywhere ran to the target's end. */
static sb_status gather(fit_job* job, sb_status searched, sb_error* err) {
    if (searched != SB_OK && job->size == 1) return searched;
    if (searched != SB_OK) job->best_score = INFINITY; /* this rank's search failed: another's may stand */
    sb_study_mpi_best(&job->best_score, job->best, job->spec.parameter_count, job->best_curve, job->target.row_count,
                      &job->evaluation);
    if (job->best_score >= FAILED_SCORE)
        return sb_error_set(err, SB_ERR_INVALID, "no evaluation ran to the target's end (see %s/fit_evaluations*.csv)",
                            job->dir);
    return SB_OK;
}

static double rms(const fit_job* job) { return sqrt(job->best_score / (double)job->target.row_count); }

static sb_status write_results(fit_job* job, sb_error* err) {
    char path[4200];
    snprintf(path, sizeof path, "%s/fit_curve.csv", job->dir);
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    fprintf(file.stream, "%s,target,model\n", job->spec.x_column);
    for (size_t r = 0; r < job->target.row_count; r++)
        fprintf(file.stream, "%.17g,%.17g,%.17g\n", sb_log_table_at(&job->target, r, 0),
                sb_log_table_at(&job->target, r, 1), job->best_curve[r]);
    status = sb_atomic_commit(&file, err);
    snprintf(path, sizeof path, "%s/fit.txt", job->dir);
    if (status == SB_OK) status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    for (size_t i = 0; i < job->spec.parameter_count; i++)
        fprintf(file.stream, "%s: %.9g\n", job->spec.parameters[i].key, job->best[i]);
    fprintf(file.stream, "rms_residual: %.9g\nevaluations: %ld\n", rms(job), job->evaluation);
    return sb_atomic_commit(&file, err);
}

/* fit.png: the target and the fitted model's curve (gnuplot; a line if it is missing). */
static void plot(const fit_job* job) {
    char command[8800];
    snprintf(command, sizeof command,
             "cd '%s' && gnuplot -e \"set terminal pngcairo size 900,600; set output 'fit.png'; "
             "set datafile separator ','; set key autotitle columnhead top left; set grid; set xlabel '%s' noenhanced; "
             "set ylabel '%s' noenhanced; plot 'fit_curve.csv' using 1:2 with points pt 7 title 'target', "
             "'' using 1:3 with lines lw 2 title 'fitted model'\" >/dev/null 2>&1",
             job->dir, job->spec.x_column, job->spec.y_column);
    bool quotable = !strpbrk(job->dir, "'\"\\$`") && !strpbrk(job->spec.x_column, "'\"\\$`") &&
                    !strpbrk(job->spec.y_column, "'\"\\$`"); /* put into a shell line and gnuplot strings */
    if (!quotable || system(command) != 0)
        fprintf(stderr, "softbond: %s/fit.png: gnuplot did not draw the fit (is gnuplot-nox installed?)\n", job->dir);
}

static sb_status prepare(fit_job* job, sb_error* err) {
    sb_status status = fit_spec_load(&job->spec, job->args.input, err);
    if (status == SB_OK) status = sb_log_table_read(job->spec.target_path, &job->target, err);
    if (status == SB_OK && (job->target.column_count != 2 || job->target.row_count == 0))
        return sb_error_set(err, SB_ERR_PARSE, "%s: expected a header and rows of two numbers, x,y",
                            job->spec.target_path);
    if (status != SB_OK) return status;
    size_t count = job->spec.set_count + (size_t)job->args.set_count;
    const char* sets[count + 1];
    for (size_t i = 0; i < job->spec.set_count; i++) sets[i] = job->spec.sets[i]; /* NULL when the file has none */
    for (int i = 0; i < job->args.set_count; i++) sets[job->spec.set_count + (size_t)i] = job->args.sets[i];
    sb_scene scene;
    status = sb_scene_read(&scene, job->spec.scene, sets, count, err);
    char prefix[600];
    snprintf(prefix, sizeof prefix, "%s: the scene", job->spec.yaml.path);
    if (status != SB_OK) return sb_error_prefix(err, status, prefix);
    sb_scene_free(&scene);
    const char* slash = strrchr(job->args.input, '/');
    char name[256];
    snprintf(name, sizeof name, "%.*s", (int)strcspn(slash ? slash + 1 : job->args.input, "."),
             slash ? slash + 1 : job->args.input);
    sb_output_dir out = {0};
    status = sb_output_dir_create(&out, job->args.output, name, err);
    job->dir = out.dir;
    return status;
}

static sb_status open_evaluations(fit_job* job, sb_error* err) {
    char path[4200];
    if (job->rank == 0) {
        snprintf(job->run_dir, sizeof job->run_dir, "%s/run", job->dir);
        snprintf(path, sizeof path, "%s/fit_evaluations.csv", job->dir);
    } else {
        snprintf(job->run_dir, sizeof job->run_dir, "%s/run_rank%d", job->dir, job->rank);
        snprintf(path, sizeof path, "%s/fit_evaluations_rank%d.csv", job->dir, job->rank);
    }
    if (!(job->evaluations = fopen(path, "w"))) return sb_error_set(err, SB_ERR_IO, "%s: cannot write", path);
    fputs("evaluation", job->evaluations);
    for (size_t i = 0; i < job->spec.parameter_count; i++) {
        fputc(',', job->evaluations);
        sb_csv_put(job->evaluations, job->spec.parameters[i].key);
    }
    fputs(",sum_of_squares,status\n", job->evaluations);
    job->curve = calloc(job->target.row_count, sizeof *job->curve);
    job->best_curve = calloc(job->target.row_count, sizeof *job->best_curve);
    job->best_score = INFINITY;
    return job->curve && job->best_curve ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory");
}

static int finish(fit_job* job, int code) {
    if (job->evaluations) fclose(job->evaluations);
    free(job->curve);
    free(job->best_curve);
    free(job->dir);
    sb_log_table_free(&job->target);
    fit_spec_free(&job->spec);
    sb_cli_args_free(&job->args);
    return code;
}

/* The fitted keys and the residual on stdout, and the plot. */
static void report(const fit_job* job) {
    for (size_t i = 0; i < job->spec.parameter_count; i++)
        printf("softbond: fitted %s = %.9g\n", job->spec.parameters[i].key, job->best[i]);
    printf("softbond: RMS residual %.6g after %ld runs%s; fit.txt, fit_curve.csv and fit.png in %s\n", rms(job),
           job->evaluation, job->size > 1 ? " over the MPI ranks" : "", job->dir);
    plot(job);
}

int sb_cli_fit(int argc, char** argv) {
    static const char* const accepted[] = {"--output", "--threads", NULL};
    fit_job job = {0};
    sb_error err;
    if (sb_cli_parse(argc, argv, accepted, &job.args, &err) != SB_OK)
        return finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    if (job.args.help) {
        sb_cli_fit_usage(stdout);
        return finish(&job, SB_EXIT_OK);
    }
    if (sb_study_mpi_begin(&job.rank, &job.size, &err) != SB_OK) return finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    int code = SB_EXIT_OK;
    if (prepare(&job, &err) != SB_OK) code = SB_EXIT_INPUT;
    if (code == SB_EXIT_OK && open_evaluations(&job, &err) != SB_OK) code = SB_EXIT_FAILURE;
    if (code == SB_EXIT_OK && gather(&job, search(&job, &err), &err) != SB_OK) code = SB_EXIT_FAILURE;
    if (code == SB_EXIT_OK && job.rank == 0 && write_results(&job, &err) != SB_OK) code = SB_EXIT_FAILURE;
    if (code == SB_EXIT_OK) sb_study_remove_dir(job.run_dir);
    if (code != SB_EXIT_OK && job.rank == 0) sb_cli_fail(code, &err);
    if (code == SB_EXIT_OK && job.rank == 0) report(&job);
    sb_study_mpi_end(code);
    return finish(&job, code);
}
