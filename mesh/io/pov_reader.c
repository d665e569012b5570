/* POV-Ray mesh2 objects with the Spring Systems film maker's locals (see
 * softbond/pov.h for what is read and what is skipped).
 *
 * The file is cut into tokens: numbers (a literal with an optional sign
 * glued to it), identifiers, directives (`#declare`, `#local`, ...),
 * strings and single punctuation characters; // and (non-nested) block
 * comments are skipped. Outside a mesh2 only `#declare NAME =` / `#local
 * NAME =` just before `mesh2` matters (it names the object); every other
 * token is passed over. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/error.h"
#include "mesh/io/mesh_readers.h"
#include "softbond/pov.h"

typedef enum pov_kind { POV_END, POV_NUMBER, POV_NAME, POV_DIRECTIVE, POV_STRING, POV_PUNCT } pov_kind;

typedef struct pov_token {
    pov_kind kind;
    const char* text;
    size_t length;
    size_t line;
    double number;
} pov_token;

typedef struct pov_reader {
    const char* path;
    const char* p;
    const char* end;
    size_t line;
    pov_token tok;
    sb_pov_object* objects;
    size_t object_count, object_capacity;
    sb_error* err;
} pov_reader;

/* ---- tokens -------------------------------------------------------------- */

static bool is_digit(char c) { return c >= '0' && c <= '9'; }
static bool is_name_start(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
static bool is_name_char(char c) { return is_name_start(c) || is_digit(c); }

static void skip_until(pov_reader* r, const char* stop) {
    size_t n = strlen(stop);
    while (r->p < r->end && !((size_t)(r->end - r->p) >= n && memcmp(r->p, stop, n) == 0)) {
        r->line += *r->p == '\n';
        r->p++;
    }
    r->p = r->p + n <= r->end ? r->p + n : r->end;
}

static void skip_blanks(pov_reader* r) {
    while (r->p < r->end) {
        char c = *r->p;
        if (c == '/' && r->p + 1 < r->end && r->p[1] == '/') {
            skip_until(r, "\n");
            r->line++;
        } else if (c == '/' && r->p + 1 < r->end && r->p[1] == '*') {
            r->p += 2;
            skip_until(r, "*/");
        } else if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f' || c == '\0') {
            r->line += c == '\n';
            r->p++;
        } else {
            return;
        }
    }
}

static bool starts_number(const char* p, const char* end) {
    if (p < end && (*p == '+' || *p == '-')) {
        p++;
    }
    return p < end && (is_digit(*p) || (*p == '.' && p + 1 < end && is_digit(p[1])));
}

/* A number literal: digits, '.', an exponent; parsed whole. */
static void read_number(pov_reader* r, pov_token* t) {
    const char* q = r->p + (*r->p == '+' || *r->p == '-');
    while (q < r->end && (is_digit(*q) || *q == '.' || *q == 'e' || *q == 'E' ||
                          ((*q == '+' || *q == '-') && (q[-1] == 'e' || q[-1] == 'E')))) {
        q++;
    }
    t->length = (size_t)(q - r->p);
    t->kind = sb_text_parse_double(r->p, t->length, &t->number) && isfinite(t->number) ? POV_NUMBER : POV_PUNCT;
    r->p = q;
}

static void next(pov_reader* r) {
    skip_blanks(r);
    pov_token* t = &r->tok;
    *t = (pov_token){.kind = POV_END, .text = r->p, .line = r->line};
    if (r->p >= r->end) {
        return;
    }
    if (starts_number(r->p, r->end)) {
        read_number(r, t);
    } else if (is_name_start(*r->p) || (*r->p == '#' && r->p + 1 < r->end && is_name_start(r->p[1]))) {
        t->kind = *r->p == '#' ? POV_DIRECTIVE : POV_NAME;
        r->p++;
        while (r->p < r->end && is_name_char(*r->p)) {
            r->p++;
        }
        t->length = (size_t)(r->p - t->text);
    } else if (*r->p == '"') {
        r->p++;
        while (r->p < r->end && *r->p != '"' && *r->p != '\n') {
            r->p += *r->p == '\\' && r->p + 1 < r->end ? 2 : 1;
        }
        r->p += r->p < r->end && *r->p == '"';
        t->kind = POV_STRING;
        t->length = (size_t)(r->p - t->text);
    } else {
        t->kind = POV_PUNCT;
        t->length = 1;
        r->p++;
    }
}

