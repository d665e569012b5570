/* Private: the box's sweep (kernels/contact/colliders/box.c). */
#ifndef SB_BOX_H
#define SB_BOX_H

#include "softbond/collider.h"

/* The box's sweep in its rest frame (collider_internal.h's sb_sweep_fn;
 * kernels/contact/colliders/sweep.h says what it answers). The box inflated
 * by thickness is the box with half_extents + thickness (square edges and
 * corners, not rounded ones). */
bool sb_box_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                  double* fraction, double* depth, double normal[3]);
/* The same with the box's rotation (sb_collider_rotation of def->rotate) given. */
bool sb_box_sweep_rotated(const sb_collider_def* def, const double rotation[9], const double from[3],
                          const double to[3], double thickness, double* fraction, double* depth, double normal[3]);

#endif
