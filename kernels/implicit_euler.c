/* Implicit (backward) Euler, solved by Newton-Raphson with a
 * preconditioned conjugate-gradient linear solve and matrix-free products.
 *
 * Backward Euler, first order, unconditionally stable, and dissipative (it
 * damps an oscillation of frequency ω by 1/√(1 + (ω dt)²) per step):
 *   v⁺ = v + dt M⁻¹ f(x⁺, v⁺),  x⁺ = x + dt v⁺.
 * The unknown is the velocity change Δv = v⁺ − v, with x⁺ = x + dt (v + Δv).
 * Newton drives the residual
 *   R(Δv) = M Δv − dt f(x + dt (v + Δv), v + Δv)
 * to zero: each iteration solves J p = −R, Δv += p, with the Jacobian
 *   J = M − dt ∂f/∂v − dt² ∂f/∂x = M + dt D + dt² K,
 * symmetric and positive definite where the stiffness K = −∂f/∂x is (near a
 * rest shape) — the system conjugate gradients solves. J is never formed:
 * its product with a direction p is a central directional difference of the
 * total force along the path (x⁺ + ε dt p, v⁺ + ε p),
 *   J p = M p − dt [f(x⁺ + ε dt p, v⁺ + ε p) − f(x⁺ − ε dt p, v⁺ − ε p)] / 2ε,
 * with ε chosen so that the largest position perturbation is 1e-6 of the
 * model's size: the truncation error (ε²) and the rounding error (1/ε) of
 * the difference are then both ~1e-12 relative in double. The preconditioner
 * is the mass matrix (z = M⁻¹ r). CG stops at a relative residual of 1e-5,
 * or on a direction of non-positive curvature (a buckling state where K is
 * indefinite), or at its iteration cap; Newton stops when |R| is below
 * implicit_tolerance × its first value or at rounding level, or at its cap.
 *
 * The Newton iterations run in double on the scalar reference forces
 * (sb_solver_forces_at): a difference of float forces at a 1e-6 perturbation
 * would be noise. The new state then goes through sb_solver_compute_forces,
 * so its forces and energies come from the chosen kernels. Gravity, drag and
 * external forces are part of f and so are treated implicitly too; fixed
 * vertices are masked out of every vector and keep Δv = 0. */
#include "kernels/solver_internal.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SB_CG_RELATIVE_TOLERANCE 1e-5
#define SB_DIFFERENCE_STEP 1e-6

/* The work vectors, 3n doubles each, allocated once per solver. */
enum { W_X0, W_V0, W_DV, W_XT, W_VT, W_F, W_RHS, W_SOL, W_RES, W_Z, W_D, W_Q, W_XP, W_VP, W_FP, W_FM, W_COUNT };

typedef struct sb_newton {
    sb_solver* s;
    size_t n3;
    double dt, size; /* size: the model's diameter, m, scales the difference step */
    double* a[W_COUNT];
} sb_newton;

static double sb_dot(const double* a, const double* b, size_t n) {
    double sum = 0.0;
    for (size_t k = 0; k < n; k++) sum += a[k] * b[k];
    return sum;
}

static void sb_mask_fixed(const sb_model* m, double* a) {
    for (uint32_t i = 0; i < m->vertex_count; i++)
        if (m->fixed[i]) a[3 * i] = a[3 * i + 1] = a[3 * i + 2] = 0.0;
}

/* xt, vt at the current Δv, f the total force there, rhs = −R(Δv). */
static sb_status sb_newton_point(sb_newton* w) {
    double **a = w->a, dt = w->dt;
    const double* mass = w->s->model->mass;
    for (size_t k = 0; k < w->n3; k++) {
        a[W_VT][k] = a[W_V0][k] + a[W_DV][k];
        a[W_XT][k] = a[W_X0][k] + dt * a[W_VT][k];
    }
    sb_status status = sb_solver_forces_at(w->s, a[W_XT], a[W_VT], a[W_F]);
    for (size_t k = 0; k < w->n3; k++) a[W_RHS][k] = dt * a[W_F][k] - mass[k / 3] * a[W_DV][k];
    sb_mask_fixed(w->s->model, a[W_RHS]);
    return status;
}

/* out = J d, by the central directional difference of the header. */
static sb_status sb_jacobian_product(sb_newton* w, const double* d, double* out) {
    double **a = w->a, dt = w->dt;
    const double* mass = w->s->model->mass;
    double largest = 0.0;
    for (size_t k = 0; k < w->n3; k++) largest = fmax(largest, fabs(d[k]));
    if (largest == 0.0) {
        memset(out, 0, w->n3 * sizeof *out);
        return SB_OK;
    }
    double eps = SB_DIFFERENCE_STEP * w->size / (dt * largest);
    for (int sign = 1; sign >= -1; sign -= 2) {
        for (size_t k = 0; k < w->n3; k++) {
            a[W_XP][k] = a[W_XT][k] + sign * eps * dt * d[k];
            a[W_VP][k] = a[W_VT][k] + sign * eps * d[k];
        }
        sb_status status = sb_solver_forces_at(w->s, a[W_XP], a[W_VP], a[sign > 0 ? W_FP : W_FM]);
        if (status != SB_OK) return status;
    }
    for (size_t k = 0; k < w->n3; k++) out[k] = mass[k / 3] * d[k] - dt * (a[W_FP][k] - a[W_FM][k]) / (2.0 * eps);
    sb_mask_fixed(w->s->model, out);
    return SB_OK;
}

/* z = M⁻¹ r on free vertices. */
static void sb_precondition(const sb_newton* w, const double* r, double* z) {
    const double* inv_mass = w->s->model->inv_mass;
    for (size_t k = 0; k < w->n3; k++) z[k] = inv_mass[k / 3] * r[k];
}

