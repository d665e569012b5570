/** @file
 * The solver advances a state of a model in time: force terms, integrator,
 * fixed vertices, gravity and external forces. */
#ifndef SOFTBOND_SOLVER_H
#define SOFTBOND_SOLVER_H

#include "softbond/export.h"

#include "softbond/model.h"
#include "softbond/runtime.h"
#include "softbond/collider.h"
#include "softbond/handle.h"
#include "softbond/blade.h"
#include "softbond/reference.h"

#ifdef __cplusplus
extern "C" {
#endif

/** How a step advances positions and velocities (sb_solver_def.integrator);
 * docs/integrators.md compares them. */
typedef enum sb_integrator {
    SB_INTEGRATOR_VERLET = 0,       /**< Störmer-Verlet, position form (Sekercioglu & Duysak 2009, Eq. 12) */
    SB_INTEGRATOR_VELOCITY_VERLET,  /**< kick ½dt, drift dt, kick ½dt */
    SB_INTEGRATOR_EXPLICIT_EULER,   /**< x⁺ = x + v dt, v⁺ = v + a(x, v) dt */
    SB_INTEGRATOR_SYMPLECTIC_EULER, /**< kick then drift: v⁺ = v + a dt, x⁺ = x + v⁺ dt */
    SB_INTEGRATOR_POSITION_VERLET,  /**< Trotter split: drift ½dt, kick dt, drift ½dt */
    SB_INTEGRATOR_IMPLICIT_EULER,   /**< backward Euler, Newton-Raphson with matrix-free CG */
    SB_INTEGRATOR_PBD,              /**< position-based: predict, project bond and corner constraints */
    SB_INTEGRATOR_XPBD,             /**< its compliant form: compliance 1/k, λ accumulated */
    SB_INTEGRATOR_VBD,              /**< Vertex Block Descent: per-vertex Newton steps on backward Euler's potential */
    SB_INTEGRATOR_COUNT             /**< the number of integrators, not one */
} sb_integrator;

/** "verlet", "velocity_verlet", "explicit_euler", "symplectic_euler",
 * "position_verlet", "implicit_euler", "pbd", "xpbd", "vbd". */
SB_API const char* sb_integrator_name(sb_integrator integrator);
/** Returns false when the name is unknown. */
SB_API bool sb_integrator_from_name(const char* name, sb_integrator* out);

/** The blow-up rule: a bond (or, in a model without bonds, a triangle edge)
 * longer than SB_STRETCH_LIMIT times its rest length means an unstable run
 * (SB_ERR_UNSTABLE); checked on every SB_STRETCH_INTERVAL-th advance. */
#define SB_STRETCH_LIMIT 10.0
/** Advances between two checks of the blow-up rule (SB_STRETCH_LIMIT). */
#define SB_STRETCH_INTERVAL 64

/** The force kernels. sb_default_solver_def() chooses the fast ones (SIMD on
 * the solver's threads, in sb_real), which the tests check against the
 * double scalar reference; ask for the reference explicitly to check a
 * result with it. */
typedef enum sb_kernels {
    SB_KERNELS_REFERENCE = 0, /**< the double scalar reference */
    SB_KERNELS_FAST           /**< SIMD on the solver's threads: the default */
} sb_kernels;

/** implicit_euler's linear solves (sb_solver_def.implicit_solver). */
typedef enum sb_linear_solver {
    SB_LINEAR_AUTO,     /**< SB_LINEAR_CHOLESKY up to SB_CHOLESKY_AUTO_VERTICES vertices, SB_LINEAR_CG above */
    SB_LINEAR_CG,       /**< block-Jacobi preconditioned conjugate gradients */
    SB_LINEAR_CHOLESKY, /**< a sparse Cholesky factorization (CHOLMOD) */
    SB_LINEAR_COUNT     /**< the number of linear solvers, not one */
} sb_linear_solver;
/** SB_LINEAR_AUTO's limit: models of at most this many vertices are factored
 * (SB_LINEAR_CHOLESKY), larger ones solved by conjugate gradients. */
#define SB_CHOLESKY_AUTO_VERTICES 20000
/** "auto", "cg", "cholesky"; false for another name. */
SB_API bool sb_linear_solver_from_name(const char* name, sb_linear_solver* out);

/** Called once per free vertex per force evaluation; adds to force[] (N). */
typedef void (*sb_external_force_fn)(void* user, uint32_t vertex, double time, const double position[3],
                                     const double velocity[3], double force[3]);

/** Called once per bond that breaks (softbond/builder.h's break_min,
 * break_max; docs/breakage.md, Cracks: past its limit, at a crack tip past
 * its tip strength, or left with no live triangle), on the thread that
 * advances the solver, after the (sub-)step it broke at, the step's bonds
 * in bond order; time is that step's end (s). */
typedef void (*sb_break_fn)(void* user, uint32_t bond, uint32_t i, uint32_t j, double time);

/** Everything a solver is made with (sb_solver_create copies it; what its
 * pointers point at must outlive the solver, except blades, which are
 * copied). Start from sb_default_solver_def(). */
typedef struct sb_solver_def {
    sb_integrator integrator; /**< default SB_INTEGRATOR_VERLET */
    double gravity[3];        /**< m/s² */
    double drag;              /**< 1/s: each free vertex feels −drag·m·v, a viscous medium (0 = none) */
    sb_kernels kernels;       /**< default SB_KERNELS_FAST */
    sb_runtime_def runtime;   /**< the threads: count, pinning, wait policy (softbond/runtime.h) */
    /** Contact (softbond/collider.h; DESIGN.md, section Contact): after every step each
     * free vertex's move is checked against the colliders in this order, and
     * the earliest contact is answered. The colliders must outlive the solver. */
    sb_collider* const* colliders;
    uint32_t collider_count;  /**< the entries of colliders; 0 = no contact pass */
    double contact_thickness; /**< m, >= 0: added to every collider's own thickness */
    /** The colliders meet the vertices only: face contact (the surface's
     * triangles between the vertices, docs/contact.md) off — to compare
     * with a model whose contact is by nodes, or to save its pass. */
    bool vertex_contact_only;
    /** Self-contact (DESIGN.md, section Contact): after the collider pass of every
     * step, the model's triangles against each other — a body folding onto
     * itself and the bodies of a multi-object model. A vertex–triangle or
     * edge–edge pair that crossed in the step, or ends it closer than
     * contact_thickness (then required > 0), is moved apart to that distance
     * and loses its closing velocity (inelastic, frictionless). */
    bool self_collision;
    /** Handles (softbond/handle.h): vertices driven to a moving pose, hard
     * (by position) or soft (a spring-damper force). They must outlive the
     * solver; each is attached to this solver only. */
    sb_handle* const* handles;
    uint32_t handle_count; /**< the entries of handles */
    /** Forces of the program's own (a wind, a pointer's pull), or NULL: called
     * for each free vertex at every force evaluation, one vertex after
     * another in vertex order on one thread (it need not be thread-safe). */
    sb_external_force_fn external_force;
    void* external_user; /**< passed to external_force as its user */
    /** Breakage (DESIGN.md, section Breakage): the breakage callback, or NULL. */
    sb_break_fn on_break;
    void* break_user; /**< passed to on_break as its user */
    /** Tearing (DESIGN.md, section Breakage), for a model with break limits and
     * triangles: where broken bonds leave a vertex's triangles in separate
     * fans, the vertex is split, one copy per fan, and the surface opens.
     * max_splits: the most vertex copies over the run, reserved at
     * creation (0 = default: one for every 32 breakable bonds, at least
     * 256, at most the vertices on breakable bonds; negative = no
     * splitting, the torn elements just lose their constants). Past it a
     * vertex stays whole. max_splits_per_step: the most a step makes (0 =
     * default 256, < 0 refused); the rest wait for the next steps, in order. */
    int32_t max_splits;
    int32_t max_splits_per_step; /**< see max_splits: the most vertex copies one step makes; 0 = 256 */
    /** How bonds past their limits break (docs/breakage.md, Cracks): false
     * (the default), as cracks: the first at the most overstrained bond,
     * then only at the cracks' tips unless a bond elsewhere is 25 % past its
     * limit; true, all at once, every bond past a limit at the step's end
     * (brittle shattering). */
    bool shatter;
    /** Cutting (softbond/blade.h): blades that sever the bonds they cross;
     * their definitions are copied. A model with blades can tear even
     * without break limits (max_splits' default then counts every bond). */
    const sb_blade_def* blades;
    uint32_t blade_count; /**< the entries of blades */
    /** Cutting through triangles (docs/breakage.md, Cutting): the blades
     * split the triangles they pass through along their path (new vertices
     * where their edge crossed a bond, the triangles split there, the two
     * sides separated), so the cut lies where the blades went, instead of
     * severing the bonds they cross. Needs blades, a model with triangles
     * (or linear tetrahedra) and no break limits, an explicit integrator
     * (Verlet, velocity Verlet, explicit or symplectic Euler, position
     * Verlet) or implicit Euler, on either kernels, no colliders and no
     * self-contact; refused at creation otherwise. max_splits reserves the new vertices (each takes up to 4
     * bonds and 2 triangles more). Default false. */
    bool cut_through;
    /** implicit_euler: Newton stops when the residual M Δv − dt f(x⁺, v⁺) has
     * fallen below implicit_tolerance times its first value (or to rounding
     * level), after at most implicit_newton_iterations; each linear solve is
     * conjugate gradients of at most implicit_cg_iterations. 0 = default
     * (1e-8, 20, 200). Each Newton iteration solves with the exact Jacobian
     * (DESIGN.md, "Second derivatives"); implicit_definite replaces each element's
     * stiffness by a positive semi-definite stand-in, so that CG never meets
     * a negative curvature (sb_step_stats.cg_indefinite counts those it met);
     * with SB_KERNELS_FAST and conjugate gradients the step runs on the fast
     * kernels, matrix-free, always with the exact
     * stiffness. */
    double implicit_tolerance;
    /** implicit_euler's linear solver: SB_LINEAR_AUTO (the default) factors
     * the Jacobian (SB_LINEAR_CHOLESKY, a sparse Cholesky) for models of at
     * most SB_CHOLESKY_AUTO_VERTICES vertices and solves by conjugate
     * gradients (SB_LINEAR_CG) above. A Jacobian that is not positive
     * definite is factored from the positive semi-definite stand-ins
     * instead; a factored one is reused by the next Newton iteration while
     * the last one at least halved the residual (DESIGN.md, "Second
     * derivatives"). The factorization allocates. */
    sb_linear_solver implicit_solver;
    int implicit_newton_iterations; /**< implicit_euler: the most Newton iterations per step; 0 = 20 */
    int implicit_cg_iterations;     /**< implicit_euler: the most CG iterations per linear solve; 0 = 200 */
    bool implicit_definite;         /**< implicit_euler: positive semi-definite stand-ins (see implicit_tolerance) */
    /** pbd, xpbd: constraint projection sweeps per step (0 = default 10);
     * docs/integrators.md has the constraints and the stiffness mapping. */
    int pbd_iterations;
    /** vbd: Gauss-Seidel sweeps over the vertex colors per step (0 = default
     * 10); Vertex Block Descent (Chen, Liu, Yang and Yuksel 2024). */
    int vbd_iterations;
    /** vbd: Chebyshev acceleration across a step's sweeps with this spectral
     * radius estimate ρ in [0, 1); 0 = off (the default). */
    double vbd_chebyshev_rho;
    /** vbd: over-relaxation of each vertex's Newton step, x_i += ω Δx_i with
     * ω in (0, 2) (successive over-relaxation; 0 = 1, plain steps, the
     * default). */
    double vbd_relaxation;
    /** Energy-stable adaptive stepping: sb_solver_advance(dt) splits dt into
     * sub-steps; a sub-step whose total energy gain minus the work of the
     * external forces exceeds adaptive_tolerance × (the largest sum of the
     * energies' magnitudes since the state was set) is undone and retried at half the size, down to min_dt (then
     * SB_ERR_UNSTABLE); after a success the next sub-step tries twice the size,
     * never more than what is left of dt. adaptive_tolerance 0 = the
     * precision's rounding level (1e-5 float, 1e-10 double). */
    bool adaptive;
    double min_dt;             /**< s, > 0; default 1e-9 */
    double adaptive_tolerance; /**< >= 0 */
} sb_solver_def;

/** Verlet on the fast kernels with the runtime's defaults (sb_default_runtime_def),
 * gravity (0, 0, −9.81) m/s², no drag, contact, handles, blades or external
 * force, the implicit defaults (1e-8, 20, 200, SB_LINEAR_AUTO), 10 pbd/xpbd
 * and vbd sweeps, no adaptive stepping (min_dt 1e-9 s once on). */
SB_API sb_solver_def sb_default_solver_def(void);

/** A model's state advancing in time, with everything a step needs; opaque. */
typedef struct sb_solver sb_solver;

/** The state starts at the model's rest positions and initial velocities.
 * The model must outlive the solver. Everything a step needs (the team's
 * threads, every integrator's and the adaptive stepper's buffers) is
 * allocated here: sb_solver_advance never allocates. */
SB_API sb_solver* sb_solver_create(const sb_model* model, const sb_solver_def* def, sb_error* err);
/** Frees the solver, its threads and buffers; safe on NULL. The model,
 * colliders and handles it used are the caller's and stay. */
SB_API void sb_solver_destroy(sb_solver* solver);

/** Advances the state by one step of dt seconds (dt > 0 and finite), or,
 * with def.adaptive, by sub-steps that add up to dt. On failure (a collapsed
 * edge, a non-finite or runaway state, a bond stretched past
 * SB_STRETCH_LIMIT times its rest length (checked every
 * SB_STRETCH_INTERVAL-th advance), an adaptive sub-step that still gains
 * energy at min_dt) the solver keeps the message, which names the step, the
 * time and the first bad vertex or element; the state is then undefined
 * (adaptive: the last good sub-step's). */
SB_API sb_status sb_solver_advance(sb_solver* solver, double dt);
/** The message of the solver's last failure ("" before any), owned by the
 * solver: valid until the next failure or sb_solver_destroy. */
SB_API const char* sb_solver_error(const sb_solver* solver);

/** What the last sb_solver_advance did. */
typedef struct sb_step_stats {
    int newton_iterations;   /**< implicit_euler: Newton iterations, summed over sub-steps */
    int cg_iterations;       /**< implicit_euler: conjugate-gradient iterations, summed */
    bool converged;          /**< implicit_euler: every Newton solve met its tolerance */
    uint32_t cg_indefinite;  /**< implicit_euler: CG solves stopped at a non-positive curvature */
    uint32_t factorizations; /**< implicit_euler: Jacobians factored (SB_LINEAR_CHOLESKY), summed */
    uint32_t substeps;       /**< sub-steps accepted (1 without adaptive stepping) */
    uint32_t rejected;       /**< adaptive: sub-steps undone and retried at half the size */
    uint32_t contacts;       /**< vertex contacts answered, summed over sub-steps */
    uint32_t self_contacts;  /**< self-contact pairs corrected, summed over sub-steps */
    uint32_t self_dropped;   /**< self-contact candidates dropped: the buffers (16 per triangle) were full */
    double last_substep;     /**< s, the last accepted sub-step */
    double min_substep;      /**< s, the smallest accepted sub-step */
} sb_step_stats;

/** The statistics of the last sb_solver_advance (zeros before the first). */
SB_API sb_step_stats sb_solver_last_step(const sb_solver* solver);

/** The force (N) collider `index` received from the bodies during the last
 * sb_solver_advance: the impulses of its contacts summed in vertex order,
 * divided by the advance's dt. Zeros for an index out of range. */
SB_API void sb_solver_contact_force(const sb_solver* solver, uint32_t index, double force[3]);
/** Newton and CG iterations of the last step (implicit_euler; 0 otherwise). */
SB_API void sb_solver_last_iterations(const sb_solver* solver, int* newton, int* cg);

/** Breakage: the bonds broken so far in this solver's run (they stay
 * broken, sb_solver_set_state included), and whether bond `bond` is one of
 * them (false out of range). A broken bond has no stiffness and no damping,
 * and the triangles (angle, stretch-bend) and hinges that use its edge lose
 * theirs too. */
SB_API uint32_t sb_solver_broken_count(const sb_solver* solver);
/** Whether bond `bond` has broken (or been cut); false out of range. */
SB_API bool sb_solver_bond_broken(const sb_solver* solver, uint32_t bond);

/** Tearing's topology (sb_solver_def.max_splits). The solver's vertices are
 * the model's, then the copies splits made: sb_solver_vertex_count of them
 * now, never more than sb_solver_vertex_capacity (size buffers for the
 * getters below by it; both equal the model's count for a solver that
 * does not tear). A copy's origin is the model vertex it was split from
 * (a model vertex's is itself; UINT32_MAX past the count). The model's
 * triangles and bonds keep their numbers; their current vertices and
 * whether a triangle is alive (no broken bond on its edges) are read
 * here. Out of range: zeros and false. */
SB_API uint32_t sb_solver_vertex_count(const sb_solver* solver);
/** The most vertices the solver can have: the model's plus the copies
 * reserved for tearing (fixed at creation). */
SB_API uint32_t sb_solver_vertex_capacity(const sb_solver* solver);
/** The model vertex `vertex` is, or was split from. */
SB_API uint32_t sb_solver_vertex_origin(const sb_solver* solver, uint32_t vertex);
/** The vertices' masses now, kg, sb_solver_vertex_capacity of them (a
 * split or a cut shares a vertex's mass among its copies). */
SB_API void sb_solver_get_masses(const sb_solver* solver, double* out);
/** The triangles now: the model's, then those a cut through triangles
 * made (sb_solver_def.cut_through; the model's count otherwise). */
SB_API uint32_t sb_solver_triangle_count(const sb_solver* solver);
/** The bonds now: the model's, then those a cut through triangles made. */
SB_API uint32_t sb_solver_bond_count(const sb_solver* solver);
/** The triangle's current three vertices, in its corner order. */
SB_API void sb_solver_triangle(const sb_solver* solver, uint32_t triangle, uint32_t vertices[3]);
/** Whether the triangle still has all its bonds (none broken or cut). */
SB_API bool sb_solver_triangle_alive(const sb_solver* solver, uint32_t triangle);
/** The bond's current two vertices. */
SB_API void sb_solver_bond(const sb_solver* solver, uint32_t bond, uint32_t ends[2]);
/** The boundary faces now (a volume's surface, for contact and frames): the
 * model's, or after a cut through tetrahedra (sb_solver_def.cut_through)
 * the pieces', the cut's faces included. */
SB_API uint32_t sb_solver_face_count(const sb_solver* solver);
/** The face's current three vertices, facing out of its body. */
SB_API void sb_solver_face(const sb_solver* solver, uint32_t face, uint32_t vertices[3]);
/** The most faces sb_solver_face_count can reach: the room a cut through
 * tetrahedra reserved at creation, or the model's count. */
SB_API uint32_t sb_solver_face_capacity(const sb_solver* solver);

/** The simulated time, s: 0 at creation, each advance adds its dt (a loaded
 * checkpoint sets it). */
SB_API double sb_solver_time(const sb_solver* solver);
/** The advances so far: every sb_solver_advance with a valid dt counts,
 * one that failed included (a loaded checkpoint sets it). */
SB_API uint64_t sb_solver_step_count(const sb_solver* solver);
/** The model the solver was created with. */
SB_API const sb_model* sb_solver_model(const sb_solver* solver);

/** Energies of the current state: each term, kinetic, gravity. After a pbd,
 * xpbd, vbd or implicit Euler step with the fast kernels they are evaluated
 * here, when first asked for (as are the forces of sb_solver_get_forces);
 * after a Verlet step with the fast kernels the kinetic and gravitational
 * energies are, unless they were also read after the step before (then
 * that step sums them in its own passes): the same numbers either way. */
SB_API sb_energies sb_solver_energies(const sb_solver* solver);

/** Copies positions, velocities or the total forces (internal, gravity, drag
 * and external, at the current positions) out as 3n interleaved doubles,
 * n = sb_solver_vertex_count.
 * These getters, like every function here that takes a const sb_solver*,
 * only read; but they read the solver's working state, so call them from the
 * thread that advances it (or while it does not). Other threads read the
 * snapshots the solver publishes (softbond/state_buffer.h). */
SB_API void sb_solver_get_positions(const sb_solver* solver, double* out);
/** Velocities, m/s (see sb_solver_get_positions). */
SB_API void sb_solver_get_velocities(const sb_solver* solver, double* out);
/** Total forces, N (see sb_solver_get_positions). */
SB_API void sb_solver_get_forces(const sb_solver* solver, double* out);
/** Replaces positions and velocities (3n interleaved, n =
 * sb_solver_vertex_count; velocities may be NULL for zero) and recomputes
 * forces. Fixed vertices keep their rest position; a torn solver stays
 * torn. */
SB_API sb_status sb_solver_set_state(sb_solver* solver, const double* positions, const double* velocities);
/** Changes gravity (m/s², finite) between steps: the forces of the current
 * state are updated to it, so the next step feels the new gravity from its
 * start (a viewer's "reverse gravity" and "gravity off"); the energies'
 * gravity term follows from that step on. On the thread that advances the
 * solver. SB_ERR_INVALID, and nothing changes, for a non-finite value. */
SB_API sb_status sb_solver_set_gravity(sb_solver* solver, const double gravity[3]);

/** Checkpoints: the solver's whole state as bytes, from which a run
 * continues bitwise as if it had not stopped (DESIGN.md, section Checkpoints,
 * says what is in it: the state, the Verlet displacement, the clock and step
 * count, the adaptive step size and energy peak, the colliders' poses and
 * dynamic bodies, the handles, the broken bonds and tearing's topology,
 * the last step's statistics and contact forces). A versioned format with
 * a header (the size of sb_real, the vertex count, a hash of the model and
 * of the definition's integrator, kernels, adaptive, self-contact,
 * colliders, handles and tearing's caps) and a checksum; the layout is the
 * host's byte order.
 * sb_solver_state_size gives the bytes sb_solver_save_state writes into a
 * buffer at least that large. sb_solver_load_state reads them into a
 * solver made as the saving one was (the same model, colliders and handles
 * in the same order: created anew, or one in which no bond has broken);
 * the thread count may differ. It refuses, with one line and the solver
 * unchanged, a truncated or corrupt buffer, another format version, the
 * other precision's, or another model's or set-up's. A program's own
 * collider (sb_collider_create_custom) keeps its state in its user data:
 * the program saves that itself. */
SB_API size_t sb_solver_state_size(const sb_solver* solver);
/** Writes the checkpoint into buffer (size bytes, at least
 * sb_solver_state_size); SB_ERR_INVALID when it is smaller. */
SB_API sb_status sb_solver_save_state(const sb_solver* solver, void* buffer, size_t size, sb_error* err);
/** Reads a checkpoint of size bytes into the solver, as described above. */
SB_API sb_status sb_solver_load_state(sb_solver* solver, const void* buffer, size_t size, sb_error* err);

#ifdef __cplusplus
}
#endif
#endif
