/* Private: the point of a triangle nearest a collider's core, for the
 * contact of colliders with the body's surface
 * (kernels/contact/colliders/triangle_point.c). A point of a triangle is
 * given by its barycentric weights w (w_i >= 0, Σ w_i = 1): Σ w_i t_i. */
#ifndef SB_TRIANGLE_POINT_H
#define SB_TRIANGLE_POINT_H

#include <stdbool.h>

/* The weights of the point of triangle t nearest x. */
void sb_triangle_nearest_to_point(const double t[3][3], const double x[3], double w[3]);
/* The weights of the point of triangle t nearest the segment p–q (p == q:
 * the point), the point of the segment it is nearest (core) and their
 * squared distance (0 where the segment pierces the triangle). */
double sb_triangle_nearest_to_segment(const double t[3][3], const double p[3], const double q[3], double w[3],
                                      double core[3]);
/* Whether the segment from–to meets triangle t (a triangle without area
 * is never met), and the weights of where. */
bool sb_triangle_pierced(const double t[3][3], const double from[3], const double to[3], double w[3]);
/* The weights of the material point of a triangle that moved from `from`
 * to `to` (its corners, in a collider's rest frame) that came nearest the
 * segment p–q (the collider's core, at rest there) in the step: where the
 * core's path relative to the triangle pierced it, when it did (the core
 * passed through the surface within the step), otherwise the point of
 * `to` nearest the core. The path relative to the triangle runs from
 * where the core stood from the triangle's nearest point at the start to
 * where it stands at the end, for the nearest point of the core and for
 * its two ends. Returns the squared
 * distance between the core and the point at the end (0 for a piercing). */
double sb_triangle_swept_nearest(const double from[3][3], const double to[3][3], const double p[3], const double q[3],
                                 double w[3]);

#endif
