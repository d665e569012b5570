/* The film maker's drawing (viewer/film_scene.h). */
#include "viewer/film_scene.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "common/geometry.h"
#include "mesh/io/pov_axes.h"
#include "kernels/contact/colliders/rotation.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void to_pov(const sb_film_scene* f, const double p[3], double out[3]) {
    sb_pov_axes axes = sb_pov_axes_for(f->up);
    sb_pov_point(&axes, p, out);
}

static void put_vector(FILE* out, const sb_film_scene* f, const double p[3]) {
    double q[3];
    to_pov(f, p, q);
    fprintf(out, "<%.9g, %.9g, %.9g>", q[0], q[1], q[2]);
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

sb_status sb_film_scene_create(sb_film_scene* f, const sb_simulation* sim, sb_error* err) {
    *f = (sb_film_scene){.sim = sim, .count = sim->colliders.colliders ? sim->colliders.count : 0};
    sb_simulation_up(sim, f->up);
    f->rest_center = calloc((size_t)f->count + 1, sizeof *f->rest_center);
    if (!f->rest_center) return sb_error_set(err, SB_ERR_NOMEM, "film: out of memory");
    for (uint32_t c = 0; c < f->count; c++) {
        sb_collider_state(sim->colliders.colliders[c], f->rest_center[c], NULL);
        const sb_collider_def* def = &sim->colliders.entries[c].def;
        double length = sqrt(dot3(def->normal, def->normal));
        if (def->shape == SB_COLLIDER_PLANE && length > 0 && dot3(def->normal, f->up) > 0.7 * length)
            f->has_floor = true;
    }
    return SB_OK;
}

void sb_film_scene_free(sb_film_scene* f) {
    free(f->rest_center);
    *f = (sb_film_scene){0};
}

/* Collider c's pose now: rotation (row-major) and the map of a rest point. */
typedef struct pose {
    double R[9], center[3], rest[3];
} pose;

static pose pose_of(const sb_film_scene* f, uint32_t c) {
    pose p;
    sb_collider_orientation(f->sim->colliders.colliders[c], p.R, NULL);
    sb_collider_state(f->sim->colliders.colliders[c], p.center, NULL);
    memcpy(p.rest, f->rest_center[c], sizeof p.rest);
    return p;
}

static void turn(const pose* p, const double v[3], double out[3]) {
    for (int i = 0; i < 3; i++) out[i] = p->R[3 * i] * v[0] + p->R[3 * i + 1] * v[1] + p->R[3 * i + 2] * v[2];
}

static void place(const pose* p, const double rest[3], double out[3]) {
    double d[3] = {rest[0] - p->rest[0], rest[1] - p->rest[1], rest[2] - p->rest[2]};
    turn(p, d, out);
    for (int k = 0; k < 3; k++) out[k] += p->center[k];
}

/* A box's half axes at rest (its def's rotation, as the collider itself
 * turns it), scene coordinates. */
static void box_axes(const sb_collider_def* def, double axes[3][3]) {
    double R[9];
    sb_collider_rotation(def->rotate, R);
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 3; k++) axes[a][k] = R[3 * k + a] * def->half_extents[a];
}

static void grow(double lo[3], double hi[3], const double p[3], double r) {
    for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], p[k] - r), hi[k] = fmax(hi[k], p[k] + r);
}

void sb_film_scene_bounds(const sb_film_scene* f, const double* positions, uint32_t n, double lo[3], double hi[3]) {
    for (uint32_t i = 0; i < n; i++) grow(lo, hi, positions + 3 * i, 0.0);
    for (uint32_t c = 0; c < f->count; c++) {
        const sb_scene_collider* e = &f->sim->colliders.entries[c];
        pose p = pose_of(f, c);
        double q[3], axes[3][3];
        switch (e->def.shape) {
        case SB_COLLIDER_PLANE: break;
        case SB_COLLIDER_SPHERE: grow(lo, hi, p.center, e->def.radius); break;
        case SB_COLLIDER_CAPSULE:
            place(&p, e->def.a, q), grow(lo, hi, q, e->def.radius);
            place(&p, e->def.b, q), grow(lo, hi, q, e->def.radius);
            break;
        case SB_COLLIDER_BOX:
            box_axes(&e->def, axes);
            for (int corner = 0; corner < 8; corner++) {
                double r[3];
                for (int k = 0; k < 3; k++)
                    r[k] = e->def.center[k] + (corner & 1 ? 1 : -1) * axes[0][k] + (corner & 2 ? 1 : -1) * axes[1][k] +
                           (corner & 4 ? 1 : -1) * axes[2][k];
                place(&p, r, q), grow(lo, hi, q, 0.0);
            }
            break;
        default:
            for (uint32_t i = 0; i < e->mesh.vertex_count; i++)
                place(&p, e->mesh.positions + 3 * i, q), grow(lo, hi, q, 0.0);
        }
    }
}

/* ---- a frame ------------------------------------------------------------------ */

