/* IRIT text data files (".itd", ".irit"): the polygons of IRIT objects.
 *
 * The format (Gershon Elber's "IRIT Data File Format") is nested bracketed
 * lists:
 *
 *     [OBJECT {ATTRS} NAME              an object; it may hold objects
 *         [POLYGON {ATTRS} N            a planar polygon of N >= 3 vertices
 *             [{ATTRS} x y z]           (the last one is not the first again)
 *             ...
 *         ]
 *         [OBJECT ...]
 *     ]
 *
 * An attribute is a bracketed list of a name and values, such as
 * [PLANE a b c d], [NORMAL x y z], [COLOR 4] or [RGB "255,0,0"]: every
 * attribute is skipped. Strings are in double quotes; `#` starts a comment
 * that runs to the end of the line. Polylines, point lists, numbers,
 * points, vectors, control points, strings and matrices are ignored;
 * freeform geometry (curves, surfaces, trimmed surfaces, trivariates,
 * models, instances) is refused with an error that says to polygonize it
 * in IRIT first.
 *
 * Each polygon is fan-triangulated (v0, vk, vk+1) after its vertices are
 * joined by bitwise-identical position; a triangle whose corners joined
 * into fewer than three is dropped and counted. Separate: each OBJECT with
 * polygons is its own mesh, in the order the OBJECTs open (an object's own
 * polygons, not those of the objects inside it), vertices joined within the
 * object; merged: one mesh, vertices joined across objects. Vertex order is
 * the order of first appearance. Errors are "FILE:LINE: what". */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/error.h"
#include "mesh/io/mesh_readers.h"

enum { IRIT_MAX_DEPTH = 64 };

typedef enum irit_kind { IRIT_END, IRIT_OPEN, IRIT_CLOSE, IRIT_WORD, IRIT_STRING } irit_kind;

typedef struct irit_token {
    irit_kind kind;
    const char* text;
    size_t length;
    size_t line;
} irit_token;

typedef struct irit_object {
    sb_mesh_builder mesh;
    sb_weld_table weld;
} irit_object;

typedef struct irit_reader {
    const char* path;
    const char* p;
    const char* end;
    size_t line;
    irit_token tok;
    bool separate;
    irit_object* objects;
    size_t object_count, object_capacity;
    uint32_t* corners; /* the current polygon */
    size_t corner_capacity;
    uint32_t dropped;
    sb_error* err;
} irit_reader;

/* ---- tokens -------------------------------------------------------------- */

static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

static void skip_blanks(irit_reader* r) {
    while (r->p < r->end) {
        if (*r->p == '#') {
            while (r->p < r->end && *r->p != '\n') {
                r->p++;
            }
        } else if (is_space(*r->p) || *r->p == '\0') {
            r->line += *r->p == '\n';
            r->p++;
        } else {
            return;
        }
    }
}

/* "what 'token'" at the token's line, the token cut at 40 characters. */
static sb_status fail_token(irit_reader* r, const char* what) {
    const irit_token* t = &r->tok;
    if (t->kind == IRIT_END) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, t->line, "%s the end of the file", what);
    }
    int shown = t->length > 40 ? 40 : (int)t->length;
    return sb_error_at(r->err, SB_ERR_PARSE, r->path, t->line, "%s '%.*s%s'", what, shown, t->text,
                       t->length > 40 ? "..." : "");
}

static sb_status next(irit_reader* r) {
    skip_blanks(r);
    irit_token* t = &r->tok;
    *t = (irit_token){.kind = IRIT_END, .text = r->p, .length = 0, .line = r->line};
    if (r->p >= r->end) {
        return SB_OK;
    }
    if (*r->p == '[' || *r->p == ']') {
        t->kind = *r->p == '[' ? IRIT_OPEN : IRIT_CLOSE;
        t->length = 1;
        r->p++;
        return SB_OK;
    }
    if (*r->p == '"') {
        const char* close = r->p + 1;
        while (close < r->end && *close != '"') {
            r->line += *close == '\n';
            close++;
        }
        if (close >= r->end) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, t->line, "unterminated string");
        }
        t->kind = IRIT_STRING;
        t->length = (size_t)(close + 1 - r->p);
        r->p = close + 1;
        return SB_OK;
    }
    while (r->p < r->end && !is_space(*r->p) && *r->p != '\0' && *r->p != '[' && *r->p != ']' && *r->p != '"' &&
           *r->p != '#') {
        r->p++;
    }
    t->kind = IRIT_WORD;
    t->length = (size_t)(r->p - t->text);
    return SB_OK;
}

