/** @file
 * Colliders: what the soft bodies touch.
 *
 * After every step the solver asks each collider, for each free vertex,
 * about the vertex's move in that step (from its position at the start of
 * the step to where the integrator put it). A collider that the move touches
 * answers with an sb_contact: how far along the move the vertex may go, the
 * surface normal there, and how much of the vertex's velocity survives
 * (restitution along the normal, Coulomb friction along the surface). The
 * solver then moves the vertex and changes its velocity (DESIGN.md, section
 * Contact)
 * and adds the impulse it took to the collider's reaction force. pbd and
 * xpbd ask about the predicted move before their sweeps and keep the answer
 * as a constraint inside their projection sweeps; the velocity answer
 * is the same.
 *
 * The built-in sphere, capsule and box also meet the body's surface between
 * its vertices: the point of each nearby triangle nearest the collider is
 * asked about like a vertex, and the answer spread over the triangle's
 * corners (a program's own collider too, given sb_collider_set_triangle_point).
 *
 * The built-in shapes (plane, sphere, capsule, box, triangle mesh) are
 * colliders written on this same interface; a program's own collider is a
 * callback of the same type (sb_collider_create_custom). */
#ifndef SOFTBOND_COLLIDER_H
#define SOFTBOND_COLLIDER_H

#include "softbond/export.h"
#include "softbond/mesh.h"
#include "softbond/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** One vertex's move in one step. */
typedef struct sb_contact_query {
    uint32_t vertex; /**< the vertex's index in the solver (a tearing solver's copies included) */
    /** s: the time at the step's start */
    double t0, t1;    /**< s: the step runs from t0 to t1 */
    double from[3];   /**< m: the position at t0 */
    double to[3];     /**< m: where the integrator moved it by t1 */
    double thickness; /**< m: the solver's contact thickness, added to the collider's own */
} sb_contact_query;

/** A collider's answer for a move that touches it. */
typedef struct sb_contact {
    /** In [0, 1]: the first point of the move, from + fraction (to − from),
     * on the collider's surface inflated by both thicknesses. A move from
     * inside (or on the surface) to inside is resting contact: fraction 1
     * and the depth of `to`; one from inside heading in: fraction 0 and the
     * depth of `from`. */
    double fraction;
    /** m, >= 0: how far that point lies inside the inflated surface (0 for a
     * move that met the surface from outside); the solver pushes the vertex
     * out by it along the normal. */
    double depth;
    double normal[3];       /**< unit, out of the collider, at the contact */
    double velocity[3];     /**< m/s: the collider's own velocity at the contact (0 when it does not move) */
    double restitution;     /**< in [0, 1]: normal velocity after = −restitution × normal velocity before */
    double friction;        /**< >= 0: Coulomb coefficient while sliding */
    double static_friction; /**< >= friction: the coefficient below which the vertex sticks */
    /** m: the point of the collider's (inflated) surface the vertex met, in
     * the world at t1; the solver takes the torque of the impulse about a
     * dynamic collider's center there. The built-in colliders fill it; a
     * program's own may leave it (it is never dynamic). */
    double point[3];
} sb_contact;

/** Returns true and fills *contact when the move touches the collider.
 * Called from the solver's threads at once, for different vertices: it must
 * only read its own data (update it in a begin-step callback). */
typedef bool (*sb_collide_fn)(void* user, const sb_contact_query* query, sb_contact* contact);

/** Optional, for a program's own collider (sb_collider_set_triangle_point):
 * which point of a triangle of the body's surface the collider would meet.
 * `from` holds the triangle's corners at the step's start, `to` where the
 * integrator moved them by its end (m, world). Returns false when the
 * triangle is nowhere near; otherwise true and the barycentric weights
 * (each >= 0, summing to 1) of the point of the triangle nearest the
 * collider, or of the one the collider passed through within the step. The
 * solver then asks the collide callback about that point's move, from
 * Σ w_i from_i to Σ w_i to_i (query.vertex: the corner of the largest
 * weight), and spreads the answer over the corners (DESIGN.md, section
 * Contact). Called on one of the solver's threads, between the collide
 * calls of the same step: it must only read its data. Weights that are not
 * finite, negative or do not sum to 1 (within 1e-6) are ignored. */
typedef bool (*sb_triangle_point_fn)(void* user, const double from[3][3], const double to[3][3], double weights[3]);

/** Called once per step, on the thread that advances the solver, before any
 * sb_collide_fn of that step: a collider that moves sets its pose for
 * [t0, t1] here. May be NULL. */
typedef void (*sb_collider_step_fn)(void* user, double t0, double t1);

/** The built-in colliders' shapes (sb_collider_def.shape). */
typedef enum sb_collider_shape {
    SB_COLLIDER_PLANE = 0,  /**< the half-space below point, normal */
    SB_COLLIDER_SPHERE,     /**< center, radius */
    SB_COLLIDER_CAPSULE,    /**< the segment a–b, radius */
    SB_COLLIDER_BOX,        /**< center, half_extents, rotate (degrees about x, then y, then z) */
    SB_COLLIDER_MESH,       /**< a triangle mesh: its volume when closed, a shell of the thickness when open */
    SB_COLLIDER_SHAPE_COUNT /**< the number of shapes, not a shape */
} sb_collider_shape;

