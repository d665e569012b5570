/* Private: a collider as the solver sees it (softbond/collider.h). Built-in
 * shapes fill the same three fields as a program's own collider, with
 * user = the collider itself.
 * The built-in shapes' sweeps answer as kernels/contact/colliders/sweep.h
 * says. Each shape's functions are declared in its own header beside this
 * one (plane.h, sphere.h, capsule.h, box.h, mesh_shape.h), as are the
 * dynamic colliders' (dynamic.h) and the bounds' (bounds.h); this one keeps
 * collider.c's: the saved state, the poses and the paths. */
#ifndef SB_COLLIDER_INTERNAL_H
#define SB_COLLIDER_INTERNAL_H

#include "softbond/collider.h"
#include "common/sections.h"

struct sb_collider {
    char name[64];
    sb_collide_fn collide;
    sb_collider_step_fn begin_step;      /* may be NULL */
    sb_triangle_point_fn triangle_point; /* a program's own collider's, may be NULL */
    void* user;
    /* Where the collider can be touched during the current step (lo x y z,
     * hi x y z, m, inflated by its own thickness): the contact pass skips
     * every vertex whose move lies outside. Infinite unless the collider
     * says (built-in shapes in their begin step; a program's own through
     * sb_collider_set_bounds). */
    double bounds[6];
    /* built-in shapes only: their definition (path copied) and the pose of
     * the current step (kernels/contact/colliders/collider.c) */
    sb_collider_def def; /* def.name = name, def.path = path */
    sb_keyframe* path;
    double pose0[12], pose1[12]; /* rotation (row-major 3x3) and translation at t0 and t1 */
    double t0, t1;
    /* sb_collider_set_pose: the pose the program set for the end of the
     * next step (it then moves from its last pose to this one) */
    bool driven;
    double driven_pose[12];
    double box_rotation[9];     /* box: sb_collider_rotation(def.rotate), made once */
    struct sb_mesh_shape* mesh; /* mesh: the copy and its hierarchy (mesh.c); def.mesh is its mesh */
    /* dynamic (def.mass > 0; kernels/contact/colliders/dynamic.c): the center now,
     * its velocity, and where the current step takes it (position +
     * velocity (t1 − t0), set by begin_step); its orientation (a unit
     * quaternion w x y z, from the rest frame), where the step turns it,
     * its angular momentum about the center (world), its principal moments
     * of inertia and their axes in the rest frame (row-major, columns) */
    bool dynamic;
    double position[3], velocity[3], next_position[3];
    double orientation[4], next_orientation[4], angular_momentum[3], inertia[3], body_axes[9];
};

/* The collider's state that changes as it runs (the saved state,
 * kernels/solver/solver_state.c): written, and read back from as many bytes as
 * sb_collider_save writes (the caller checked the length). A program's own
 * collider keeps its own state in its user data. */
void sb_collider_save(const sb_collider* collider, sb_sections_writer* w);
void sb_collider_load(sb_collider* collider, sb_cursor* r);

/* def.footprint, m: > 0 where the collider presses patches of the body's
 * surface (kernels/contact/surface.c) and no vertex on its own; 0 for a
 * program's own collider. */
double sb_collider_footprint(const sb_collider* collider);

/* Whether the collider is a built-in shape that stands still in the world
 * through the current step (no path, not driven, not dynamic): its rest
 * frame is the world, and it answers with zero velocity. */
bool sb_collider_is_static_builtin(const sb_collider* collider);

/* A shape's sweep in its rest frame (see above). */
typedef bool (*sb_sweep_fn)(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                            double* fraction, double* depth, double normal[3]);

/* A built-in collider's pose at time t: rotation (row-major 3x3) then
 * translation; identity when it has no path. */
void sb_collider_pose(const sb_collider* collider, double t, double pose[12]);

/* Whether the collider stops the body's surface as well as its vertices
 * (the built-in sphere, capsule and box, and a program's own collider with
 * a triangle_point callback: kernels/contact/surface.c). */
bool sb_collider_meets_surface(const sb_collider* collider);
/* For such a collider, the barycentric weights w of the material point of
 * a triangle that moved from `from` to `to` in the step (its corners in
 * the world) nearest the collider's core (the center, the segment, the
 * box's edges) in its rest frame, or the point the core passed through
 * within the step (kernels/contact/colliders/triangle_point.h); false for
 * a collider that does not meet the surface. */
bool sb_collider_triangle_point(const sb_collider* collider, const double from[3][3], const double to[3][3],
                                double w[3]);

/* For such a collider, a ball (world, m) that holds it, inflated by its
 * own thickness, all through the current step: the surface pass's test of
 * a triangle's box (a program's own: the ball around its bounds). */
void sb_collider_surface_ball(const sb_collider* collider, double center[3], double* radius);

/* Keyframed poses, shared with the handles (kernels/interaction/handle.c). A pose is a
 * rotation (row-major 3x3) then a translation: pose(x) = R (x − c) + c + T
 * for the keyframe's rotate (degrees, R = Rz Ry Rx) and translate T about
 * the reference point c. */
void sb_pose_from(const double translate[3], const double rotate[3], const double center[3], double pose[12]);
/* The pose of a path at time t (interpolated as above; the identity
 * without keyframes). */
void sb_path_pose(const sb_keyframe* path, uint32_t count, sb_interpolation interpolation, const double center[3],
                  double t, double pose[12]);
/* y = pose(x) */
void sb_pose_apply(const double pose[12], const double x[3], double y[3]);
/* The keyframes are in increasing, finite time with finite poses and the
 * interpolation is known; `owner` ("collider 'name'") starts the message. */
sb_status sb_path_check(const char* owner, const sb_keyframe* path, uint32_t count, sb_interpolation interpolation,
                        sb_error* err);

#endif