static bool word_is(const irit_token* t, const char* word) {
    return t->kind == IRIT_WORD && strlen(word) == t->length && memcmp(t->text, word, t->length) == 0;
}

static bool word_in(const irit_token* t, const char* const* words) {
    for (; *words != NULL; words++) {
        if (word_is(t, *words)) {
            return true;
        }
    }
    return false;
}

/* Skips up to and including the ']' that closes a '[' already read (at
 * open_line), nested lists included. */
static sb_status skip_rest(irit_reader* r, size_t open_line) {
    size_t depth = 1;
    while (depth > 0) {
        if (r->tok.kind == IRIT_END) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, open_line,
                               "unterminated '[': no matching ']' before the end of the file");
        }
        depth += r->tok.kind == IRIT_OPEN;
        depth -= r->tok.kind == IRIT_CLOSE;
        sb_status status = next(r);
        if (status != SB_OK) {
            return status;
        }
    }
    return SB_OK;
}

/* The current token opens a list: skips it. */
static sb_status skip_list(irit_reader* r) {
    size_t open_line = r->tok.line;
    sb_status status = next(r);
    return status == SB_OK ? skip_rest(r, open_line) : status;
}

static sb_status skip_attributes(irit_reader* r) {
    sb_status status = SB_OK;
    while (status == SB_OK && r->tok.kind == IRIT_OPEN) {
        status = skip_list(r);
    }
    return status;
}

/* ---- polygons ------------------------------------------------------------ */

static sb_status nomem(irit_reader* r) {
    return sb_error_at(r->err, SB_ERR_NOMEM, r->path, r->tok.line,
                       "out of memory or more than 2^32-1 vertices or triangles");
}

/* [{ATTRS} x y z]: the current token is its '['. */
static sb_status read_vertex(irit_reader* r, irit_object* object, size_t k) {
    sb_status status = next(r);
    if (status == SB_OK) {
        status = skip_attributes(r);
    }
    double xyz[3];
    for (int c = 0; c < 3 && status == SB_OK; c++) {
        if (r->tok.kind != IRIT_WORD || !sb_text_parse_double(r->tok.text, r->tok.length, &xyz[c])) {
            return fail_token(r, r->tok.kind == IRIT_CLOSE ? "polygon vertex needs x y z, found" : "malformed number");
        }
        if (!isfinite(xyz[c])) {
            return fail_token(r, "non-finite coordinate");
        }
        status = next(r);
    }
    if (status != SB_OK) {
        return status;
    }
    if (r->tok.kind != IRIT_CLOSE) {
        return fail_token(r, "polygon vertex has x y z only: expected ']', found");
    }
    if (k >= r->corner_capacity) {
        size_t capacity = r->corner_capacity ? 2 * r->corner_capacity : 16;
        uint32_t* grown = realloc(r->corners, capacity * sizeof *grown);
        if (grown == NULL) {
            return nomem(r);
        }
        r->corners = grown;
        r->corner_capacity = capacity;
    }
    if (!sb_mesh_builder_weld_vertex(&object->mesh, &object->weld, xyz, &r->corners[k])) {
        return nomem(r);
    }
    return next(r);
}

static sb_status add_fan(irit_reader* r, irit_object* object, size_t count) {
    const uint32_t* c = r->corners;
    for (size_t k = 1; k + 1 < count; k++) {
        if (c[0] == c[k] || c[k] == c[k + 1] || c[k + 1] == c[0]) {
            r->dropped++;
        } else if (!sb_mesh_builder_add_triangle(&object->mesh, c[0], c[k], c[k + 1])) {
            return nomem(r);
        }
    }
    return SB_OK;
}

