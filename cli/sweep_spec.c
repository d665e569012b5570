/* A sweep file (see sweep_spec.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/sweep_spec.h"
#include "common/error.h"
#include "scenes/scene.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MAX_CASES = 1000000 };

/* Whether format holds one conversion [flags][width][.precision]{e,E,f,g,G}
 * and no other '%' but "%%". */
static bool one_number_conversion(const char* format) {
    int conversions = 0;
    for (const char* p = format; *p; p++) {
        if (*p != '%') continue;
        if (p[1] == '%') {
            p++;
            continue;
        }
        p++;
        while (*p && strchr("-+ #0", *p)) p++;
        while (isdigit((unsigned char)*p)) p++;
        if (*p == '.')
            for (p++; isdigit((unsigned char)*p);) p++;
        if (!*p || !strchr("eEfgG", *p)) return false;
        conversions++;
    }
    return conversions == 1;
}

sb_status sb_study_read_format(sb_study_yaml* y, const yaml_node_t* map, const char** format) {
    *format = NULL;
    yaml_node_t* node = sb_study_yaml_get(y, map, "format");
    if (!node) return SB_OK;
    sb_status status = sb_study_yaml_text(y, node, "format", format);
    if (status == SB_OK && !one_number_conversion(*format))
        return sb_study_yaml_fail(y, node, "format: expected one number conversion (%%g, %%.6e, %%f), got '%s'",
                                  *format);
    return status;
}

sb_status sb_study_read_key(sb_study_yaml* y, const yaml_node_t* node, const char** key) {
    sb_scene_key found;
    sb_status status = sb_study_yaml_text(y, node, "key", key);
    if (status == SB_OK && !sb_scene_key_find(*key, &found))
        return sb_study_yaml_fail(y, node, "key: no scene key '%s' (softbond keys lists them)", *key);
    return status;
}

void sb_study_format_value(const char* format, double x, char* out, size_t size) {
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
    snprintf(out, size, format ? format : "%.17g", x); /* format checked by one_number_conversion */
#pragma GCC diagnostic pop
}

static sb_status read_list(sb_sweep_spec* spec, sb_sweep_axis* axis, const yaml_node_t* node) {
    sb_study_yaml* y = &spec->yaml;
    sb_status status = sb_study_yaml_sequence(y, node, "values");
    if (status != SB_OK) return status;
    axis->count = sb_study_yaml_count(node);
    axis->values = calloc(axis->count, sizeof *axis->values);
    if (!axis->values) return sb_error_set(y->err, SB_ERR_NOMEM, "out of memory");
    for (size_t i = 0; i < axis->count && status == SB_OK; i++) {
        yaml_node_t* item = sb_study_yaml_item(y, node, i);
        status = sb_study_yaml_text(y, item, "values", &axis->values[i]);
        double number;
        if (status == SB_OK && axis->format) status = sb_study_yaml_number(y, item, "values (with format)", &number);
    }
    return status;
}

static sb_status read_range(sb_sweep_spec* spec, sb_sweep_axis* axis, const yaml_node_t* node, bool sampled) {
    sb_study_yaml* y = &spec->yaml;
    static const char* const known[] = {"from", "to", "count", "scale", NULL};
    static const char* const scales[] = {"linear", "log", NULL};
    sb_status status = sb_study_yaml_map(y, node, "range");
    if (status == SB_OK) status = sb_study_yaml_check_keys(y, node, known);
    yaml_node_t *from = status == SB_OK ? sb_study_yaml_get(y, node, "from") : NULL,
                *to = status == SB_OK ? sb_study_yaml_get(y, node, "to") : NULL;
    if (status == SB_OK && (!from || !to)) return sb_study_yaml_fail(y, node, "range: needs from and to");
    if (status == SB_OK) status = sb_study_yaml_number(y, from, "range.from", &axis->from);
    if (status == SB_OK) status = sb_study_yaml_number(y, to, "range.to", &axis->to);
    yaml_node_t* scale = status == SB_OK ? sb_study_yaml_get(y, node, "scale") : NULL;
    int log_scale = 0;
    if (scale) status = sb_study_yaml_choice(y, scale, "range.scale", scales, &log_scale);
    axis->log = log_scale == 1;
    if (status == SB_OK && axis->log && !(axis->from > 0.0 && axis->to > 0.0))
        return sb_study_yaml_fail(y, node, "range: a log scale needs from and to > 0");
    yaml_node_t* count = status == SB_OK ? sb_study_yaml_get(y, node, "count") : NULL;
    if (status != SB_OK) return status;
    if (sampled && count)
        return sb_study_yaml_fail(y, count, "range.count: not with a sampled design (samples says how many cases)");
    if (!sampled && !count) return sb_study_yaml_fail(y, node, "range: needs count (with combine grid or zip)");
    long n = 0;
    if (count) status = sb_study_yaml_whole(y, count, "range.count", 1, MAX_CASES, &n);
    if (status == SB_OK && n == 1 && axis->from != axis->to)
        return sb_study_yaml_fail(y, count, "range.count: 1 value cannot span from %g to %g", axis->from, axis->to);
    axis->count = (size_t)n;
    return status;
}

