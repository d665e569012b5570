/* Readers of tetrahedral meshes: TetGen (.node + .ele) and Gmsh (.msh
 * version 4.0 and 4.1, ASCII). Each parses a whole file already in memory,
 * line by line; every error is one line "FILE:LINE: what" (SB_ERR_PARSE).
 * Arrays grow as lines are read, never from a count in a header, so a
 * lying header costs nothing. */
#include "mesh/io/mesh_readers.h"
#include "softbond/volume.h"
#include "common/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- lines and tokens ------------------------------------------------------ */

typedef struct tet_text {
    const char* path;
    const char* p;
    const char* end;
    size_t line;      /* number of the current line, 1-based */
    sb_text_line cur; /* the current line, comment removed */
    bool comments;    /* '#' starts a comment (TetGen) */
} tet_text;

/* The next line with a token on it; false at the end of the text. */
static bool tet_next_line(tet_text* t) {
    while (t->p < t->end) {
        const char* start = t->p;
        const char* stop = memchr(start, '\n', (size_t)(t->end - start));
        if (!stop) stop = t->end;
        t->p = stop < t->end ? stop + 1 : t->end;
        t->line++;
        const char* hash = t->comments ? memchr(start, '#', (size_t)(stop - start)) : NULL;
        t->cur = (sb_text_line){start, hash ? hash : stop};
        sb_text_line probe = t->cur;
        const char* token;
        size_t length;
        if (sb_text_next_token(&probe, &token, &length)) return true;
    }
    return false;
}

static bool tet_integer(tet_text* t, long long* out) {
    const char* token;
    size_t length;
    return sb_text_next_token(&t->cur, &token, &length) && sb_text_parse_integer(token, length, out);
}

static bool tet_double(tet_text* t, double* out) {
    const char* token;
    size_t length;
    return sb_text_next_token(&t->cur, &token, &length) && sb_text_parse_double(token, length, out) && isfinite(*out);
}

/* The current line's first token equals word. */
static bool tet_line_is(const tet_text* t, const char* word) {
    sb_text_line probe = t->cur;
    const char* token;
    size_t length;
    return sb_text_next_token(&probe, &token, &length) && length == strlen(word) && memcmp(token, word, length) == 0;
}

#define TET_ERROR(t, err, ...) sb_error_at(err, SB_ERR_PARSE, (t)->path, (t)->line, __VA_ARGS__)

/* ---- growing the mesh ------------------------------------------------------- */

typedef struct tet_build {
    sb_tet_mesh mesh;
    size_t vertex_capacity, tet_capacity;
} tet_build;

static bool tet_grow(void** data, size_t* capacity, size_t needed, size_t size) {
    if (needed <= *capacity) return true;
    size_t c = *capacity ? *capacity : 256;
    while (c < needed) c *= 2;
    if (c > UINT32_MAX) c = UINT32_MAX;
    if (c < needed) return false;
    void* grown = realloc(*data, c * size);
    if (!grown) return false;
    *data = grown;
    *capacity = c;
    return true;
}

static bool tet_add_vertex(tet_build* b, const double p[3]) {
    if (!tet_grow((void**)&b->mesh.positions, &b->vertex_capacity, (size_t)b->mesh.vertex_count + 1,
                  3 * sizeof(double)))
        return false;
    memcpy(b->mesh.positions + 3 * (size_t)b->mesh.vertex_count++, p, 3 * sizeof(double));
    return true;
}

static bool tet_add_tet(tet_build* b, const uint32_t v[4]) {
    if (!tet_grow((void**)&b->mesh.tets, &b->tet_capacity, (size_t)b->mesh.tet_count + 1, 4 * sizeof(uint32_t)))
        return false;
    memcpy(b->mesh.tets + 4 * (size_t)b->mesh.tet_count++, v, 4 * sizeof(uint32_t));
    return true;
}

static sb_status tet_nomem(const tet_text* t, sb_error* err) {
    return sb_error_at(err, SB_ERR_NOMEM, t->path, t->line, "out of memory or more than 2^32-1 items");
}

/* ---- TetGen ------------------------------------------------------------------ */

/* "<count> <a> <b> <c>" header: count and the second number. */
static sb_status tetgen_header(tet_text* t, const char* what, long long* count, long long* second, sb_error* err) {
    if (!tet_next_line(t)) return TET_ERROR(t, err, "empty file: expected the %s header", what);
    if (!tet_integer(t, count) || *count < 1 || *count > UINT32_MAX)
        return TET_ERROR(t, err, "expected the number of %s (1 to 2^32-1)", what);
    if (!tet_integer(t, second))
        return TET_ERROR(t, err, "header: expected %s",
                         strcmp(what, "points") == 0 ? "the dimension" : "the nodes per tetrahedron");
    return SB_OK;
}

