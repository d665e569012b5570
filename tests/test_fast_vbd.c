/* vbd's fast sweep (kernels/integrators/fast_vbd.c) against its scalar reference
 * (kernels/integrators/vbd.c) on a bent, jittered sheet with every term, bitwise the
 * same for 1, 2 and 3 threads; and the hinge's closed-form vertex share
 * (kernels/forces/hessian_hinges.c) against the dual run and central differences. */
#include "test_util.h"

#include "kernels/forces/hessian.h"
#include "common/geometry.h"

#include <stdio.h>

/* Four sweeps a step, with Chebyshev's acceleration at rho (0: none) and
 * each vertex's step over-relaxed by relaxation (1: plain). */
static sb_solver_def vbd_def(sb_kernels kernels, int threads, double rho, double relaxation) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_VBD;
    def.kernels = kernels;
    def.vbd_iterations = 4;
    def.vbd_chebyshev_rho = rho;
    def.vbd_relaxation = relaxation;
    def.drag = 0.5;
    def.runtime.threads = threads;
    return def;
}

/* The sheet bent into a wave (every hinge away from rest), jittered and
 * moving; after `steps` steps of 2 ms, the positions in out (and the start
 * in start, when not NULL). */
static void bent_run(const sb_model* m, const sb_solver_def* def, int steps, double* out, double* start) {
    size_t n3 = 3 * (size_t)sb_model_vertex_count(m);
    double *x = tu_rest_positions(m), *v = calloc(n3, sizeof *v);
    tu_rng rng = {11};
    for (size_t k = 0; k < n3; k += 3) {
        if (sb_model_is_fixed(m, (uint32_t)(k / 3))) continue;
        x[k + 2] += 0.04 * sin(9.0 * x[k]) * cos(7.0 * x[k + 1]);
        for (int c = 0; c < 3; c++) {
            x[k + c] += tu_uniform(&rng, -0.003, 0.003);
            v[k + c] = tu_uniform(&rng, -0.2, 0.2);
        }
    }
    sb_solver* s = tu_solver(m, def);
    assert_int_equal(sb_solver_set_state(s, x, v), SB_OK);
    if (start) sb_solver_get_positions(s, start);
    tu_advance(s, 2e-3, (uint64_t)steps);
    sb_solver_get_positions(s, out);
    sb_solver_destroy(s);
    free(x), free(v);
}

/* Five steps of the fast sweep land where the reference's do. In double
 * the two differ by the order of their sums and the vector atan2 (5e-16
 * rad): 1e-10 of the motion. In float the fast sweep's positions are
 * rounded to 2^-24 of the sheet's 1 m size, 6e-8 m, each step, and the
 * Newton steps on them see forces with that relative noise: measured
 * 6e-5 of the motion (which is ~5 mm), bound 2e-4, far below what leaving
 * out a term does (the springs' damping force: 6e-2, the hinges: 0.3).
 * The same with Chebyshev's acceleration (rho 0.9), and with it and each
 * vertex's step over-relaxed (vbd.relaxation 1.3). */
static void test_fast_matches_reference(void** state) {
    (void)state;
    sb_model* m = tu_every_term_sheet(12, false);
    size_t n3 = 3 * (size_t)sb_model_vertex_count(m);
    double *start = malloc(n3 * sizeof *start), *fast = malloc(n3 * sizeof *fast), *ref = malloc(n3 * sizeof *ref);
    for (int accelerated = 0; accelerated < 3; accelerated++) {
        double rho = accelerated ? 0.9 : 0.0, relaxation = accelerated == 2 ? 1.3 : 1.0;
        sb_solver_def def = vbd_def(SB_KERNELS_REFERENCE, 1, rho, relaxation);
        bent_run(m, &def, 5, ref, start);
        def = vbd_def(SB_KERNELS_FAST, 1, rho, relaxation);
        bent_run(m, &def, 5, fast, NULL);
        double motion = 0.0, distance = 0.0;
        for (size_t k = 0; k < n3; k++) {
            motion = fmax(motion, fabs(ref[k] - start[k]));
            distance = fmax(distance, fabs(fast[k] - ref[k]));
        }
        print_message("fast vbd (rho %g, relaxation %g) %.3g m from the reference after 5 steps that move %.3g m "
                      "(%.3g)\n",
                      rho, relaxation, distance, motion, distance / motion);
        assert_true(motion > 1e-3);
        TU_ASSERT_LE(distance, (sizeof(sb_real) == sizeof(double) ? 1e-10 : 2e-4) * motion);
    }
    free(start), free(fast), free(ref);
    sb_model_destroy(m);
}

