/* Drawing the bodies (viewer/mesh_draw.h). The positions and the normals
 * (area-weighted per vertex, worked out here each frame) go to the GPU
 * once per new snapshot, the triangles and edges once per new topology;
 * the strain colouring needs a colour per edge, so it draws from its own
 * buffer of two vertices per edge, filled only while it is on. The
 * texture is a checker in the plane of the rest shape's two largest
 * extents; a split vertex takes its origin's place in it. */
#include "viewer/mesh_draw.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { CHECKER = 64, CHECKER_SQUARES = 8 };

static GLuint buffer(GLenum target, const void* data, size_t bytes, GLenum usage) {
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(target, b);
    glBufferData(target, (GLsizeiptr)bytes, data, usage);
    return b;
}

static void attribute(GLuint vbo, GLuint location, int size, int stride, size_t offset) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glEnableVertexAttribArray(location);
    glVertexAttribPointer(location, size, GL_FLOAT, GL_FALSE, stride, (const void*)offset);
}

/* u, v: the rest positions along the rest box's two largest extents, 0..1. */
static float* texture_coordinates(const sb_model* model) {
    uint32_t n = sb_model_vertex_count(model);
    float* uv = malloc(2 * ((size_t)n + 1) * sizeof *uv);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, p[3];
    for (uint32_t i = 0; i < n; i++) {
        sb_model_rest_position(model, i, p);
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], p[k]), hi[k] = fmax(hi[k], p[k]);
    }
    int smallest = 0;
    for (int k = 1; k < 3; k++)
        if (hi[k] - lo[k] < hi[smallest] - lo[smallest]) smallest = k;
    int a = (smallest + 1) % 3, b = (smallest + 2) % 3;
    for (uint32_t i = 0; i < n && uv; i++) {
        sb_model_rest_position(model, i, p);
        uv[2 * i] = (float)((p[a] - lo[a]) / fmax(hi[a] - lo[a], 1e-12));
        uv[2 * i + 1] = (float)((p[b] - lo[b]) / fmax(hi[b] - lo[b], 1e-12));
    }
    return uv;
}

static GLuint checker_texture(void) {
    static unsigned char pixels[CHECKER * CHECKER * 4];
    for (int y = 0; y < CHECKER; y++)
        for (int x = 0; x < CHECKER; x++) {
            bool dark = ((x * CHECKER_SQUARES / CHECKER) + (y * CHECKER_SQUARES / CHECKER)) % 2;
            unsigned char* p = pixels + 4 * (y * CHECKER + x);
            p[0] = dark ? 40 : 240, p[1] = dark ? 110 : 200, p[2] = dark ? 60 : 90, p[3] = 255;
        }
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, CHECKER, CHECKER, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
}

static bool allocate(sb_mesh_draw* d, const sb_model* model) {
    size_t n = (size_t)d->capacity + 1, e = (size_t)sb_model_bond_count(model) + 1;
    d->rest = malloc(e * sizeof *d->rest);
    d->uv = malloc(2 * n * sizeof *d->uv);
    d->positions = calloc(3 * n, sizeof *d->positions);
    d->normals = calloc(3 * n, sizeof *d->normals);
    d->strain_vertices = malloc(14 * e * sizeof *d->strain_vertices);
    if (!d->rest || !d->uv || !d->positions || !d->normals || !d->strain_vertices) return false;
    for (uint32_t b = 0; b + 1 < e; b++) d->rest[b] = (float)sb_model_bond(model, b).rest_length;
    return true;
}

static void make_buffers(sb_mesh_draw* d, const sb_model* model) {
    size_t n = d->capacity, e = sb_model_bond_count(model);
    glGenVertexArrays(1, &d->vao);
    glBindVertexArray(d->vao);
    d->positions_vbo = buffer(GL_ARRAY_BUFFER, NULL, 3 * n * sizeof(float), GL_STREAM_DRAW);
    attribute(d->positions_vbo, SB_ATTR_POSITION, 3, 0, 0);
    d->normals_vbo = buffer(GL_ARRAY_BUFFER, NULL, 3 * n * sizeof(float), GL_STREAM_DRAW);
    attribute(d->normals_vbo, SB_ATTR_NORMAL, 3, 0, 0);
    d->uv_vbo = buffer(GL_ARRAY_BUFFER, NULL, 2 * n * sizeof(float), GL_STREAM_DRAW);
    attribute(d->uv_vbo, SB_ATTR_UV, 2, 0, 0);
    d->triangles_ebo = buffer(GL_ELEMENT_ARRAY_BUFFER, NULL, 0, GL_STREAM_DRAW); /* filled by sb_mesh_draw_topology */
    glBindVertexArray(0);
    d->edges_ebo = buffer(GL_ELEMENT_ARRAY_BUFFER, NULL, 0, GL_STREAM_DRAW);
    glGenVertexArrays(1, &d->strain_vao);
    glBindVertexArray(d->strain_vao);
    d->strain_vbo = buffer(GL_ARRAY_BUFFER, NULL, 14 * e * sizeof(float), GL_STREAM_DRAW);
    attribute(d->strain_vbo, SB_ATTR_POSITION, 3, 7 * sizeof(float), 0);
    attribute(d->strain_vbo, SB_ATTR_COLOR, 4, 7 * sizeof(float), 3 * sizeof(float));
    glBindVertexArray(0);
}

