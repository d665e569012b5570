/* The "scripted" device: a CSV trajectory replayed on the servo's clock.
 * Header `time,x,y,z`, then optionally `qw,qx,qy,qz`, then optionally
 * `button`; one row per time (s, increasing), position (m), unit
 * quaternion, 0 or 1. Between rows the position is linear, the orientation
 * the normalized linear blend of the two quaternions (their shorter arc),
 * the button the earlier row's; before the first row and after the last the
 * pose holds. The whole file is read at open; reading a pose is a binary
 * search, with no allocation and no system call. */
#include "haptics/device.h"
#include "common/csv.h"
#include "common/error.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct scripted_row {
    double time, position[3], orientation[4];
    uint32_t buttons;
} scripted_row;

typedef struct scripted {
    scripted_row* rows;
    size_t count;
} scripted;

/* The columns the header names: 4, 8 (with the quaternion), 5 or 9 (with the button). */
static int scripted_columns(const sb_csv* csv) {
    static const char* forms[] = {"time,x,y,z", "time,x,y,z,button", "time,x,y,z,qw,qx,qy,qz",
                                  "time,x,y,z,qw,qx,qy,qz,button"};
    static const int columns[] = {4, 5, 8, 9};
    char h[128];
    sb_csv_joined(csv, h, sizeof h);
    for (int i = 0; i < 4; i++)
        if (strcmp(h, forms[i]) == 0) return columns[i];
    return 0;
}

static sb_status scripted_parse_row(const sb_csv* csv, int columns, scripted_row* row, sb_error* err) {
    const char* path = csv->path;
    size_t line = csv->line_number;
    double v[9];
    if (csv->count != columns)
        return sb_error_at(err, SB_ERR_PARSE, path, line, "expected %d columns, found %d", columns, csv->count);
    for (int i = 0; i < columns; i++) {
        sb_status status = sb_csv_number(csv, i, &v[i], err);
        if (status != SB_OK) return status;
    }
    *row = (scripted_row){.time = v[0], .position = {v[1], v[2], v[3]}, .orientation = {1, 0, 0, 0}};
    if (columns >= 8) {
        double norm = sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
        if (fabs(norm - 1) > 1e-3)
            return sb_error_at(err, SB_ERR_PARSE, path, line, "the quaternion is not a unit one (norm %g)", norm);
        for (int k = 0; k < 4; k++) row->orientation[k] = v[4 + k] / norm;
    }
    if (columns == 5 || columns == 9) {
        double b = v[columns - 1];
        if (b != 0 && b != 1) return sb_error_at(err, SB_ERR_PARSE, path, line, "button must be 0 or 1 (got %g)", b);
        row->buttons = (uint32_t)b;
    }
    return SB_OK;
}

/* Read through common/csv.h's tokenizer: a NUL byte in a row
 * (1,0,0,-0.01<NUL>5) was read as the row cut there, a 200 kB field as
 * several lines (the line numbers off after it). */
static sb_status scripted_load(const char* path, scripted* s, sb_error* err) {
    sb_csv csv;
    sb_status status = sb_csv_open(&csv, path, err);
    if (status != SB_OK) return status;
    size_t capacity = 0;
    int columns = 0;
    bool row;
    while ((status = sb_csv_next(&csv, &row, err)) == SB_OK && row) {
        if (!columns) {
            columns = scripted_columns(&csv);
            if (!columns) {
                status = sb_error_at(err, SB_ERR_PARSE, path, csv.line_number,
                                     "the header must be time,x,y,z [,qw,qx,qy,qz] [,button]");
                break;
            }
            continue;
        }
        if (s->count == capacity) {
            capacity = capacity ? 2 * capacity : 64;
            scripted_row* grown = realloc(s->rows, capacity * sizeof *grown);
            if (!grown) {
                status = sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
                break;
            }
            s->rows = grown;
        }
        status = scripted_parse_row(&csv, columns, &s->rows[s->count], err);
        if (status == SB_OK && s->count > 0 && !(s->rows[s->count].time > s->rows[s->count - 1].time))
            status = sb_error_at(err, SB_ERR_PARSE, path, csv.line_number, "times must increase (%g after %g)",
                                 s->rows[s->count].time, s->rows[s->count - 1].time);
        s->count++;
        if (status != SB_OK) break;
    }
    size_t line = csv.line_number;
    sb_csv_close(&csv);
    if (status == SB_OK && s->count == 0) status = sb_error_at(err, SB_ERR_PARSE, path, line, "no rows");
    return status;
}

static sb_status scripted_read(void* user, double time, sb_haptic_pose* pose) {
    const scripted* s = user;
    size_t lo = 0, hi = s->count - 1;
    if (time <= s->rows[0].time)
        hi = 0;
    else if (time >= s->rows[hi].time)
        lo = hi;
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (s->rows[mid].time <= time)
            lo = mid;
        else
            hi = mid;
    }
    const scripted_row *a = &s->rows[lo], *b = &s->rows[hi];
    double u = hi == lo ? 0 : (time - a->time) / (b->time - a->time);
    pose->time = time;
    for (int k = 0; k < 3; k++) pose->position[k] = a->position[k] + u * (b->position[k] - a->position[k]);
    double dot = 0, norm = 0;
    for (int k = 0; k < 4; k++) dot += a->orientation[k] * b->orientation[k];
    double sign = dot < 0 ? -1 : 1;
    for (int k = 0; k < 4; k++) {
        pose->orientation[k] = (1 - u) * a->orientation[k] + u * sign * b->orientation[k];
        norm += pose->orientation[k] * pose->orientation[k];
    }
    for (int k = 0; k < 4; k++) pose->orientation[k] /= sqrt(norm);
    pose->buttons = a->buttons;
    return SB_OK;
}

static sb_status scripted_write(void* user, double time, const double force[3]) {
    (void)user, (void)time, (void)force;
    return SB_OK;
}

static void scripted_close(void* user) {
    scripted* s = user;
    free(s->rows);
    free(s);
}

sb_haptic_device* sb_device_scripted_open(const sb_haptic_device_def* def, sb_error* err) {
    if (!def->file) {
        sb_error_set(err, SB_ERR_INVALID, "scripted device: a file is required");
        return NULL;
    }
    scripted* s = calloc(1, sizeof *s);
    if (!s) {
        sb_error_set(err, SB_ERR_NOMEM, "scripted device: out of memory");
        return NULL;
    }
    static const sb_haptic_device_ops ops = {scripted_read, scripted_write, scripted_close};
    sb_haptic_device* d = NULL;
    if (scripted_load(def->file, s, err) == SB_OK) d = sb_haptic_device_custom(&ops, s, err);
    if (!d) scripted_close(s);
    return d;
}
