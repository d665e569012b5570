/* Private: a collider as the solver sees it (softbond/collider.h). Built-in
 * shapes fill the same three fields as a program's own collider, with
 * user = the collider itself.
 * The built-in shapes' sweeps answer as kernels/contact/colliders/sweep.h
 * says. */
#ifndef SB_COLLIDER_INTERNAL_H
#define SB_COLLIDER_INTERNAL_H

#include "softbond/collider.h"
#include "softbond/mesh.h"
#include "common/sections.h"

struct sb_collider {
    char name[64];
    sb_collide_fn collide;
    sb_collider_step_fn begin_step; /* may be NULL */
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

/* A dynamic collider's motion (kernels/contact/colliders/dynamic.c). Its state
 * from its def (center, velocity, angular_velocity; inertia from mass and
 * shape), called once by sb_collider_create. */
void sb_dynamic_init(sb_collider* collider);
/* The torque (N m s) about the center at the end of the step of an impulse
 * (N s) the collider receives at `point` (m, world at t1); zero for a
 * collider that is not dynamic. */
void sb_collider_torque(const sb_collider* collider, const double point[3], const double impulse[3], double torque[3]);
/* After a step the solver keeps (each accepted step, in order), the
 * collider takes the impulse and the torque it received in it and gravity
 * (m/s²) over dt (s): it moves and turns to where the step's pose took it,
 * v += impulse / mass + gravity dt, L += torque. Does nothing to a collider
 * that is not dynamic. */
void sb_collider_after_step(sb_collider* collider, const double impulse[3], const double torque[3],
                            const double gravity[3], double dt);
/* The same for each of `count` colliders: `impulses` holds 3 impulses per
 * collider, then 3 torques per collider (the solver's contact_step). */
void sb_colliders_after_step(sb_collider* const* colliders, uint32_t count, const double* impulses,
                             const double gravity[3], double dt);
/* The work (J) the dynamic ones among `count` colliders would do on the
 * soft bodies in the step just taken if it were kept: the energy (kinetic,
 * translational and the torque's rotational part, and in gravity) they
 * would lose by sb_collider_after_step (impulses then torques, as there).
 * The adaptive step's energy balance counts it as external work. */
double sb_colliders_step_work(sb_collider* const* colliders, uint32_t count, const double* impulses,
                              const double gravity[3], double dt);
/* Their kinetic energy (translation and rotation) plus the size of their
 * energy in gravity (J): the adaptive step's energy scale counts them. */
double sb_colliders_energy_scale(sb_collider* const* colliders, uint32_t count, const double gravity[3]);
/* begin_step of a dynamic collider: its poses for [t0, t1]. */
void sb_dynamic_begin_step(sb_collider* collider, double t0, double t1);
/* A dynamic collider's orientation now (row-major, from the rest frame)
 * and angular velocity (rad/s, world). */
void sb_dynamic_spin(const sb_collider* collider, double rotation[9], double angular_velocity[3]);

/* The collider's state that changes as it runs (the saved state,
 * kernels/solver/solver_state.c): written, and read back from as many bytes as
 * sb_collider_save writes (the caller checked the length). A program's own
 * collider keeps its own state in its user data. */
void sb_collider_save(const sb_collider* collider, sb_sections_writer* w);
void sb_collider_load(sb_collider* collider, sb_cursor* r);

/* The built-in shape's bounds for its poses at t0 and t1 (kernels/contact/colliders/bounds.c). */
void sb_collider_step_bounds(sb_collider* collider);

/* A shape's sweep in its rest frame (see above). */
typedef bool (*sb_sweep_fn)(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                            double* fraction, double* depth, double normal[3]);
bool sb_plane_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                    double* fraction, double* depth, double normal[3]);
bool sb_sphere_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                     double* fraction, double* depth, double normal[3]);
/* a == b: the sphere about a. */
bool sb_capsule_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                      double* fraction, double* depth, double normal[3]);
/* The box inflated by thickness is the box with half_extents + thickness
 * (square edges and corners, not rounded ones). */
bool sb_box_sweep(const sb_collider_def* def, const double from[3], const double to[3], double thickness,
                  double* fraction, double* depth, double normal[3]);
/* The same with the box's rotation (sb_collider_rotation of def->rotate) given. */
bool sb_box_sweep_rotated(const sb_collider_def* def, const double rotation[9], const double from[3],
                          const double to[3], double thickness, double* fraction, double* depth, double normal[3]);

/* The ball of radius r about center (sphere.c; the capsule's end caps):
 * its sweep, and the interval [lo, hi] of the line from + s (to − from)
 * inside it with the outward normal at lo, for a line that enters it from
 * outside (false otherwise, and for a tangent line). */
bool sb_ball_sweep(const double center[3], double r, const double from[3], const double to[3], double* fraction,
                   double* depth, double normal[3]);
bool sb_ball_line(const double center[3], double r, const double from[3], const double to[3], double* lo, double* hi,
                  double normal[3]);
/* The capsule of radius r about the segment a–b (capsule.c; the mesh's
 * rounded triangles): the interval [lo, hi] of the line from + s (to −
 * from) inside it with the outward normal at lo, for a line that enters it
 * from outside (false otherwise). */
bool sb_capsule_line(const double a[3], const double b[3], double r, const double from[3], const double to[3],
                     double* lo, double* hi, double normal[3]);

/* The triangle mesh of a mesh collider (mesh.c): a copy of the def's mesh
 * with its bounding-volume hierarchy. Checked as it is made: at least one
 * triangle, indices in range, finite positions, no triangle of zero area;
 * a closed mesh consistently oriented (it is turned outward when it faces
 * in); an open one only with thickness > 0. Messages name the collider
 * (label) and the element. */
typedef struct sb_mesh_shape sb_mesh_shape;
sb_mesh_shape* sb_mesh_shape_create(const char* label, const sb_mesh* mesh, double thickness, sb_error* err);
void sb_mesh_shape_destroy(sb_mesh_shape* shape);
/* Its copy of the mesh (triangles in the hierarchy's order, wound outward
 * when closed) and the box around it (lo x y z, hi x y z). */
const sb_mesh* sb_mesh_shape_mesh(const sb_mesh_shape* shape);
void sb_mesh_shape_box(const sb_mesh_shape* shape, double box[6]);
/* The mesh's sweep (see above and mesh.c): a closed mesh bounds its volume,
 * an open one is a shell of the thickness around its surface. */
bool sb_mesh_sweep(const sb_mesh_shape* shape, const double from[3], const double to[3], double thickness,
                   double* fraction, double* depth, double normal[3]);

/* A built-in collider's pose at time t: rotation (row-major 3x3) then
 * translation; identity when it has no path. */
void sb_collider_pose(const sb_collider* collider, double t, double pose[12]);

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
