/** @file
 * Blades: cutting. A blade is a kinematic edge, the segment
 * between two points, that moves along a keyframed path (sb_keyframe and
 * sb_interpolation, as a collider's; the pose turns about the edge's
 * midpoint). Each step it sweeps a surface, the edge at the step's start to
 * the edge at its end (two triangles); every bond whose segment, at the
 * step's end, crosses that surface is severed: it breaks as a bond past its
 * limits does (DESIGN.md, section Breakage: no stiffness or damping any more, the
 * triangles and hinges on its edge with it, the breakage callback, the
 * surface split where the cut runs, as tearing splits it). A blade that does
 * not move cuts nothing. Bonds are looked at in bond order, blades in
 * their order: the same cuts for any thread count. */
#ifndef SOFTBOND_BLADE_H
#define SOFTBOND_BLADE_H

#include "softbond/collider.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A blade (sb_solver_def.blades; the solver copies it). */
typedef struct sb_blade_def {
    /** m: one end of the edge at time 0; a and b distinct */
    double a[3], b[3];              /**< the edge's ends at time 0 (before the path's pose), m; distinct */
    const sb_keyframe* path;        /**< keyframes in increasing time, copied by the solver; NULL = static */
    uint32_t path_count;            /**< the keyframes in path; 0 = static */
    sb_interpolation interpolation; /**< between keyframes; before the first and after the last the pose holds */
} sb_blade_def;

#ifdef __cplusplus
}
#endif
#endif
