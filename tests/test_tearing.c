/* Tearing (kernels/interaction/topology.c): a sheet pulled apart by two handles tears
 * through, shattering (sb_solver_def.shatter) — its live triangles, joined through their current vertices
 * (union-find here), fall into separate components, one holding the
 * bottom row and one the top, and the halves move apart — with the fast
 * and the reference kernels; every step leaves a valid mesh (live
 * triangles' vertices below the vertex count, every position finite,
 * every copy's origin a model vertex); the fast model's colors stay valid
 * after the splits (checked slot by slot: blocks of a block color share no
 * vertex, nor do the elements of a SIMD color within a block), and the
 * fast kernels' energies equal the reference's of the working copy; 1 and
 * 2 threads tear bitwise the same, with every integrator; a cap on the
 * splits is kept. */
#define _POSIX_C_SOURCE 200809L
#include "pulled_sheet.h"
#include "kernels/state/solver_data.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"

#define SIDE 12

typedef struct pulled_run {
    sb_model* model;
    sb_handle* handles[2];
    uint32_t rows[2][SIDE];
    sb_solver* solver;
} pulled_run;

static void pulled_start(pulled_run* r, sb_solver_def def) {
    r->model = ps_sheet_model(SIDE, 0.2, 0.3);
    ps_handles(SIDE, r->handles, r->rows[0]);
    def.drag = 5.0;
    def.gravity[2] = 0.0;
    def.handles = r->handles;
    def.handle_count = 2;
    r->solver = tu_solver(r->model, &def);
}

static void pulled_end(pulled_run* r) { ps_destroy(r->solver, r->handles, r->model); }

/* Shattering (every bond past its limit breaks at once) splits vertices
 * where cracks running from their tips (tests/test_crack.c) need not. */
static sb_solver_def kernels_def(sb_kernels kernels, int threads) {
    sb_solver_def def = sb_default_solver_def();
    def.shatter = true;
    def.kernels = kernels;
    def.runtime.threads = threads;
    return def;
}

/* Every live triangle's vertices are below the vertex count, every
 * position finite, every vertex's origin a model vertex; returns the
 * vertex count. */
static uint32_t check_mesh(const sb_solver* s) {
    uint32_t n = sb_solver_vertex_count(s), model_n = sb_model_vertex_count(sb_solver_model(s));
    uint32_t triangles = sb_model_triangle_count(sb_solver_model(s));
    assert_true(n >= model_n && n <= sb_solver_vertex_capacity(s));
    for (uint32_t t = 0; t < triangles; t++) {
        uint32_t v[3];
        sb_solver_triangle(s, t, v);
        for (int c = 0; c < 3; c++) assert_true(v[c] < n);
    }
    for (uint32_t i = 0; i < n; i++) {
        uint32_t origin = sb_solver_vertex_origin(s, i);
        assert_true(origin < model_n);
        if (i < model_n) assert_int_equal(origin, i);
    }
    double* x = malloc(3 * (size_t)n * sizeof *x);
    sb_solver_get_positions(s, x);
    assert_true(tu_all_finite(x, 3 * (size_t)n));
    free(x);
    return n;
}

/* The run: `steps` steps of dt, the mesh checked at every step. */
static void pull_for(pulled_run* r, double dt, int steps) {
    for (int step = 0; step < steps; step++) {
        sb_status st = sb_solver_advance(r->solver, dt);
        if (st != SB_OK) fail_msg("step %d: %s", step, sb_solver_error(r->solver));
        check_mesh(r->solver);
    }
}

/* 0.6 s: torn through. */
static void pull(pulled_run* r) { pull_for(r, 1e-4, 6000); }

