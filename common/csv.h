/* Private: the one checked CSV tokenizer of the numeric CSV readers (the
 * scripted haptic device's trajectory, --positions). A row is a line split
 * at commas, each field's surrounding blanks trimmed; blank lines are
 * skipped but counted, so every message names the file's own line. A NUL
 * byte, a line longer than SB_CSV_MAX_LINE, more than SB_CSV_MAX_FIELDS
 * fields or a field longer than SB_CSV_MAX_FIELD is refused with
 * "PATH:LINE: ..." (fgets into a fixed buffer read a 200 kB field as
 * several lines, and a NUL ended a line early, its rest unread). */
#ifndef SB_CSV_H
#define SB_CSV_H

#include "softbond/types.h"

#include <stddef.h>
#include <stdio.h>

enum { SB_CSV_MAX_LINE = 4096, SB_CSV_MAX_FIELDS = 32, SB_CSV_MAX_FIELD = 256 };

typedef struct sb_csv {
    const char* path;
    FILE* file;
    char* line;
    size_t capacity, line_number;
    int count;                        /* the row's fields */
    char* fields[SB_CSV_MAX_FIELDS]; /* into line */
} sb_csv;

/* Opens a regular file (a directory or a device is refused). */
sb_status sb_csv_open(sb_csv* csv, const char* path, sb_error* err);
void sb_csv_close(sb_csv* csv);
/* The next non-blank line into csv->fields: SB_OK with *row true, or at
 * the end *row false; an error names the line. */
sb_status sb_csv_next(sb_csv* csv, bool* row, sb_error* err);
/* Field `index` (from 0) as a finite number, the whole field; an error
 * names the line and the column (from 1). */
sb_status sb_csv_number(const sb_csv* csv, int index, double* value, sb_error* err);
/* The row with its blanks removed and the fields joined by commas ("x,y,z"), for a header. */
void sb_csv_joined(const sb_csv* csv, char* out, size_t capacity);

#endif
