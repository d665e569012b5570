/* Drawing the colliders (viewer/collider_draw.h). Shapes are made once as
 * sb_meshes with the library's generators and placement, flattened to
 * flat-shaded triangles; each frame moves them by the reported poses. */
#include "viewer/collider_draw.h"
#include "common/error.h"
#include "common/geometry.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { SPHERE_SUBDIVISIONS = 2 };

static sb_status sphere(const double center[3], double radius, sb_mesh* out, sb_error* err) {
    sb_status status = sb_mesh_generate_icosphere(SPHERE_SUBDIVISIONS, radius, out, err);
    for (uint32_t i = 0; status == SB_OK && i < out->vertex_count; i++)
        for (int k = 0; k < 3; k++) out->positions[3 * i + k] += center[k];
    return status;
}

/* An icosphere of the radius, its two halves moved to the ends a and b. */
static sb_status capsule(const double a[3], const double b[3], double radius, sb_mesh* out, sb_error* err) {
    const double origin[3] = {0, 0, 0};
    sb_status status = sphere(origin, radius, out, err);
    sb_vec3 axis = sb_v3_sub(sb_v3(b), sb_v3(a));
    for (uint32_t i = 0; status == SB_OK && i < out->vertex_count; i++) {
        double* p = out->positions + 3 * i;
        const double* end = sb_v3_dot(sb_v3(p), axis) > 0 ? b : a;
        for (int k = 0; k < 3; k++) p[k] += end[k];
    }
    return status;
}

static sb_status from_arrays(const double* positions, uint32_t n, const uint32_t* triangles, uint32_t t, sb_mesh* out,
                             sb_error* err) {
    out->positions = malloc(3 * (size_t)n * sizeof *out->positions);
    out->triangles = malloc(3 * (size_t)t * sizeof *out->triangles);
    if (!out->positions || !out->triangles) return sb_error_set(err, SB_ERR_NOMEM, "view: out of memory");
    memcpy(out->positions, positions, 3 * (size_t)n * sizeof *positions);
    memcpy(out->triangles, triangles, 3 * (size_t)t * sizeof *triangles);
    out->vertex_count = n;
    out->triangle_count = t;
    return SB_OK;
}

static sb_status box(const sb_collider_def* def, sb_mesh* out, sb_error* err) {
    double corners[24];
    for (int c = 0; c < 8; c++)
        for (int k = 0; k < 3; k++) corners[3 * c + k] = ((c >> k) & 1 ? 1 : -1) * def->half_extents[k];
    static const uint32_t faces[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                       2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    sb_status status = from_arrays(corners, 8, faces, 12, out, err);
    sb_mesh_transform_def place = sb_default_mesh_transform_def();
    memcpy(place.rotate, def->rotate, sizeof place.rotate);
    memcpy(place.translate, def->center, sizeof place.translate);
    return status == SB_OK ? sb_mesh_transform(out, &place, err) : status;
}

/* A square of side 4 extent in the plane, around the bodies' center's foot. */
static sb_status plane(const sb_collider_def* def, double extent, const double center[3], sb_mesh* out, sb_error* err) {
    sb_vec3 n = sb_v3_scale(sb_v3(def->normal), 1.0 / sb_v3_length(sb_v3(def->normal)));
    sb_vec3 foot = sb_v3_sub(sb_v3(center), sb_v3_scale(n, sb_v3_dot(sb_v3_sub(sb_v3(center), sb_v3(def->point)), n)));
    sb_vec3 helper = fabs(n.x) < 0.9 ? (sb_vec3){1, 0, 0} : (sb_vec3){0, 1, 0};
    sb_vec3 u = sb_v3_cross(n, helper);
    u = sb_v3_scale(u, 2.0 * extent / sb_v3_length(u));
    sb_vec3 v = sb_v3_cross(n, u);
    double corners[12];
    for (int c = 0; c < 4; c++) {
        sb_vec3 p = sb_v3_add(foot, sb_v3_add(sb_v3_scale(u, c & 1 ? 1 : -1), sb_v3_scale(v, c & 2 ? 1 : -1)));
        corners[3 * c] = p.x, corners[3 * c + 1] = p.y, corners[3 * c + 2] = p.z;
    }
    static const uint32_t faces[6] = {0, 1, 2, 1, 3, 2};
    return from_arrays(corners, 4, faces, 2, out, err);
}

static sb_status shape_mesh(const sb_scene_collider* e, double extent, const double center[3], sb_mesh* out,
                            sb_error* err) {
    const sb_collider_def* def = &e->def;
    switch (def->shape) {
    case SB_COLLIDER_PLANE: return plane(def, extent, center, out, err);
    case SB_COLLIDER_SPHERE: return sphere(def->center, def->radius, out, err);
    case SB_COLLIDER_CAPSULE: return capsule(def->a, def->b, def->radius, out, err);
    case SB_COLLIDER_BOX: return box(def, out, err);
    default:
        return from_arrays(e->mesh.positions, e->mesh.vertex_count, e->mesh.triangles, e->mesh.triangle_count, out,
                           err);
    }
}

static sb_status flatten(const sb_mesh* m, sb_collider_shape_draw* s, sb_error* err) {
    s->triangle_count = m->triangle_count;
    s->rest = malloc(9 * ((size_t)m->triangle_count + 1) * sizeof *s->rest);
    s->normals = malloc(3 * ((size_t)m->triangle_count + 1) * sizeof *s->normals);
    if (!s->rest || !s->normals) return sb_error_set(err, SB_ERR_NOMEM, "view: out of memory");
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t* tri = m->triangles + 3 * t;
        sb_vec3 p[3];
        for (int c = 0; c < 3; c++) {
            p[c] = sb_v3(m->positions + 3 * tri[c]);
            for (int k = 0; k < 3; k++) s->rest[9 * t + 3 * c + k] = (float)m->positions[3 * tri[c] + k];
        }
        sb_vec3 n = sb_v3_cross(sb_v3_sub(p[1], p[0]), sb_v3_sub(p[2], p[0]));
        double len = sb_v3_length(n);
        s->normals[3 * t] = (float)(len > 0 ? n.x / len : 0), s->normals[3 * t + 1] = (float)(len > 0 ? n.y / len : 0);
        s->normals[3 * t + 2] = (float)(len > 0 ? n.z / len : 1);
    }
    return SB_OK;
}

