/* A CSV of numbers with a header, as `softbond run` writes log.csv and a
 * fit's target curve is given: read whole, columns looked up by name. */
#ifndef SB_LOG_TABLE_H
#define SB_LOG_TABLE_H

#include <stddef.h>

#include "softbond/types.h"

typedef struct sb_log_table {
    char** names;
    size_t column_count;
    double* values; /* [row * column_count + column] */
    size_t row_count;
} sb_log_table;

/* Fails naming the file and line: no header, a row with another count of
 * fields, a field that is not a number. */
sb_status sb_log_table_read(const char* path, sb_log_table* table, sb_error* err);
void sb_log_table_free(sb_log_table* table);
/* The column's index, or -1. */
long sb_log_table_column(const sb_log_table* table, const char* name);
static inline double sb_log_table_at(const sb_log_table* table, size_t row, size_t column) {
    return table->values[row * table->column_count + column];
}

#endif
