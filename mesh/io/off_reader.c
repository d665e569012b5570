/* Object File Format (OFF), ASCII, one element per line.
 *
 *     OFF                      header (also COFF, NOFF, CNOFF, STOFF, ...;
 *     nv nf ne                 optional; counts may follow it on its line)
 *     x y z [extra...]         nv vertex lines; extra numbers (colour,
 *     ...                      normal, texture) are ignored
 *     n i0 i1 ... [extra...]   nf face lines, indices from 0; extra tokens
 *     ...                      after the n indices (a colour) are ignored
 *
 * `#` starts a comment; blank lines are skipped. The edge count is ignored.
 * Faces are fan-triangulated (i0, ik, ik+1). Binary OFF and other
 * dimensions (4OFF, nOFF) are rejected. Vertex order and count are exactly
 * the file's; anything after the last face is ignored. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/error.h"
#include "mesh/io/mesh_readers.h"

typedef enum off_stage { OFF_HEADER, OFF_COUNTS, OFF_VERTICES, OFF_FACES, OFF_DONE } off_stage;

typedef struct off_reader {
    const char* path;
    size_t line;
    off_stage stage;
    long long vertices_expected, faces_expected, faces_read;
    sb_mesh_builder mesh;
    sb_error* err;
} off_reader;

static sb_status fail_token(off_reader* r, const char* what, const char* token, size_t length) {
    int shown = length > 40 ? 40 : (int)length;
    return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "%s '%.*s%s'", what, shown, token,
                       length > 40 ? "..." : "");
}

static bool ends_with_off(const char* token, size_t length) {
    return length >= 3 && memcmp(token + length - 3, "OFF", 3) == 0;
}

static sb_status read_counts(off_reader* r, sb_text_line* line, const char* token, size_t length) {
    long long counts[2];
    for (int c = 0; c < 2; c++) {
        if (c > 0 && !sb_text_next_token(line, &token, &length)) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "expected the counts: vertices faces edges");
        }
        if (!sb_text_parse_integer(token, length, &counts[c]) || counts[c] < 0) {
            return fail_token(r, "malformed count", token, length);
        }
    }
    if (counts[0] > (long long)UINT32_MAX || counts[1] > (long long)UINT32_MAX) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "more than 2^32-1 vertices or faces");
    }
    r->vertices_expected = counts[0];
    r->faces_expected = counts[1];
    r->stage = counts[0] > 0 ? OFF_VERTICES : counts[1] > 0 ? OFF_FACES : OFF_DONE;
    return SB_OK;
}

static sb_status read_header(off_reader* r, sb_text_line* line, const char* token, size_t length) {
    long long ignored;
    if (sb_text_parse_integer(token, length, &ignored)) {
        return read_counts(r, line, token, length); /* header omitted */
    }
    if (!ends_with_off(token, length)) {
        return fail_token(r, "expected the OFF header, found", token, length);
    }
    if (length >= 4 && (token[length - 4] == '4' || token[length - 4] == 'n')) {
        return fail_token(r, "only 3-dimensional OFF is supported, not", token, length);
    }
    r->stage = OFF_COUNTS;
    if (sb_text_next_token(line, &token, &length)) {
        if (length == 6 && memcmp(token, "BINARY", 6) == 0) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "binary OFF is not supported");
        }
        return read_counts(r, line, token, length);
    }
    return SB_OK;
}

static sb_status read_vertex(off_reader* r, sb_text_line* line, const char* token, size_t length) {
    double xyz[3];
    for (int c = 0; c < 3; c++) {
        if (c > 0 && !sb_text_next_token(line, &token, &length)) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "vertex %zu needs three coordinates x y z",
                               r->mesh.vertex_count);
        }
        if (!sb_text_parse_double(token, length, &xyz[c])) {
            return fail_token(r, "malformed number", token, length);
        }
        if (!isfinite(xyz[c])) {
            return fail_token(r, "non-finite coordinate", token, length);
        }
    }
    if (!sb_mesh_builder_add_vertex(&r->mesh, xyz[0], xyz[1], xyz[2])) {
        return sb_error_at(r->err, SB_ERR_NOMEM, r->path, r->line, "out of memory");
    }
    if ((long long)r->mesh.vertex_count == r->vertices_expected) {
        r->stage = r->faces_expected > 0 ? OFF_FACES : OFF_DONE;
    }
    return SB_OK;
}