static sb_status read_count(irit_reader* r, long long* count) {
    if (r->tok.kind != IRIT_WORD || !sb_text_parse_integer(r->tok.text, r->tok.length, count)) {
        return fail_token(r, "POLYGON: expected the vertex count, found");
    }
    if (*count < 3 || *count > (long long)UINT32_MAX) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->tok.line,
                           "POLYGON with %lld vertices (a polygon needs 3 to 2^32-1)", *count);
    }
    return next(r);
}

/* [POLYGON {ATTRS} N vertices...]: the current token is POLYGON. */
static sb_status read_polygon(irit_reader* r, size_t object, size_t open_line) {
    long long count = 0;
    sb_status status = next(r);
    if (status == SB_OK) {
        status = skip_attributes(r);
    }
    if (status == SB_OK) {
        status = read_count(r, &count);
    }
    for (long long k = 0; k < count && status == SB_OK; k++) {
        if (r->tok.kind != IRIT_OPEN) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->tok.line,
                               "POLYGON (line %zu) lists %lld of its %lld vertices", open_line, k, count);
        }
        status = read_vertex(r, &r->objects[object], (size_t)k);
    }
    if (status != SB_OK) {
        return status;
    }
    if (r->tok.kind == IRIT_OPEN) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->tok.line,
                           "POLYGON (line %zu) has more vertices than its count %lld", open_line, count);
    }
    if (r->tok.kind != IRIT_CLOSE) {
        return fail_token(r, "POLYGON: expected ']', found");
    }
    status = add_fan(r, &r->objects[object], (size_t)count);
    return status == SB_OK ? next(r) : status;
}

/* ---- objects ------------------------------------------------------------- */

/* Separate: a new mesh per object; merged: all in the first. */
static sb_status object_slot(irit_reader* r, size_t* slot) {
    if (r->object_count > 0 && !r->separate) {
        *slot = 0;
        return SB_OK;
    }
    if (r->object_count == r->object_capacity) {
        size_t capacity = r->object_capacity ? 2 * r->object_capacity : 8;
        irit_object* grown = realloc(r->objects, capacity * sizeof *grown);
        if (grown == NULL) {
            return nomem(r);
        }
        r->objects = grown;
        r->object_capacity = capacity;
    }
    memset(&r->objects[r->object_count], 0, sizeof r->objects[0]);
    *slot = r->object_count++;
    return SB_OK;
}

static const char* const freeform[] = {"CURVE",    "SURFACE", "TRIMSRF",  "TRIVAR", "TRISRF",
                                       "MULTIVAR", "MODEL",   "INSTANCE", NULL};
static const char* const ignored[] = {"POLYLINE", "POINTLIST", "NUMBER", "POINT", "VECTOR",
                                      "CTLPT",    "STRING",    "MATRIX", NULL};

static sb_status read_object(irit_reader* r, size_t open_line, int depth);

/* One item of an object: the current token is the word after '['. */
static sb_status read_item(irit_reader* r, size_t object, size_t open_line, int depth) {
    if (word_is(&r->tok, "POLYGON")) {
        return read_polygon(r, object, open_line);
    }
    if (word_is(&r->tok, "OBJECT")) {
        return read_object(r, open_line, depth + 1);
    }
    if (word_in(&r->tok, freeform)) {
        return fail_token(r, "freeform geometry is not read (polygonize it in IRIT first):");
    }
    if (!word_in(&r->tok, ignored)) {
        return fail_token(r, "unknown IRIT object type");
    }
    return skip_rest(r, open_line);
}

static sb_status read_contents(irit_reader* r, size_t object, size_t object_line, int depth) {
    for (;;) {
        if (r->tok.kind == IRIT_CLOSE) {
            return next(r);
        }
        if (r->tok.kind == IRIT_END) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, object_line,
                               "unterminated OBJECT: no matching ']' before the end of "
                               "the file");
        }
        if (r->tok.kind != IRIT_OPEN) {
            return fail_token(r, "OBJECT: expected '[' or ']', found");
        }
        size_t open_line = r->tok.line;
        sb_status status = next(r);
        if (status == SB_OK) {
            status = read_item(r, object, open_line, depth);
        }
        if (status != SB_OK) {
            return status;
        }
    }
}

