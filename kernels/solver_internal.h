/* Private: the solver's layout, shared by solver.c, solver_forces.c,
 * solver_fast.c, integrators.c, implicit_euler.c and adaptive.c. */
#ifndef SB_SOLVER_INTERNAL_H
#define SB_SOLVER_INTERNAL_H

#include "softbond/solver.h"
#include "mesh/model_internal.h"
#include "kernels/fast_model.h"
#include "kernels/state.h"
#include "kernels/team.h"

struct sb_solver {
    const sb_model* model;
    sb_solver_def def;
    sb_state state;
    sb_real *disp_x, *disp_y, *disp_z; /* the last step's displacement, x − x⁻ */
    bool has_displacement;
    double prev_dt;
    double *scratch_x, *scratch_v, *scratch_f; /* 3n interleaved doubles for the reference */
    double center[3], runaway;                 /* a vertex further than runaway from center (any axis) ran away */
    sb_fast_model* fast;                       /* NULL with the reference kernels */
    sb_team* team;             /* the threads of every parallel pass (kernels/team.c) */
    double* partials; /* per-block energy sums of the fast passes */
    /* The fast path's working state, packed x y z w per vertex; the state's
     * arrays are filled from it on demand (published). */
    sb_real *positions4, *velocities4, *displacements4, *forces4;
    sb_real* weight4; /* m g per vertex, packed */
    bool published;
    double* external;             /* 3n: the external forces of the last evaluation (NULL without a callback) */
    struct sb_backup* backup;    /* adaptive stepping: the state before a sub-step */
    double trial_substep;         /* adaptive: the size the next sub-step tries (0: the whole dt) */
    double energy_peak;           /* adaptive: the largest energy scale since the state was set */
    double* implicit_work;        /* implicit Euler: 7 arrays of 3n doubles */
    sb_real* stretch4;            /* the blow-up rule's packed copy of the positions (generic integrators) */
    struct sb_pbd* pbd;           /* pbd, xpbd: colored constraints and work arrays */
    sb_step_stats stats;
    double time;
    uint64_t steps;
    sb_energies energies;
    sb_error error;
};

/* Forces at the state's positions, with the state's velocities for damping:
 * fills state.f (internal + gravity + external) and energies.term[]. */
sb_status sb_solver_compute_forces(sb_solver* solver);

/* Copies the current positions and velocities as 3n interleaved sb_reals,
 * in parallel on the solver's team; reads only (sb_solver_publish). */
void sb_solver_copy_state(const sb_solver* solver, sb_real* positions, sb_real* velocities);

/* out[3i..3i+2] = (a[i], b[i], c[i]): SoA to interleaved doubles. */
void sb_interleave(double* out, const sb_real* a, const sb_real* b, const sb_real* c, uint32_t n);

/* The fast kernels' counterparts (kernels/solver_fast.c). */
sb_status sb_fast_prepare(sb_solver* solver, sb_error* err);
sb_status sb_fast_compute_forces(sb_solver* solver);
sb_status sb_fast_verlet_step(sb_solver* solver, double dt);
/* Fills the state's arrays from the packed working state, when stale. */
void sb_fast_publish(sb_solver* solver);

/* Fills the solver's error naming the first vertex that is not finite or ran
 * away; SB_OK if there is none. */
sb_status sb_check_state(sb_solver* solver);
void sb_update_energies(sb_solver* solver);

/* One step of each integrator; each leaves forces, velocities and term
 * energies at the new positions (through sb_solver_compute_forces). */
sb_status sb_integrate_verlet(sb_solver* solver, double dt);
sb_status sb_integrate_velocity_verlet(sb_solver* solver, double dt);
sb_status sb_integrate_explicit_euler(sb_solver* solver, double dt);
sb_status sb_integrate_symplectic_euler(sb_solver* solver, double dt);
sb_status sb_integrate_position_verlet(sb_solver* solver, double dt);
sb_status sb_integrate_implicit_euler(sb_solver* solver, double dt);
/* Allocates implicit Euler's work arrays; false when out of memory. */
bool sb_implicit_prepare(sb_solver* solver);
/* pbd and xpbd (kernels/pbd.c). */
sb_status sb_integrate_pbd(sb_solver* solver, double dt);
/* Colors the constraints and allocates the work arrays (at creation). */
sb_status sb_pbd_prepare(sb_solver* solver);
void sb_pbd_destroy(struct sb_pbd* pbd);
int sb_pbd_iterations(const sb_solver_def* def);

/* One step of the chosen integrator with the chosen kernels, the state
 * checked and the energies updated (kernels/solver.c). */
sb_status sb_solver_step(sb_solver* solver, double dt);
/* sb_solver_step over sub-steps with energy control (kernels/adaptive.c). */
sb_status sb_adaptive_advance(sb_solver* solver, double dt);
/* The adaptive stepper's copy of the state, made at creation. */
struct sb_backup* sb_backup_create(sb_solver* solver);
void sb_backup_destroy(struct sb_backup* backup);

/* Forces in double at given positions and velocities (3n interleaved):
 * reference terms, gravity, drag and external forces on free vertices.
 * Used by the implicit solver's Newton iterations. */
sb_status sb_solver_forces_at(sb_solver* solver, const double* x, const double* v, double* f);

#endif
