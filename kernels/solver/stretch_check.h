/* Private: the blow-up rule of softbond/solver.h (kernels/solver/stretch_check.c). */
#ifndef SB_STRETCH_CHECK_H
#define SB_STRETCH_CHECK_H

#include "kernels/state/solver_data.h"

/* Every SB_STRETCH_INTERVAL-th advance: fails with SB_ERR_UNSTABLE naming
 * the first bond (in a model without bonds, the first triangle edge) past
 * SB_STRETCH_LIMIT times its rest length. */
sb_status sb_check_stretch(sb_solver* solver);

#endif