/* The item number at the start of a line: base + k, base 0 or 1 from the first. */
static sb_status tetgen_number(tet_text* t, const char* what, long long k, long long* base, sb_error* err) {
    long long number;
    if (!tet_integer(t, &number)) return TET_ERROR(t, err, "expected the %s number", what);
    if (k == 0 && number != 0 && number != 1)
        return TET_ERROR(t, err, "first %s is numbered %lld: expected 0 or 1", what, number);
    if (k == 0) *base = number;
    if (number != *base + k) return TET_ERROR(t, err, "%s numbered %lld, expected %lld", what, number, *base + k);
    return SB_OK;
}

static sb_status tetgen_nodes(tet_text* t, tet_build* b, long long* base, sb_error* err) {
    long long count, dimension;
    sb_status status = tetgen_header(t, "points", &count, &dimension, err);
    if (status != SB_OK) return status;
    if (dimension != 3) return TET_ERROR(t, err, "dimension %lld: only 3 is read", dimension);
    for (long long k = 0; k < count; k++) {
        if (!tet_next_line(t)) return TET_ERROR(t, err, "unexpected end of file: %lld of %lld points read", k, count);
        status = tetgen_number(t, "point", k, base, err);
        if (status != SB_OK) return status;
        double p[3];
        for (int c = 0; c < 3; c++)
            if (!tet_double(t, &p[c]))
                return TET_ERROR(t, err, "point %lld: expected three finite coordinates", *base + k);
        if (!tet_add_vertex(b, p)) return tet_nomem(t, err);
    }
    return SB_OK;
}

/* A 10-node tetrahedron's six edge nodes: read and checked, not kept (the
 * header's count must be in the row, not merely claimed). */
static sb_status tetgen_extra_nodes(tet_text* t, const tet_build* b, long long extra, long long node_base,
                                    long long tet, sb_error* err) {
    for (long long c = 0; c < extra; c++) {
        long long node;
        if (!tet_integer(t, &node))
            return TET_ERROR(t, err, "tetrahedron %lld: expected %lld point numbers", tet, extra + 4);
        if (node < node_base || node - node_base >= b->mesh.vertex_count)
            return TET_ERROR(t, err, "tetrahedron %lld: point %lld does not exist", tet, node);
    }
    return SB_OK;
}

static sb_status tetgen_elements(tet_text* t, tet_build* b, long long node_base, sb_error* err) {
    long long count, corners, base = 0;
    sb_status status = tetgen_header(t, "tetrahedra", &count, &corners, err);
    if (status != SB_OK) return status;
    if (corners != 4 && corners != 10)
        return TET_ERROR(t, err, "%lld nodes per tetrahedron: expected 4 or 10", corners);
    for (long long k = 0; k < count; k++) {
        if (!tet_next_line(t))
            return TET_ERROR(t, err, "unexpected end of file: %lld of %lld tetrahedra read", k, count);
        status = tetgen_number(t, "tetrahedron", k, &base, err);
        if (status != SB_OK) return status;
        uint32_t v[4];
        for (int c = 0; c < 4; c++) {
            long long node;
            if (!tet_integer(t, &node))
                return TET_ERROR(t, err, "tetrahedron %lld: expected %lld point numbers", base + k, corners);
            if (node < node_base || node - node_base >= b->mesh.vertex_count)
                return TET_ERROR(t, err, "tetrahedron %lld: point %lld does not exist", base + k, node);
            v[c] = (uint32_t)(node - node_base);
        }
        status = tetgen_extra_nodes(t, b, corners - 4, node_base, base + k, err);
        if (status != SB_OK) return status;
        if (!tet_add_tet(b, v)) return tet_nomem(t, err);
    }
    return SB_OK;
}

static sb_status tet_read(const char* path, tet_text* t, char** text, bool comments, sb_error* err) {
    size_t size = 0;
    sb_status status = sb_read_whole_file(path, text, &size, err);
    /* a file that could not be read leaves *text NULL: no offset on it */
    *t = (tet_text){.path = path, .p = *text, .end = *text ? *text + size : NULL, .comments = comments};
    return status;
}