static void test_sheet_tears_in_two(void** state) {
    (void)state;
    for (int kernels = 0; kernels < 2; kernels++) {
        pulled_run r;
        pulled_start(&r, kernels_def((sb_kernels)kernels, 1));
        pull(&r);
        const sb_solver* s = r.solver;
        uint32_t n = sb_solver_vertex_count(s);
        print_message("kernels %d: %u bonds broken, %u vertices made\n", kernels, sb_solver_broken_count(s),
                      n - SIDE * SIDE);
        assert_true(n > SIDE * SIDE);
        uint32_t* parent = ps_components(s);
        uint32_t bottom = ps_find(parent, r.rows[0][0]), top = ps_find(parent, r.rows[1][0]);
        for (uint32_t i = 1; i < SIDE; i++) { /* each row holds together */
            assert_int_equal(ps_find(parent, r.rows[0][i]), bottom);
            assert_int_equal(ps_find(parent, r.rows[1][i]), top);
        }
        assert_true(bottom != top);
        /* and the halves are apart: no vertex of the bottom's within 1 cm of the top's */
        double* x = malloc(3 * (size_t)n * sizeof *x);
        sb_solver_get_positions(s, x);
        double nearest = INFINITY;
        for (uint32_t i = 0; i < n; i++)
            for (uint32_t j = 0; j < n; j++)
                if (ps_find(parent, i) == bottom && ps_find(parent, j) == top)
                    nearest = fmin(nearest, tu_dist(x + 3 * i, x + 3 * j));
        print_message("kernels %d: the halves are %g m apart\n", kernels, nearest);
        assert_true(nearest > 0.01);
        free(x);
        free(parent);
        pulled_end(&r);
    }
}

/* After the sheet tore in two, a 3 mm sphere lowered through the middle of
 * the gap between the halves touches nothing: the triangles on the
 * broken bonds' edges, which span the crack, are out of face contact (they
 * would hold the sphere as a membrane across the gap). */
static void test_a_tool_passes_through_the_crack(void** state) {
    (void)state;
    sb_collider_def cd = sb_default_collider_def();
    cd.shape = SB_COLLIDER_SPHERE;
    cd.radius = 0.003;
    cd.center[0] = 0.05, cd.center[1] = 0.05, cd.center[2] = 0.5; /* far above, until the sheet is torn */
    sb_error err;
    sb_collider* tool = sb_collider_create(&cd, &err);
    assert_non_null(tool);
    sb_solver_def def = kernels_def(SB_KERNELS_FAST, 1);
    def.colliders = &tool;
    def.collider_count = 1;
    def.contact_thickness = 0.0005;
    pulled_run r;
    pulled_start(&r, def);
    pull(&r);
    uint32_t n = sb_solver_vertex_count(r.solver);
    uint32_t* parent = ps_components(r.solver);
    uint32_t bottom = ps_find(parent, r.rows[0][0]);
    double* x = malloc(3 * (size_t)n * sizeof *x);
    sb_solver_get_positions(r.solver, x);
    double below = -INFINITY, above = INFINITY; /* the halves' edges near x = 5 cm */
    for (uint32_t i = 0; i < n; i++) {
        if (fabs(x[3 * i] - 0.05) > 0.01) continue;
        if (ps_find(parent, i) == bottom)
            below = fmax(below, x[3 * i + 1]);
        else
            above = fmin(above, x[3 * i + 1]);
    }
    double gap = 0.5 * (below + above), largest = 0.0;
    print_message("the gap at x = 5 cm: y from %.4f to %.4f m\n", below, above);
    assert_true(above - below > 2 * (cd.radius + 0.003));
    for (int step = 0; step <= 200; step++) { /* down through the sheet's plane, 2 cm in 20 ms */
        double translate[3] = {0.0, gap - 0.05, -0.49 - 1e-4 * step}, rotate[3] = {0, 0, 0};
        sb_collider_set_pose(tool, translate, rotate);
        assert_int_equal(sb_solver_advance(r.solver, 1e-4), SB_OK);
        double f[3];
        sb_solver_contact_force(r.solver, 0, f);
        largest = fmax(largest, tu_norm(f));
    }
    print_message("the largest contact force on the tool: %g N\n", largest);
    assert_true(largest == 0.0);
    free(x);
    free(parent);
    pulled_end(&r);
    sb_collider_destroy(tool);
}