sb_status sb_collider_draw_create(sb_collider_draw* d, const sb_scene_colliders* colliders, double extent,
                                  const double center[3], sb_error* err) {
    *d = (sb_collider_draw){.count = colliders->count};
    d->shapes = calloc(d->count + 1, sizeof *d->shapes);
    if (!d->shapes) return sb_error_set(err, SB_ERR_NOMEM, "view: out of memory");
    for (uint32_t c = 0; c < d->count; c++) {
        sb_mesh m = {0};
        sb_status status = shape_mesh(&colliders->entries[c], extent, center, &m, err);
        if (status == SB_OK) status = flatten(&m, &d->shapes[c], err);
        sb_mesh_free(&m);
        if (status != SB_OK) return status;
        sb_collider_state(colliders->colliders[c], d->shapes[c].center, NULL);
        d->corner_count += 3 * d->shapes[c].triangle_count;
    }
    d->vertices = malloc(6 * ((size_t)d->corner_count + 1) * sizeof *d->vertices);
    if (!d->vertices) return sb_error_set(err, SB_ERR_NOMEM, "view: out of memory");
    glGenVertexArrays(1, &d->vao);
    glBindVertexArray(d->vao);
    glGenBuffers(1, &d->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, d->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(6 * (size_t)d->corner_count * sizeof(float)), NULL, GL_STREAM_DRAW);
    glEnableVertexAttribArray(SB_ATTR_POSITION);
    glVertexAttribPointer(SB_ATTR_POSITION, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), 0);
    glEnableVertexAttribArray(SB_ATTR_NORMAL);
    glVertexAttribPointer(SB_ATTR_NORMAL, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (const void*)(3 * sizeof(float)));
    glBindVertexArray(0);
    return SB_OK;
}

void sb_collider_draw_free(sb_collider_draw* d) {
    for (uint32_t c = 0; d->shapes && c < d->count; c++) {
        free(d->shapes[c].rest);
        free(d->shapes[c].normals);
    }
    if (d->vao) {
        glDeleteBuffers(1, &d->vbo);
        glDeleteVertexArrays(1, &d->vao);
    }
    free(d->shapes);
    free(d->vertices);
    *d = (sb_collider_draw){0};
}

/* One shape's corners moved by its pose into out (6 floats a corner). */
static float* place(const sb_collider_shape_draw* s, const double pose[12], float* out) {
    const double* R = pose;
    for (uint32_t t = 0; t < s->triangle_count; t++)
        for (int c = 0; c < 3; c++, out += 6) {
            const float* p = s->rest + 9 * t + 3 * c;
            const float* n = s->normals + 3 * t;
            for (int i = 0; i < 3; i++) {
                out[i] = (float)(pose[9 + i] + R[3 * i] * (p[0] - s->center[0]) + R[3 * i + 1] * (p[1] - s->center[1]) +
                                 R[3 * i + 2] * (p[2] - s->center[2]));
                out[3 + i] = (float)(R[3 * i] * n[0] + R[3 * i + 1] * n[1] + R[3 * i + 2] * n[2]);
            }
        }
    return out;
}

void sb_collider_draw_render(sb_collider_draw* d, const sb_shaders* s, const float matrix[16], const float light[3],
                             const double (*poses)[12], uint32_t pose_count) {
    if (d->corner_count == 0) return;
    float* out = d->vertices;
    uint32_t drawn = d->count < pose_count ? d->count : pose_count;
    for (uint32_t c = 0; c < drawn; c++) out = place(&d->shapes[c], poses[c], out);
    size_t corners = (size_t)(out - d->vertices) / 6;
    glBindBuffer(GL_ARRAY_BUFFER, d->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(6 * corners * sizeof(float)), d->vertices);
    glUseProgram(s->surface);
    glUniformMatrix4fv(s->surface_matrix, 1, GL_FALSE, matrix);
    glUniform3fv(s->surface_light, 1, light);
    glUniform1i(s->surface_textured, 0);
    glBindVertexArray(d->vao);
    glVertexAttrib4f(SB_ATTR_COLOR, 0.62f, 0.68f, 0.75f, 1.0f); /* steel */
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)corners);
    glBindVertexArray(0);
}