static bool sampled(const sb_sweep_spec* spec) {
    return spec->combine == SB_COMBINE_RANDOM || spec->combine == SB_COMBINE_LATIN;
}

static sb_status read_axis(sb_sweep_spec* spec, sb_sweep_axis* axis, const yaml_node_t* node) {
    sb_study_yaml* y = &spec->yaml;
    static const char* const known[] = {"key", "format", "values", "range", NULL};
    sb_status status = sb_study_yaml_map(y, node, "vary item");
    if (status == SB_OK) status = sb_study_yaml_check_keys(y, node, known);
    yaml_node_t* key = status == SB_OK ? sb_study_yaml_get(y, node, "key") : NULL;
    if (status == SB_OK && !key) return sb_study_yaml_fail(y, node, "vary item: needs key (a scene key, as --set)");
    if (status == SB_OK) status = sb_study_read_key(y, key, &axis->key);
    if (status == SB_OK) status = sb_study_read_format(y, node, &axis->format);
    if (status != SB_OK) return status;
    yaml_node_t *values = sb_study_yaml_get(y, node, "values"), *range = sb_study_yaml_get(y, node, "range");
    if (!values == !range)
        return sb_study_yaml_fail(y, node, "vary item '%s': give values or range, one of them", axis->key);
    if (values && sampled(spec))
        return sb_study_yaml_fail(y, values, "values: a sampled design (random, latin) draws within a range");
    return values ? read_list(spec, axis, values) : read_range(spec, axis, range, sampled(spec));
}

/* zip: every axis as long as the first. */
static sb_status check_zip(sb_sweep_spec* spec, const yaml_node_t* vary) {
    for (size_t a = 1; a < spec->axis_count; a++)
        if (spec->axes[a].count != spec->axes[0].count)
            return sb_study_yaml_fail(&spec->yaml, sb_study_yaml_item(&spec->yaml, vary, a),
                                      "combine zip: '%s' has %zu values, '%s' %zu (each the same)", spec->axes[a].key,
                                      spec->axes[a].count, spec->axes[0].key, spec->axes[0].count);
    return SB_OK;
}

static sb_status read_vary(sb_sweep_spec* spec, const yaml_node_t* vary) {
    sb_study_yaml* y = &spec->yaml;
    sb_status status = sb_study_yaml_sequence(y, vary, "vary");
    if (status != SB_OK) return status;
    spec->axis_count = sb_study_yaml_count(vary);
    spec->axes = calloc(spec->axis_count, sizeof *spec->axes);
    if (!spec->axes) return sb_error_set(y->err, SB_ERR_NOMEM, "out of memory");
    for (size_t a = 0; a < spec->axis_count && status == SB_OK; a++)
        status = read_axis(spec, &spec->axes[a], sb_study_yaml_item(y, vary, a));
    if (status == SB_OK && spec->combine == SB_COMBINE_ZIP) status = check_zip(spec, vary);
    double cases = 1.0;
    for (size_t a = 0; a < spec->axis_count && spec->combine == SB_COMBINE_GRID; a++)
        cases *= (double)spec->axes[a].count;
    if (status == SB_OK && cases > MAX_CASES)
        return sb_study_yaml_fail(y, vary, "vary: the grid has %.0f cases, more than %d", cases, MAX_CASES);
    return status;
}

static const char* const metric_keys[] = {"name", "column", "force", "vertex", "axis", "of", "value", NULL};

