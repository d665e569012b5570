/* The checked CSV tokenizer (see csv.h). */
#define _POSIX_C_SOURCE 200809L
#include "common/csv.h"
#include "common/error.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define CSV_FAIL(c, ...) sb_error_at(err, SB_ERR_PARSE, (c)->path, (c)->line_number, __VA_ARGS__)

sb_status sb_csv_open(sb_csv* csv, const char* path, sb_error* err) {
    *csv = (sb_csv){.path = path};
    if (!(csv->file = fopen(path, "rb"))) return sb_error_at(err, SB_ERR_IO, path, 0, "cannot open: %s", strerror(errno));
    struct stat info;
    if (fstat(fileno(csv->file), &info) != 0 || !S_ISREG(info.st_mode)) {
        bool directory = S_ISDIR(info.st_mode);
        sb_csv_close(csv);
        return sb_error_at(err, SB_ERR_IO, path, 0, "%s", directory ? "is a directory" : "not a regular file");
    }
    return SB_OK;
}

void sb_csv_close(sb_csv* csv) {
    if (csv->file) fclose(csv->file);
    free(csv->line);
    csv->file = NULL;
    csv->line = NULL;
}

static bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

static char* trim(char* s) {
    while (blank(*s)) s++;
    size_t n = strlen(s);
    while (n > 0 && blank(s[n - 1])) s[--n] = '\0';
    return s;
}

sb_status sb_csv_next(sb_csv* csv, bool* row, sb_error* err) {
    *row = false;
    for (;;) {
        errno = 0;
        ssize_t length = getline(&csv->line, &csv->capacity, csv->file);
        if (length < 0) {
            if (ferror(csv->file)) return CSV_FAIL(csv, "cannot read: %s", strerror(errno ? errno : EIO));
            return SB_OK;
        }
        csv->line_number++;
        if (memchr(csv->line, '\0', (size_t)length)) return CSV_FAIL(csv, "a NUL byte in the line");
        if (length > SB_CSV_MAX_LINE)
            return CSV_FAIL(csv, "the line is %zd bytes long, more than a row needs (at most %d)", length,
                            SB_CSV_MAX_LINE);
        char* text = trim(csv->line);
        if (*text == '\0') continue;
        csv->count = 0;
        for (char* field = text;;) {
            char* comma = strchr(field, ',');
            if (comma) *comma = '\0';
            if (csv->count == SB_CSV_MAX_FIELDS) return CSV_FAIL(csv, "more than %d columns", SB_CSV_MAX_FIELDS);
            csv->fields[csv->count++] = trim(field);
            if (strlen(csv->fields[csv->count - 1]) > SB_CSV_MAX_FIELD)
                return CSV_FAIL(csv, "column %d is %zu bytes long (at most %d)", csv->count,
                                strlen(csv->fields[csv->count - 1]), SB_CSV_MAX_FIELD);
            if (!comma) break;
            field = comma + 1;
        }
        *row = true;
        return SB_OK;
    }
}

sb_status sb_csv_number(const sb_csv* csv, int index, double* value, sb_error* err) {
    if (index >= csv->count) return CSV_FAIL(csv, "column %d: missing", index + 1);
    const char* field = csv->fields[index];
    char* end;
    errno = 0;
    *value = strtod(field, &end);
    if (end == field || *end != '\0')
        return CSV_FAIL(csv, "column %d: expected a number, got '%.40s'", index + 1, field);
    if (errno == ERANGE || !isfinite(*value))
        return CSV_FAIL(csv, "column %d: expected a finite number, got '%.40s'", index + 1, field);
    return SB_OK;
}

void sb_csv_joined(const sb_csv* csv, char* out, size_t capacity) {
    size_t n = 0;
    for (int i = 0; i < csv->count; i++)
        for (const char* c = i ? "," : ""; ; ) {
            for (; *c && n + 1 < capacity; c++) out[n++] = *c;
            for (const char* f = csv->fields[i]; *f && n + 1 < capacity; f++)
                if (!blank(*f)) out[n++] = *f;
            break;
        }
    if (capacity) out[n < capacity ? n : capacity - 1] = '\0';
}