static bool token_is(const pov_token* t, const char* text) {
    return t->kind != POV_END && t->kind != POV_STRING && strlen(text) == t->length &&
           memcmp(t->text, text, t->length) == 0;
}

static sb_status fail_token(pov_reader* r, const char* what) {
    const pov_token* t = &r->tok;
    if (t->kind == POV_END) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, t->line, "%s the end of the file", what);
    }
    int shown = t->length > 40 ? 40 : (int)t->length;
    return sb_error_at(r->err, SB_ERR_PARSE, r->path, t->line, "%s '%.*s%s'", what, shown, t->text,
                       t->length > 40 ? "..." : "");
}

static sb_status expect(pov_reader* r, const char* text, const char* where) {
    if (!token_is(&r->tok, text)) {
        char what[96];
        snprintf(what, sizeof what, "%s: expected '%s', found", where, text);
        return fail_token(r, what);
    }
    next(r);
    return SB_OK;
}

static sb_status read_number_token(pov_reader* r, const char* where, double* out) {
    if (r->tok.kind != POV_NUMBER) {
        char what[96];
        snprintf(what, sizeof what, "%s: expected a number, found", where);
        return fail_token(r, what);
    }
    *out = r->tok.number;
    next(r);
    return SB_OK;
}

/* Skips commas (POV separates list items with them; some writers omit them). */
static void skip_commas(pov_reader* r) {
    while (token_is(&r->tok, ",")) {
        next(r);
    }
}

/* A block that opens at the current '{': skipped, nested blocks included. */
static sb_status skip_block(pov_reader* r) {
    size_t open_line = r->tok.line, depth = 0;
    do {
        if (r->tok.kind == POV_END) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, open_line,
                               "unclosed '{': no matching '}' before the end of the file");
        }
        depth += token_is(&r->tok, "{");
        depth -= token_is(&r->tok, "}");
        next(r);
    } while (depth > 0);
    return SB_OK;
}

/* ---- mesh2 --------------------------------------------------------------- */

typedef struct pov_mesh {
    sb_mesh_builder mesh;
    bool vertices, faces; /* lists seen */
    sb_pov_object* object;
} pov_mesh;

static sb_status nomem(pov_reader* r) {
    return sb_error_at(r->err, SB_ERR_NOMEM, r->path, r->tok.line,
                       "out of memory or more than 2^32-1 vertices or triangles");
}

/* <a, b, c> */
static sb_status read_vector(pov_reader* r, const char* where, double v[3]) {
    sb_status status = expect(r, "<", where);
    for (int c = 0; c < 3 && status == SB_OK; c++) {
        if (c > 0) {
            status = expect(r, ",", where);
        }
        if (status == SB_OK) {
            status = read_number_token(r, where, &v[c]);
        }
    }
    return status == SB_OK ? expect(r, ">", where) : status;
}

/* "{ n," of a list; n a whole number in [0, 2^32-1]. */
static sb_status read_list_count(pov_reader* r, const char* where, long long* count) {
    double value = 0.0;
    sb_status status = expect(r, "{", where);
    size_t line = r->tok.line;
    if (status == SB_OK) {
        status = read_number_token(r, where, &value);
    }
    if (status == SB_OK && (value != floor(value) || value < 0 || value > (double)UINT32_MAX)) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, line,
                           "%s: the count %.17g is not a whole number in [0, 2^32-1]", where, value);
    }
    *count = (long long)value;
    skip_commas(r);
    return status;
}

/* After the last of `count` items: '}', else a count mismatch. */
static sb_status end_list(pov_reader* r, const char* where, long long count) {
    if (token_is(&r->tok, "<")) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->tok.line, "%s lists more than its count %lld", where,
                           count);
    }
    return expect(r, "}", where);
}

static sb_status list_short(pov_reader* r, const char* where, long long k, long long count) {
    return sb_error_at(r->err, SB_ERR_PARSE, r->path, r->tok.line, "%s lists %lld of its %lld items", where, k, count);
}

