/* Private: the triangles of a body's surface that the colliders meet
 * (kernels/contact/surface.c's pass), whatever terms the body is made of. */
#ifndef SB_SURFACE_TRIANGLES_H
#define SB_SURFACE_TRIANGLES_H

#include "mesh/model_internal.h"

typedef struct sb_surface_triangles {
    uint32_t count;
    const uint32_t* v[3]; /* corner c of triangle t: v[c][t] */
    uint32_t* owned[3];   /* the arrays made here (NULL where v reads the model's) */
} sb_surface_triangles;

/* Whether the model has a surface: triangles, membranes or tetrahedra. */
bool sb_surface_triangles_exist(const sb_model* model);
/* The model's surface: its triangles (read in place, so a tearing model's
 * splits are seen), else its membranes, else its faces, else the boundary of its
 * tetrahedra at rest, a quadratic tetrahedron's face split at its edges'
 * middle vertices into four. */
sb_status sb_surface_triangles_make(const sb_model* model, sb_surface_triangles* out, sb_error* err);
void sb_surface_triangles_free(sb_surface_triangles* surface);

#endif