/** How a path's pose goes from one keyframe to the next: translate and
 * rotate are blended with a weight w of s, the fraction of the interval
 * elapsed, s in [0, 1]. */
typedef enum sb_interpolation {
    SB_INTERPOLATION_LINEAR = 0, /**< w = s: constant velocity, which jumps at each keyframe */
    SB_INTERPOLATION_SMOOTH      /**< w = s² (3 − 2s) (smoothstep): at rest at every keyframe */
} sb_interpolation;

/** A pose of a kinematic collider at a time: rotate (degrees about the
 * collider's reference point — plane point, sphere or box center, capsule
 * midpoint, the center of a mesh's bounding box — about x, then y, then
 * z), then translate. */
typedef struct sb_keyframe {
    double time;         /**< s */
    double translate[3]; /**< m */
    double rotate[3];    /**< degrees */
} sb_keyframe;

/** Fields of other shapes are ignored (and not checked). static_friction
 * left at 0 while friction > 0 becomes friction. */
typedef struct sb_collider_def {
    sb_collider_shape shape; /**< which of the fields below apply */
    const char* name;        /**< how logs and handles refer to it; copied */
    /** m: plane, a point on it */
    double point[3], normal[3]; /**< plane (normal need not be unit; not zero) */
    double center[3];           /**< sphere, box */
    double radius;              /**< sphere, capsule (m, > 0) */
    /** m: capsule, one end of its segment */
    double a[3], b[3];      /**< capsule */
    double half_extents[3]; /**< box (m, > 0) */
    double rotate[3];       /**< box: degrees about x, then y, then z */
    /** mesh: the triangles, in world coordinates (place them first with
     * sb_mesh_transform; copied, with a bounding-volume hierarchy built
     * over them). A closed mesh (every edge on two triangles) is solid
     * inside: the volume it encloses, inflated by the thickness, its
     * winding made outward if it faces in (a closed mesh whose triangles
     * disagree about the winding is refused). An open mesh (a sheet, a
     * bowl, a mesh with an edge on three triangles) encloses nothing: it
     * is a shell of the points within the thickness of its surface, so its
     * thickness must be > 0. A triangle of zero area is refused. */
    const sb_mesh* mesh;
    double friction;        /**< Coulomb, sliding (>= 0) */
    double static_friction; /**< sticking (>= friction; default: friction) */
    double restitution;     /**< [0, 1] */
    double thickness;       /**< m, >= 0: the surface is inflated by it */
    /** sphere, capsule, box, mesh: m, >= 0. 0 (the default): the collider
     * stops the body's vertices and, between them, the points of its
     * triangles, each contact's load spread over the triangle's corners by
     * their barycentric weights. > 0: the radius of the patch of the
     * body's surface (measured at rest) that each contact presses: the
     * collider stops the patch's weighted mean position, its load spread
     * over the patch's vertices by the same weights, which fall smoothly
     * from the point of contact to 0 at this distance (no vertex is
     * answered on its own). A tool smaller than the mesh's spacing then
     * feels nearly the same stiffness over a vertex as between vertices,
     * where a load held by one vertex of a spring net meets a softer net
     * than one shared; in exchange the body deforms as under a tool of
     * this radius, and its vertices may lie inside the collider by what
     * the patch's mean rounds off a sharp dent. It must be at least the
     * longest edge of the body's surface at rest, and cannot be used with
     * tearing (max_splits > 0). About twice the spacing removes the bump
     * (docs/contact.md). */
    double footprint;
    const sb_keyframe* path;        /**< kinematic: keyframes in increasing time (copied); NULL = static */
    uint32_t path_count;            /**< the keyframes in path; 0 = static */
    sb_interpolation interpolation; /**< between keyframes; before the first and after the last the pose holds */
    /** Dynamic (two-way) colliders: a sphere or box with mass > 0 (kg) is a
     * rigid body the solver moves, a solid one: its inertia about its
     * center is 2/5 mass radius² (sphere) or mass/3 (h_j² + h_k²) about the
     * box's own axis i (h its half_extents). In each accepted step it takes
     * the sum of the contact impulses J it received and their torque τ
     * about its center (the opposites of what the vertices took, summed in
     * a fixed order: the same for any thread count) and gravity (the
     * solver's def.gravity): v += J / mass + g dt, L += τ (L = I ω, its
     * angular momentum); its pose in the next step moves by v dt and turns
     * by ω dt (symplectic Euler), and the vertices it touches are answered
     * with the velocity of its point they meet (v + ω × r), as for a
     * kinematic collider. So friction spins it, and a spinning body drags
     * what it touches. Not affected by the solver's drag; it touches only
     * the soft bodies (no contact with other colliders). 0 = static or
     * kinematic; a dynamic collider cannot have a path; a plane, capsule
     * or mesh cannot be dynamic. Attach it to one solver at a time: every
     * solver it is attached to moves it. */
    double mass;                /**< kg, >= 0 */
    double velocity[3];         /**< m/s: a dynamic collider's velocity at the start */
    double angular_velocity[3]; /**< rad/s, world frame: a dynamic collider's spin at the start */
} sb_collider_def;

