/* Private: the changing state of a simulation, apart from the immutable model:
 * structure-of-arrays in sb_real. */
#ifndef SB_STATE_H
#define SB_STATE_H

#include "softbond/types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sb_state {
    uint32_t vertex_count;
    sb_real *x, *y, *z;    /* positions, m */
    sb_real *vx, *vy, *vz; /* velocities, m/s */
    sb_real *fx, *fy, *fz; /* total force at the current positions, N */
} sb_state;

#ifdef __cplusplus
}
#endif
#endif
