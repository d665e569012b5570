/* A sweep file (`softbond sweep SWEEP.yaml`, docs/sweep.md): the base
 * scene and its overrides, the keys varied and how they combine into
 * cases, and the metrics recorded per case. Read whole and checked before
 * any case runs; every error is one line naming the file and line.
 *
 *     scene: hanging.yaml           # relative to this file
 *     set: [duration=0.5]           # overrides of every case (as --set)
 *     vary:
 *       - {key: dt, values: [1e-4, 2e-4]}
 *       - {key: bond.k, range: {from: 10, to: 1000, count: 5, scale: log}}
 *       - {key: handles, format: "[{vertices: [0], stiffness: %g}]", values: [1, 2]}
 *     combine: grid                 # grid, zip, random or latin
 *     samples: 20                   # random, latin: how many cases
 *     seed: 1                       # random, latin
 *     metrics:
 *       - {name: ke, column: kinetic, of: max}   # of: end (default), max, min
 *       - {name: fz, force: floor, axis: z}      # the column floor_fz
 *       - {name: z0, vertex: 0, axis: z}         # the end position
 *       - {name: blew_at, value: blowup_step}    # or wall_time
 *     keep_outputs: false */
#ifndef SB_SWEEP_SPEC_H
#define SB_SWEEP_SPEC_H

#include <stdbool.h>
#include <stddef.h>

#include "cli/study_yaml.h"

typedef enum sb_sweep_combine { SB_COMBINE_GRID, SB_COMBINE_ZIP, SB_COMBINE_RANDOM, SB_COMBINE_LATIN } sb_sweep_combine;

/* One varied key: a list of values (texts), or a range from..to of count
 * values (linear or logarithmic), which a sampled design draws within. */
typedef struct sb_sweep_axis {
    const char* key;
    const char* format;  /* NULL, or a printf format of one number: the --set value */
    const char** values; /* a list's items; NULL for a range */
    size_t count;        /* the list's length or the range's count (0 in a sampled design) */
    double from, to;
    bool log;
} sb_sweep_axis;

typedef enum sb_metric_kind {
    SB_METRIC_COLUMN,
    SB_METRIC_VERTEX,
    SB_METRIC_BLOWUP_STEP,
    SB_METRIC_WALL_TIME
} sb_metric_kind;
typedef enum sb_metric_of { SB_OF_END, SB_OF_MAX, SB_OF_MIN } sb_metric_of;

typedef struct sb_sweep_metric {
    const char* name;
    size_t line; /* where the file gives it, for messages */
    sb_metric_kind kind;
    char column[96]; /* SB_METRIC_COLUMN: log.csv's column */
    sb_metric_of of; /* SB_METRIC_COLUMN */
    long vertex;     /* SB_METRIC_VERTEX */
    int axis;        /* SB_METRIC_VERTEX: 0 x, 1 y, 2 z */
} sb_sweep_metric;

typedef struct sb_sweep_spec {
    sb_study_yaml yaml; /* owns every text below */
    char* scene;        /* the base scene's path */
    const char** sets;
    size_t set_count;
    sb_sweep_axis* axes;
    size_t axis_count;
    sb_sweep_combine combine;
    long samples;
    unsigned long seed;
    sb_sweep_metric* metrics;
    size_t metric_count;
    bool keep_outputs;
} sb_sweep_spec;

sb_status sb_sweep_spec_load(sb_sweep_spec* spec, const char* path, sb_error* err);
void sb_sweep_spec_free(sb_sweep_spec* spec);

/* Reads `key`/`format` of one varied key's map (shared with fit files):
 * format, when given, must hold exactly one number conversion (%g, %.6e,
 * %f ...) and no other '%' but "%%". */
sb_status sb_study_read_format(sb_study_yaml* y, const yaml_node_t* map, const char** format);
/* A scene key's dotted name (refused when no scene has it). */
sb_status sb_study_read_key(sb_study_yaml* y, const yaml_node_t* node, const char** key);
enum { SB_SWEEP_VALUE_SIZE = 4096 }; /* a formatted value's room */

/* The --set value of number x under format (NULL: x itself, %.17g). */
void sb_study_format_value(const char* format, double x, char* out, size_t size);

#endif
