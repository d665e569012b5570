/* sb_mesh_transform: places a mesh, p' = T + Rz(rz) Ry(ry) Rx(rx) S p.
 *
 * The steps, in this order: scale each axis by scale[0..2] about the
 * origin; rotate by rotate[0] degrees about x, then rotate[1] about y, then
 * rotate[2] about z (right-handed: a positive angle turns y toward z about x,
 * z toward x about y, x toward y about z; the axes are the fixed world axes,
 * so this is the extrinsic x-y-z sequence); then translate. A mirror (an odd
 * number of negative scale factors) reverses every triangle's winding, so an
 * outward-facing surface stays outward-facing. */
#include <math.h>
#include <string.h>

#include "common/error.h"
#include "softbond/mesh.h"

sb_mesh_transform_def sb_default_mesh_transform_def(void) {
    return (sb_mesh_transform_def){.scale = {1, 1, 1}, .rotate = {0, 0, 0}, .translate = {0, 0, 0}};
}

/* The rotation matrix R = Rz Ry Rx, row-major. */
static void rotation(const double degrees[3], double r[9]) {
    const double to_radians = 3.14159265358979323846 / 180.0;
    double cx = cos(degrees[0] * to_radians), sx = sin(degrees[0] * to_radians);
    double cy = cos(degrees[1] * to_radians), sy = sin(degrees[1] * to_radians);
    double cz = cos(degrees[2] * to_radians), sz = sin(degrees[2] * to_radians);
    double m[9] = {cz * cy,
                   cz * sy * sx - sz * cx,
                   cz * sy * cx + sz * sx,
                   sz * cy,
                   sz * sy * sx + cz * cx,
                   sz * sy * cx - cz * sx,
                   -sy,
                   cy * sx,
                   cy * cx};
    memcpy(r, m, sizeof m);
}

sb_status sb_mesh_transform(sb_mesh* mesh, const sb_mesh_transform_def* def, sb_error* err) {
    if (mesh == NULL || def == NULL) {
        return sb_error_set(err, SB_ERR_INVALID, "sb_mesh_transform: no mesh or no transform");
    }
    for (int k = 0; k < 3; k++) {
        if (!isfinite(def->scale[k]) || !isfinite(def->rotate[k]) || !isfinite(def->translate[k])) {
            return sb_error_set(err, SB_ERR_INVALID, "sb_mesh_transform: scale, rotate and translate must be finite");
        }
        if (def->scale[k] == 0.0) {
            return sb_error_set(err, SB_ERR_INVALID,
                                "sb_mesh_transform: a scale factor is zero (the mesh would collapse)");
        }
    }
    double r[9];
    rotation(def->rotate, r);
    for (size_t v = 0; v < mesh->vertex_count; v++) {
        double* p = mesh->positions + 3 * v;
        double s[3] = {p[0] * def->scale[0], p[1] * def->scale[1], p[2] * def->scale[2]};
        for (int i = 0; i < 3; i++) {
            p[i] = r[3 * i] * s[0] + r[3 * i + 1] * s[1] + r[3 * i + 2] * s[2] + def->translate[i];
        }
    }
    bool mirror = (def->scale[0] < 0) ^ (def->scale[1] < 0) ^ (def->scale[2] < 0);
    for (size_t t = 0; mirror && t < mesh->triangle_count; t++) {
        uint32_t* tri = mesh->triangles + 3 * t;
        uint32_t swap = tri[1];
        tri[1] = tri[2];
        tri[2] = swap;
    }
    return SB_OK;
}
