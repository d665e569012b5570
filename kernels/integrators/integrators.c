/* The explicit integrators. Each reads the forces of the current state
 * (left there by the previous step or by sb_solver_set_state), moves the
 * state to t + dt and evaluates the forces there through
 * sb_solver_compute_forces, so they run with either kernel choice. a = f/m
 * is the total acceleration: internal terms, gravity, drag and external
 * forces; fixed vertices have zero inverse mass and zero velocity and never
 * move.
 *
 * Explicit (forward) Euler, first order, gains energy on any undamped
 * oscillation (its amplification factor is |1 + iωdt| > 1):
 *   x⁺ = x + v dt,  v⁺ = v + a(x, v) dt.
 * Symplectic Euler (kick then drift), first order, symplectic, stable for
 * ω dt < 2:
 *   v⁺ = v + a(x, v) dt,  x⁺ = x + v⁺ dt.
 * Position Verlet (Trotter split of the Liouville operator: drift ½dt, kick
 * dt, drift ½dt), second order, symplectic, stable for ω dt < 2:
 *   x½ = x + v dt/2,  v⁺ = v + a(x½, v) dt,  x⁺ = x½ + v⁺ dt/2.
 * Its kick needs the forces at x½ (evaluated at t + dt/2, with v for the
 * damping) and the state's forces at x⁺, so it evaluates forces twice per
 * step where the other forms evaluate them once.
 *
 * The two Verlet forms below evaluate forces once per step, at the new
 * positions, with the half-step velocity for damping, and leave the state
 * at t + dt with its forces (reused by the next step).
 *
 * Störmer-Verlet, position form (Eq. 12), generalised to a step dt after a
 * step dt_prev:  x⁺ = x + (x − x⁻)·dt/dt_prev + a·dt·(dt + dt_prev)/2.
 * It is computed in its summed form, keeping the displacement Δ = x − x⁻
 * as a variable of its own: Δ⁺ = Δ·dt/dt_prev + a·dt·(dt + dt_prev)/2,
 * x⁺ = x + Δ⁺. That is the same recurrence, but in float the difference of
 * two nearby positions would lose most of its digits at small dt (measured:
 * 0.4 % energy drift over 6400 steps), and a separate Δ loses none.
 * The sum x + Δ⁺ is compensated (sb_compensated_add, kernels/state/vertex_state.h):
 * in float its rounding was a random walk that heated a long run.
 * The first step has no x⁻ and starts from the velocity:
 * x⁺ = x + v dt + a dt²/2. The velocity it reports is
 * v⁺ = (x⁺ − x)/dt + a⁺ dt/2, the same as velocity Verlet's.
 *
 * Velocity Verlet: v½ = v + a dt/2, x⁺ = x + v½ dt, v⁺ = v½ + a⁺ dt/2.
 * Fixed vertices have zero inverse mass and zero velocity and never move. */
#include "kernels/state/solver_data.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"
#include "kernels/integrators/integrators.h"

/* v += a dt/2 for every vertex (a = f/m; 0 on fixed vertices). */
static void sb_half_kick(sb_solver* s, double dt) {
    const double* inv_mass = sb_inv_mass(s);
    sb_state* st = &s->state;
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        double h = 0.5 * dt * inv_mass[i];
        st->vx[i] = (sb_real)(st->vx[i] + h * st->fx[i]);
        st->vy[i] = (sb_real)(st->vy[i] + h * st->fy[i]);
        st->vz[i] = (sb_real)(st->vz[i] + h * st->fz[i]);
    }
}

/* *x += d, compensated (the carry in *carry). */
static void sb_drift_compensated(sb_real* x, sb_real d, sb_real* carry) {
    sb_compensated next = sb_compensated_add(*x, d, *carry);
    *x = next.sum, *carry = next.carry;
}

