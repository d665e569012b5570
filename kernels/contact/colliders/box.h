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
/* The sign (1, 0 or −1) of the dot product of the box's axes a and b
 * (columns of its rotation) as sb_sweep_from_inside rounds it for two of
 * its faces' normals: the SIMD answer (kernels/contact/fast_contact.c,
 * compiled with fused multiply-adds) takes it from here. */
int sb_box_axes_facing(const double rotation[9], int a, int b);

#endif
