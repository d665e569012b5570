/* A POV-Ray 3.7 scene per mesh, like the Spring Systems film maker's frames,
 * that renders as it is (`povray +W640 +H480 frame.pov`):
 *
 *   - the mesh as `#declare softbond_mesh = mesh2 { vertex_vectors { n, <x,
 *     y, z>, ... } face_indices { m, <i, j, k>, ... } }`, the positions
 *     exactly as softbond has them, so a reader gets them back unchanged;
 *   - one `object` using it with a matrix that swaps y and z: softbond is
 *     right-handed with z up (gravity along -z), POV-Ray left-handed with y
 *     up, and a swap of two axes maps one onto the other without mirroring;
 *   - a white background, a plain orange texture with some ambient light so
 *     that faces turned away stay visible, a perspective camera looking at
 *     the centre of the bounding box from the front, above and the right,
 *     and a light above the camera.
 *
 * The camera's horizontal field of view is 50°; at SB_POV_DISTANCE times
 * the bounding sphere's radius the sphere fits the image's height for any
 * aspect ratio up to 4:3, POV-Ray's default (the vertical half-angle is then
 * 19.3° and asin(1 / 3.5) = 16.6°). */
#include "mesh/mesh_writers.h"

#include <math.h>

#define SB_POV_DISTANCE 3.5

typedef struct pov_view {
    double center[3]; /* POV-Ray coordinates */
    double radius;
} pov_view;

/* The bounding box's centre and half diagonal, in POV-Ray's axes. */
static pov_view view_of(const sb_mesh* mesh, const double* positions) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], positions[3 * v + k]);
            hi[k] = fmax(hi[k], positions[3 * v + k]);
        }
    if (mesh->vertex_count == 0) lo[0] = lo[1] = lo[2] = hi[0] = hi[1] = hi[2] = 0.0;
    double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    double radius = 0.5 * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return (pov_view){{0.5 * (lo[0] + hi[0]), 0.5 * (lo[2] + hi[2]), 0.5 * (lo[1] + hi[1])},
                      radius > 0.0 ? radius : 1.0};
}

static void write_setting(FILE* f, const pov_view* view) {
    static const double direction[3] = {0.4, 0.6, -0.7}; /* centre to eye, length ~1 */
    double eye[3], lamp[3], r = view->radius;
    for (int k = 0; k < 3; k++) eye[k] = view->center[k] + SB_POV_DISTANCE * r * direction[k];
    for (int k = 0; k < 3; k++) lamp[k] = eye[k] + (k == 1 ? 2.0 * r : 0.0);
    fprintf(f,
            "#version 3.7;\n"
            "global_settings { assumed_gamma 1.0 }\n"
            "background { color rgb <1, 1, 1> }\n"
            "camera {\n  perspective\n  location <%.9g, %.9g, %.9g>\n"
            "  right x * image_width / image_height\n  angle 50\n"
            "  look_at <%.9g, %.9g, %.9g>\n}\n"
            "light_source { <%.9g, %.9g, %.9g> color rgb <1, 1, 1> }\n",
            eye[0], eye[1], eye[2], view->center[0], view->center[1], view->center[2], lamp[0],
            lamp[1], lamp[2]);
}

static void write_mesh2(FILE* f, const sb_mesh* mesh, const double* positions) {
    fprintf(f, "#declare softbond_mesh = mesh2 {\n  vertex_vectors {\n    %u", mesh->vertex_count);
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        fprintf(f, ",\n    <%.9g, %.9g, %.9g>", positions[3 * v], positions[3 * v + 1],
                positions[3 * v + 2]);
    fprintf(f, "\n  }\n  face_indices {\n    %u", mesh->triangle_count);
    for (uint32_t t = 0; t < mesh->triangle_count; t++)
        fprintf(f, ",\n    <%u, %u, %u>", mesh->triangles[3 * t], mesh->triangles[3 * t + 1],
                mesh->triangles[3 * t + 2]);
    fprintf(f, "\n  }\n}\n");
}

void sb_pov_write(FILE* f, const sb_mesh* mesh, const double* positions) {
    pov_view view = view_of(mesh, positions);
    fprintf(f, "// softbond frame: %u vertices, %u triangles (softbond's z up)\n",
            mesh->vertex_count, mesh->triangle_count);
    write_setting(f, &view);
    write_mesh2(f, mesh, positions);
    fprintf(f, "object {\n  softbond_mesh\n"
               "  matrix <1, 0, 0,  0, 0, 1,  0, 1, 0,  0, 0, 0> // z up -> y up\n"
               "  texture {\n    pigment { color rgb <0.9, 0.45, 0.15> }\n"
               "    finish { ambient 0.25 diffuse 0.75 }\n  }\n}\n");
}
