/* Dynamic colliders (softbond/collider.h): a built-in sphere or box with
 * mass, moved by the solver as a rigid body that only translates.
 *
 * Design. Symplectic Euler, split over the step. In begin_step the pose of
 * the step is set from the body's state: pose0 at its center now, pose1 at
 * center + v (t1 − t0), so the contact pass sweeps the moves against the
 * body moving at v and answers each vertex with that velocity (the same
 * machinery as a kinematic collider: collider.c). After the step, once the
 * solver keeps it (sb_solver_advance, or an accepted adaptive sub-step; a
 * rejected one leaves the body as it was, so that its retry starts from the
 * same state), the solver hands the body the impulse it received in the
 * step: the opposite of the vertices' m Δv, summed per fixed chunk of
 * vertices and the chunks in order (kernels/contact.c), so the same for any
 * thread count. The body then stands at pose1's center and takes
 * v += J / m + g dt. Momentum is exchanged exactly: what the vertices gain
 * the body loses, step by step. */
#include "kernels/colliders/collider_internal.h"

#include <math.h>
#include <string.h>

void sb_dynamic_begin_step(sb_collider* c, double t0, double t1) {
    static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double dt = t1 - t0;
    memcpy(c->pose0, identity, sizeof identity);
    memcpy(c->pose1, identity, sizeof identity);
    for (int k = 0; k < 3; k++) {
        c->next_position[k] = c->position[k] + c->velocity[k] * dt;
        c->pose0[9 + k] = c->position[k] - c->def.center[k];
        c->pose1[9 + k] = c->next_position[k] - c->def.center[k];
    }
}

void sb_collider_after_step(sb_collider* c, const double impulse[3], const double gravity[3], double dt) {
    if (!c || !c->dynamic) return;
    for (int k = 0; k < 3; k++) {
        c->position[k] = c->next_position[k];
        c->velocity[k] += impulse[k] / c->def.mass + gravity[k] * dt;
    }
}

void sb_colliders_after_step(sb_collider* const* colliders, uint32_t count, const double* impulses,
                             const double gravity[3], double dt) {
    for (uint32_t i = 0; i < count; i++) sb_collider_after_step(colliders[i], impulses + 3 * (size_t)i, gravity, dt);
}

double sb_colliders_step_work(sb_collider* const* colliders, uint32_t count, const double* impulses,
                              const double gravity[3], double dt) {
    double work = 0.0;
    for (uint32_t i = 0; i < count; i++) {
        const sb_collider* c = colliders[i];
        if (!c || !c->dynamic) continue;
        double m = c->def.mass, kinetic = 0.0, potential = 0.0;
        for (int k = 0; k < 3; k++) {
            double v = c->velocity[k], after = v + impulses[3 * (size_t)i + k] / m + gravity[k] * dt;
            kinetic += 0.5 * m * (after * after - v * v);
            potential -= m * gravity[k] * (c->next_position[k] - c->position[k]);
        }
        work -= kinetic + potential;
    }
    return work;
}

double sb_colliders_energy_scale(sb_collider* const* colliders, uint32_t count, const double gravity[3]) {
    double scale = 0.0;
    for (uint32_t i = 0; i < count; i++) {
        const sb_collider* c = colliders[i];
        if (!c || !c->dynamic) continue;
        double m = c->def.mass, kinetic = 0.0, potential = 0.0;
        for (int k = 0; k < 3; k++) {
            kinetic += 0.5 * m * c->velocity[k] * c->velocity[k];
            potential -= m * gravity[k] * c->position[k];
        }
        scale += kinetic + fabs(potential);
    }
    return scale;
}
