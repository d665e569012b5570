/* A sweep's charts (see sweep_charts.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/sweep_charts.h"
#include "cli/sweep_table.h"
#include "common/atomic_file.h"
#include "common/error.h"

#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

extern char** environ;

enum { MAX_FIELDS = 1024 };

/* A varied value as a number: itself, or its index in the axis's list. */
static double axis_number(const sb_sweep_axis* axis, const char* text) {
    char* end;
    double x = strtod(text, &end);
    if (end != text && *end == '\0') return x;
    for (size_t i = 0; axis->values && i < axis->count; i++)
        if (strcmp(axis->values[i], text) == 0) return (double)i;
    return 0.0 / 0.0;
}

static void put_row(FILE* out, const sb_sweep_spec* spec, char** fields, bool* drawn) {
    for (size_t a = 0; a < spec->axis_count; a++) fprintf(out, "%.17g ", axis_number(&spec->axes[a], fields[1 + a]));
    for (size_t m = 0; m < spec->metric_count; m++) {
        const char* text = fields[1 + spec->axis_count + m];
        fprintf(out, "%s ", text[0] ? text : "NaN");
        drawn[m] |= text[0] != '\0';
    }
    fprintf(out, "%s\n", fields[1 + spec->axis_count + spec->metric_count]);
}

/* charts.dat: the rows of sweep.csv as numbers; drawn[m]: whether metric m has a value. */
static sb_status write_data(const sb_sweep_spec* spec, const char* dir, bool* drawn, sb_error* err) {
    char path[4096];
    snprintf(path, sizeof path, "%s/sweep.csv", dir);
    FILE* in = fopen(path, "r");
    if (!in) return sb_error_set(err, SB_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
    snprintf(path, sizeof path, "%s/charts.dat", dir);
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) {
        fclose(in);
        return status;
    }
    char* line = NULL;
    size_t size = 0, expected = spec->axis_count + spec->metric_count + 3;
    char* fields[MAX_FIELDS];
    for (size_t number = 1; getline(&line, &size, in) >= 0; number++) {
        line[strcspn(line, "\r\n")] = '\0';
        if (number > 1 && sb_csv_split(line, fields, MAX_FIELDS) == expected) put_row(file.stream, spec, fields, drawn);
    }
    free(line);
    fclose(in);
    return sb_atomic_commit(&file, err);
}

/* Whether a list's items are text (integrator names): charted at their indices, named on the axis. */
static bool text_items(const sb_sweep_axis* axis) {
    for (size_t i = 0; axis->values && i < axis->count; i++) {
        char* end;
        strtod(axis->values[i], &end);
        if (end == axis->values[i] || *end != '\0') return true;
    }
    return false;
}

static void axis_settings(FILE* f, const sb_sweep_axis* axis, char which) {
    fprintf(f, "set %clabel \"%s\" noenhanced\n", which, axis->key);
    fprintf(f, axis->log ? "set logscale %c\n" : "unset logscale %c\n", which);
    if (!text_items(axis)) {
        fprintf(f, "set %ctics autofreq\n", which);
        return;
    }
    fprintf(f, "set %ctics (", which);
    for (size_t i = 0; i < axis->count; i++) {
        fputs(i ? ", \"" : "\"", f);
        for (const char* c = axis->values[i]; *c; c++) fprintf(f, *c == '"' || *c == '\\' ? "\\%c" : "%c", *c);
        fprintf(f, "\" %zu", i);
    }
    fprintf(f, ") noenhanced\n");
}

static void metric_chart(FILE* f, const sb_sweep_spec* spec, size_t m) {
    const char* name = spec->metrics[m].name;
    size_t column = spec->axis_count + m + 1;
    fprintf(f, "set output \"%s.png\"\nset title \"%s\" noenhanced\nset ylabel \"%s\" noenhanced\n", name, name, name);
    axis_settings(f, &spec->axes[0], 'x');
    fprintf(f, "unset logscale y\n");
    if (spec->axis_count >= 2)
        fprintf(f,
                "set cblabel \"%s\" noenhanced\nplot \"charts.dat\" using 1:%zu:2 with points pt 7 palette notitle\n",
                spec->axes[1].key, column);
    else
        fprintf(f, "plot \"charts.dat\" using 1:%zu with linespoints pt 7 notitle\n", column);
}

static void stability_chart(FILE* f, const sb_sweep_spec* spec) {
    size_t status = spec->axis_count + spec->metric_count + 1;
    fprintf(f,
            "set output \"stability.png\"\nset title \"stability: which cases ran to the end\"\n"
            "set offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05\nset format x \"%%g\"\nset format y \"%%g\"\n");
    axis_settings(f, &spec->axes[0], 'x');
    axis_settings(f, &spec->axes[1], 'y');
    fprintf(f,
            "plot \"charts.dat\" using 1:($%zu == 0 ? $2 : 1/0) with points pt 7 ps 1.5 lc rgb \"#2ca02c\" title "
            "\"ran\", \\\n"
            "     \"charts.dat\" using 1:($%zu == 3 ? $2 : 1/0) with points pt 2 ps 1.5 lc rgb \"#d62728\" title "
            "\"blew up (3)\", \\\n"
            "     \"charts.dat\" using 1:($%zu != 0 && $%zu != 3 ? $2 : 1/0) with points pt 6 ps 1.5 lc rgb "
            "\"#7f7f7f\" title "
            "\"other failure\"\n",
            status, status, status, status);
}

static sb_status write_script(const sb_sweep_spec* spec, const char* dir, const bool* drawn, sb_error* err) {
    char path[4096];
    snprintf(path, sizeof path, "%s/charts.gp", dir);
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    FILE* f = file.stream;
    fprintf(f, "# softbond sweep's charts from charts.dat (sweep.csv as numbers); run in this folder:\n"
               "#   gnuplot charts.gp\n"
               "set terminal pngcairo size 900,600 font \"sans,11\"\n"
               "set grid\nset key outside right top\n");
    for (size_t m = 0; m < spec->metric_count; m++)
        if (drawn[m]) metric_chart(f, spec, m); /* a metric no case has (no blow-up) has no chart */
    if (spec->axis_count >= 2) stability_chart(f, spec);
    return sb_atomic_commit(&file, err);
}

/* gnuplot charts.gp in dir; false when it could not run or failed. */
static bool run_gnuplot(const char* dir) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    pid_t pid;
    /* gnuplot writes its PNGs in the current folder: a shell cd's there */
    char* const shell[] = {"sh", "-c", "cd \"$0\" && exec gnuplot charts.gp", (char*)dir, NULL};
    int code = posix_spawnp(&pid, "sh", &actions, NULL, shell, environ);
    posix_spawn_file_actions_destroy(&actions);
    int wait_status = 0;
    if (code == 0)
        while (waitpid(pid, &wait_status, 0) < 0 && errno == EINTR) continue;
    return code == 0 && WIFEXITED(wait_status) && WEXITSTATUS(wait_status) == 0;
}

sb_status sb_sweep_charts(const sb_sweep_spec* spec, const char* dir, sb_error* err) {
    bool* drawn = calloc(spec->metric_count + 1, sizeof *drawn);
    if (!drawn) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    sb_status status = write_data(spec, dir, drawn, err);
    if (status == SB_OK) status = write_script(spec, dir, drawn, err);
    free(drawn);
    if (status == SB_OK && !run_gnuplot(dir))
        fprintf(stderr, "softbond: %s/charts.gp: gnuplot did not draw the charts (is gnuplot-nox installed?)\n", dir);
    return status;
}
