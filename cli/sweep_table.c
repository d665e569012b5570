/* A sweep's results (see sweep_table.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/sweep_table.h"
#include "common/atomic_file.h"
#include "common/error.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

size_t sb_csv_split(char* line, char** fields, size_t max) {
    size_t n = 0;
    char* p = line;
    while (n < max) {
        char* out = p;
        fields[n++] = p;
        if (*p == '"') {
            char* in = p + 1;
            for (; *in && !(in[0] == '"' && in[1] != '"'); in++) {
                if (in[0] == '"') in++;
                *out++ = *in;
            }
            p = *in ? in + 1 : in;
        } else {
            while (*p && *p != ',') *out++ = *p++;
        }
        bool more = *p == ',';
        *out = '\0';
        if (!more) break;
        p++;
    }
    return n;
}

void sb_csv_put(FILE* f, const char* text) {
    if (!strpbrk(text, ",\"\r\n")) {
        fputs(text, f);
        return;
    }
    fputc('"', f);
    for (const char* p = text; *p; p++) {
        if (*p == '"') fputc('"', f);
        fputc(*p == '\n' || *p == '\r' ? ' ' : *p, f);
    }
    fputc('"', f);
}

static void keep_row(sb_sweep_table* t, size_t c, char* row) {
    t->rows[c] = row;
    t->order[t->done++] = c;
}

/* One row of a resumed file: its case, in range and new. */
static sb_status read_row(sb_sweep_table* t, const char* line, size_t number, sb_error* err) {
    char* end;
    errno = 0;
    unsigned long long c = strtoull(line, &end, 10);
    if (end == line || *end != ',' || errno || c >= t->case_count)
        return sb_error_set(err, SB_ERR_PARSE, "%s:%zu: expected a case from 0 to %zu first, got '%.40s'", t->path,
                            number, t->case_count - 1, line);
    if (t->rows[c]) return sb_error_set(err, SB_ERR_PARSE, "%s:%zu: case %llu a second time", t->path, number, c);
    char* row = strdup(line);
    if (!row) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    keep_row(t, (size_t)c, row);
    return SB_OK;
}

static sb_status read_back(sb_sweep_table* t, sb_error* err) {
    FILE* f = fopen(t->path, "r");
    if (!f) return sb_error_set(err, SB_ERR_IO, "--resume: %s: cannot read: %s", t->path, strerror(errno));
    char* line = NULL;
    size_t size = 0;
    sb_status status = SB_OK;
    for (size_t number = 1; status == SB_OK && getline(&line, &size, f) >= 0; number++) {
        line[strcspn(line, "\r\n")] = '\0';
        if (number == 1 && strcmp(line, t->header) != 0)
            status =
                sb_error_set(err, SB_ERR_PARSE, "%s:1: not this sweep's header: expected '%.200s'", t->path, t->header);
        else if (number > 1 && line[0])
            status = read_row(t, line, number, err);
    }
    free(line);
    fclose(f);
    return status;
}

static sb_status rewrite(sb_sweep_table* t, sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, t->path, err);
    if (status != SB_OK) return status;
    fprintf(file.stream, "%s\n", t->header);
    for (size_t k = 0; k < t->done; k++) fprintf(file.stream, "%s\n", t->rows[t->order[k]]);
    return sb_atomic_commit(&file, err);
}

sb_status sb_sweep_table_open(sb_sweep_table* t, const char* path, const char* header, size_t case_count, bool resume,
                              sb_error* err) {
    *t = (sb_sweep_table){.case_count = case_count};
    t->path = strdup(path);
    t->header = strdup(header);
    t->rows = calloc(case_count ? case_count : 1, sizeof *t->rows);
    t->order = calloc(case_count ? case_count : 1, sizeof *t->order);
    if (!t->path || !t->header || !t->rows || !t->order) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    return resume ? read_back(t, err) : rewrite(t, err);
}

void sb_sweep_table_free(sb_sweep_table* t) {
    for (size_t c = 0; c < t->case_count && t->rows; c++) free(t->rows[c]);
    free(t->rows);
    free(t->order);
    free(t->path);
    free(t->header);
    *t = (sb_sweep_table){0};
}

sb_status sb_sweep_table_add(sb_sweep_table* t, size_t c, char* row, sb_error* err) {
    keep_row(t, c, row);
    return rewrite(t, err);
}