/* A mesh2 of n points (already in POV coordinates when pov is set) with smooth normals. */
static void put_mesh2(FILE* out, const sb_film_scene* f, const double* points, uint32_t n, const uint32_t* triangles,
                      uint32_t m, const char* texture, double* scratch) {
    double* p = scratch;                      /* 3n: POV coordinates */
    double* normal = scratch + 3 * (size_t)n; /* 3n */
    for (uint32_t i = 0; i < n; i++) to_pov(f, points + 3 * i, p + 3 * i);
    memset(normal, 0, 3 * (size_t)n * sizeof *normal);
    for (uint32_t t = 0; t < m; t++) {
        const uint32_t* v = triangles + 3 * t;
        double e1[3], e2[3], c[3];
        for (int k = 0; k < 3; k++)
            e1[k] = p[3 * v[1] + k] - p[3 * v[0] + k], e2[k] = p[3 * v[2] + k] - p[3 * v[0] + k];
        c[0] = e1[1] * e2[2] - e1[2] * e2[1], c[1] = e1[2] * e2[0] - e1[0] * e2[2],
        c[2] = e1[0] * e2[1] - e1[1] * e2[0];
        for (int corner = 0; corner < 3; corner++)
            for (int k = 0; k < 3; k++) normal[3 * v[corner] + k] += c[k];
    }
    fprintf(out, "mesh2 {\n  vertex_vectors { %u", n);
    for (uint32_t i = 0; i < n; i++) fprintf(out, ",\n    <%.9g, %.9g, %.9g>", p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    fprintf(out, "\n  }\n  normal_vectors { %u", n);
    for (uint32_t i = 0; i < n; i++) {
        double* q = normal + 3 * i;
        double length = sqrt(dot3(q, q));
        if (length > 0)
            fprintf(out, ",\n    <%.6g, %.6g, %.6g>", q[0] / length, q[1] / length, q[2] / length);
        else
            fprintf(out, ",\n    <0, 1, 0>");
    }
    fprintf(out, "\n  }\n  face_indices { %u", m);
    for (uint32_t t = 0; t < m; t++)
        fprintf(out, ",\n    <%u, %u, %u>", triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]);
    fprintf(out, "\n  }\n  texture { %s }\n}\n", texture);
}

static void put_collider(FILE* out, const sb_film_scene* f, uint32_t c, double* scratch, double* moved) {
    const sb_scene_collider* e = &f->sim->colliders.entries[c];
    const sb_collider_def* def = &e->def;
    pose p = pose_of(f, c);
    double a[3], b[3], n[3], axes[3][3];
    fprintf(out, "// collider %u: %s\n", c, e->name);
    switch (def->shape) {
    case SB_COLLIDER_PLANE: {
        turn(&p, def->normal, n);
        place(&p, def->point, a);
        double length = sqrt(dot3(n, n)), q[3], m[3];
        for (int k = 0; k < 3; k++) n[k] /= length;
        to_pov(f, n, m), to_pov(f, a, q);
        bool floor = dot3(n, f->up) > 0.7;
        fprintf(out, "plane { <%.9g, %.9g, %.9g>, %.9g texture { %s } }\n", m[0], m[1], m[2], dot3(m, q),
                floor ? "softbond_floor" : "softbond_collider");
        break;
    }
    case SB_COLLIDER_SPHERE:
        fprintf(out, "sphere { "), put_vector(out, f, p.center);
        fprintf(out, ", %.9g texture { softbond_collider } }\n", def->radius);
        break;
    case SB_COLLIDER_CAPSULE:
        place(&p, def->a, a), place(&p, def->b, b);
        fprintf(out, "merge {\n  sphere { "), put_vector(out, f, a), fprintf(out, ", %.9g }\n", def->radius);
        fprintf(out, "  sphere { "), put_vector(out, f, b), fprintf(out, ", %.9g }\n", def->radius);
        double d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        if (sqrt(dot3(d, d)) > 1e-9 * def->radius) {
            fprintf(out, "  cylinder { "), put_vector(out, f, a), fprintf(out, ", "), put_vector(out, f, b);
            fprintf(out, ", %.9g }\n", def->radius);
        }
        fprintf(out, "  texture { softbond_collider }\n}\n");
        break;
    case SB_COLLIDER_BOX: {
        box_axes(def, axes);
        place(&p, def->center, a);
        fprintf(out, "box { <-1, -1, -1>, <1, 1, 1>\n  matrix <");
        for (int k = 0; k < 3; k++) {
            double w[3], q[3];
            turn(&p, axes[k], w);
            to_pov(f, w, q);
            fprintf(out, "%.9g, %.9g, %.9g, ", q[0], q[1], q[2]);
        }
        double q[3];
        to_pov(f, a, q);
        fprintf(out, "%.9g, %.9g, %.9g>\n  texture { softbond_collider }\n}\n", q[0], q[1], q[2]);
        break;
    }
    default:
        if (e->mesh.vertex_count == 0 || e->mesh.triangle_count == 0) break;
        for (uint32_t i = 0; i < e->mesh.vertex_count; i++) place(&p, e->mesh.positions + 3 * i, moved + 3 * i);
        put_mesh2(out, f, moved, e->mesh.vertex_count, e->mesh.triangles, e->mesh.triangle_count, "softbond_collider",
                  scratch);
    }
}

