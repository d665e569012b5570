/* Private: what every stage does to the solver's per-vertex state — check
 * it, sum its energies, and move it between the state's arrays, the packed
 * working state and interleaved doubles. */
#ifndef SB_VERTEX_STATE_H
#define SB_VERTEX_STATE_H

#include "kernels/state/solver_data.h"

/* Fills the solver's error naming the first vertex that is not finite or ran
 * away; SB_OK if there is none. */
sb_status sb_check_state(sb_solver* solver);
/* The kinetic and gravitational energies of the state's arrays. */
void sb_update_energies(sb_solver* solver);

/* out[3i..3i+2] = (a[i], b[i], c[i]): SoA to interleaved doubles. */
void sb_interleave(double* out, const sb_real* a, const sb_real* b, const sb_real* c, uint32_t n);
/* out[3i..3i+2] = packed[4i..4i+2] for vertices [begin, end). */
void sb_unpack_xyz(const sb_real* packed, sb_real* out, int64_t begin, int64_t end);
/* The state's positions and velocities from interleaved doubles, on every
 * vertex that is not fixed (an implicit integrator's result). */
void sb_store_free_vertices(sb_solver* solver, const double* x, const double* v);
/* The same for vertices [begin, end) (vbd: each worker its own range). */
void sb_store_free_range(sb_solver* solver, const double* x, const double* v, uint32_t begin, uint32_t end);
/* The current positions packed x y z w: the fast path's working state, or
 * the state's arrays gathered into stretch4 (the reference kernels). */
const sb_real* sb_packed_positions(sb_solver* solver);

/* Compensated drifts (Kahan's summation, in double: a float's sum with a
 * float is exact there). In float a position is 24 bits, and rounding
 * x + Δ at every step is a random walk that heats an undamped body (+154 %
 * energy over 4 × 10⁵ Verlet steps at half the stable step for the sheet of
 * tests/test_long_run_energy.c); so the drift keeps what the rounding left
 * out in *carry and adds it to the next step's Δ. The position stays the
 * one contact, handles and the output read; the force kernels add the
 * carry (the reference below, the fast kernels in
 * kernels/forces/fast_block.h); it is at most half its last place. In a
 * double build the carry stays zero and the sum is x + Δ as before. */
typedef struct sb_compensated {
    sb_real sum, carry;
} sb_compensated;
/* By value, not through a pointer to the carry: a pointer made GCC 12
 * leave the fused drift's loop scalar (36 % of the 100k sheet's step). */
static inline sb_compensated sb_compensated_add(sb_real x, sb_real d, sb_real carry) {
    double sum = (double)x + (double)d + (double)carry;
    sb_real rounded = (sb_real)sum;
    return (sb_compensated){rounded, (sb_real)(sum - (double)rounded)};
}
/* The state's positions with their carries, x + carry in double, as 3n
 * interleaved doubles: where the reference's forces are evaluated, so that
 * they see the positions the compensated drifts track, not their 24-bit
 * roundings (whose noise alone heats a long float run). */
void sb_interleave_positions(const sb_solver* solver, double* out);
/* Forgets the drifts' carries (the positions were set from outside). */
void sb_clear_carries(sb_solver* solver);

/* Whether anything between a step and the next reads the new state's
 * forces or energies, so that the step must evaluate them: the correct
 * stage (collider, self-contact, hard handles), the external and soft
 * handles' forces (evaluated with the forces, read by the next step),
 * adaptive stepping's energies. Otherwise a step that can leaves them to
 * sb_solver_settle: pbd's and xpbd's SIMD sweeps (which run only without
 * colliders and handles), the fast vbd sweep (only without breakage), the
 * fast implicit Euler. Breakage does not need them: it reads positions,
 * and the forces only for Verlet's re-kick, whose step never leaves them
 * (tests/test_tearing.c). */
bool sb_step_needs_forces(const sb_solver* solver);

#endif
