/* Private: the plane's sweep (kernels/contact/colliders/plane.c). */
#ifndef SB_PLANE_H
#define SB_PLANE_H

#include "softbond/collider.h"

/* The plane's sweep in its rest frame (collider_internal.h's sb_sweep_fn;
 * kernels/contact/colliders/sweep.h says what it answers). */
bool sb_plane_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                    double* fraction, double* depth, double normal[3]);

#endif