/** A plane through the origin with normal +z, no friction, no restitution,
 * no thickness, static. */
SB_API sb_collider_def sb_default_collider_def(void);

/** A collider: a built-in shape (sb_collider_create) or a program's own
 * (sb_collider_create_custom). Opaque. */
typedef struct sb_collider sb_collider;

/** A built-in collider, checked (a message names the bad field). */
SB_API sb_collider* sb_collider_create(const sb_collider_def* def, sb_error* err);
/** A program's own collider: collide (required) and begin_step (may be NULL)
 * with their user data. */
SB_API sb_collider* sb_collider_create_custom(const char* name, sb_collide_fn collide, sb_collider_step_fn begin_step,
                                              void* user, sb_error* err);
/** Lets a program's own collider meet the body's surface between its
 * vertices, as the built-in sphere, capsule and box do: triangle_point (NULL:
 * vertices only, the default) names the point of a triangle to answer.
 * Give the collider bounds (sb_collider_set_bounds): the solver asks it
 * about the triangles whose moves reach them. Does nothing to a built-in
 * collider. Call it before making a solver with the collider. */
SB_API void sb_collider_set_triangle_point(sb_collider* collider, sb_triangle_point_fn triangle_point);
/** Frees the collider (its copied path and mesh with it); safe on NULL.
 * Destroy every solver it is attached to first. */
SB_API void sb_collider_destroy(sb_collider* collider);

/** Drives a built-in collider from the program (a tool held by a haptic
 * device, a mouse): the pose it reaches at the end of the next step,
 * rotate (degrees about x, then y, then z, about its reference point) then
 * translate, as a keyframe's; during that step it moves from its last pose
 * to this one, and the vertices it sweeps are answered with its velocity.
 * From the first call on it overrides the path. Call it from the thread
 * that advances the solver, between steps. Does nothing to a program's own
 * collider, which moves itself in its begin-step callback, nor to a dynamic
 * one, which the solver moves. */
SB_API void sb_collider_set_pose(sb_collider* collider, const double translate[3], const double rotate[3]);

/** A built-in sphere's or box's center and velocity now (m, m/s): a dynamic
 * collider's as the solver moved it, a kinematic one's center at the end of
 * its last step with its velocity over that step, a static one's center and
 * zero. A plane's point, a capsule's midpoint, the center of a mesh's
 * bounding box; a program's own collider: zeros. Either output may be
 * NULL. */
SB_API void sb_collider_state(const sb_collider* collider, double position[3], double velocity[3]);

/** A built-in collider's orientation now (row-major rotation from its def's
 * rest frame: the identity for a static one) and angular velocity (rad/s,
 * world frame): a dynamic collider's as the solver turned it, a kinematic
 * one's at the end of its last step with its mean angular velocity over
 * that step; a program's own collider: the identity and zero. Either
 * output may be NULL. */
SB_API void sb_collider_orientation(const sb_collider* collider, double rotation[9], double angular_velocity[3]);

/** Where a program's own collider can be touched until it says otherwise
 * (an axis-aligned box, inflated by its thickness; NULL, NULL: everywhere,
 * the default). The contact pass asks the collider only about moves that
 * reach into the box: a collider that knows where it is should say, from
 * its begin-step callback if it moves. The built-in shapes set their own. */
SB_API void sb_collider_set_bounds(sb_collider* collider, const double lo[3], const double hi[3]);
/** How far a built-in collider may move in one step without a vertex it
 * meets passing its middle (m): the radius of a sphere or capsule, the
 * smallest half extent of a box, half the smallest extent of a mesh's box
 * (an estimate: a ring is thinner than its box), each plus the thickness;
 * a plane and a program's own collider: infinity. A contact pushes a vertex
 * out of the nearest face, so a tool moved further than this in one step
 * can push what it passes through out of its far side. */
SB_API double sb_collider_inner_radius(const sb_collider* collider);
/** The collider's name as copied at creation (cut to 63 bytes): the def's
 * name, or when that was NULL or empty the shape's name ("sphere", ...) or
 * "custom" for a program's own. Owned by the collider; NULL for a NULL
 * collider. */
SB_API const char* sb_collider_name(const sb_collider* collider);

/** "plane", "sphere", "capsule", "box", "mesh". */
SB_API const char* sb_collider_shape_name(sb_collider_shape shape);
/** The shape named by one of those names: true and *out set (out may be
 * NULL); false, *out untouched, for another name or NULL. */
SB_API bool sb_collider_shape_from_name(const char* name, sb_collider_shape* out);

#ifdef __cplusplus
}
#endif
#endif
