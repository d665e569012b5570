/* Private: a collider's or a handle's rotation from its angles. */
#ifndef SB_ROTATION_H
#define SB_ROTATION_H

/* The rotation (row-major) of `degrees` about x, then y, then z (fixed
 * axes); exact at multiples of 90 degrees. */
void sb_collider_rotation(const double degrees[3], double r[9]);

#endif