static sb_status read_face(off_reader* r, sb_text_line* line, const char* token, size_t length) {
    long long n;
    if (!sb_text_parse_integer(token, length, &n)) {
        return fail_token(r, "malformed vertex count", token, length);
    }
    if (n < 3) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "face with %lld vertices (a face needs at least 3)",
                           n);
    }
    uint32_t first = 0, previous = 0;
    for (long long k = 0; k < n; k++) {
        long long index;
        if (!sb_text_next_token(line, &token, &length)) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "face lists %lld of its %lld vertices", k, n);
        }
        if (!sb_text_parse_integer(token, length, &index)) {
            return fail_token(r, "malformed vertex index", token, length);
        }
        if (index < 0 || index >= r->vertices_expected) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "vertex index %lld out of range (%lld vertices)",
                               index, r->vertices_expected);
        }
        uint32_t current = (uint32_t)index;
        if (k == 0) {
            first = current;
        } else if (k >= 2 && !sb_mesh_builder_add_triangle(&r->mesh, first, previous, current)) {
            return sb_error_at(r->err, SB_ERR_NOMEM, r->path, r->line, "out of memory or more than 2^32-1 triangles");
        }
        previous = current;
    }
    if (++r->faces_read == r->faces_expected) {
        r->stage = OFF_DONE;
    }
    return SB_OK;
}

static sb_status read_line(off_reader* r, const char* begin, const char* end) {
    const char* hash = memchr(begin, '#', (size_t)(end - begin));
    sb_text_line line = {begin, hash != NULL ? hash : end};
    const char* token;
    size_t length;
    if (!sb_text_next_token(&line, &token, &length)) {
        return SB_OK;
    }
    switch (r->stage) {
    case OFF_HEADER: return read_header(r, &line, token, length);
    case OFF_COUNTS: return read_counts(r, &line, token, length);
    case OFF_VERTICES: return read_vertex(r, &line, token, length);
    case OFF_FACES: return read_face(r, &line, token, length);
    case OFF_DONE: break;
    }
    return SB_OK;
}

static sb_status check_complete(off_reader* r) {
    switch (r->stage) {
    case OFF_HEADER: return sb_error_at(r->err, SB_ERR_PARSE, r->path, 0, "empty file (no OFF header)");
    case OFF_COUNTS: return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "file ends before the counts");
    case OFF_VERTICES:
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "file ends after %zu of %lld vertices",
                           r->mesh.vertex_count, r->vertices_expected);
    case OFF_FACES:
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "file ends after %lld of %lld faces", r->faces_read,
                           r->faces_expected);
    case OFF_DONE: break;
    }
    if (r->mesh.triangle_count == 0) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, 0, "no triangles (%zu vertices, no faces)",
                           r->mesh.vertex_count);
    }
    return SB_OK;
}

sb_status sb_off_parse(const char* path, const char* text, size_t size, sb_mesh* out, sb_error* err) {
    off_reader r = {.path = path, .err = err, .stage = OFF_HEADER};
    sb_status status = SB_OK;
    const char* p = text;
    const char* end = text + size;
    while (status == SB_OK && r.stage != OFF_DONE && p < end) {
        const char* newline = memchr(p, '\n', (size_t)(end - p));
        const char* line_end = newline != NULL ? newline : end;
        r.line++;
        status = read_line(&r, p, line_end);
        p = line_end + 1;
    }
    if (status == SB_OK) {
        status = check_complete(&r);
    }
    if (status != SB_OK) {
        sb_mesh_builder_free(&r.mesh);
        return status;
    }
    sb_mesh_builder_finish(&r.mesh, out);
    return SB_OK;
}