sb_status sb_tet_mesh_load_tetgen(const char* node_path, const char* ele_path, sb_tet_mesh* out, sb_error* err) {
    memset(out, 0, sizeof *out);
    tet_build b = {0};
    tet_text t;
    char* text = NULL;
    long long base = 0;
    sb_status status = tet_read(node_path, &t, &text, true, err);
    if (status == SB_OK) status = tetgen_nodes(&t, &b, &base, err);
    free(text);
    text = NULL;
    if (status == SB_OK) status = tet_read(ele_path, &t, &text, true, err);
    if (status == SB_OK) status = tetgen_elements(&t, &b, base, err);
    free(text);
    if (status != SB_OK) {
        sb_tet_mesh_free(&b.mesh);
        return status;
    }
    *out = b.mesh;
    return SB_OK;
}

/* ---- Gmsh 4 ------------------------------------------------------------------- */

typedef struct gmsh_state {
    tet_text t;
    tet_build b;
    bool v41;        /* 4.1, else 4.0 */
    long long* tags; /* per node read */
    size_t tag_capacity;
    uint32_t* by_tag; /* tag -> node index + 1 (0: none) */
    long long max_tag;
    bool nodes, elements; /* sections seen */
} gmsh_state;

static sb_status gmsh_format(gmsh_state* g, sb_error* err) {
    tet_text* t = &g->t;
    if (!tet_next_line(t) || !tet_line_is(t, "$MeshFormat"))
        return TET_ERROR(t, err, "expected $MeshFormat: not a Gmsh .msh file");
    const char* token;
    size_t length;
    long long file_type;
    if (!tet_next_line(t) || !sb_text_next_token(&t->cur, &token, &length))
        return TET_ERROR(t, err, "expected the version line");
    if (length < 1 || token[0] != '4' || (length > 1 && token[1] != '.'))
        return TET_ERROR(t, err, "version %.*s: only version 4 (4.0, 4.1) is read", (int)length, token);
    g->v41 = length >= 3 && token[2] != '0'; /* "4" and "4.0" are 4.0 */
    if (!tet_integer(t, &file_type)) return TET_ERROR(t, err, "expected the file type after the version");
    if (file_type != 0) return TET_ERROR(t, err, "binary .msh files are not read (file type %lld)", file_type);
    if (!tet_next_line(t) || !tet_line_is(t, "$EndMeshFormat")) return TET_ERROR(t, err, "expected $EndMeshFormat");
    return SB_OK;
}

static bool gmsh_counts(tet_text* t, int count, long long* out) {
    for (int i = 0; i < count; i++)
        if (!tet_integer(t, &out[i]) || out[i] < 0) return false;
    return true;
}

static sb_status gmsh_node(gmsh_state* g, long long tag, const double p[3], sb_error* err) {
    if (tag < 1) return TET_ERROR(&g->t, err, "node tag %lld: tags start at 1", tag);
    if (!tet_add_vertex(&g->b, p) ||
        !tet_grow((void**)&g->tags, &g->tag_capacity, g->b.mesh.vertex_count, sizeof *g->tags))
        return tet_nomem(&g->t, err);
    g->tags[g->b.mesh.vertex_count - 1] = tag;
    if (tag > g->max_tag) g->max_tag = tag;
    return SB_OK;
}

static sb_status gmsh_point(gmsh_state* g, double p[3], sb_error* err) {
    for (int c = 0; c < 3; c++)
        if (!tet_double(&g->t, &p[c])) return TET_ERROR(&g->t, err, "expected three finite node coordinates");
    return SB_OK;
}

/* One entity block of nodes: 4.1 lists the tags, then the coordinates; 4.0
 * gives "tag x y z" per line. */
static sb_status gmsh_node_block(gmsh_state* g, sb_error* err) {
    tet_text* t = &g->t;
    long long h[4];
    if (!tet_next_line(t) || !gmsh_counts(t, 4, h))
        return TET_ERROR(t, err, "expected a node block header (4 numbers)");
    long long count = h[3], parametric = h[2];
    sb_status status = SB_OK;
    if (!g->v41) {
        for (long long k = 0; k < count && status == SB_OK; k++) {
            long long tag;
            double p[3];
            if (!tet_next_line(t) || !tet_integer(t, &tag)) return TET_ERROR(t, err, "expected a node tag");
            status = gmsh_point(g, p, err);
            if (status == SB_OK) status = gmsh_node(g, tag, p, err);
        }
        return status;
    }
    long long* tags = malloc((size_t)(count < 1 << 20 ? count : 1 << 20) * sizeof *tags + sizeof *tags);
    size_t tag_capacity = (size_t)(count < 1 << 20 ? count : 1 << 20) + 1;
    if (!tags) return tet_nomem(t, err);
    for (long long k = 0; k < count && status == SB_OK; k++) {
        if (!tet_grow((void**)&tags, &tag_capacity, (size_t)k + 1, sizeof *tags))
            status = tet_nomem(t, err);
        else if (!tet_next_line(t) || !tet_integer(t, &tags[k]))
            status = TET_ERROR(t, err, "expected a node tag");
    }
    for (long long k = 0; k < count && status == SB_OK; k++) {
        double p[3];
        if (!tet_next_line(t)) status = TET_ERROR(t, err, "unexpected end of file in a node block");
        if (status == SB_OK) status = gmsh_point(g, p, err);
        if (status == SB_OK) status = gmsh_node(g, tags[k], p, err);
    }
    (void)parametric; /* parametric coordinates follow x y z on the line: ignored */
    free(tags);
    return status;
}