/* 1, 2 and 3 threads: the same state, bit for bit, on a sheet whose colors
 * span many SIMD blocks, without and with Chebyshev's acceleration, and
 * with it and over-relaxed steps. */
static void test_fast_deterministic(void** state) {
    (void)state;
    sb_model* m = tu_every_term_sheet(40, false);
    size_t n3 = 3 * (size_t)sb_model_vertex_count(m);
    double *one = malloc(n3 * sizeof *one), *other = malloc(n3 * sizeof *other);
    for (int accelerated = 0; accelerated < 3; accelerated++) {
        double rho = accelerated ? 0.9 : 0.0, relaxation = accelerated == 2 ? 1.3 : 1.0;
        sb_solver_def def = vbd_def(SB_KERNELS_FAST, 1, rho, relaxation);
        bent_run(m, &def, 3, one, NULL);
        for (int threads = 2; threads <= 3; threads++) {
            def = vbd_def(SB_KERNELS_FAST, threads, rho, relaxation);
            bent_run(m, &def, 3, other, NULL);
            assert_memory_equal(one, other, n3 * sizeof *one);
        }
    }
    free(one), free(other);
    sb_model_destroy(m);
}

/* A vertex thrown out of the runaway box: the fast step checks the new
 * state on the team (each worker its range) and, finding it bad, reports
 * it as sb_check_state does, naming the vertex; the same on 1, 2 and 3
 * threads, and the steps before it pass. */
static void test_fast_reports_runaway(void** state) {
    (void)state;
    sb_model* m = tu_every_term_sheet(12, false);
    uint32_t n = sb_model_vertex_count(m), thrown = n / 2;
    assert_false(sb_model_is_fixed(m, thrown));
    double *x = tu_rest_positions(m), *v = calloc(3 * (size_t)n, sizeof *v);
    v[3 * (size_t)thrown + 2] = 1e11; /* 2e8 m in a 2 ms step, the box 1e6 sheet diameters */
    char first[256] = "";
    for (int threads = 1; threads <= 3; threads++) {
        sb_solver_def def = vbd_def(SB_KERNELS_FAST, threads, 0.9, 1.3);
        sb_solver* s = tu_solver(m, &def);
        assert_int_equal(sb_solver_set_state(s, x, NULL), SB_OK);
        tu_advance(s, 2e-3, 2); /* at rest: sound */
        assert_int_equal(sb_solver_set_state(s, x, v), SB_OK);
        sb_status st = sb_solver_advance(s, 2e-3);
        print_message("%d threads: %s: %s\n", threads, sb_status_name(st), sb_solver_error(s));
        assert_int_equal(st, SB_ERR_UNSTABLE);
        TU_ASSERT_CONTAINS(sb_solver_error(s), "ran away");
        if (threads == 1)
            snprintf(first, sizeof first, "%s", sb_solver_error(s));
        else
            assert_string_equal(sb_solver_error(s), first);
        sb_solver_destroy(s);
    }
    free(x), free(v);
    sb_model_destroy(m);
}

/* φ of hinge h at x (3n interleaved). */
static double hinge_angle(const sb_model* m, uint32_t h, const double* x) {
    sb_element e = sb_element_at(m, (uint64_t)m->bond_count + m->triangle_count + h);
    return sb_hinge_measure(sb_v3(x + 3 * e.vertex[0]), sb_v3(x + 3 * e.vertex[1]), sb_v3(x + 3 * e.vertex[2]),
                            sb_v3(x + 3 * e.vertex[3]))
        .phi;
}

/* The hinge's share in closed form: the force is the dual run's value and
 * k (φ − φ0) u_p with u_p = −∇_p φ by central differences of φ
 * (h = 1e-6 m on ~0.1 m edges: truncation ~1e-10, rounding ~1e-10 of u);
 * the block is k u_p u_pᵀ, which at rest (φ = φ0, where the left-out
 * k (φ − φ0) ∇²φ vanishes) is the dual run's exact diagonal block. */
