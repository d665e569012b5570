/* A sweep case's row (see sweep_row.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/sweep_row.h"
#include "cli/log_table.h"
#include "cli/sweep_table.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

char* sb_sweep_header(const sb_sweep_spec* spec) {
    char* text = NULL;
    size_t size = 0;
    FILE* f = open_memstream(&text, &size);
    if (!f) return NULL;
    fputs("case", f);
    for (size_t a = 0; a < spec->axis_count; a++) {
        fputc(',', f);
        sb_csv_put(f, spec->axes[a].key);
    }
    for (size_t m = 0; m < spec->metric_count; m++) fprintf(f, ",%s", spec->metrics[m].name);
    fputs(",status,message", f);
    fclose(f);
    return text;
}

/* A log.csv column's last, largest or smallest value. */
static void column_metric(const sb_sweep_metric* m, const sb_log_table* log, char* out, size_t size) {
    long c = sb_log_table_column(log, m->column);
    if (c < 0 || log->row_count == 0) return;
    double value = sb_log_table_at(log, log->row_count - 1, (size_t)c);
    for (size_t r = 0; r < log->row_count && m->of != SB_OF_END; r++) {
        double x = sb_log_table_at(log, r, (size_t)c);
        if (m->of == SB_OF_MAX ? x > value : x < value) value = x;
    }
    snprintf(out, size, "%.17g", value);
}

static void vertex_metric(const sb_sweep_metric* m, const sb_log_table* positions, char* out, size_t size) {
    if ((size_t)m->vertex < positions->row_count && positions->column_count == 3)
        snprintf(out, size, "%.17g", sb_log_table_at(positions, (size_t)m->vertex, (size_t)m->axis));
}

/* A blow-up's step: the solver's message "step N (t = ...): ...". */
static void blowup_metric(const sb_study_outcome* outcome, char* out, size_t size) {
    const char* at = outcome->status == 3 ? strstr(outcome->message, "step ") : NULL;
    unsigned long long step;
    if (at && sscanf(at, "step %llu", &step) == 1) snprintf(out, size, "%llu", step);
}

static void put_metrics(FILE* f, const sb_sweep_spec* spec, const char* dir, const sb_study_outcome* outcome,
                        double seconds) {
    char path[4096];
    sb_error ignored;
    sb_log_table log = {0}, positions = {0};
    snprintf(path, sizeof path, "%s/log.csv", dir);
    if (sb_log_table_read(path, &log, &ignored) != SB_OK) sb_log_table_free(&log);
    snprintf(path, sizeof path, "%s/end_positions.csv", dir);
    if (sb_log_table_read(path, &positions, &ignored) != SB_OK) sb_log_table_free(&positions);
    for (size_t k = 0; k < spec->metric_count; k++) {
        const sb_sweep_metric* m = &spec->metrics[k];
        char text[64] = "";
        if (m->kind == SB_METRIC_COLUMN) column_metric(m, &log, text, sizeof text);
        if (m->kind == SB_METRIC_VERTEX) vertex_metric(m, &positions, text, sizeof text);
        if (m->kind == SB_METRIC_BLOWUP_STEP) blowup_metric(outcome, text, sizeof text);
        if (m->kind == SB_METRIC_WALL_TIME) snprintf(text, sizeof text, "%.6f", seconds);
        fprintf(f, ",%s", text);
    }
    sb_log_table_free(&log);
    sb_log_table_free(&positions);
}

char* sb_sweep_row(const sb_sweep_spec* spec, const sb_sweep_design* design, size_t c, const char* dir,
                   const sb_study_outcome* outcome, double seconds) {
    char* text = NULL;
    size_t size = 0;
    FILE* f = open_memstream(&text, &size);
    if (!f) return NULL;
    fprintf(f, "%zu", c);
    for (size_t a = 0; a < spec->axis_count; a++) {
        char number[32];
        fputc(',', f);
        sb_csv_put(f, sb_sweep_design_value(design, c, a, number, sizeof number));
    }
    put_metrics(f, spec, dir, outcome, seconds);
    fprintf(f, ",%d,", outcome->status);
    sb_csv_put(f, outcome->message);
    fclose(f);
    return text;
}