sb_status sb_mesh_draw_create(sb_mesh_draw* d, const sb_model* model, uint32_t capacity, sb_error* err) {
    *d = (sb_mesh_draw){.capacity = capacity, .model_vertices = sb_model_vertex_count(model)};
    d->model_uv = texture_coordinates(model);
    if (!d->model_uv || !allocate(d, model)) {
        sb_mesh_draw_free(d);
        return sb_error_set(err, SB_ERR_NOMEM, "view: out of memory");
    }
    make_buffers(d, model);
    d->texture = checker_texture();
    return SB_OK;
}

void sb_mesh_draw_free(sb_mesh_draw* d) {
    GLuint buffers[] = {d->positions_vbo, d->normals_vbo, d->uv_vbo, d->triangles_ebo, d->edges_ebo, d->strain_vbo};
    if (d->vao) {
        glDeleteBuffers(6, buffers);
        glDeleteVertexArrays(1, &d->vao);
        glDeleteVertexArrays(1, &d->strain_vao);
        glDeleteTextures(1, &d->texture);
    }
    free(d->rest);
    free(d->model_uv);
    free(d->uv);
    free(d->positions);
    free(d->normals);
    free(d->strain_vertices);
    *d = (sb_mesh_draw){0};
}

void sb_mesh_draw_topology(sb_mesh_draw* d, const sb_view_topology* t) {
    d->topology = t;
    d->triangle_count = t->triangle_count;
    d->edge_count = t->edge_count;
    for (uint32_t i = 0; i < t->vertex_count; i++) { /* a vertex a cut made has no model vertex: the first's */
        uint32_t origin = t->origins[i] < d->model_vertices ? t->origins[i] : 0;
        memcpy(d->uv + 2 * i, d->model_uv + 2 * origin, 2 * sizeof *d->uv);
    }
    glBindBuffer(GL_ARRAY_BUFFER, d->uv_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(2 * (size_t)t->vertex_count * sizeof(float)), d->uv);
    glBindVertexArray(d->vao);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(3 * (size_t)t->triangle_count * sizeof(uint32_t)), t->triangles,
                 GL_STREAM_DRAW);
    glBindVertexArray(0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, d->edges_ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(2 * (size_t)t->edge_count * sizeof(uint32_t)), t->edges,
                 GL_STREAM_DRAW);
}

void sb_strain_color(double strain, double scale, float rgba[4]) {
    double s = fmax(-1.0, fmin(1.0, strain / scale));
    float w = (float)(1.0 - fabs(s));
    rgba[0] = s > 0 ? 1.0f : w;
    rgba[1] = w;
    rgba[2] = s < 0 ? 1.0f : w;
    rgba[3] = 1.0f;
}

/* Area-weighted vertex normals (the cross products summed, then made unit). */
static void compute_normals(sb_mesh_draw* d) {
    const float* x = d->positions;
    float* n = d->normals;
    memset(n, 0, 3 * (size_t)d->capacity * sizeof *n);
    for (uint32_t k = 0; k < d->triangle_count; k++) {
        const uint32_t* t = d->topology->triangles + 3 * k;
        float a[3], b[3];
        for (int c = 0; c < 3; c++) a[c] = x[3 * t[1] + c] - x[3 * t[0] + c], b[c] = x[3 * t[2] + c] - x[3 * t[0] + c];
        float cr[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        for (int v = 0; v < 3; v++)
            for (int c = 0; c < 3; c++) n[3 * t[v] + c] += cr[c];
    }
    for (uint32_t i = 0; i < d->capacity; i++) {
        float* ni = n + 3 * i;
        float len = sqrtf(ni[0] * ni[0] + ni[1] * ni[1] + ni[2] * ni[2]);
        for (int c = 0; c < 3 && len > 0; c++) ni[c] /= len;
    }
}

/* Edge e's strain: its length over its bond's rest length, less 1. */
static double edge_strain(const sb_mesh_draw* d, uint32_t e) {
    const uint32_t* ends = d->topology->edges + 2 * e;
    const float *p = d->positions + 3 * ends[0], *q = d->positions + 3 * ends[1];
    double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2], rest = d->rest[d->topology->bonds[e]];
    return rest > 0 ? (sqrt(dx * dx + dy * dy + dz * dz) - rest) / rest : 0.0;
}