static sb_status gmsh_map_tags(gmsh_state* g, sb_error* err) {
    uint32_t n = g->b.mesh.vertex_count;
    if (g->max_tag > 16 * (long long)n + 1024)
        return TET_ERROR(&g->t, err, "node tags up to %lld are too sparse for %u nodes", g->max_tag, n);
    g->by_tag = calloc((size_t)g->max_tag + 1, sizeof *g->by_tag);
    if (!g->by_tag) return tet_nomem(&g->t, err);
    for (uint32_t i = 0; i < n; i++) {
        if (g->by_tag[g->tags[i]]) return TET_ERROR(&g->t, err, "node tag %lld appears twice", g->tags[i]);
        g->by_tag[g->tags[i]] = i + 1;
    }
    return SB_OK;
}

static sb_status gmsh_nodes(gmsh_state* g, sb_error* err) {
    tet_text* t = &g->t;
    long long h[4];
    if (g->nodes) return TET_ERROR(t, err, "a second $Nodes section");
    g->nodes = true;
    if (!tet_next_line(t) || !gmsh_counts(t, g->v41 ? 4 : 2, h))
        return TET_ERROR(t, err, "expected the $Nodes header (%d numbers)", g->v41 ? 4 : 2);
    for (long long block = 0; block < h[0]; block++) {
        sb_status status = gmsh_node_block(g, err);
        if (status != SB_OK) return status;
    }
    if (!tet_next_line(t) || !tet_line_is(t, "$EndNodes")) return TET_ERROR(t, err, "expected $EndNodes");
    return gmsh_map_tags(g, err);
}

static sb_status gmsh_tet(gmsh_state* g, sb_error* err) {
    tet_text* t = &g->t;
    long long tag, node;
    uint32_t v[4];
    if (!tet_integer(t, &tag)) return TET_ERROR(t, err, "expected an element tag");
    for (int c = 0; c < 4; c++) {
        if (!tet_integer(t, &node)) return TET_ERROR(t, err, "tetrahedron %lld: expected 4 node tags", tag);
        if (node < 1 || node > g->max_tag || !g->by_tag[node])
            return TET_ERROR(t, err, "tetrahedron %lld: node %lld does not exist", tag, node);
        v[c] = g->by_tag[node] - 1;
    }
    return tet_add_tet(&g->b, v) ? SB_OK : tet_nomem(t, err);
}

static sb_status gmsh_elements(gmsh_state* g, sb_error* err) {
    tet_text* t = &g->t;
    long long h[4];
    if (!g->nodes) return TET_ERROR(t, err, "$Elements before $Nodes");
    if (g->elements) return TET_ERROR(t, err, "a second $Elements section");
    g->elements = true;
    if (!tet_next_line(t) || !gmsh_counts(t, g->v41 ? 4 : 2, h))
        return TET_ERROR(t, err, "expected the $Elements header (%d numbers)", g->v41 ? 4 : 2);
    for (long long block = 0; block < h[0]; block++) {
        long long b[4];
        if (!tet_next_line(t) || !gmsh_counts(t, 4, b))
            return TET_ERROR(t, err, "expected an element block header (4 numbers)");
        bool tets = b[2] == 4 || b[2] == 11; /* linear and quadratic tetrahedra */
        for (long long k = 0; k < b[3]; k++) {
            if (!tet_next_line(t)) return TET_ERROR(t, err, "unexpected end of file in an element block");
            sb_status status = tets ? gmsh_tet(g, err) : SB_OK;
            if (status != SB_OK) return status;
        }
    }
    if (!tet_next_line(t) || !tet_line_is(t, "$EndElements")) return TET_ERROR(t, err, "expected $EndElements");
    return SB_OK;
}

