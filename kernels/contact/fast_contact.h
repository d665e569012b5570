/* Private: the contact of the static built-in planes, spheres, capsules
 * and boxes answered in SIMD over the packed state
 * (kernels/contact/fast_contact.c), beside the scalar reference of
 * kernels/contact/contact.c. */
#ifndef SB_FAST_CONTACT_H
#define SB_FAST_CONTACT_H

#include "kernels/state/solver_data.h"

/* How the kernel sees one collider in a step. */
typedef enum sb_fast_shape_kind {
    SB_FAST_SHAPE_NONE = 0, /* answered by the scalar reference */
    SB_FAST_SHAPE_PLANE,
    SB_FAST_SHAPE_SPHERE,
    SB_FAST_SHAPE_CAPSULE,
    SB_FAST_SHAPE_BOX
} sb_fast_shape_kind;

typedef struct sb_fast_shape {
    sb_fast_shape_kind kind;
    sb_real origin[4];  /* plane: its point; sphere, box: the center; capsule: a (w 0) */
    sb_real normal[4];  /* plane: its unit normal; capsule: the normal on its axis (w 0) */
    sb_real axis[3][4]; /* box: its axes; capsule: b − a, the unit axis, b (w 0) */
    sb_real extent[3];  /* box: half extents + thickness; capsule: |b − a|, |b − a|² */
    sb_real facing[3];  /* box: the signs (1, 0, −1) of its axes' dot products 01 02 12 in double */
    sb_real reach;      /* plane: the thickness; sphere, capsule: radius + thickness */
    sb_real restitution, friction, static_friction;
} sb_fast_shape;

/* The colliders of a step as the kernel sees them. */
typedef struct sb_fast_colliders {
    uint64_t simd; /* a bit for each collider the kernel answers */
    sb_fast_shape shape[SB_MAX_COLLIDERS];
} sb_fast_colliders;

/* The kernel's view of the colliders for the current step: the static
 * built-in planes, spheres, capsules (a = b: the ball about a) and boxes
 * (sb_collider_is_static_builtin), the solver's contact thickness added to
 * their own. None where a register does not hold whole packed vertices
 * (the scalar SIMD variant). */
void sb_fast_colliders_set(sb_fast_colliders* out, sb_collider* const* colliders, uint32_t count,
                           double contact_thickness);

/* A run of consecutive vertices of the packed state, from its first one:
 * positions, velocities, Verlet displacements and forces (x y z w, w 0),
 * masses and inverse masses (one real a vertex). */
typedef struct sb_packed_run {
    sb_real *x, *v, *d, *f;
    const sb_real *mass, *inv_mass;
    uint32_t count;
} sb_packed_run;

/* The step's constants the answer needs: its dt, the drag and gravity of
 * a force's starting value m (g − drag v); and, where a feature follows
 * the contacts (body restitution), touch(user, i, collider, contact,
 * impulse) for each vertex answered, i counted from the run's first vertex
 * `first` (the contact's normal, restitution and point, the collider at
 * rest; the impulse m Δv). */
typedef struct sb_fast_contact_step {
    double dt, drag, gravity[3];
    void (*touch)(void* user, uint32_t i, int collider, const sb_contact* contact, const double impulse[3]);
    void* user;
    uint32_t first;
} sb_fast_contact_step;

/* Vertices per register (SB_WIDTH, one a lane); 0 where no answer is in SIMD. */
uint32_t sb_fast_contact_granule(void);

/* Answers the moves (from x − d to x) of the first vertices of the run,
 * the whole registers of it (the count rounded down to the granule),
 * against the colliders of `near`, every one of them in `colliders->simd`:
 * as sb_contact_vertex does (the design note of kernels/contact/contact.c:
 * the earliest contact, the first collider on a tie; restitution and
 * Coulomb friction; the position after it), with a force's starting value
 * set again for the new velocity. A vertex of inverse mass 0 is left
 * alone. Subtracts the impulses m Δv from sums[3 c + k] (what collider c
 * receives, summed in the order of the vertices' registers) and adds the
 * vertices answered to *contacts. Returns the vertices it went through. */
uint32_t sb_fast_contact_answer(const sb_fast_colliders* colliders, uint64_t near, const sb_packed_run* run,
                                const sb_fast_contact_step* step, double* sums, double* contacts);

#endif
