/* Dynamic colliders (softbond/collider.h): a built-in sphere or box with
 * mass, moved by the solver as a rigid body that translates and rotates.
 *
 * Design. Symplectic Euler, split over the step. The body's state is its
 * center c and velocity v, its orientation q (a unit quaternion: the
 * rotation from the def's rest frame to now) and its angular momentum L
 * about c (world frame), with the inertia of a solid body of its mass:
 * 2/5 m r² for a sphere; m/3 (h_j² + h_k²) about the box's axis i (its
 * half extents h, its axes the columns of its `rotate`). Its angular
 * velocity is ω = I⁻¹ L, I = Q diag(I_body) Qᵀ with Q = R(q) times the
 * box's axes: L is the state, so a free body keeps L exactly, and a sphere,
 * or a box spinning about one of its axes, keeps ω.
 *
 * In begin_step the pose of the step is set from the state: pose0 at c and
 * R(q), pose1 at c + v (t1 − t0) and R(q1), q1 = exp(ω (t1 − t0)) q (the
 * turn by |ω| dt about ω), so the contact pass sweeps the moves against the
 * body moving and turning, and answers each vertex with the velocity of the
 * body's point it met, (pose1(p) − pose0(p)) / dt: v + ω × r to first order
 * (the machinery of a kinematic collider: collider.c). After the step, once
 * the solver keeps it (sb_solver_advance, or an accepted adaptive sub-step;
 * a rejected one leaves the body as it was, so that its retry starts from
 * the same state), the solver hands the body the impulse J it received in
 * the step and its torque τ about the center at t1 (Σ r × J at each
 * contact point, r = point − center): the opposites of the vertices' m Δv
 * and of their moments, summed per fixed chunk of vertices and the chunks
 * in order (kernels/contact/contact.c), so the same for any thread count. The body
 * then stands at pose1 and takes v += J / m + g dt, L += τ. Momentum and
 * angular momentum are exchanged exactly: what the vertices gain the body
 * loses, step by step. */
#include "kernels/contact/colliders/dynamic.h"
#include "kernels/contact/colliders/collider_internal.h"

#include <math.h>
#include <string.h>

/* ---- rotations ---------------------------------------------------------------- */

/* The rotation matrix (row-major) of the unit quaternion q = (w, x, y, z). */
static void sb_quaternion_matrix(const double q[4], double r[9]) {
    double w = q[0], x = q[1], y = q[2], z = q[3];
    r[0] = 1.0 - 2.0 * (y * y + z * z), r[1] = 2.0 * (x * y - w * z), r[2] = 2.0 * (x * z + w * y);
    r[3] = 2.0 * (x * y + w * z), r[4] = 1.0 - 2.0 * (x * x + z * z), r[5] = 2.0 * (y * z - w * x);
    r[6] = 2.0 * (x * z - w * y), r[7] = 2.0 * (y * z + w * x), r[8] = 1.0 - 2.0 * (x * x + y * y);
}

/* q turned by the angle |w| dt about w (world frame): exp(w dt) q, normalized. */
static void sb_quaternion_turn(const double q[4], const double w[3], double dt, double out[4]) {
    double speed = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (!(speed * dt > 0.0)) {
        memcpy(out, q, 4 * sizeof *out);
        return;
    }
    double half = 0.5 * speed * dt, s = sin(half) / speed;
    double d[4] = {cos(half), s * w[0], s * w[1], s * w[2]};
    out[0] = d[0] * q[0] - d[1] * q[1] - d[2] * q[2] - d[3] * q[3];
    out[1] = d[0] * q[1] + d[1] * q[0] + d[2] * q[3] - d[3] * q[2];
    out[2] = d[0] * q[2] - d[1] * q[3] + d[2] * q[0] + d[3] * q[1];
    out[3] = d[0] * q[3] + d[1] * q[2] - d[2] * q[1] + d[3] * q[0];
    double length = sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
    for (int k = 0; k < 4; k++) out[k] /= length;
}

/* The body's principal axes in the world at orientation q: R(q) times its
 * axes in the rest frame. */
static void sb_body_axes(const sb_collider* c, const double q[4], double axes[9]) {
    double r[9];
    sb_quaternion_matrix(q, r);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            axes[3 * i + j] =
                r[3 * i] * c->body_axes[j] + r[3 * i + 1] * c->body_axes[3 + j] + r[3 * i + 2] * c->body_axes[6 + j];
}

/* out = Q diag(scale) Qᵀ x, Q the body's axes at orientation q. */
static void sb_body_apply(const sb_collider* c, const double q[4], const double scale[3], const double x[3],
                          double out[3]) {
    double axes[9], local[3];
    sb_body_axes(c, q, axes);
    for (int j = 0; j < 3; j++) local[j] = scale[j] * (axes[j] * x[0] + axes[3 + j] * x[1] + axes[6 + j] * x[2]);
    for (int i = 0; i < 3; i++)
        out[i] = axes[3 * i] * local[0] + axes[3 * i + 1] * local[1] + axes[3 * i + 2] * local[2];
}

/* ω = I⁻¹ L at orientation q. */
static void sb_angular_velocity_at(const sb_collider* c, const double q[4], const double momentum[3], double w[3]) {
    const double inverse[3] = {1.0 / c->inertia[0], 1.0 / c->inertia[1], 1.0 / c->inertia[2]};
    sb_body_apply(c, q, inverse, momentum, w);
}

/* ½ Lᵀ I⁻¹ L at orientation q. */
static double sb_rotational_energy(const sb_collider* c, const double q[4], const double momentum[3]) {
    double w[3];
    sb_angular_velocity_at(c, q, momentum, w);
    return 0.5 * (w[0] * momentum[0] + w[1] * momentum[1] + w[2] * momentum[2]);
}

