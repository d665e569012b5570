/* Private: a mesh collider's triangle mesh and its sweep (kernels/contact/colliders/mesh.c). */
#ifndef SB_MESH_SHAPE_H
#define SB_MESH_SHAPE_H

#include "softbond/mesh.h"

/* The triangle mesh of a mesh collider (mesh.c): a copy of the def's mesh
 * with its bounding-volume hierarchy. Checked as it is made: at least one
 * triangle, indices in range, finite positions, no triangle of zero area;
 * a closed mesh consistently oriented (it is turned outward when it faces
 * in); an open one only with thickness > 0. Messages name the collider
 * (label) and the element. */
typedef struct sb_mesh_shape sb_mesh_shape;
sb_mesh_shape* sb_mesh_shape_create(const char* label, const sb_mesh* mesh, double thickness, sb_error* err);
void sb_mesh_shape_destroy(sb_mesh_shape* shape);
/* Its copy of the mesh (triangles in the hierarchy's order, wound outward
 * when closed) and the box around it (lo x y z, hi x y z). */
const sb_mesh* sb_mesh_shape_mesh(const sb_mesh_shape* shape);
void sb_mesh_shape_box(const sb_mesh_shape* shape, double box[6]);
/* The mesh's sweep (kernels/contact/colliders/sweep.h and mesh.c): a closed mesh bounds its volume,
 * an open one is a shell of the thickness around its surface. */
bool sb_mesh_sweep(const sb_mesh_shape* shape, const double from[3], const double to[3], double thickness,
                   double* fraction, double* depth, double normal[3]);

/* The weights of the material point of a body's triangle that moved from
 * `from` to `to` (in the collider's rest frame) that came nearest one of
 * the mesh's ridges (its convex edges, not flat ones, and an open mesh's
 * rim; sb_triangle_swept_nearest) within `reach`: a sharp edge or corner
 * between the body's vertices. False when none is within reach. */
bool sb_mesh_triangle_point(const sb_mesh_shape* shape, const double from[3][3], const double to[3][3], double reach,
                            double w[3]);

#endif
