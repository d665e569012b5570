/** @file
 * softbond: real-time soft bodies with molecular-mechanics bonded terms. */
#ifndef SOFTBOND_H
#define SOFTBOND_H

#include "softbond/types.h"
#include "softbond/mesh.h"
#include "softbond/builder.h"
#include "softbond/volume.h"
#include "softbond/pov.h"
#include "softbond/model.h"
#include "softbond/reference.h"
#include "softbond/solver.h"
#include "softbond/runtime.h"
#include "softbond/state_buffer.h"
#include "softbond/haptics.h"

#endif
