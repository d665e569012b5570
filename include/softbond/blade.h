/** @file
 * Blades: cutting. A blade is a kinematic edge, the segment
 * between two points, that moves along a keyframed path (sb_keyframe and
 * sb_interpolation, as a collider's; the pose turns about the edge's
 * midpoint). Over each step the edge and the tissue both move, continuously
 * in time; every bond that meets the edge during the step is severed, so
 * no bond slips past a blade however fast either moves: it breaks as a
 * bond past its limits does (DESIGN.md, section Breakage: no stiffness or
 * damping any more, the triangles and hinges on its edge with it, the
 * breakage callback, the surface split where the cut runs, as tearing
 * splits it). A blade held still cuts tissue pulled across it, and nothing
 * in tissue at rest. With sb_solver_def.cut_through the blades split the
 * triangles they pass through along their path instead (the incision lies
 * where they went). Bonds are looked at in bond order, blades in their
 * order: the same cuts for any thread count. */
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