/* The colour scale's end: the 98th percentile of |strain| (a histogram of
 * 256 bins up to the largest), so that a few wild edges of a tear do not
 * wash out the rest. */
static double strain_scale(const sb_mesh_draw* d) {
    enum { BINS = 256 };
    double largest = 0.0;
    for (uint32_t e = 0; e < d->edge_count; e++) largest = fmax(largest, fabs(edge_strain(d, e)));
    if (!(largest > 1e-6)) return 1e-6;
    uint32_t counts[BINS] = {0};
    for (uint32_t e = 0; e < d->edge_count; e++) {
        int bin = (int)(BINS * fabs(edge_strain(d, e)) / largest);
        counts[bin < BINS ? bin : BINS - 1]++;
    }
    uint64_t seen = 0, wanted = (uint64_t)ceil(0.98 * d->edge_count);
    int bin = 0;
    while (bin < BINS - 1 && (seen += counts[bin]) < wanted) bin++;
    return fmax(largest * (bin + 1) / BINS, 1e-6);
}

/* The strain lines: each edge's two ends in its colour. */
static void fill_strain(sb_mesh_draw* d) {
    d->strain_scale = strain_scale(d);
    for (uint32_t b = 0; b < d->edge_count; b++) {
        float rgba[4];
        sb_strain_color(edge_strain(d, b), d->strain_scale, rgba);
        for (int end = 0; end < 2; end++) {
            float* out = d->strain_vertices + 14 * (size_t)b + 7 * end;
            memcpy(out, d->positions + 3 * d->topology->edges[2 * b + end], 3 * sizeof *out);
            memcpy(out + 3, rgba, sizeof rgba);
        }
    }
}

void sb_mesh_draw_update(sb_mesh_draw* d, const sb_real* positions, uint32_t count, bool strain) {
    d->vertex_count = count < d->capacity ? count : d->capacity;
    for (size_t k = 0; k < 3 * (size_t)d->vertex_count; k++) d->positions[k] = (float)positions[k];
    compute_normals(d);
    size_t bytes = 3 * (size_t)d->vertex_count * sizeof(float);
    glBindBuffer(GL_ARRAY_BUFFER, d->positions_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)bytes, d->positions);
    glBindBuffer(GL_ARRAY_BUFFER, d->normals_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)bytes, d->normals);
    if (!strain) return;
    fill_strain(d);
    glBindBuffer(GL_ARRAY_BUFFER, d->strain_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(14 * (size_t)d->edge_count * sizeof(float)), d->strain_vertices);
}

static void draw_faces(const sb_mesh_draw* d, const sb_shaders* s, const float matrix[16], const float light[3],
                       bool textured) {
    glUseProgram(s->surface);
    glUniformMatrix4fv(s->surface_matrix, 1, GL_FALSE, matrix);
    glUniform3fv(s->surface_light, 1, light);
    glUniform1i(s->surface_textured, textured);
    glUniform1i(s->surface_texture, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, d->texture);
    glBindVertexArray(d->vao);
    glVertexAttrib4f(SB_ATTR_COLOR, 0.93f, 0.72f, 0.62f, 1.0f); /* tissue */
    glDrawElements(GL_TRIANGLES, (GLsizei)(3 * d->triangle_count), GL_UNSIGNED_INT, 0);
}

void sb_mesh_draw_render(const sb_mesh_draw* d, const sb_shaders* s, const float matrix[16], const float light[3],
                         sb_draw_flags flags) {
    if (flags.faces || flags.texture) draw_faces(d, s, matrix, light, flags.texture);
    glUseProgram(s->lines);
    glUniformMatrix4fv(s->lines_matrix, 1, GL_FALSE, matrix);
    glUniform1f(s->lines_point_size, 5.0f);
    if (flags.strain) {
        glBindVertexArray(d->strain_vao);
        glDrawArrays(GL_LINES, 0, (GLsizei)(2 * d->edge_count));
    }
    glBindVertexArray(d->vao);
    if (flags.edges && !flags.strain) {
        glVertexAttrib4f(SB_ATTR_COLOR, 0.1f, 0.1f, 0.12f, 1.0f);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, d->edges_ebo);
        glDrawElements(GL_LINES, (GLsizei)(2 * d->edge_count), GL_UNSIGNED_INT, 0);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, d->triangles_ebo);
    }
    if (flags.vertices) {
        glVertexAttrib4f(SB_ATTR_COLOR, 0.1f, 0.3f, 0.9f, 1.0f);
        glDrawArrays(GL_POINTS, 0, (GLsizei)d->vertex_count);
    }
    glBindVertexArray(0);
}