static sb_status read_vertices(pov_reader* r, pov_mesh* m) {
    long long count = 0;
    sb_status status = read_list_count(r, "vertex_vectors", &count);
    for (long long k = 0; k < count && status == SB_OK; k++) {
        if (token_is(&r->tok, "}")) {
            return list_short(r, "vertex_vectors", k, count);
        }
        double v[3];
        status = read_vector(r, "vertex_vectors", v);
        if (status == SB_OK && !sb_mesh_builder_add_vertex(&m->mesh, v[0], v[1], v[2])) {
            status = nomem(r);
        }
        skip_commas(r);
    }
    m->vertices = true;
    return status == SB_OK ? end_list(r, "vertex_vectors", count) : status;
}

/* <a, b, c> with each a whole number naming a vertex, then up to three
 * texture indices (skipped). */
static sb_status read_face(pov_reader* r, pov_mesh* m) {
    size_t line = r->tok.line;
    double v[3];
    sb_status status = read_vector(r, "face_indices", v);
    uint32_t t[3];
    for (int c = 0; c < 3 && status == SB_OK; c++) {
        if (v[c] != floor(v[c]) || v[c] < 0 || v[c] >= (double)m->mesh.vertex_count) {
            return sb_error_at(r->err, SB_ERR_PARSE, r->path, line,
                               "face_indices: index %.17g out of range (%zu vertices)", v[c], m->mesh.vertex_count);
        }
        t[c] = (uint32_t)v[c];
    }
    if (status == SB_OK && !sb_mesh_builder_add_triangle(&m->mesh, t[0], t[1], t[2])) {
        return nomem(r);
    }
    for (int texture = 0; texture < 3 && status == SB_OK; texture++) {
        skip_commas(r);
        if (r->tok.kind == POV_NUMBER) {
            next(r);
        }
    }
    skip_commas(r);
    return status;
}

static sb_status read_faces(pov_reader* r, pov_mesh* m) {
    if (!m->vertices) {
        return fail_token(r, "mesh2: face_indices before vertex_vectors at");
    }
    long long count = 0;
    sb_status status = read_list_count(r, "face_indices", &count);
    for (long long k = 0; k < count && status == SB_OK; k++) {
        status = token_is(&r->tok, "}") ? list_short(r, "face_indices", k, count) : read_face(r, m);
    }
    m->faces = true;
    return status == SB_OK ? end_list(r, "face_indices", count) : status;
}

/* ---- the locals ---------------------------------------------------------- */

typedef struct pov_local {
    const char* name;
    unsigned bit;
    size_t offset; /* of the double in sb_pov_object */
} pov_local;

static const pov_local pov_locals[] = {
    {"spring_system_ks", SB_POV_KS, offsetof(sb_pov_object, stretch_k)},
    {"spring_system_kb", SB_POV_KB, offsetof(sb_pov_object, bend_k)},
    {"spring_system_ds", SB_POV_DS, offsetof(sb_pov_object, stretch_damping)},
    {"spring_system_db", SB_POV_DB, offsetof(sb_pov_object, bend_damping)},
    {"spring_system_mass", SB_POV_MASS, offsetof(sb_pov_object, mass)},
    {"spring_system_vicinity", SB_POV_VICINITY, offsetof(sb_pov_object, vicinity)},
};

static sb_status read_fixed(pov_reader* r, sb_pov_object* o) {
    static const char* const truths[] = {"true", "on", "yes"};
    static const char* const lies[] = {"false", "off", "no"};
    if (r->tok.kind == POV_NUMBER) {
        o->fixed = r->tok.number != 0.0;
        next(r);
        return SB_OK;
    }
    for (int i = 0; i < 3; i++) {
        if (token_is(&r->tok, truths[i]) || token_is(&r->tok, lies[i])) {
            o->fixed = token_is(&r->tok, truths[i]);
            next(r);
            return SB_OK;
        }
    }
    return fail_token(r, "spring_system_fixed: expected true or false, found");
}

static sb_status read_value(pov_reader* r, sb_pov_object* o, const pov_local* local) {
    size_t line = r->tok.line;
    double value = 0.0;
    sb_status status = read_number_token(r, local->name, &value);
    if (status == SB_OK && value < 0.0) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, line, "%s = %.17g: expected a number >= 0", local->name,
                           value);
    }
    *(double*)((char*)o + local->offset) = value;
    o->given |= local->bit;
    return status;
}