static void sb_stormer_update(sb_real* x, sb_real* displacement, sb_real* v, sb_real* carry, double displacement_scale,
                              double accel_term, double dt) {
    *displacement = (sb_real)(displacement_scale * *displacement + accel_term);
    sb_drift_compensated(x, *displacement, carry);
    *v = (sb_real)(*displacement / dt);
}

sb_status sb_integrate_verlet(sb_solver* s, double dt) {
    if (!s->has_displacement) return sb_integrate_velocity_verlet(s, dt); /* same first step; leaves Δ set */
    const double* inv_mass = sb_inv_mass(s);
    sb_state* st = &s->state;
    double scale = dt / s->prev_dt, accel = 0.5 * dt * (dt + s->prev_dt);
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        double w = accel * inv_mass[i];
        sb_stormer_update(&st->x[i], &s->disp_x[i], &st->vx[i], &s->carry_x[i], scale, w * st->fx[i], dt);
        sb_stormer_update(&st->y[i], &s->disp_y[i], &st->vy[i], &s->carry_y[i], scale, w * st->fy[i], dt);
        sb_stormer_update(&st->z[i], &s->disp_z[i], &st->vz[i], &s->carry_z[i], scale, w * st->fz[i], dt);
    }
    sb_status status = sb_solver_compute_forces(s);
    if (status == SB_OK) sb_half_kick(s, dt);
    s->prev_dt = dt;
    return status;
}

sb_status sb_integrate_velocity_verlet(sb_solver* s, double dt) {
    sb_state* st = &s->state;
    sb_half_kick(s, dt);
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        s->disp_x[i] = (sb_real)(dt * st->vx[i]);
        s->disp_y[i] = (sb_real)(dt * st->vy[i]);
        s->disp_z[i] = (sb_real)(dt * st->vz[i]);
        sb_drift_compensated(&st->x[i], s->disp_x[i], &s->carry_x[i]);
        sb_drift_compensated(&st->y[i], s->disp_y[i], &s->carry_y[i]);
        sb_drift_compensated(&st->z[i], s->disp_z[i], &s->carry_z[i]);
    }
    s->has_displacement = true;
    s->prev_dt = dt;
    sb_status status = sb_solver_compute_forces(s);
    if (status == SB_OK) sb_half_kick(s, dt);
    return status;
}

/* x += v·scale for every vertex (fixed vertices have v = 0). */
static void sb_drift(sb_solver* s, double scale) {
    sb_state* st = &s->state;
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        st->x[i] = (sb_real)(st->x[i] + scale * st->vx[i]);
        st->y[i] = (sb_real)(st->y[i] + scale * st->vy[i]);
        st->z[i] = (sb_real)(st->z[i] + scale * st->vz[i]);
    }
}

sb_status sb_integrate_explicit_euler(sb_solver* s, double dt) {
    sb_drift(s, dt);           /* x⁺ = x + v dt, with the old v */
    sb_half_kick(s, 2.0 * dt); /* v⁺ = v + a(x, v) dt, with the old forces */
    s->has_displacement = false;
    return sb_solver_compute_forces(s);
}

sb_status sb_integrate_symplectic_euler(sb_solver* s, double dt) {
    sb_half_kick(s, 2.0 * dt); /* v⁺ = v + a(x, v) dt */
    sb_drift(s, dt);           /* x⁺ = x + v⁺ dt */
    s->has_displacement = false;
    return sb_solver_compute_forces(s);
}

sb_status sb_integrate_position_verlet(sb_solver* s, double dt) {
    double end = s->time; /* sb_solver_advance already moved the clock to t + dt */
    sb_drift(s, 0.5 * dt);
    s->time = end - 0.5 * dt;
    sb_status status = sb_solver_compute_forces(s); /* a(x½), with v for the damping */
    s->time = end;
    if (status != SB_OK) return status;
    sb_half_kick(s, 2.0 * dt);
    sb_drift(s, 0.5 * dt);
    s->has_displacement = false;
    return sb_solver_compute_forces(s);
}
