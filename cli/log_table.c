/* A CSV of numbers with a header (see log_table.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/log_table.h"
#include "common/error.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static sb_status read_header(FILE* f, const char* path, sb_log_table* t, sb_error* err) {
    char* line = NULL;
    size_t size = 0;
    if (getline(&line, &size, f) < 0) {
        free(line);
        return sb_error_set(err, SB_ERR_PARSE, "%s:1: no header (column names)", path);
    }
    line[strcspn(line, "\r\n")] = '\0';
    sb_status status = SB_OK;
    for (char *save, *name = strtok_r(line, ",", &save); name && status == SB_OK; name = strtok_r(NULL, ",", &save)) {
        char** names = realloc(t->names, (t->column_count + 1) * sizeof *names);
        if (!names || !(names[t->column_count] = strdup(name)))
            status = sb_error_set(err, SB_ERR_NOMEM, "out of memory");
        if (names) t->names = names;
        if (status == SB_OK) t->column_count++;
    }
    free(line);
    return status;
}

static sb_status read_row(char* line, const char* path, size_t number, sb_log_table* t, double* out, sb_error* err) {
    char* p = line;
    for (size_t c = 0; c < t->column_count; c++) {
        char* end;
        out[c] = strtod(p, &end);
        bool last = c + 1 == t->column_count;
        if (end == p || (last ? (*end != '\0') : (*end != ',')))
            return sb_error_set(err, SB_ERR_PARSE, "%s:%zu: expected %zu numbers separated by commas", path, number,
                                t->column_count);
        p = end + 1;
    }
    return SB_OK;
}

static sb_status read_rows(FILE* f, const char* path, sb_log_table* t, sb_error* err) {
    char* line = NULL;
    size_t size = 0, capacity = 0;
    sb_status status = SB_OK;
    for (size_t number = 2; status == SB_OK && getline(&line, &size, f) >= 0; number++) {
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '\0') continue;
        if (t->row_count == capacity) {
            capacity = capacity ? 2 * capacity : 64;
            double* values = realloc(t->values, capacity * t->column_count * sizeof *values);
            if (!values) {
                status = sb_error_set(err, SB_ERR_NOMEM, "out of memory");
                break;
            }
            t->values = values;
        }
        status = read_row(line, path, number, t, t->values + t->row_count * t->column_count, err);
        if (status == SB_OK) t->row_count++;
    }
    free(line);
    return status;
}

sb_status sb_log_table_read(const char* path, sb_log_table* t, sb_error* err) {
    *t = (sb_log_table){0};
    FILE* f = fopen(path, "r");
    if (!f) return sb_error_set(err, SB_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
    sb_status status = read_header(f, path, t, err);
    if (status == SB_OK) status = read_rows(f, path, t, err);
    fclose(f);
    return status;
}

void sb_log_table_free(sb_log_table* t) {
    for (size_t c = 0; c < t->column_count; c++) free(t->names[c]);
    free(t->names);
    free(t->values);
    *t = (sb_log_table){0};
}

long sb_log_table_column(const sb_log_table* t, const char* name) {
    for (size_t c = 0; c < t->column_count; c++)
        if (strcmp(t->names[c], name) == 0) return (long)c;
    return -1;
}