/* #local NAME = VALUE; inside a mesh2 (the current token is the directive).
 * A local that is not the film maker's is skipped up to its ';'. */
static sb_status read_local(pov_reader* r, sb_pov_object* o) {
    next(r);
    pov_token name = r->tok;
    bool fixed = token_is(&name, "spring_system_fixed");
    const pov_local* local = NULL;
    for (size_t i = 0; i < sizeof pov_locals / sizeof pov_locals[0]; i++) {
        local = token_is(&name, pov_locals[i].name) ? &pov_locals[i] : local;
    }
    if (!fixed && local == NULL) {
        if (name.length > 14 && memcmp(name.text, "spring_system_", 14) == 0) {
            return fail_token(r, "unknown spring-system local (ks, kb, ds, db, mass, vicinity, fixed):");
        }
        while (r->tok.kind != POV_END && !token_is(&r->tok, ";") && !token_is(&r->tok, "}")) {
            next(r);
        }
        return token_is(&r->tok, ";") ? expect(r, ";", "#local") : SB_OK;
    }
    next(r);
    sb_status status = expect(r, "=", "#local");
    if (status == SB_OK) {
        status = fixed ? read_fixed(r, o) : read_value(r, o, local);
    }
    if (status == SB_OK && fixed) {
        o->given |= SB_POV_FIXED;
    }
    return status == SB_OK ? expect(r, ";", "#local") : status;
}

/* ---- objects ------------------------------------------------------------- */

static sb_status new_object(pov_reader* r, const pov_token* name, size_t line, sb_pov_object** out) {
    if (r->object_count == r->object_capacity) {
        size_t capacity = r->object_capacity ? 2 * r->object_capacity : 8;
        sb_pov_object* grown = realloc(r->objects, capacity * sizeof *grown);
        if (grown == NULL) {
            return nomem(r);
        }
        r->objects = grown;
        r->object_capacity = capacity;
    }
    sb_pov_object* o = &r->objects[r->object_count++];
    memset(o, 0, sizeof *o);
    o->line = line;
    if (name != NULL) {
        size_t n = name->length < sizeof o->name ? name->length : sizeof o->name - 1;
        memcpy(o->name, name->text, n);
    }
    *out = o;
    return SB_OK;
}

static sb_status read_mesh2_item(pov_reader* r, pov_mesh* m) {
    if (token_is(&r->tok, "vertex_vectors")) {
        next(r);
        return read_vertices(r, m);
    }
    if (token_is(&r->tok, "face_indices")) {
        next(r);
        return read_faces(r, m);
    }
    if (token_is(&r->tok, "#local") || token_is(&r->tok, "#declare")) {
        return read_local(r, m->object);
    }
    if (token_is(&r->tok, "{")) {
        return skip_block(r); /* the block of normal_vectors, texture, ... */
    }
    next(r);
    return SB_OK;
}

static sb_status check_mesh2(pov_reader* r, pov_mesh* m) {
    if (!m->vertices || !m->faces || m->mesh.triangle_count == 0) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, m->object->line, "mesh2 without %s",
                           !m->vertices ? "vertex_vectors" : "triangles (face_indices)");
    }
    return SB_OK;
}

/* mesh2 { ... }: the current token is `mesh2`. */
static sb_status read_mesh2(pov_reader* r, const pov_token* name) {
    pov_mesh m = {0};
    size_t line = r->tok.line;
    sb_status status = new_object(r, name, line, &m.object);
    next(r);
    if (status == SB_OK) {
        status = expect(r, "{", "mesh2");
    }
    while (status == SB_OK && !token_is(&r->tok, "}")) {
        status = r->tok.kind == POV_END ? sb_error_at(r->err, SB_ERR_PARSE, r->path, line,
                                                      "mesh2 has no closing '}' before the end of the file")
                                        : read_mesh2_item(r, &m);
    }
    if (status == SB_OK) {
        status = check_mesh2(r, &m);
    }
    if (status != SB_OK) {
        sb_mesh_builder_free(&m.mesh);
        return status;
    }
    next(r);
    sb_mesh_builder_finish(&m.mesh, &m.object->mesh);
    return SB_OK;
}

