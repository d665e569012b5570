/* Private: the capsule's sweep and line (kernels/contact/colliders/capsule.c). */
#ifndef SB_CAPSULE_H
#define SB_CAPSULE_H

#include "softbond/collider.h"

/* The capsule's sweep in its rest frame (collider_internal.h's sb_sweep_fn;
 * kernels/contact/colliders/sweep.h says what it answers);
 * a == b: the sphere about a. */
bool sb_capsule_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                      double* fraction, double* depth, double normal[3]);

/* The capsule of radius r about the segment a–b (capsule.c; the mesh's
 * rounded triangles): the interval [lo, hi] of the line from + s (to −
 * from) inside it with the outward normal at lo, for a line that enters it
 * from outside (false otherwise). */
bool sb_capsule_line(const double a[3], const double b[3], double r, const double from[3], const double to[3],
                     double* lo, double* hi, double normal[3]);

/* The outward normal a point on the axis takes (ab = b − a, ab2 = |ab|² >
 * 0): the unit normal to ab nearest the axis ab is least along. The SIMD
 * answer (kernels/contact/fast_contact.c) takes it from here, so both
 * round it alike. */
void sb_capsule_axis_normal(const double ab[3], double ab2, double normal[3]);

#endif
