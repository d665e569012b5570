/* A POV-Ray 3.7 scene per mesh, like the Spring Systems film maker's frames,
 * that renders as it is (`povray +W640 +H480 frame.pov`):
 *
 *   - the mesh as `#declare softbond_mesh = mesh2 { vertex_vectors { n, <x,
 *     y, z>, ... } face_indices { m, <i, j, k>, ... } }`, the positions
 *     exactly as softbond has them, so a reader gets them back unchanged;
 *   - one `object` using it with a `matrix` that permutes the axes so that
 *     the axis nearest to def->up becomes POV-Ray's up, +y: the other two
 *     keep their order (and both change sign when up points along a
 *     negative axis). Up +z (softbond's default, gravity along -z) swaps y
 *     and z, which also turns softbond's right-handed frame into POV-Ray's
 *     left-handed one without mirroring; up +y (a film-maker scene read
 *     from a .pov file with gravity along -y) is the identity, so its
 *     frames render as the scene it came from;
 *   - a white background, a plain orange texture with some ambient light so
 *     that faces turned away stay visible, a perspective camera looking at
 *     the centre of the bounding box from the front, above and the right
 *     (or from def->eye at def->target), and a light above the camera.
 *
 * The camera's horizontal field of view is 50°; at SB_POV_DISTANCE times
 * the bounding sphere's radius the sphere fits the image's height for any
 * aspect ratio up to 4:3, POV-Ray's default (the vertical half-angle is then
 * 19.3° and asin(1 / 3.5) = 16.6°). */
#include "mesh/io/mesh_writers.h"
#include "mesh/io/pov_axes.h"

#include <math.h>

#define SB_POV_DISTANCE 3.5

typedef struct pov_view {
    double center[3]; /* POV-Ray coordinates */
    double radius;
} pov_view;

/* The bounding box's centre and half diagonal. */
static pov_view view_of(const sb_mesh* mesh, const double* positions, const sb_pov_axes* axes) {
    double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {0.0, 0.0, 0.0};
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            double x = positions[3 * v + k];
            lo[k] = v == 0 || x < lo[k] ? x : lo[k];
            hi[k] = v == 0 || x > hi[k] ? x : hi[k];
        }
    double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    double center[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
    double radius = 0.5 * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    pov_view view = {{0.0, 0.0, 0.0}, radius > 0.0 ? radius : 1.0};
    sb_pov_point(axes, center, view.center);
    return view;
}

/* The eye: def's, or from the front, above and the right of the view. */
static void place_eye(const sb_mesh_export_def* def, const sb_pov_axes* axes, pov_view* view, double eye[3]) {
    static const double direction[3] = {0.4, 0.6, -0.7}; /* centre to eye, length ~1 */
    if (def->eye && def->target) {
        sb_pov_point(axes, def->eye, eye);
        sb_pov_point(axes, def->target, view->center);
        double d[3] = {eye[0] - view->center[0], eye[1] - view->center[1], eye[2] - view->center[2]};
        view->radius = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / SB_POV_DISTANCE;
        return;
    }
    for (int k = 0; k < 3; k++) eye[k] = view->center[k] + SB_POV_DISTANCE * view->radius * direction[k];
}

static void write_setting(FILE* f, const pov_view* view, const double eye[3]) {
    double lamp[3], r = view->radius;
    for (int k = 0; k < 3; k++) lamp[k] = eye[k] + (k == 1 ? 2.0 * r : 0.0);
    fprintf(f,
            "#version 3.7;\n"
            "global_settings { assumed_gamma 1.0 }\n"
            "background { color rgb <1, 1, 1> }\n"
            "camera {\n  perspective\n  location <%.9g, %.9g, %.9g>\n"
            "  right x * image_width / image_height\n  angle 50\n"
            "  look_at <%.9g, %.9g, %.9g>\n}\n"
            "light_source { <%.9g, %.9g, %.9g> color rgb <1, 1, 1> }\n",
            eye[0], eye[1], eye[2], view->center[0], view->center[1], view->center[2], lamp[0], lamp[1], lamp[2]);
}

static void write_mesh2(FILE* f, const sb_mesh* mesh, const double* positions) {
    fprintf(f, "#declare softbond_mesh = mesh2 {\n  vertex_vectors {\n    %u", mesh->vertex_count);
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        fprintf(f, ",\n    <%.9g, %.9g, %.9g>", positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
    fprintf(f, "\n  }\n  face_indices {\n    %u", mesh->triangle_count);
    for (uint32_t t = 0; t < mesh->triangle_count; t++)
        fprintf(f, ",\n    <%u, %u, %u>", mesh->triangles[3 * t], mesh->triangles[3 * t + 1],
                mesh->triangles[3 * t + 2]);
    fprintf(f, "\n  }\n}\n");
}

/* POV-Ray's matrix maps <x, y, z> to x m[0] + y m[1] + z m[2] (rows of 3). */
static void write_object(FILE* f, const sb_pov_axes* axes) {
    double m[3][3] = {{0.0}};
    for (int k = 0; k < 3; k++) m[axes->axis[k]][k] = axes->sign[k];
    fprintf(f, "object {\n  softbond_mesh\n  matrix <");
    for (int j = 0; j < 3; j++) fprintf(f, "%g, %g, %g,  ", m[j][0], m[j][1], m[j][2]);
    fprintf(f, "0, 0, 0> // softbond's up -> +y\n"
               "  texture {\n    pigment { color rgb <0.9, 0.45, 0.15> }\n"
               "    finish { ambient 0.25 diffuse 0.75 }\n  }\n}\n");
}

void sb_pov_write(FILE* f, const sb_mesh* mesh, const sb_mesh_export_def* def) {
    sb_pov_axes axes = sb_pov_axes_for(def->up);
    pov_view view = view_of(mesh, def->positions, &axes);
    double eye[3];
    place_eye(def, &axes, &view, eye);
    fprintf(f, "// softbond frame: %u vertices, %u triangles, up <%g, %g, %g>\n", mesh->vertex_count,
            mesh->triangle_count, def->up[0], def->up[1], def->up[2]);
    write_setting(f, &view, eye);
    write_mesh2(f, mesh, def->positions);
    write_object(f, &axes);
}