/* No two blocks of a block color share a vertex; within a block, no two
 * slots of one SIMD color (the overflow color runs one at a time). */
static void check_group_colors(const sb_element_group* g, const uint32_t* const* v, int arity, uint32_t vertices) {
    uint32_t* owner = malloc(vertices * sizeof *owner);
    for (uint32_t k = 0; k < g->block_colors; k++) {
        for (uint32_t i = 0; i < vertices; i++) owner[i] = UINT32_MAX;
        if (k == SB_OVERFLOW_COLOR) continue;
        for (uint32_t b = g->color_first_block[k]; b < g->color_first_block[k + 1]; b++)
            for (uint32_t r = g->blocks[b].first_range; r < g->blocks[b].first_range + g->blocks[b].range_count; r++)
                for (uint32_t s = g->ranges[r].begin; s < g->ranges[r].end; s++)
                    for (int a = 0; a < arity; a++) {
                        uint32_t i = v[a][s];
                        assert_true(owner[i] == UINT32_MAX || owner[i] == b);
                        owner[i] = b;
                    }
    }
    for (uint32_t r = 0; r < g->range_count; r++) {
        if (g->ranges[r].serial) continue;
        for (uint32_t i = 0; i < vertices; i++) owner[i] = UINT32_MAX;
        for (uint32_t s = g->ranges[r].begin; s < g->ranges[r].end; s++)
            for (int a = 0; a < arity; a++) {
                assert_true(owner[v[a][s]] == UINT32_MAX || owner[v[a][s]] == s);
                owner[v[a][s]] = s;
            }
    }
    free(owner);
}

static void test_colors_stay_valid_and_kernels_agree(void** state) {
    (void)state;
    pulled_run r;
    pulled_start(&r, kernels_def(SB_KERNELS_FAST, 2));
    pull(&r);
    const sb_fast_model* f = r.solver->fast;
    uint32_t vertices = sb_solver_vertex_capacity(r.solver);
    const uint32_t* bonds[2] = {f->bond_i, f->bond_j};
    /* with the other vertices of the hinges the triangles carry */
    const uint32_t* triangles[6] = {f->tri_v[0],           f->tri_v[1],           f->tri_v[2],
                                    f->tri_hinge_other[0], f->tri_hinge_other[1], f->tri_hinge_other[2]};
    const uint32_t* hinges[4] = {f->hinge_v[0], f->hinge_v[1], f->hinge_v[2], f->hinge_v[3]};
    assert_true(f->fused_hinges);
    check_group_colors(&f->bonds, bonds, 2, vertices);
    check_group_colors(&f->triangles, triangles, 6, vertices);
    check_group_colors(&f->hinges, hinges, 4, vertices);
    /* the slots and the working copy agree: the same energies */
    uint32_t n = sb_solver_vertex_capacity(r.solver);
    double* x = calloc(6 * (size_t)n, sizeof *x);
    double* force = malloc(3 * (size_t)n * sizeof *force);
    sb_solver_get_positions(r.solver, x);
    sb_solver_get_velocities(r.solver, x + 3 * (size_t)n);
    for (uint32_t i = sb_solver_vertex_count(r.solver); i < n; i++) /* the spare slots sit on vertex 0's rest */
        sb_model_rest_position(r.model, 0, x + 3 * (size_t)i);
    sb_energies expected, got = sb_solver_energies(r.solver);
    sb_error err;
    assert_int_equal(sb_reference_forces(r.solver->model, x, x + 3 * (size_t)n, force, &expected, &err), SB_OK);
    for (int t = 0; t < SB_TERM_COUNT; t++) {
        print_message("%s: %g J (reference %g J)\n", sb_term_name((sb_term)t), got.term[t], expected.term[t]);
        TU_ASSERT_NEAR(got.term[t], expected.term[t], 1e-3 * sb_energies_internal(&expected) + 1e-15);
    }
    free(x);
    free(force);
    pulled_end(&r);
}