/* Solves J sol = rhs by preconditioned CG from sol = 0; counts iterations. */
static sb_status sb_conjugate_gradients(sb_newton* w, int cap, int* iterations) {
    double **a = w->a, *sol = a[W_SOL], *res = a[W_RES], *z = a[W_Z], *d = a[W_D], *q = a[W_Q];
    size_t n3 = w->n3;
    memset(sol, 0, n3 * sizeof *sol);
    memcpy(res, a[W_RHS], n3 * sizeof *res);
    sb_precondition(w, res, z);
    memcpy(d, z, n3 * sizeof *d);
    double rz = sb_dot(res, z, n3), target = SB_CG_RELATIVE_TOLERANCE * sqrt(sb_dot(res, res, n3));
    for (int it = 0; it < cap; it++) {
        sb_status status = sb_jacobian_product(w, d, q);
        if (status != SB_OK) return status;
        double curvature = sb_dot(d, q, n3);
        if (!(curvature > 0.0)) {                          /* not positive definite here: keep what we have */
            if (it == 0) memcpy(sol, z, n3 * sizeof *sol); /* J ≈ M: a mass-scaled step */
            break;
        }
        double alpha = rz / curvature;
        for (size_t k = 0; k < n3; k++) {
            sol[k] += alpha * d[k];
            res[k] -= alpha * q[k];
        }
        ++*iterations;
        if (sqrt(sb_dot(res, res, n3)) <= target) break;
        sb_precondition(w, res, z);
        double rz_next = sb_dot(res, z, n3), beta = rz_next / rz;
        rz = rz_next;
        for (size_t k = 0; k < n3; k++) d[k] = z[k] + beta * d[k];
    }
    return SB_OK;
}

/* The residual's rounding level: 1e-12 of the magnitudes it is made of. */
static double sb_residual_floor(const sb_newton* w) {
    const sb_solver* s = w->s;
    const double* g = s->def.gravity;
    double momentum = 0.0, weight = 0.0, g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    for (size_t k = 0; k < w->n3; k++) {
        double m = s->model->mass[k / 3];
        momentum += m * m * w->a[W_VT][k] * w->a[W_VT][k];
        if (k % 3 == 0) weight += m * m * g2;
    }
    double force = sqrt(sb_dot(w->a[W_F], w->a[W_F], w->n3));
    return 1e-12 * (sqrt(momentum) + w->dt * (force + sqrt(weight))) + 1e-300;
}

bool sb_implicit_prepare(sb_solver* s) {
    size_t n3 = 3 * (size_t)s->model->vertex_count;
    s->implicit_work = calloc(W_COUNT * (n3 ? n3 : 1), sizeof(double));
    return s->implicit_work != NULL;
}

static sb_newton sb_newton_init(sb_solver* s, double dt) {
    sb_newton w = {.s = s, .n3 = 3 * (size_t)s->model->vertex_count, .dt = dt};
    for (int k = 0; k < W_COUNT; k++) w.a[k] = s->implicit_work + (size_t)k * w.n3;
    w.size = s->runaway * 1e-6; /* the runaway box is 1e6 model diameters */
    const sb_state* st = &s->state;
    sb_interleave(w.a[W_X0], st->x, st->y, st->z, st->vertex_count);
    sb_interleave(w.a[W_V0], st->vx, st->vy, st->vz, st->vertex_count);
    memset(w.a[W_DV], 0, w.n3 * sizeof(double));
    return w;
}

static void sb_store_state(sb_solver* s, const sb_newton* w) {
    sb_state* st = &s->state;
    sb_real* pos[3] = {st->x, st->y, st->z};
    sb_real* vel[3] = {st->vx, st->vy, st->vz};
    for (uint32_t i = 0; i < st->vertex_count; i++) {
        if (s->model->fixed[i]) continue;
        for (int c = 0; c < 3; c++) {
            pos[c][i] = (sb_real)w->a[W_XT][3 * i + c];
            vel[c][i] = (sb_real)w->a[W_VT][3 * i + c];
        }
    }
}

sb_status sb_integrate_implicit_euler(sb_solver* s, double dt) {
    sb_newton w = sb_newton_init(s, dt);
    const double tolerance = s->def.implicit_tolerance > 0 ? s->def.implicit_tolerance : 1e-8;
    const int newton_cap = s->def.implicit_newton_iterations > 0 ? s->def.implicit_newton_iterations : 20;
    const int cg_cap = s->def.implicit_cg_iterations > 0 ? s->def.implicit_cg_iterations : 200;
    double first = 0.0;
    bool converged = false;
    for (int it = 0;; it++) {
        sb_status status = sb_newton_point(&w);
        if (status != SB_OK) return status;
        double norm = sqrt(sb_dot(w.a[W_RHS], w.a[W_RHS], w.n3));
        if (it == 0) first = norm;
        if (!isfinite(norm)) break; /* the state check names the vertex */
        if (norm <= tolerance * first || norm <= sb_residual_floor(&w)) {
            converged = true;
            break;
        }
        if (it == newton_cap) break;
        status = sb_conjugate_gradients(&w, cg_cap, &s->stats.cg_iterations);
        if (status != SB_OK) return status;
        for (size_t k = 0; k < w.n3; k++) w.a[W_DV][k] += w.a[W_SOL][k];
        s->stats.newton_iterations++;
    }
    if (!converged) s->stats.converged = false;
    sb_store_state(s, &w);
    s->has_displacement = false;
    return sb_solver_compute_forces(s);
}
