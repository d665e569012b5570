/* Private: a dynamic collider's motion (kernels/contact/colliders/dynamic.c). */
#ifndef SB_DYNAMIC_H
#define SB_DYNAMIC_H

#include "softbond/collider.h"

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

#endif