/* Top level: `#declare NAME = mesh2` names the object; everything but mesh2 is passed over. */
static sb_status read_file(pov_reader* r) {
    pov_token name = {0}, previous[3] = {{0}};
    next(r);
    sb_status status = SB_OK;
    while (status == SB_OK && r->tok.kind != POV_END) {
        if (token_is(&r->tok, "mesh2")) {
            bool declared = (token_is(&previous[0], "#declare") || token_is(&previous[0], "#local")) &&
                            previous[1].kind == POV_NAME && token_is(&previous[2], "=");
            name = previous[1];
            status = read_mesh2(r, declared ? &name : NULL);
            memset(previous, 0, sizeof previous);
            continue;
        }
        previous[0] = previous[1];
        previous[1] = previous[2];
        previous[2] = r->tok;
        next(r);
    }
    if (status == SB_OK && r->object_count == 0) {
        return sb_error_at(r->err, SB_ERR_PARSE, r->path, 0, "no mesh2 object");
    }
    return status;
}

bool sb_pov_path(const char* path) { return sb_path_has_extension(path, ".pov"); }

void sb_pov_objects_free(sb_pov_object* objects, uint32_t count) {
    for (uint32_t i = 0; objects != NULL && i < count; i++) {
        sb_mesh_free(&objects[i].mesh);
    }
    free(objects);
}

sb_status sb_pov_load(const char* path, sb_pov_object** objects, uint32_t* object_count, sb_error* err) {
    *objects = NULL;
    *object_count = 0;
    char* text = NULL;
    size_t size = 0;
    sb_status status = sb_read_whole_file(path, &text, &size, err);
    if (status != SB_OK) {
        return status;
    }
    pov_reader r = {.path = path, .p = text, .end = text + size, .line = 1, .err = err};
    status = read_file(&r);
    free(text);
    if (status != SB_OK) {
        sb_pov_objects_free(r.objects, (uint32_t)r.object_count);
        return status;
    }
    *objects = r.objects;
    *object_count = (uint32_t)r.object_count;
    return SB_OK;
}

sb_spring_mesh_def sb_pov_object_springs(const sb_pov_object* object, const sb_spring_mesh_def* defaults) {
    sb_spring_mesh_def d = *defaults;
    unsigned given = object->given;
    d.stretch_k = given & SB_POV_KS ? object->stretch_k : d.stretch_k;
    d.bend_k = given & SB_POV_KB ? object->bend_k : d.bend_k;
    d.stretch_damping = given & SB_POV_DS ? object->stretch_damping : d.stretch_damping;
    d.bend_damping = given & SB_POV_DB ? object->bend_damping : d.bend_damping;
    if (given & SB_POV_VICINITY) {
        d.vicinity = object->vicinity;
        d.vicinity_k = d.stretch_k;
        d.vicinity_damping = d.stretch_damping;
    }
    if ((given & SB_POV_MASS) && object->mesh.vertex_count > 0) {
        d.mass = object->mass / object->mesh.vertex_count;
        d.density = 0.0;
    }
    return d;
}

sb_status sb_pov_load_meshes(const char* path, bool separate, sb_mesh** meshes, uint32_t* count, sb_error* err) {
    sb_pov_object* objects = NULL;
    uint32_t object_count = 0;
    sb_status status = sb_pov_load(path, &objects, &object_count, err);
    sb_mesh* out = status == SB_OK ? calloc(separate ? object_count : 1, sizeof *out) : NULL;
    if (status == SB_OK && out == NULL) {
        status = sb_error_at(err, SB_ERR_NOMEM, path, 0, "out of memory");
    }
    if (status == SB_OK && separate) {
        for (uint32_t i = 0; i < object_count; i++) {
            out[i] = objects[i].mesh;
            objects[i].mesh = (sb_mesh){0};
        }
    }
    if (status == SB_OK && !separate) {
        sb_mesh* parts = malloc(object_count * sizeof *parts);
        for (uint32_t i = 0; parts != NULL && i < object_count; i++) {
            parts[i] = objects[i].mesh;
        }
        status = parts != NULL ? sb_mesh_concatenate(parts, object_count, out, err)
                               : sb_error_at(err, SB_ERR_NOMEM, path, 0, "out of memory");
        free(parts);
    }
    sb_pov_objects_free(objects, object_count);
    if (status != SB_OK) {
        free(out);
        return status;
    }
    *meshes = out;
    *count = separate ? object_count : 1;
    return SB_OK;
}