static void test_hinge_share(void** state) {
    (void)state;
    sb_model* m = tu_every_term_sheet(5, false);
    size_t n3 = 3 * (size_t)sb_model_vertex_count(m);
    double* rest = tu_rest_positions(m);
    /* fold the rest shape so the hinges' rest angles are not all 0 */
    for (size_t k = 0; k < n3; k += 3) rest[k + 2] = 0.2 * sin(4.0 * rest[k]);
    for (uint32_t h = 0; h < m->hinge_count; h++) m->hinge_phi0[h] = hinge_angle(m, h, rest);
    double* x = tu_rest_positions(m);
    tu_rng rng = {3};
    for (size_t k = 0; k < n3; k++) x[k] = rest[k] + tu_uniform(&rng, -0.01, 0.01);
    double worst_f = 0.0, largest_f = 0.0, worst_u = 0.0, largest_u = 0.0, worst_k = 0.0, largest_k = 0.0;
    for (uint32_t h = 0; h < m->hinge_count; h++) {
        uint64_t id = (uint64_t)m->bond_count + m->triangle_count + h;
        sb_element e = sb_element_at(m, id);
        sb_dvec3 xs[4], dual[4];
        for (int a = 0; a < 4; a++) xs[a] = sb_dv3(x + 3 * e.vertex[a], (const double[3]){0, 0, 0});
        assert_true(sb_element_forces_dual(m, &e, xs, dual));
        double k_at_rest[144], magnitude = m->hinge_k[h] * sb_angle_difference(hinge_angle(m, h, x), m->hinge_phi0[h]);
        assert_true(sb_element_stiffness(m, &e, rest, k_at_rest));
        for (int place = 0; place < 4; place++) {
            double f[3] = {0, 0, 0}, block[9] = {0}, f_rest[3] = {0, 0, 0}, block_rest[9] = {0}, u[3];
            assert_true(sb_element_vertex_share(m, &e, x, place, f, block));
            assert_true(sb_element_vertex_share(m, &e, rest, place, f_rest, block_rest));
            const double want[3] = {dual[place].v.x, dual[place].v.y, dual[place].v.z};
            for (int c = 0; c < 3; c++) {
                double* p = x + 3 * e.vertex[place] + c;
                double saved = *p;
                *p = saved + 1e-6;
                double up = hinge_angle(m, h, x);
                *p = saved - 1e-6;
                u[c] = -(up - hinge_angle(m, h, x)) / 2e-6;
                *p = saved;
            }
            for (int r = 0; r < 3; r++) {
                largest_f = fmax(largest_f, fabs(want[r]));
                worst_f = fmax(worst_f, fabs(f[r] - want[r]));
                largest_u = fmax(largest_u, fabs(magnitude * u[r]));
                worst_u = fmax(worst_u, fabs(f[r] - magnitude * u[r]));
                for (int c = 0; c < 3; c++) {
                    double exact = k_at_rest[(3 * place + r) * 12 + 3 * place + c];
                    largest_k = fmax(largest_k, fabs(exact));
                    worst_k = fmax(worst_k, fabs(block_rest[3 * r + c] - exact));
                    /* away from rest: k u uᵀ with the differenced u */
                    TU_ASSERT_NEAR(block[3 * r + c], m->hinge_k[h] * u[r] * u[c], 1e-6 * m->hinge_k[h] * tu_dot(u, u));
                }
            }
        }
    }
    print_message("hinge share: force %.3g of the dual run's, %.3g of the differenced; block at rest %.3g\n",
                  worst_f / largest_f, worst_u / largest_u, worst_k / largest_k);
    assert_true(largest_f > 0.0 && largest_k > 0.0);
    TU_ASSERT_LE(worst_f, 1e-12 * largest_f);
    TU_ASSERT_LE(worst_u, 1e-7 * largest_u);
    TU_ASSERT_LE(worst_k, 1e-10 * largest_k);
    free(rest), free(x);
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fast_matches_reference),
        cmocka_unit_test(test_fast_deterministic),
        cmocka_unit_test(test_fast_reports_runaway),
        cmocka_unit_test(test_hinge_share),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
