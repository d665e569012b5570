/* Private: the sphere's sweep and the ball's (kernels/contact/colliders/sphere.c). */
#ifndef SB_SPHERE_H
#define SB_SPHERE_H

#include "softbond/collider.h"

/* The sphere's sweep in its rest frame (collider_internal.h's sb_sweep_fn;
 * kernels/contact/colliders/sweep.h says what it answers). */
bool sb_sphere_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                     double* fraction, double* depth, double normal[3]);

/* The ball of radius r about center (sphere.c; the capsule's end caps):
 * its sweep, and the interval [lo, hi] of the line from + s (to − from)
 * inside it with the outward normal at lo, for a line that enters it from
 * outside (false otherwise, and for a tangent line). */
bool sb_ball_sweep(const double center[3], double r, const double from[3], const double to[3], double* fraction,
                   double* depth, double normal[3]);
bool sb_ball_line(const double center[3], double r, const double from[3], const double to[3], double* lo, double* hi,
                  double normal[3]);

#endif