/* Skips a section we do not read, up to its $End line. */
static sb_status gmsh_skip(gmsh_state* g, sb_error* err) {
    tet_text* t = &g->t;
    const char* token;
    size_t length;
    sb_text_line probe = t->cur;
    sb_text_next_token(&probe, &token, &length);
    char end[64];
    snprintf(end, sizeof end, "$End%.*s", (int)(length < 50 ? length - 1 : 49), token + 1);
    size_t start = t->line;
    while (tet_next_line(t))
        if (tet_line_is(t, end)) return SB_OK;
    t->line = start;
    return TET_ERROR(t, err, "section %.*s has no %s", (int)(length < 50 ? length : 50), token, end);
}

/* Keeps the nodes some tetrahedron uses, in file order. */
static void gmsh_compact(tet_build* b) {
    uint32_t n = b->mesh.vertex_count, used = 0;
    uint32_t* index = calloc(n ? n : 1, sizeof *index);
    if (!index) return; /* keep every node: still a valid mesh */
    for (size_t i = 0; i < 4 * (size_t)b->mesh.tet_count; i++) index[b->mesh.tets[i]] = 1;
    for (uint32_t v = 0; v < n; v++)
        if (index[v]) {
            memmove(b->mesh.positions + 3 * (size_t)used, b->mesh.positions + 3 * (size_t)v, 3 * sizeof(double));
            index[v] = ++used;
        }
    for (size_t i = 0; i < 4 * (size_t)b->mesh.tet_count; i++) b->mesh.tets[i] = index[b->mesh.tets[i]] - 1;
    b->mesh.vertex_count = used;
    free(index);
}

static sb_status gmsh_parse(gmsh_state* g, sb_error* err) {
    sb_status status = gmsh_format(g, err);
    while (status == SB_OK && tet_next_line(&g->t)) {
        if (tet_line_is(&g->t, "$Nodes"))
            status = gmsh_nodes(g, err);
        else if (tet_line_is(&g->t, "$Elements"))
            status = gmsh_elements(g, err);
        else if (g->t.cur.p < g->t.cur.end && *g->t.cur.p == '$')
            status = gmsh_skip(g, err);
        else
            status = TET_ERROR(&g->t, err, "expected a section ($Name)");
    }
    if (status != SB_OK) return status;
    if (g->b.mesh.tet_count == 0)
        return sb_error_at(err, SB_ERR_PARSE, g->t.path, 0, "no tetrahedra (element type 4 or 11)");
    gmsh_compact(&g->b);
    return SB_OK;
}

sb_status sb_tet_mesh_load_gmsh(const char* path, sb_tet_mesh* out, sb_error* err) {
    memset(out, 0, sizeof *out);
    gmsh_state g = {0};
    char* text = NULL;
    sb_status status = tet_read(path, &g.t, &text, false, err);
    if (status == SB_OK) status = gmsh_parse(&g, err);
    free(text);
    free(g.tags);
    free(g.by_tag);
    if (status != SB_OK) {
        sb_tet_mesh_free(&g.b.mesh);
        return status;
    }
    *out = g.b.mesh;
    return SB_OK;
}

/* Loading by extension: .node or .ele (TetGen, the other file beside it) or .msh (Gmsh). */
bool sb_tet_mesh_path(const char* path) {
    return path && (sb_path_has_extension(path, ".node") || sb_path_has_extension(path, ".ele") ||
                    sb_path_has_extension(path, ".msh"));
}

/* path with its extension replaced (caller frees). */
static char* sb_swap_extension(const char* path, const char* extension) {
    const char* slash = strrchr(path, '/');
    const char* dot = strrchr(slash ? slash : path, '.');
    size_t stem = dot ? (size_t)(dot - path) : strlen(path);
    char* out = malloc(stem + strlen(extension) + 1);
    if (!out) return NULL;
    memcpy(out, path, stem);
    strcpy(out + stem, extension);
    return out;
}

sb_status sb_tet_mesh_load(const char* path, sb_tet_mesh* out, sb_error* err) {
    memset(out, 0, sizeof *out);
    if (!path || !sb_tet_mesh_path(path))
        return sb_error_set(err, SB_ERR_INVALID, "%s: not a tetrahedral mesh file (.node, .ele or .msh)",
                            path ? path : "(null)");
    if (sb_path_has_extension(path, ".msh")) return sb_tet_mesh_load_gmsh(path, out, err);
    bool node = sb_path_has_extension(path, ".node");
    char* other = sb_swap_extension(path, node ? ".ele" : ".node");
    if (!other) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    sb_status status =
        node ? sb_tet_mesh_load_tetgen(path, other, out, err) : sb_tet_mesh_load_tetgen(other, path, out, err);
    free(other);
    return status;
}
