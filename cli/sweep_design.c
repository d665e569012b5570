/* The cases of a sweep (see sweep_design.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/sweep_design.h"
#include "common/error.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* SplitMix64's finalizer: a well-mixed 64-bit word from a counter. */
static uint64_t mix(uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* A uniform number in [0, 1) keyed by (seed, stream, index). */
static double uniform(unsigned long seed, uint64_t stream, uint64_t index) {
    uint64_t word = mix(mix(mix((uint64_t)seed) ^ stream) ^ index);
    return (double)(word >> 11) * 0x1.0p-53;
}

/* The point at fraction u in [0, 1] of the axis's range. */
static double along(const sb_sweep_axis* axis, double u) {
    if (axis->log) return axis->from * pow(axis->to / axis->from, u); /* 10 * 10000^0.25 is 100 exactly */
    return axis->from + u * (axis->to - axis->from);
}

/* Value i of a grid or zip axis (a range's ends exact). */
static double range_value(const sb_sweep_axis* axis, size_t i) {
    if (axis->count == 1 || i == 0) return axis->from;
    if (i + 1 == axis->count) return axis->to;
    return along(axis, (double)i / (double)(axis->count - 1));
}

/* Each axis's index of case c in a grid (the last axis fastest) or a zip. */
static size_t axis_index(const sb_sweep_spec* spec, size_t c, size_t a) {
    if (spec->combine == SB_COMBINE_ZIP) return c;
    size_t stride = 1;
    for (size_t b = a + 1; b < spec->axis_count; b++) stride *= spec->axes[b].count;
    return c / stride % spec->axes[a].count;
}

/* A Latin hypercube's strata of one axis: a seeded Fisher-Yates shuffle of 0..n-1. */
static void shuffle(size_t* order, size_t n, unsigned long seed, uint64_t axis) {
    for (size_t i = 0; i < n; i++) order[i] = i;
    for (size_t i = n; i > 1; i--) {
        size_t j = (size_t)(uniform(seed, 2 * axis + 1, i) * (double)i);
        size_t t = order[i - 1];
        order[i - 1] = order[j];
        order[j] = t;
    }
}

static void put(sb_sweep_design* d, size_t c, size_t a, const char* item, double number) {
    d->items[c * d->axis_count + a] = item;
    d->numbers[c * d->axis_count + a] = number;
}

static void fill_listed(const sb_sweep_spec* spec, sb_sweep_design* d) {
    for (size_t c = 0; c < d->case_count; c++)
        for (size_t a = 0; a < spec->axis_count; a++) {
            const sb_sweep_axis* axis = &spec->axes[a];
            size_t i = axis_index(spec, c, a);
            put(d, c, a, axis->values ? axis->values[i] : NULL, axis->values ? 0.0 : range_value(axis, i));
        }
}

static sb_status fill_sampled(const sb_sweep_spec* spec, sb_sweep_design* d, sb_error* err) {
    size_t* order = malloc(d->case_count * sizeof *order);
    if (!order) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    for (size_t a = 0; a < spec->axis_count; a++) {
        if (spec->combine == SB_COMBINE_LATIN) shuffle(order, d->case_count, spec->seed, a);
        for (size_t c = 0; c < d->case_count; c++) {
            double u = uniform(spec->seed, 2 * (uint64_t)a, c);
            if (spec->combine == SB_COMBINE_LATIN) u = ((double)order[c] + u) / (double)d->case_count;
            put(d, c, a, NULL, along(&spec->axes[a], u));
        }
    }
    free(order);
    return SB_OK;
}

static size_t case_count(const sb_sweep_spec* spec) {
    if (spec->combine == SB_COMBINE_RANDOM || spec->combine == SB_COMBINE_LATIN) return (size_t)spec->samples;
    if (spec->combine == SB_COMBINE_ZIP) return spec->axes[0].count;
    size_t n = 1;
    for (size_t a = 0; a < spec->axis_count; a++) n *= spec->axes[a].count;
    return n;
}

sb_status sb_sweep_design_make(const sb_sweep_spec* spec, sb_sweep_design* d, sb_error* err) {
    *d = (sb_sweep_design){.case_count = case_count(spec), .axis_count = spec->axis_count};
    size_t cells = d->case_count * d->axis_count;
    d->items = calloc(cells ? cells : 1, sizeof *d->items);
    d->numbers = calloc(cells ? cells : 1, sizeof *d->numbers);
    if (!d->items || !d->numbers) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    if (spec->combine == SB_COMBINE_GRID || spec->combine == SB_COMBINE_ZIP) {
        fill_listed(spec, d);
        return SB_OK;
    }
    return fill_sampled(spec, d, err);
}

void sb_sweep_design_free(sb_sweep_design* d) {
    free(d->items);
    free(d->numbers);
    *d = (sb_sweep_design){0};
}

const char* sb_sweep_design_value(const sb_sweep_design* d, size_t c, size_t axis, char* buffer, size_t size) {
    size_t k = c * d->axis_count + axis;
    if (d->items[k]) return d->items[k];
    snprintf(buffer, size, "%.17g", d->numbers[k]);
    return buffer;
}

void sb_sweep_design_set(const sb_sweep_spec* spec, const sb_sweep_design* d, size_t c, size_t axis, char* out,
                         size_t size) {
    const sb_sweep_axis* a = &spec->axes[axis];
    char number[32], formatted[SB_SWEEP_VALUE_SIZE];
    const char* value = sb_sweep_design_value(d, c, axis, number, sizeof number);
    if (a->format) sb_study_format_value(a->format, strtod(value, NULL), formatted, sizeof formatted);
    snprintf(out, size, "%s=%s", a->key, a->format ? formatted : value);
}