sb_status sb_film_scene_write_frame(const sb_film_scene* f, const char* path, const sb_mesh* mesh,
                                    const double* positions, sb_error* err) {
    size_t most = mesh->vertex_count;
    for (uint32_t c = 0; c < f->count; c++)
        if (f->sim->colliders.entries[c].mesh.vertex_count > most)
            most = f->sim->colliders.entries[c].mesh.vertex_count;
    double* scratch = malloc(9 * (most + 1) * sizeof *scratch);
    if (!scratch) return sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status == SB_OK) {
        FILE* out = file.stream;
        fprintf(out,
                "// softbond film frame at t = %.9g s: %u vertices, %u triangles, %u colliders\n"
                "// render: povray +L<this folder> +I<this file> (the setting: " SB_FILM_SETTING ")\n"
                "#version 3.7;\n#include \"" SB_FILM_SETTING "\"\n",
                sb_solver_time(f->sim->solver), mesh->vertex_count, mesh->triangle_count, f->count);
        put_mesh2(out, f, positions, mesh->vertex_count, mesh->triangles, mesh->triangle_count, "softbond_body",
                  scratch);
        for (uint32_t c = 0; c < f->count; c++) put_collider(out, f, c, scratch, scratch + 6 * (most + 1));
        status = sb_atomic_commit(&file, err);
    }
    free(scratch);
    return status;
}

/* ---- the setting ------------------------------------------------------------------ */

/* 1, 2 or 5 times a power of ten, near x. */
static double round_size(double x) {
    double p = pow(10.0, floor(log10(x))), m = x / p;
    return p * (m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0);
}

sb_status sb_film_scene_write_setting(const sb_film_scene* f, const char* path, const double eye[3],
                                      const double target[3], double fov, double aspect, const double lo[3],
                                      const double hi[3], sb_error* err) {
    double e[3], t[3], l[3], h[3];
    to_pov(f, eye, e), to_pov(f, target, t), to_pov(f, lo, l), to_pov(f, hi, h);
    double size = 0.0;
    for (int k = 0; k < 3; k++) size = fmax(size, fabs(hi[k] - lo[k]));
    size = size > 0 ? size : 1.0;
    double bottom = fmin(l[1], h[1]); /* POV-Ray's up is +y */
    /* the key light above, behind the camera's shoulder: shadows fall away from the eye, onto the floor */
    double back[3] = {e[0] - t[0], 0.0, e[2] - t[2]}, length = sqrt(dot3(back, back));
    if (length < 1e-12) back[0] = 1.0, length = 1.0;
    double key[3] = {t[0] + 1.2 * size * (back[0] + back[2]) / length, t[1] + 3.0 * size,
                     t[2] + 1.2 * size * (back[2] - back[0]) / length};
    double angle = 2.0 * atan(tan(0.5 * fov) * aspect) * 180.0 / SB_PI;
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    FILE* out = file.stream;
    fprintf(out,
            "// softbond film: the camera, lights, sky and floor of every frame (POV-Ray's up +y is the scene's up)\n"
            "global_settings { assumed_gamma 1.0 ambient_light rgb <1, 1, 1> }\n"
            "camera {\n  perspective\n  location <%.9g, %.9g, %.9g>\n  right x * image_width / image_height\n"
            "  angle %.6g\n  look_at <%.9g, %.9g, %.9g>\n}\n",
            e[0], e[1], e[2], angle, t[0], t[1], t[2]);
    fprintf(out,
            "light_source { <%.9g, %.9g, %.9g> color rgb <1, 0.97, 0.92> }\n"
            "light_source { <%.9g, %.9g, %.9g> color rgb <0.3, 0.32, 0.36> shadowless }\n"
            "sky_sphere { pigment { gradient y color_map { [0 color rgb <0.97, 0.97, 0.98>] [0.5 color rgb "
            "<0.97, 0.97, 0.98>] [1 color rgb <0.70, 0.78, 0.88>] } scale 2 translate -y } }\n",
            key[0], key[1], key[2], e[0], e[1], e[2]);
    fprintf(out,
            "#declare softbond_body = texture { pigment { color rgb <0.9, 0.42, 0.12> }\n"
            "  finish { ambient 0.12 diffuse 0.8 specular 0.15 roughness 0.05 } }\n"
            "#declare softbond_collider = texture { pigment { color rgb <0.12, 0.58, 0.36> }\n"
            "  finish { ambient 0.12 diffuse 0.75 specular 0.4 roughness 0.02 } }\n"
            "#declare softbond_floor = texture { pigment { checker color rgb <0.86, 0.86, 0.84> color rgb <0.66, "
            "0.66, 0.65> scale %.9g }\n  finish { ambient 0.15 diffuse 0.75 } }\n",
            round_size(size / 8.0));
    if (!f->has_floor)
        fprintf(out, "plane { y, %.9g texture { softbond_floor } } // under the run's lowest point\n",
                bottom - 0.05 * size);
    return sb_atomic_commit(&file, err);
}
