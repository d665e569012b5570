/* Private: the built-in shapes' bounds over a step (kernels/contact/colliders/bounds.c). */
#ifndef SB_BOUNDS_H
#define SB_BOUNDS_H

#include "softbond/collider.h"

/* The built-in shape's bounds for its poses at t0 and t1 (kernels/contact/colliders/bounds.c). */
void sb_collider_step_bounds(sb_collider* collider);

#endif
