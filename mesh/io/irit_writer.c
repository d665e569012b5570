/* IRIT text polygons, the Spring Systems demo's output#.irit frames: one
 * object holding a POLYGON per triangle, each with its PLANE (unit normal
 * a b c and d, so that a x + b y + c z + d = 0; all zero for a degenerate
 * triangle) and its three corners in order:
 *
 *     [OBJECT softbond
 *         [POLYGON [PLANE 0 0 1 -0] 3
 *             [0 0 0]
 *             [1 0 0]
 *             [0 1 0]
 *         ]
 *     ]
 *
 * Corners are written per polygon, as IRIT does, so shared vertices repeat. */
#include "mesh/io/mesh_writers.h"

#include <math.h>

static void plane(const double* a, const double* b, const double* c, double out[4]) {
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    double length = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double scale = length > 0.0 ? 1.0 / length : 0.0;
    for (int k = 0; k < 3; k++) out[k] = n[k] * scale;
    out[3] = -(out[0] * a[0] + out[1] * a[1] + out[2] * a[2]);
}

static void write_polygon(FILE* f, const sb_mesh* mesh, const double* positions, uint32_t t) {
    const double* corner[3];
    for (int c = 0; c < 3; c++) corner[c] = positions + 3 * (size_t)mesh->triangles[3 * t + c];
    double p[4];
    plane(corner[0], corner[1], corner[2], p);
    fprintf(f, "    [POLYGON [PLANE %.9g %.9g %.9g %.9g] 3\n", p[0], p[1], p[2], p[3]);
    for (int c = 0; c < 3; c++) fprintf(f, "        [%.9g %.9g %.9g]\n", corner[c][0], corner[c][1], corner[c][2]);
    fprintf(f, "    ]\n");
}

void sb_irit_write(FILE* f, const sb_mesh* mesh, const sb_mesh_export_def* def) {
    fprintf(f, "[OBJECT softbond\n");
    for (uint32_t t = 0; t < mesh->triangle_count; t++) write_polygon(f, mesh, def->positions, t);
    fprintf(f, "]\n");
}
