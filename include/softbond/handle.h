/** @file
 * Handles: vertices driven to a pose that changes with time (a hook, a
 * grasper, a pulled vertex).
 *
 * A handle holds a set of vertices and a rigid pose, pose(t)(x) = R (x − c)
 * + c + T, from keyframes (sb_keyframe and sb_interpolation, as a
 * collider's path) or set by the program each step (sb_handle_set_pose).
 * When it grabs its vertices (when the solver is created, and at each
 * sb_handle_grab) it keeps their positions p in its rest frame, q =
 * pose(t_grab)⁻¹ p; the target of each vertex is then pose(t)(q): the grab
 * does not move them, and they follow the pose from there.
 *
 * A hard handle (stiffness 0) works by position, not by velocity, so it
 * never lags its target: at the end of every step its vertices are exactly
 * at their targets, with the target's velocity over the step
 * ((target(t1) − target(t0)) / dt), and while held they are fixed vertices
 * for the integration (DESIGN.md, section Handles, says where each
 * integrator does it).
 * A soft handle (stiffness > 0) is a spring-damper between each vertex and
 * its target, f = stiffness (target − x) + damping (target velocity − v),
 * a force like the external callback's: every integrator sees it, the
 * adaptive stepper counts its work. sb_handle_force reports the sum of these
 * forces over the handle's vertices, the force the handle exerts on the
 * body (a grasper feels the opposite).
 *
 * Handles are attached through sb_solver_def.handles and must outlive the
 * solver; attach a handle to one solver at a time. Release and grab it on
 * the thread that advances the solver, between steps: a released vertex is
 * free again with the velocity it had. */
#ifndef SOFTBOND_HANDLE_H
#define SOFTBOND_HANDLE_H

#include "softbond/export.h"
#include "softbond/collider.h"
#include "softbond/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A handle's definition (sb_handle_create copies what it needs). */
typedef struct sb_handle_def {
    const char* name;         /**< how logs refer to it; copied */
    const uint32_t* vertices; /**< the model's vertices it holds (copied; at least one, none twice) */
    uint32_t vertex_count;    /**< the entries of vertices, >= 1 */
    /** m: the point the pose's rotations turn about; NULL = the centroid of
     * the vertices' rest positions (copied) */
    const double* center;
    double stiffness;               /**< N/m per vertex, >= 0: 0 = hard, > 0 = soft */
    double damping;                 /**< N·s/m per vertex, >= 0 (soft handles) */
    const sb_keyframe* path;        /**< keyframes in increasing time (copied); NULL = the pose stays the identity */
    uint32_t path_count;            /**< the keyframes in path; 0 = the identity pose */
    sb_interpolation interpolation; /**< between keyframes; before the first and after the last the pose holds */
    /** s: the handle lets go at the end of the first step that reaches this
     * time (once; a later sb_handle_grab holds again); INFINITY = never */
    double release_time;
} sb_handle_def;

/** No vertices, hard, no path, linear, never released. */
SB_API sb_handle_def sb_default_handle_def(void);

/** A handle (sb_handle_create); opaque. */
typedef struct sb_handle sb_handle;

/** Checked (the message names the handle and the bad field); the vertex
 * indices are checked against the model when the solver is created. */
SB_API sb_handle* sb_handle_create(const sb_handle_def* def, sb_error* err);
/** Frees the handle; safe on NULL. Destroy the solver it is attached to
 * first. */
SB_API void sb_handle_destroy(sb_handle* handle);

/** The pose the handle reaches at the end of the next step (rotate degrees
 * about x, then y, then z about the center, then translate); during that
 * step it moves from its last pose to this one. From the first call on it
 * overrides the path. */
SB_API void sb_handle_set_pose(sb_handle* handle, const double translate[3], const double rotate[3]);
/** Lets the vertices go (they keep their velocities) / holds them again
 * where they are now. SB_ERR_INVALID when the handle is not attached to a
 * solver (grab). */
SB_API void sb_handle_release(sb_handle* handle);
/** Holds the handle's vertices again, grabbed where they are now (see
 * sb_handle_release): SB_OK, or SB_ERR_INVALID when the handle is not
 * attached to a solver. */
SB_API sb_status sb_handle_grab(sb_handle* handle);
/** Whether the handle holds its vertices: true from creation until it is
 * released (sb_handle_release or release_time), true again after a grab. */
SB_API bool sb_handle_held(const sb_handle* handle);
/** A handle of one vertex (a mouse that picks any vertex): holds `vertex`
 * instead, grabbed where it is now (its target there, the pose unchanged).
 * SB_ERR_INVALID when the handle holds more than one vertex, is not
 * attached to a solver, or the vertex is not in the solver's model. */
SB_API sb_status sb_handle_grab_vertex(sb_handle* handle, uint32_t vertex);
/** The force (N) a soft handle exerted on the body at the last force
 * evaluation of the last step; zeros for a hard or released handle. */
SB_API void sb_handle_force(const sb_handle* handle, double force[3]);
/** Vertex k's target (m) at the end of the last step. */
SB_API void sb_handle_target(const sb_handle* handle, uint32_t k, double target[3]);
/** The handle's name as copied at creation (cut to 63 bytes; "handle"
 * when the def's was NULL). Owned by the handle. */
SB_API const char* sb_handle_name(const sb_handle* handle);
/** The number of vertices the handle holds (its def's vertex_count). */
SB_API uint32_t sb_handle_vertex_count(const sb_handle* handle);

#ifdef __cplusplus
}
#endif
#endif
