/* The positions CSV reader (see positions_csv.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/positions_csv.h"
#include "common/csv.h"
#include "common/error.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Read through common/csv.h's tokenizer (the NUL byte, the line numbers,
 * overlong lines and fields, as the haptic trajectory's). */
static sb_status read_rows(sb_csv* csv, uint32_t vertex_count, double* out, sb_error* err) {
    bool row;
    sb_status status = sb_csv_next(csv, &row, err);
    if (status != SB_OK) return status;
    char header[64];
    if (!row) return sb_error_at(err, SB_ERR_PARSE, csv->path, csv->line_number, "empty file: expected the header 'x,y,z'");
    sb_csv_joined(csv, header, sizeof header);
    if (strcmp(header, "x,y,z") != 0)
        return sb_error_at(err, SB_ERR_PARSE, csv->path, csv->line_number, "expected the header 'x,y,z', got '%.60s'",
                           header);
    uint32_t rows = 0;
    while ((status = sb_csv_next(csv, &row, err)) == SB_OK && row) {
        if (rows == vertex_count)
            return sb_error_at(err, SB_ERR_PARSE, csv->path, csv->line_number, "more rows than the mesh's %u vertices",
                               vertex_count);
        if (csv->count != 3)
            return sb_error_at(err, SB_ERR_PARSE, csv->path, csv->line_number,
                               "expected three numbers x,y,z, found %d columns", csv->count);
        for (int c = 0; c < 3 && status == SB_OK; c++) status = sb_csv_number(csv, c, &out[3 * (size_t)rows + c], err);
        if (status != SB_OK) return status;
        rows++;
    }
    if (status != SB_OK) return status;
    if (rows < vertex_count)
        return sb_error_at(err, SB_ERR_PARSE, csv->path, csv->line_number + 1, "%u rows, but the mesh has %u vertices", rows,
                           vertex_count);
    return SB_OK;
}

sb_status sb_positions_read(const char* path, uint32_t vertex_count, double* out, sb_error* err) {
    sb_csv csv;
    sb_status status = sb_csv_open(&csv, path, err);
    if (status != SB_OK) return status;
    status = read_rows(&csv, vertex_count, out, err);
    sb_csv_close(&csv);
    return status;
}
