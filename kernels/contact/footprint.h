/* Private: the patches of a body's surface that a collider with a
 * footprint presses (kernels/contact/footprint.c), for the surface pass of
 * kernels/contact/surface.c. */
#ifndef SB_FOOTPRINT_H
#define SB_FOOTPRINT_H

#include "kernels/contact/surface_triangles.h"

typedef struct sb_footprint {
    uint32_t *first, *vertex; /* each vertex's neighbours on the surface (CSR) */
    uint32_t *mark, stamp;    /* the patch being gathered marks the vertices it looked at */
    uint32_t room;            /* the most vertices a patch of the largest radius holds */
} sb_footprint;

/* The neighbours from the surface's edges, and the room for a patch of
 * `radius` (m, at rest) about any point of a triangle. */
bool sb_footprint_make(const sb_model* model, const sb_surface_triangles* triangles, double radius, sb_footprint* out);
void sb_footprint_free(sb_footprint* footprint);
/* The longest edge of the surface at rest, m. */
double sb_footprint_longest_edge(const sb_model* model, const sb_surface_triangles* triangles);
/* The patch of `radius` (at least the longest edge) about the point of the
 * triangle with `corners` at barycentric weights w, at rest: the vertices
 * within the radius reached from the corners through vertices within it,
 * in the order they are reached (the same on every call), into vertex[],
 * and their weights, which sum to 1, into weight[]; returns how many (at
 * least 1, at most room). */
uint32_t sb_footprint_patch(sb_footprint* footprint, const sb_model* model, const uint32_t corners[3],
                            const double w[3], double radius, uint32_t* vertex, double* weight);

#endif