static sb_status read_axis_letter(sb_study_yaml* y, const yaml_node_t* map, int* axis) {
    static const char* const letters[] = {"x", "y", "z", NULL};
    yaml_node_t* node = sb_study_yaml_get(y, map, "axis");
    if (!node) return sb_study_yaml_fail(y, map, "metric: needs axis (x, y or z)");
    return sb_study_yaml_choice(y, node, "axis", letters, axis);
}

/* What a metric measures: exactly one of column, force, vertex, value. */
static sb_status read_metric_source(sb_study_yaml* y, sb_sweep_metric* m, const yaml_node_t* map) {
    yaml_node_t *column = sb_study_yaml_get(y, map, "column"), *force = sb_study_yaml_get(y, map, "force"),
                *vertex = sb_study_yaml_get(y, map, "vertex"), *value = sb_study_yaml_get(y, map, "value");
    if ((column != NULL) + (force != NULL) + (vertex != NULL) + (value != NULL) != 1)
        return sb_study_yaml_fail(y, map, "metric '%s': give one of column, force, vertex or value", m->name);
    const char* text;
    sb_status status = SB_OK;
    if (column || force) {
        status = sb_study_yaml_text(y, column ? column : force, column ? "column" : "force", &text);
        if (status == SB_OK && force) status = read_axis_letter(y, map, &m->axis);
        m->kind = SB_METRIC_COLUMN;
        if (column)
            snprintf(m->column, sizeof m->column, "%.80s", text);
        else
            snprintf(m->column, sizeof m->column, "%.80s_f%c", text, "xyz"[m->axis]);
        return status;
    }
    if (vertex) {
        m->kind = SB_METRIC_VERTEX;
        status = sb_study_yaml_whole(y, vertex, "vertex", 0, 0x7fffffff, &m->vertex);
        return status == SB_OK ? read_axis_letter(y, map, &m->axis) : status;
    }
    static const char* const values[] = {"blowup_step", "wall_time", NULL};
    int which;
    status = sb_study_yaml_choice(y, value, "value", values, &which);
    m->kind = which == 0 ? SB_METRIC_BLOWUP_STEP : SB_METRIC_WALL_TIME;
    return status;
}

static sb_status read_metric(sb_sweep_spec* spec, sb_sweep_metric* m, const yaml_node_t* map) {
    sb_study_yaml* y = &spec->yaml;
    sb_status status = sb_study_yaml_map(y, map, "metric");
    if (status == SB_OK) status = sb_study_yaml_check_keys(y, map, metric_keys);
    yaml_node_t* name = status == SB_OK ? sb_study_yaml_get(y, map, "name") : NULL;
    if (status == SB_OK && !name) return sb_study_yaml_fail(y, map, "metric: needs name (its CSV column)");
    if (status == SB_OK) status = sb_study_yaml_text(y, name, "name", &m->name);
    m->line = map->start_mark.line + 1;
    if (status == SB_OK && strpbrk(m->name, ",\"\n"))
        return sb_study_yaml_fail(y, name, "name: no commas or quotes in a column name");
    if (status == SB_OK) status = read_metric_source(y, m, map);
    yaml_node_t* of = status == SB_OK ? sb_study_yaml_get(y, map, "of") : NULL;
    if (of && m->kind != SB_METRIC_COLUMN) return sb_study_yaml_fail(y, of, "of: only with column or force");
    static const char* const ofs[] = {"end", "max", "min", NULL};
    int which = 0;
    if (of) status = sb_study_yaml_choice(y, of, "of", ofs, &which);
    m->of = (sb_metric_of)which;
    return status;
}

static sb_status read_metrics(sb_sweep_spec* spec, const yaml_node_t* node) {
    sb_study_yaml* y = &spec->yaml;
    sb_status status = sb_study_yaml_sequence(y, node, "metrics");
    if (status != SB_OK) return status;
    spec->metric_count = sb_study_yaml_count(node);
    spec->metrics = calloc(spec->metric_count, sizeof *spec->metrics);
    if (!spec->metrics) return sb_error_set(y->err, SB_ERR_NOMEM, "out of memory");
    for (size_t i = 0; i < spec->metric_count && status == SB_OK; i++)
        status = read_metric(spec, &spec->metrics[i], sb_study_yaml_item(y, node, i));
    return status;
}

