/* Scripted input for the viewer (viewer/input_script.h): read whole, each
 * line checked, the first bad one named by file and line. */
#define _POSIX_C_SOURCE 200809L
#include "viewer/input_script.h"
#include "common/error.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum { LINE_MAX_BYTES = 512 };

static bool number(const char* word, double* out) {
    char* end;
    if (!word) return false;
    *out = strtod(word, &end);
    return end != word && *end == '\0' && isfinite(*out);
}

static int button_of(const char* word) {
    if (!word) return -1;
    if (strcmp(word, "left") == 0) return SB_BUTTON_LEFT;
    if (strcmp(word, "right") == 0) return SB_BUTTON_RIGHT;
    if (strcmp(word, "middle") == 0) return SB_BUTTON_MIDDLE;
    return -1;
}

/* A press, move or release: [button] x y. */
static bool pointer(char** words, int n, sb_view_event* e) {
    int at = 0;
    if (e->kind == SB_EVENT_PRESS || e->kind == SB_EVENT_RELEASE) {
        int b = button_of(words[0]);
        if (b >= 0) e->button = b, at = 1;
    }
    return n == at + 2 && number(words[at], &e->x) && number(words[at + 1], &e->y);
}

/* One event from the words after the time; NULL or the expected form. */
static const char* parse_event(char** words, int n, sb_view_event* e) {
    const char* verb = words[0];
    *e = (sb_view_event){.button = SB_BUTTON_LEFT};
    if (strcmp(verb, "key") == 0) {
        e->kind = SB_EVENT_KEY;
        e->key = n == 2 ? sb_view_key_from_name(words[1]) : SB_VKEY_NONE;
        return e->key == SB_VKEY_NONE ? "key NAME (F1-F5, r, s, g, space, backspace, h, c, escape)" : NULL;
    }
    static const struct {
        const char* verb;
        sb_view_event_kind kind;
    } pointers[] = {{"press", SB_EVENT_PRESS}, {"release", SB_EVENT_RELEASE}, {"move", SB_EVENT_MOVE}};
    for (size_t i = 0; i < sizeof pointers / sizeof pointers[0]; i++)
        if (strcmp(verb, pointers[i].verb) == 0) {
            e->kind = pointers[i].kind;
            return pointer(words + 1, n - 1, e) ? NULL : "press|release [left|right|middle] X Y, or move X Y";
        }
    if (strcmp(verb, "scroll") == 0) {
        e->kind = SB_EVENT_SCROLL;
        return n == 2 && number(words[1], &e->y) ? NULL : "scroll STEPS";
    }
    if (strcmp(verb, "quit") == 0) {
        e->kind = SB_EVENT_QUIT;
        return n == 1 ? NULL : "quit";
    }
    return "key, press, move, release, scroll or quit";
}

static int split(char* line, char** words, int max) {
    char* hash = strchr(line, '#');
    if (hash) *hash = '\0';
    int n = 0;
    for (char* w = strtok(line, " \t\r\n"); w && n < max; w = strtok(NULL, " \t\r\n")) words[n++] = w;
    return n;
}

static sb_status append(sb_input_script* s, double time, const sb_view_event* e, sb_error* err) {
    sb_view_event* events = realloc(s->events, (s->count + 1) * sizeof *events);
    if (events) s->events = events;
    double* times = events ? realloc(s->times, (s->count + 1) * sizeof *times) : NULL;
    if (!times) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    s->times = times;
    s->events[s->count] = *e;
    s->times[s->count++] = time;
    return SB_OK;
}

static sb_status parse_line(sb_input_script* s, char* line, const char* path, size_t number_of_line, sb_error* err) {
    char* words[8];
    int n = split(line, words, 8);
    if (n == 0) return SB_OK;
    double time;
    if (!number(words[0], &time) || time < 0)
        return sb_error_at(err, SB_ERR_INVALID, path, number_of_line, "expected a time in seconds >= 0, got '%s'",
                           words[0]);
    if (s->count && time < s->times[s->count - 1])
        return sb_error_at(err, SB_ERR_INVALID, path, number_of_line, "time %g is before the line above's %g", time,
                           s->times[s->count - 1]);
    sb_view_event e;
    const char* expected = n > 1 ? parse_event(words + 1, n - 1, &e) : "an event after the time";
    if (expected) return sb_error_at(err, SB_ERR_INVALID, path, number_of_line, "expected %s", expected);
    return append(s, time, &e, err);
}

/* A directory opened for reading reads as nothing: `view --script DIR`
 * was an empty script (exit 0, or no end without --frames). Only a regular
 * file or a pipe is a script. */
static sb_status open_script(const char* path, FILE** f, sb_error* err) {
    *f = fopen(path, "r");
    if (!*f) return sb_error_at(err, SB_ERR_IO, path, 0, "cannot read: %s", strerror(errno));
    struct stat info;
    if (fstat(fileno(*f), &info) == 0 && (S_ISREG(info.st_mode) || S_ISFIFO(info.st_mode))) return SB_OK;
    bool directory = S_ISDIR(info.st_mode);
    fclose(*f);
    *f = NULL;
    return sb_error_at(err, SB_ERR_IO, path, 0, "%s", directory ? "is a directory, not a script" : "not a regular file");
}

sb_status sb_input_script_load(const char* path, sb_input_script* out, sb_error* err) {
    *out = (sb_input_script){0};
    FILE* f;
    sb_status status = open_script(path, &f, err);
    if (status != SB_OK) return status;
    char* line = NULL;
    size_t capacity = 0;
    ssize_t length;
    for (size_t number_of_line = 1; status == SB_OK && (length = getline(&line, &capacity, f)) >= 0; number_of_line++) {
        if (memchr(line, '\0', (size_t)length)) /* it was 'line longer than 510 bytes' */
            status = sb_error_at(err, SB_ERR_INVALID, path, number_of_line, "a NUL byte in the line");
        else if (length > LINE_MAX_BYTES - 2 + (line[length - 1] == '\n'))
            status = sb_error_at(err, SB_ERR_INVALID, path, number_of_line, "line longer than %d bytes (%zd)",
                                 LINE_MAX_BYTES - 2, length);
        else
            status = parse_line(out, line, path, number_of_line, err);
    }
    free(line);
    fclose(f);
    if (status != SB_OK) sb_input_script_free(out);
    return status;
}

void sb_input_script_free(sb_input_script* s) {
    free(s->events);
    free(s->times);
    *s = (sb_input_script){0};
}

bool sb_input_script_next(sb_input_script* s, double time, sb_view_event* event) {
    if (s->next >= s->count || s->times[s->next] > time) return false;
    *event = s->events[s->next++];
    return true;
}

double sb_input_script_next_time(const sb_input_script* s) {
    return s->next < s->count ? s->times[s->next] : INFINITY;
}