static void test_threads_tear_the_same(void** state) {
    (void)state;
    pulled_run one, two;
    pulled_start(&one, kernels_def(SB_KERNELS_FAST, 1));
    pulled_start(&two, kernels_def(SB_KERNELS_FAST, 2));
    pull(&one);
    pull(&two);
    assert_int_equal(sb_solver_vertex_count(one.solver), sb_solver_vertex_count(two.solver));
    assert_true(sb_solver_vertex_count(one.solver) > SIDE * SIDE);
    for (uint32_t t = 0; t < sb_model_triangle_count(one.model); t++) {
        uint32_t a[3], b[3];
        sb_solver_triangle(one.solver, t, a);
        sb_solver_triangle(two.solver, t, b);
        assert_memory_equal(a, b, sizeof a);
    }
    assert_true(tu_state_hash(one.solver) == tu_state_hash(two.solver));
    pulled_end(&one);
    pulled_end(&two);
}

/* Every integrator tears the sheet (kernels/interaction/topology.c re-points what each
 * of them reads: the working copy, the fast slots, pbd's colored
 * constraints, implicit Euler's matrix pattern and its factorization's
 * analysis), a valid mesh at every step, the same for 1 and 2 threads.
 * The last case is implicit Euler again with every system factored. */
static void test_every_integrator_tears(void** state) {
    (void)state;
    for (int i = 0; i <= SB_INTEGRATOR_COUNT; i++) {
        bool factored = i == SB_INTEGRATOR_COUNT;
        uint64_t hash[2];
        uint32_t made = 0, factorizations = 0;
        for (int threads = 1; threads <= 2; threads++) {
            sb_solver_def def = kernels_def(SB_KERNELS_FAST, threads);
            def.integrator = factored ? SB_INTEGRATOR_IMPLICIT_EULER : (sb_integrator)i;
            def.implicit_solver = factored ? SB_LINEAR_CHOLESKY : SB_LINEAR_AUTO;
            pulled_run r;
            pulled_start(&r, def);
            bool implicit = def.integrator == SB_INTEGRATOR_IMPLICIT_EULER || def.integrator == SB_INTEGRATOR_VBD;
            pull_for(&r, implicit ? 1e-3 : 1e-4, implicit ? 250 : 2500); /* to the first splits */
            made = sb_solver_vertex_count(r.solver) - SIDE * SIDE;
            factorizations = sb_solver_last_step(r.solver).factorizations;
            hash[threads - 1] = tu_state_hash(r.solver);
            pulled_end(&r);
        }
        print_message("%s%s: %u vertices split off\n",
                      sb_integrator_name(factored ? SB_INTEGRATOR_IMPLICIT_EULER : (sb_integrator)i),
                      factored ? " (cholesky)" : "", made);
        assert_true(made > 0);
        assert_true(hash[0] == hash[1]);
        if (factored) assert_true(factorizations > 0);
    }
}

/* The steps that can leave the new state's forces and energies for
 * sb_solver_settle leave them where bonds break and the sheet tears too
 * (sb_step_needs_forces): breakage and the splits read the state's forces
 * only for Verlet's re-kick, whose step never leaves them. pbd's and
 * xpbd's SIMD sweeps and the fast implicit Euler (the fast vbd sweep does
 * not run with breakage) on a sheet thrown apart from its middle (no
 * handles: their pass reads the forces at once), run twice, once settling
 * after every step: every step left the forces, and the runs are bitwise
 * the same, with bonds broken and vertices split. A re-kick for every
 * integrator fails it (pbd: the hashes differ). */