/* ---- the body ------------------------------------------------------------------ */

void sb_dynamic_init(sb_collider* c) {
    const sb_collider_def* d = &c->def;
    static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(c->position, d->center, sizeof c->position);
    memcpy(c->velocity, d->velocity, sizeof c->velocity);
    memcpy(c->body_axes, d->shape == SB_COLLIDER_BOX ? c->box_rotation : identity, sizeof c->body_axes);
    for (int i = 0; i < 3; i++) {
        const double* h = d->half_extents;
        c->inertia[i] = d->shape == SB_COLLIDER_SPHERE
                            ? 0.4 * d->mass * d->radius * d->radius
                            : d->mass / 3.0 * (h[(i + 1) % 3] * h[(i + 1) % 3] + h[(i + 2) % 3] * h[(i + 2) % 3]);
    }
    const double start[4] = {1.0, 0.0, 0.0, 0.0};
    memcpy(c->orientation, start, sizeof c->orientation);
    sb_body_apply(c, c->orientation, c->inertia, d->angular_velocity, c->angular_momentum); /* L = I ω */
}

/* A pose (row-major rotation, then translation) that turns the rest frame by
 * R(q) about the def's center and puts that center at `center`. */
static void sb_body_pose(const sb_collider* c, const double q[4], const double center[3], double pose[12]) {
    sb_quaternion_matrix(q, pose);
    const double* rest = c->def.center;
    for (int i = 0; i < 3; i++)
        pose[9 + i] = center[i] - (pose[3 * i] * rest[0] + pose[3 * i + 1] * rest[1] + pose[3 * i + 2] * rest[2]);
}

void sb_dynamic_begin_step(sb_collider* c, double t0, double t1) {
    double dt = t1 - t0, w[3];
    sb_angular_velocity_at(c, c->orientation, c->angular_momentum, w);
    sb_quaternion_turn(c->orientation, w, dt, c->next_orientation);
    for (int k = 0; k < 3; k++) c->next_position[k] = c->position[k] + c->velocity[k] * dt;
    sb_body_pose(c, c->orientation, c->position, c->pose0);
    sb_body_pose(c, c->next_orientation, c->next_position, c->pose1);
}

void sb_collider_torque(const sb_collider* c, const double point[3], const double impulse[3], double torque[3]) {
    double r[3];
    for (int k = 0; k < 3; k++) r[k] = c->dynamic ? point[k] - c->next_position[k] : 0.0;
    torque[0] = r[1] * impulse[2] - r[2] * impulse[1];
    torque[1] = r[2] * impulse[0] - r[0] * impulse[2];
    torque[2] = r[0] * impulse[1] - r[1] * impulse[0];
}

void sb_collider_after_step(sb_collider* c, const double impulse[3], const double torque[3], const double gravity[3],
                            double dt) {
    if (!c || !c->dynamic) return;
    for (int k = 0; k < 3; k++) {
        c->position[k] = c->next_position[k];
        c->velocity[k] += impulse[k] / c->def.mass + gravity[k] * dt;
        c->angular_momentum[k] += torque[k];
    }
    memcpy(c->orientation, c->next_orientation, sizeof c->orientation);
}

void sb_colliders_after_step(sb_collider* const* colliders, uint32_t count, const double* impulses,
                             const double gravity[3], double dt) {
    const double* torques = impulses + 3 * (size_t)count;
    for (uint32_t i = 0; i < count; i++)
        sb_collider_after_step(colliders[i], impulses + 3 * (size_t)i, torques + 3 * (size_t)i, gravity, dt);
}

double sb_colliders_step_work(sb_collider* const* colliders, uint32_t count, const double* impulses,
                              const double gravity[3], double dt) {
    const double* torques = impulses + 3 * (size_t)count;
    double work = 0.0;
    for (uint32_t i = 0; i < count; i++) {
        const sb_collider* c = colliders[i];
        if (!c || !c->dynamic) continue;
        double m = c->def.mass, kinetic = 0.0, potential = 0.0, momentum[3];
        for (int k = 0; k < 3; k++) {
            double v = c->velocity[k], after = v + impulses[3 * (size_t)i + k] / m + gravity[k] * dt;
            kinetic += 0.5 * m * (after * after - v * v);
            potential -= m * gravity[k] * (c->next_position[k] - c->position[k]);
            momentum[k] = c->angular_momentum[k] + torques[3 * (size_t)i + k];
        }
        /* the torque's part only, both at the orientation the step ends in: a free body's turn is no work */
        kinetic += sb_rotational_energy(c, c->next_orientation, momentum) -
                   sb_rotational_energy(c, c->next_orientation, c->angular_momentum);
        work -= kinetic + potential;
    }
    return work;
}

double sb_colliders_energy_scale(sb_collider* const* colliders, uint32_t count, const double gravity[3]) {
    double scale = 0.0;
    for (uint32_t i = 0; i < count; i++) {
        const sb_collider* c = colliders[i];
        if (!c || !c->dynamic) continue;
        double m = c->def.mass, kinetic = sb_rotational_energy(c, c->orientation, c->angular_momentum), potential = 0.0;
        for (int k = 0; k < 3; k++) {
            kinetic += 0.5 * m * c->velocity[k] * c->velocity[k];
            potential -= m * gravity[k] * c->position[k];
        }
        scale += kinetic + fabs(potential);
    }
    return scale;
}

void sb_dynamic_spin(const sb_collider* c, double rotation[9], double angular_velocity[3]) {
    sb_quaternion_matrix(c->orientation, rotation);
    sb_angular_velocity_at(c, c->orientation, c->angular_momentum, angular_velocity);
}
