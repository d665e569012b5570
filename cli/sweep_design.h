/* The cases of a sweep: for each case, the value of each varied key.
 *
 * grid: every combination, the last key varying fastest; zip: the i-th
 * values together; random: `samples` cases, each key uniform in its range
 * (in its logarithm on a log scale); latin: a Latin hypercube of `samples`
 * cases (each key's range cut into `samples` strata, each stratum used
 * once, a uniform point within it). The draws come from a counter-based
 * generator keyed by (seed, case, key), so a case's values depend on the
 * seed alone — never on the order the cases run in, nor on the ranks. */
#ifndef SB_SWEEP_DESIGN_H
#define SB_SWEEP_DESIGN_H

#include "cli/sweep_spec.h"

/* [case * axis_count + axis]: a list's item (its text), else a number. */
typedef struct sb_sweep_design {
    size_t case_count;
    size_t axis_count;
    const char** items; /* a list's item, or NULL */
    double* numbers;    /* a range's or a sample's value */
} sb_sweep_design;

sb_status sb_sweep_design_make(const sb_sweep_spec* spec, sb_sweep_design* design, sb_error* err);
void sb_sweep_design_free(sb_sweep_design* design);

/* The value of `axis` in case c as the CSV shows it (a number as %.17g, in buffer). */
const char* sb_sweep_design_value(const sb_sweep_design* design, size_t c, size_t axis, char* buffer, size_t size);
/* "key=value" for --set: the value through the axis's format, if any. */
void sb_sweep_design_set(const sb_sweep_spec* spec, const sb_sweep_design* design, size_t c, size_t axis, char* out,
                         size_t size);

#endif