static void test_tearing_leaves_the_forces_for_later(void** state) {
    (void)state;
    const sb_integrator integrators[] = {SB_INTEGRATOR_PBD, SB_INTEGRATOR_XPBD, SB_INTEGRATOR_IMPLICIT_EULER};
    enum { STEPS = 1000 };
    for (size_t k = 0; k < sizeof integrators / sizeof *integrators; k++) {
        uint64_t hash[2];
        uint32_t broken = 0, made = 0, stale = 0;
        for (int settle = 0; settle < 2; settle++) {
            sb_model* m = ps_sheet_model(SIDE, 0.2, 0.3);
            sb_solver_def def = kernels_def(SB_KERNELS_FAST, 1);
            def.integrator = integrators[k];
            def.implicit_solver = SB_LINEAR_CG; /* the fast implicit Euler */
            def.gravity[2] = 0.0;
            sb_solver* s = tu_solver(m, &def);
            double* v = calloc(3 * SIDE * SIDE, sizeof *v);
            for (uint32_t i = 0; i < SIDE * SIDE; i++) { /* outwards from the middle, 2 m/s at the corners */
                v[3 * i] = 0.25 * ((double)(i % SIDE) - 0.5 * (SIDE - 1));
                v[3 * i + 1] = 0.25 * ((double)(i / SIDE) - 0.5 * (SIDE - 1));
            }
            assert_int_equal(sb_solver_set_state(s, NULL, v), SB_OK);
            free(v);
            for (int step = 0; step < STEPS; step++) {
                sb_status st = sb_solver_advance(s, 1e-4);
                if (st != SB_OK) fail_msg("step %d: %s", step, sb_solver_error(s));
                stale += !settle && s->forces_stale;
                if (settle) sb_solver_energies(s);
            }
            broken = sb_solver_broken_count(s);
            made = check_mesh(s) - SIDE * SIDE;
            hash[settle] = tu_state_hash(s);
            sb_solver_destroy(s);
            sb_model_destroy(m);
        }
        print_message("%s: %u bonds broken, %u vertices split off\n", sb_integrator_name(integrators[k]), broken, made);
        assert_int_equal(stale, STEPS);
        assert_true(hash[0] == hash[1]);
        assert_true(broken > 0 && made > 0);
    }
}

static void test_caps_are_kept(void** state) {
    (void)state;
    sb_solver_def def = kernels_def(SB_KERNELS_FAST, 1);
    def.max_splits = 5;
    def.max_splits_per_step = 1;
    pulled_run r;
    pulled_start(&r, def);
    uint32_t before = SIDE * SIDE;
    for (int step = 0; step < 6000; step++) {
        tu_advance(r.solver, 1e-4, 1);
        uint32_t now = check_mesh(r.solver);
        assert_true(now - before <= 2); /* one vertex a step, two copies at most for it in this sheet */
        before = now;
    }
    assert_int_equal(sb_solver_vertex_capacity(r.solver), SIDE * SIDE + 5);
    pulled_end(&r);
    /* no splitting: the vertices stay the model's */
    def.max_splits = -1;
    pulled_start(&r, def);
    tu_advance(r.solver, 1e-4, 6000);
    assert_true(sb_solver_broken_count(r.solver) > 0);
    assert_int_equal(sb_solver_vertex_count(r.solver), SIDE * SIDE);
    assert_int_equal(sb_solver_vertex_capacity(r.solver), SIDE * SIDE);
    pulled_end(&r);
    def.max_splits_per_step = -1;
    sb_model* m = ps_sheet_model(SIDE, 0.2, 0.3);
    sb_error err;
    assert_null(sb_solver_create(m, &def, &err));
    assert_non_null(strstr(err.message, "max_splits_per_step"));
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sheet_tears_in_two),
        cmocka_unit_test(test_a_tool_passes_through_the_crack),
        cmocka_unit_test(test_colors_stay_valid_and_kernels_agree),
        cmocka_unit_test(test_threads_tear_the_same),
        cmocka_unit_test(test_every_integrator_tears),
        cmocka_unit_test(test_caps_are_kept),
        cmocka_unit_test(test_tearing_leaves_the_forces_for_later),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
