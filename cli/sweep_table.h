/* A sweep's results: DIR/sweep.csv, one row per finished case,
 *
 *     case,<each varied key>,<each metric>,status,message
 *
 * in the order the cases finished. The file is rewritten whole after each
 * case (written beside, then renamed: common/atomic_file.h), so it is a
 * whole CSV at every moment, even when the sweep is killed; --resume reads
 * it back and skips the cases it holds. */
#ifndef SB_SWEEP_TABLE_H
#define SB_SWEEP_TABLE_H

#include <stdbool.h>
#include <stdio.h>

#include "softbond/types.h"

typedef struct sb_sweep_table {
    char* path;
    char* header; /* without the newline */
    size_t case_count;
    char** rows;   /* [case]: its row (without the newline), or NULL while not done */
    size_t* order; /* the done cases in the order they finished */
    size_t done;
} sb_sweep_table;

/* A new table, or (resume) the one at path: its header must be `header`
 * and each row a case < case_count, once. */
sb_status sb_sweep_table_open(sb_sweep_table* table, const char* path, const char* header, size_t case_count,
                              bool resume, sb_error* err);
void sb_sweep_table_free(sb_sweep_table* table);
/* Takes the row of case c (a malloc'd string starting "c,"; a case the
 * table does not hold yet) and rewrites the file. */
sb_status sb_sweep_table_add(sb_sweep_table* table, size_t c, char* row, sb_error* err);

/* Splits a CSV line in place into at most max fields ("..." quoted, ""
 * for a quote); returns how many. */
size_t sb_csv_split(char* line, char** fields, size_t max);
/* Writes text as one CSV field: quoted when it holds a comma, a quote or a line break. */
void sb_csv_put(FILE* f, const char* text);

#endif
