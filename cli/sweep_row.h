/* A sweep case's row of sweep.csv (sweep_table.h): the case, its values,
 * its metrics read from the run's folder, its exit status and message.
 *
 * A metric the run did not produce (a failed run's end positions, a column
 * log.csv lacks, the blow-up step of a run that did not blow up) is an
 * empty field. */
#ifndef SB_SWEEP_ROW_H
#define SB_SWEEP_ROW_H

#include "cli/study_case.h"
#include "cli/sweep_design.h"
#include "cli/sweep_spec.h"

/* "case,<keys>,<metric names>,status,message" (malloc'd). */
char* sb_sweep_header(const sb_sweep_spec* spec);
/* Case c's row (malloc'd, NULL when out of memory) from its run's folder. */
char* sb_sweep_row(const sb_sweep_spec* spec, const sb_sweep_design* design, size_t c, const char* dir,
                   const sb_study_outcome* outcome, double seconds);

#endif