/* [OBJECT {ATTRS} NAME items...]: the current token is OBJECT. */
static sb_status read_object(irit_reader* r, size_t open_line, int depth) {
    if (depth >= IRIT_MAX_DEPTH) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, open_line, "objects nested deeper than %d", IRIT_MAX_DEPTH);
    }
    sb_status status = next(r);
    if (status == SB_OK) {
        status = skip_attributes(r);
    }
    if (status != SB_OK) {
        return status;
    }
    if (r->tok.kind != IRIT_WORD && r->tok.kind != IRIT_STRING) {
        return fail_token(r, "OBJECT: expected its name, found");
    }
    size_t slot = 0;
    status = object_slot(r, &slot);
    if (status == SB_OK) {
        status = next(r);
    }
    return status == SB_OK ? read_contents(r, slot, open_line, depth) : status;
}

static sb_status read_file(irit_reader* r) {
    sb_status status = next(r);
    while (status == SB_OK && r->tok.kind != IRIT_END) {
        if (r->tok.kind != IRIT_OPEN) {
            return fail_token(r, "expected '[OBJECT', found");
        }
        size_t open_line = r->tok.line;
        status = next(r);
        if (status == SB_OK && !word_is(&r->tok, "OBJECT")) {
            return fail_token(r, "expected OBJECT after '[', found");
        }
        if (status == SB_OK) {
            status = read_object(r, open_line, 0);
        }
    }
    return status;
}

/* ---- results ------------------------------------------------------------- */

static void reader_free(irit_reader* r) {
    for (size_t i = 0; i < r->object_count; i++) {
        sb_mesh_builder_free(&r->objects[i].mesh);
        free(r->objects[i].weld.slots);
    }
    free(r->objects);
    free(r->corners);
}

/* The objects with triangles, in order; the others are dropped. */
static sb_status finish(irit_reader* r, sb_mesh** objects, uint32_t* object_count) {
    size_t kept = 0;
    for (size_t i = 0; i < r->object_count; i++) {
        kept += r->objects[i].mesh.triangle_count > 0;
    }
    if (kept == 0) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, 0,
                           "no polygons (%zu objects, %u degenerate triangles dropped)", r->object_count, r->dropped);
    }
    sb_mesh* out = calloc(kept, sizeof *out);
    if (out == NULL) {
        return sb_error_at(r->err, SB_ERR_NOMEM, r->path, 0, "out of memory");
    }
    size_t n = 0;
    for (size_t i = 0; i < r->object_count; i++) {
        if (r->objects[i].mesh.triangle_count > 0) {
            sb_mesh_builder_finish(&r->objects[i].mesh, &out[n++]);
        }
    }
    *objects = out;
    *object_count = (uint32_t)n;
    return SB_OK;
}

static sb_status irit_parse(const char* path, const char* text, size_t size, bool separate, sb_mesh** objects,
                            uint32_t* object_count, uint32_t* dropped, sb_error* err) {
    irit_reader r = {.path = path, .p = text, .end = text + size, .line = 1, .separate = separate, .err = err};
    sb_status status = read_file(&r);
    if (status == SB_OK) {
        status = finish(&r, objects, object_count);
    }
    *dropped = r.dropped;
    reader_free(&r);
    return status;
}

sb_status sb_irit_load(const char* path, bool separate, sb_mesh** objects, uint32_t* object_count, uint32_t* dropped,
                       sb_error* err) {
    char* text = NULL;
    size_t size = 0;
    *dropped = 0;
    sb_status status = sb_read_whole_file(path, &text, &size, err);
    if (status == SB_OK) {
        status = irit_parse(path, text, size, separate, objects, object_count, dropped, err);
    }
    free(text);
    return status;
}
