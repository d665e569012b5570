/* Wavefront OBJ, the subset a physics mesh needs.
 *
 * Read: `v x y z [w ...]` (extra numbers such as w or vertex colours are
 * checked to be numbers and ignored) and `f`/`fo` with corners written `i`,
 * `i/t`, `i//n` or `i/t/n`. Indices start at 1; a negative index counts back
 * from the last vertex defined so far (-1 is the latest). An index must name
 * a vertex defined before its face. Polygons are fan-triangulated
 * (v0, vk, vk+1) in the order written; faces with repeated vertices are kept
 * as they are (compiling a model reports them). Every other statement (vn,
 * vt, vp, o, g, s, usemtl, mtllib, l, p, curves) is ignored, as is anything
 * after a `#`. Vertex order and count are exactly the file's. Line
 * continuation with a trailing backslash is not supported. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/error.h"
#include "mesh/io/mesh_readers.h"

typedef struct obj_reader {
    const char* path;
    size_t line;
    sb_mesh_builder mesh;
    uint32_t* corners; /* the current face */
    size_t corner_count, corner_capacity;
    sb_error* err;
} obj_reader;

static sb_status fail(obj_reader* r, sb_status status, const char* what, const char* token, size_t length) {
    if (token == NULL) {
        return sb_error_at(r->err, status, r->path, r->line, "%s", what);
    }
    int shown = length > 40 ? 40 : (int)length;
    return sb_error_at(r->err, status, r->path, r->line, "%s '%.*s%s'", what, shown, token, length > 40 ? "..." : "");
}

static sb_status read_vertex(obj_reader* r, sb_text_line* line) {
    double xyz[3];
    int count = 0;
    const char* token;
    size_t length;
    while (sb_text_next_token(line, &token, &length)) {
        double value;
        if (!sb_text_parse_double(token, length, &value)) {
            return fail(r, SB_ERR_PARSE, "malformed number", token, length);
        }
        if (count < 3) {
            if (!isfinite(value)) {
                return fail(r, SB_ERR_PARSE, "non-finite coordinate", token, length);
            }
            xyz[count] = value;
        }
        count++;
    }
    if (count < 3) {
        return fail(r, SB_ERR_PARSE, "vertex needs three coordinates x y z", NULL, 0);
    }
    if (!sb_mesh_builder_add_vertex(&r->mesh, xyz[0], xyz[1], xyz[2])) {
        return fail(r, SB_ERR_NOMEM, "out of memory or more than 2^32-1 vertices", NULL, 0);
    }
    return SB_OK;
}

/* Checks that [p, end) is empty or an integer (a texture or normal index). */
static bool optional_integer(const char* p, const char* end) {
    long long ignored;
    return p == end || sb_text_parse_integer(p, (size_t)(end - p), &ignored);
}

static sb_status read_corner(obj_reader* r, const char* token, size_t length, uint32_t* index) {
    const char* end = token + length;
    const char* slash1 = memchr(token, '/', length);
    const char* vertex_end = slash1 != NULL ? slash1 : end;
    bool ok = true;
    if (slash1 != NULL) {
        const char* rest = slash1 + 1;
        const char* slash2 = memchr(rest, '/', (size_t)(end - rest));
        if (slash2 == NULL) {
            ok = rest < end && optional_integer(rest, end); /* i/t */
        } else {
            ok = optional_integer(rest, slash2) && slash2 + 1 < end &&
                 optional_integer(slash2 + 1, end); /* i/t/n or i//n */
        }
    }
    long long i = 0;
    if (!ok || !sb_text_parse_integer(token, (size_t)(vertex_end - token), &i)) {
        return fail(r, SB_ERR_PARSE, "malformed face vertex", token, length);
    }
    long long defined = (long long)r->mesh.vertex_count;
    long long resolved = i > 0 ? i - 1 : defined + i;
    if (i == 0 || resolved < 0 || resolved >= defined) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line,
                           "vertex index %lld out of range (%lld vertices defined so far)", i, defined);
    }
    *index = (uint32_t)resolved;
    return SB_OK;
}

static sb_status read_face(obj_reader* r, sb_text_line* line) {
    r->corner_count = 0;
    const char* token;
    size_t length;
    while (sb_text_next_token(line, &token, &length)) {
        if (r->corner_count == r->corner_capacity) {
            size_t capacity = r->corner_capacity ? 2 * r->corner_capacity : 16;
            uint32_t* grown = realloc(r->corners, capacity * sizeof(uint32_t));
            if (grown == NULL) {
                return fail(r, SB_ERR_NOMEM, "out of memory", NULL, 0);
            }
            r->corners = grown;
            r->corner_capacity = capacity;
        }
        sb_status status = read_corner(r, token, length, &r->corners[r->corner_count]);
        if (status != SB_OK) {
            return status;
        }
        r->corner_count++;
    }
    if (r->corner_count < 3) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->line, "face with %zu vertices (a face needs at least 3)",
                           r->corner_count);
    }
    for (size_t k = 1; k + 1 < r->corner_count; k++) {
        if (!sb_mesh_builder_add_triangle(&r->mesh, r->corners[0], r->corners[k], r->corners[k + 1])) {
            return fail(r, SB_ERR_NOMEM, "out of memory or more than 2^32-1 triangles", NULL, 0);
        }
    }
    return SB_OK;
}

static bool keyword_is(const char* token, size_t length, const char* keyword) {
    return strlen(keyword) == length && memcmp(token, keyword, length) == 0;
}

static sb_status read_line(obj_reader* r, const char* begin, const char* end) {
    const char* hash = memchr(begin, '#', (size_t)(end - begin));
    sb_text_line line = {begin, hash != NULL ? hash : end};
    const char* keyword;
    size_t length;
    if (!sb_text_next_token(&line, &keyword, &length)) {
        return SB_OK;
    }
    if (keyword_is(keyword, length, "v")) {
        return read_vertex(r, &line);
    }
    if (keyword_is(keyword, length, "f") || keyword_is(keyword, length, "fo")) {
        return read_face(r, &line);
    }
    return SB_OK;
}

sb_status sb_obj_parse(const char* path, const char* text, size_t size, sb_mesh* out, sb_error* err) {
    obj_reader r = {.path = path, .err = err};
    sb_status status = SB_OK;
    const char* p = text;
    const char* end = text + size;
    while (status == SB_OK && p < end) {
        const char* newline = memchr(p, '\n', (size_t)(end - p));
        const char* line_end = newline != NULL ? newline : end;
        r.line++;
        status = read_line(&r, p, line_end);
        p = line_end + 1;
    }
    if (status == SB_OK && r.mesh.triangle_count == 0) {
        status = sb_error_at(err, SB_ERR_PARSE, path, 0, "no triangles (%zu vertices, no faces)", r.mesh.vertex_count);
    }
    free(r.corners);
    if (status != SB_OK) {
        sb_mesh_builder_free(&r.mesh);
        return status;
    }
    sb_mesh_builder_finish(&r.mesh, out);
    return SB_OK;
}