static sb_status read_sets(sb_sweep_spec* spec, const yaml_node_t* node) {
    sb_study_yaml* y = &spec->yaml;
    sb_status status = sb_study_yaml_sequence(y, node, "set");
    if (status != SB_OK) return status;
    spec->set_count = sb_study_yaml_count(node);
    spec->sets = calloc(spec->set_count, sizeof *spec->sets);
    if (!spec->sets) return sb_error_set(y->err, SB_ERR_NOMEM, "out of memory");
    for (size_t i = 0; i < spec->set_count && status == SB_OK; i++) {
        yaml_node_t* item = sb_study_yaml_item(y, node, i);
        status = sb_study_yaml_text(y, item, "set", &spec->sets[i]);
        if (status == SB_OK && !strchr(spec->sets[i], '='))
            return sb_study_yaml_fail(y, item, "set: expected key=value, got '%s'", spec->sets[i]);
    }
    return status;
}

static sb_status read_design(sb_sweep_spec* spec, const yaml_node_t* root) {
    sb_study_yaml* y = &spec->yaml;
    static const char* const combines[] = {"grid", "zip", "random", "latin", NULL};
    yaml_node_t *combine = sb_study_yaml_get(y, root, "combine"), *samples = sb_study_yaml_get(y, root, "samples"),
                *seed = sb_study_yaml_get(y, root, "seed");
    int which = 0;
    sb_status status = combine ? sb_study_yaml_choice(y, combine, "combine", combines, &which) : SB_OK;
    spec->combine = (sb_sweep_combine)which;
    if (status != SB_OK) return status;
    if (!sampled(spec) && (samples || seed))
        return sb_study_yaml_fail(y, samples ? samples : seed, "%s: only with combine random or latin",
                                  samples ? "samples" : "seed");
    if (sampled(spec) && !samples) return sb_study_yaml_fail(y, combine, "combine %s: needs samples", combines[which]);
    long n = 1;
    spec->samples = 0;
    if (samples) status = sb_study_yaml_whole(y, samples, "samples", 1, MAX_CASES, &spec->samples);
    if (status == SB_OK && seed) status = sb_study_yaml_whole(y, seed, "seed", 0, 0x7fffffffL, &n);
    spec->seed = (unsigned long)n;
    return status;
}

static sb_status read_spec(sb_sweep_spec* spec) {
    sb_study_yaml* y = &spec->yaml;
    static const char* const known[] = {"scene", "set",     "vary",         "combine", "samples",
                                        "seed",  "metrics", "keep_outputs", NULL};
    yaml_node_t* root = sb_study_yaml_root(y);
    sb_status status = sb_study_yaml_check_keys(y, root, known);
    yaml_node_t *scene = sb_study_yaml_get(y, root, "scene"), *vary = sb_study_yaml_get(y, root, "vary"),
                *metrics = sb_study_yaml_get(y, root, "metrics"), *set = sb_study_yaml_get(y, root, "set"),
                *keep = sb_study_yaml_get(y, root, "keep_outputs");
    if (status == SB_OK && (!scene || !vary))
        return sb_study_yaml_fail(y, root, "needs %s",
                                  !scene ? "scene (the base scene's file)" : "vary (the keys varied)");
    const char* name;
    if (status == SB_OK) status = sb_study_yaml_text(y, scene, "scene", &name);
    if (status == SB_OK && !(spec->scene = sb_study_yaml_relative(y, name)))
        return sb_error_set(y->err, SB_ERR_NOMEM, "out of memory");
    if (status == SB_OK && set) status = read_sets(spec, set);
    if (status == SB_OK) status = read_design(spec, root);
    if (status == SB_OK) status = read_vary(spec, vary);
    if (status == SB_OK && metrics) status = read_metrics(spec, metrics);
    if (status == SB_OK && keep) status = sb_study_yaml_bool(y, keep, "keep_outputs", &spec->keep_outputs);
    return status;
}

sb_status sb_sweep_spec_load(sb_sweep_spec* spec, const char* path, sb_error* err) {
    *spec = (sb_sweep_spec){0};
    sb_status status = sb_study_yaml_load(&spec->yaml, path, err);
    return status == SB_OK ? read_spec(spec) : status;
}

void sb_sweep_spec_free(sb_sweep_spec* spec) {
    for (size_t a = 0; a < spec->axis_count; a++) free(spec->axes[a].values);
    free(spec->axes);
    free(spec->metrics);
    free(spec->sets);
    free(spec->scene);
    sb_study_yaml_free(&spec->yaml);
    *spec = (sb_sweep_spec){0};
}
