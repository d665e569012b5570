/* A sweep's charts, drawn from its finished sweep.csv with gnuplot:
 * DIR/charts.dat (the table as numbers: a list's item that is not a
 * number is its index in the list, an empty metric NaN), DIR/charts.gp
 * (the gnuplot script; `gnuplot charts.gp` in DIR draws them again), and
 * its PNGs: <metric>.png, each metric against the first varied key (the
 * points coloured by the second, if any), and stability.png with two keys
 * or more: the cases that ran to the end and those that failed, over the
 * first two keys. Without gnuplot, the script is written and a line says so. */
#ifndef SB_SWEEP_CHARTS_H
#define SB_SWEEP_CHARTS_H

#include "cli/sweep_spec.h"

sb_status sb_sweep_charts(const sb_sweep_spec* spec, const char* dir, sb_error* err);

#endif
