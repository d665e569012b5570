/* The positions CSV reader (see positions_csv.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/positions_csv.h"
#include "common/error.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct csv_reader {
    const char* path;
    FILE* file;
    char* line;
    size_t capacity;
    size_t line_number;
    sb_error* err;
} csv_reader;

/* "PATH:LINE: message" at the reader's current line. */
#define CSV_FAIL(r, ...) sb_error_at((r)->err, SB_ERR_PARSE, (r)->path, (r)->line_number, __VA_ARGS__)

static bool is_blank(const char* s) {
    for (; *s; s++)
        if (!isspace((unsigned char)*s)) return false;
    return true;
}

/* The next non-blank line without its line ending; false at the end.
 * *nul when the line holds a NUL byte (which would end it early). */
static bool next_line(csv_reader* r, bool* nul) {
    for (;;) {
        ssize_t length = getline(&r->line, &r->capacity, r->file);
        r->line_number++;
        if (length < 0) return false;
        *nul = memchr(r->line, '\0', (size_t)length) != NULL;
        r->line[strcspn(r->line, "\r\n")] = '\0';
        if (*nul || !is_blank(r->line)) return true;
    }
}

static bool is_header(const char* line) {
    char compact[16];
    size_t n = 0;
    for (; *line && n + 1 < sizeof compact; line++)
        if (!isspace((unsigned char)*line)) compact[n++] = *line;
    compact[n] = '\0';
    return *line == '\0' && strcmp(compact, "x,y,z") == 0;
}

/* Three comma-separated numbers and nothing else. */
static sb_status parse_row(const csv_reader* r, double* xyz) {
    const char* p = r->line;
    for (int c = 0; c < 3; c++) {
        char* end;
        xyz[c] = strtod(p, &end);
        while (isspace((unsigned char)*end)) end++;
        bool separated = c < 2 ? *end == ',' : *end == '\0';
        if (end == p || !separated) return CSV_FAIL(r, "expected three numbers x,y,z, got '%.60s'", r->line);
        if (!isfinite(xyz[c])) return CSV_FAIL(r, "non-finite number in '%.60s'", r->line);
        p = end + 1;
    }
    return SB_OK;
}

static sb_status read_rows(csv_reader* r, uint32_t vertex_count, double* out) {
    bool nul = false;
    if (!next_line(r, &nul)) return CSV_FAIL(r, "empty file: expected the header 'x,y,z'");
    if (nul) return CSV_FAIL(r, "a NUL byte in the line");
    if (!is_header(r->line)) return CSV_FAIL(r, "expected the header 'x,y,z', got '%.60s'", r->line);
    uint32_t rows = 0;
    while (next_line(r, &nul)) {
        if (nul) return CSV_FAIL(r, "a NUL byte in the line");
        if (rows == vertex_count) return CSV_FAIL(r, "more rows than the mesh's %u vertices", vertex_count);
        sb_status status = parse_row(r, &out[3 * (size_t)rows]);
        if (status != SB_OK) return status;
        rows++;
    }
    if (ferror(r->file)) return CSV_FAIL(r, "read error: %s", strerror(errno));
    if (rows < vertex_count) return CSV_FAIL(r, "%u rows, but the mesh has %u vertices", rows, vertex_count);
    return SB_OK;
}

sb_status sb_positions_read(const char* path, uint32_t vertex_count, double* out, sb_error* err) {
    csv_reader r = {.path = path, .file = fopen(path, "rb"), .err = err};
    if (!r.file) return sb_error_set(err, SB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat info;
    if (fstat(fileno(r.file), &info) == 0 && S_ISDIR(info.st_mode)) {
        fclose(r.file);
        return sb_error_set(err, SB_ERR_IO, "%s: is a directory", path);
    }
    sb_status status = read_rows(&r, vertex_count, out);
    free(r.line);
    fclose(r.file);
    return status;
}
