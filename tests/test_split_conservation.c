/* Conservation where tearing splits a vertex (kernels/interaction/topology.c):
 * tests/pulled_sheet.h's sheet shattering (sb_solver_def.shatter, which
 * splits vertices) under symplectic Euler (no re-kick after a break, so the
 * state just after a split is the split's own). At every step that split:
 * every copy is at its origin's position with its origin's velocity, and
 * the masses of a model vertex's copies sum to its mass to rounding — so
 * the mass, the momentum and the centre of mass of what was split are
 * kept; and no free piece (the vertices joined by unbroken bonds, none
 * held by a handle, which would feed it the handle's work) has more
 * kinetic energy than the elastic energy the broken bonds released (each
 * bond's ½ (k + spring_k) (l − r0)² at the end of the step it broke in,
 * the oracle the closed-form bond energy). */
#include "pulled_sheet.h"
#include "kernels/state/solver_data.h"
#include "kernels/interaction/breakage.h"
#include "mesh/model_internal.h"

#define SIDE 12

static uint32_t find(uint32_t* parent, uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

/* The elastic energy of bond b at x (3 per vertex), from the model's constants. */
static double bond_energy(const sb_solver* s, uint32_t b, const double* x) {
    sb_bond_info info = sb_model_bond(sb_solver_model(s), b);
    uint32_t e[2];
    sb_solver_bond(s, b, e);
    double stretch = tu_dist(x + 3 * e[0], x + 3 * e[1]) - info.rest_length;
    return 0.5 * (info.k + info.spring_k) * stretch * stretch;
}

/* Each copy made since vertex `first` where its origin is, moving as it
 * does; every model vertex's copies' masses sum to its mass. */
static void check_copies(const sb_solver* s, const double* x, const double* v, uint32_t first) {
    const sb_model* model = sb_solver_model(s);
    const sb_model* live = sb_breakage_model(s->breakage);
    uint32_t n = sb_solver_vertex_count(s), model_n = sb_model_vertex_count(model);
    double* mass = calloc(model_n, sizeof *mass);
    for (uint32_t i = 0; i < n; i++) {
        uint32_t o = sb_solver_vertex_origin(s, i);
        mass[o] += live->mass[i];
        for (int a = 0; i >= first && a < 3; a++) {
            assert_true(x[3 * i + a] == x[3 * o + a]);
            assert_true(v[3 * i + a] == v[3 * o + a]);
        }
    }
    for (uint32_t o = 0; o < model_n; o++) assert_true(fabs(mass[o] - model->mass[o]) <= 4e-16 * model->mass[o]);
    free(mass);
}

/* Every free piece's kinetic energy against the energy released so far;
 * returns the largest ratio. */
static double check_pieces(const sb_solver* s, const double* v, double released) {
    const sb_model* live = sb_breakage_model(s->breakage);
    uint32_t n = sb_solver_vertex_count(s), bonds = sb_model_bond_count(sb_solver_model(s)), e[2];
    uint32_t* parent = malloc(n * sizeof *parent);
    double *kinetic = calloc(n, sizeof *kinetic), *mass = calloc(n, sizeof *mass), worst = 0.0;
    uint8_t* held = calloc(n, 1);
    for (uint32_t i = 0; i < n; i++) parent[i] = i;
    for (uint32_t b = 0; b < bonds; b++) {
        if (sb_solver_bond_broken(s, b)) continue;
        sb_solver_bond(s, b, e);
        parent[find(parent, e[0])] = find(parent, e[1]);
    }
    for (uint32_t i = 0; i < n; i++) {
        uint32_t r = find(parent, i);
        kinetic[r] +=
            0.5 * live->mass[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
        mass[r] += live->mass[i];
        uint32_t o = sb_solver_vertex_origin(s, i);
        held[r] |= o < SIDE || o >= SIDE * (SIDE - 1); /* the handles' rows */
    }
    for (uint32_t r = 0; r < n; r++) {
        if (parent[r] != r || held[r]) continue;
        if (kinetic[r] > released)
            fail_msg("a free piece of %g kg has %g J, more than the %g J released", mass[r], kinetic[r], released);
        worst = fmax(worst, kinetic[r] / released);
    }
    free(held);
    free(parent);
    free(kinetic);
    free(mass);
    return worst;
}

static void test_splits_conserve(void** state) {
    (void)state;
    sb_model* model = ps_sheet_model(SIDE, 0.2, 0.3);
    sb_handle* handles[2];
    uint32_t rows[2][SIDE];
    ps_handles(SIDE, handles, rows[0]);
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_SYMPLECTIC_EULER;
    def.shatter = true;
    def.drag = 5.0;
    def.gravity[2] = 0.0;
    def.handles = handles;
    def.handle_count = 2;
    sb_solver* s = tu_solver(model, &def);
    uint32_t cap = sb_solver_vertex_capacity(s), bonds = sb_model_bond_count(model), splits = 0;
    double *x = malloc(3 * (size_t)cap * sizeof *x), *v = malloc(3 * (size_t)cap * sizeof *v), released = 0.0;
    double worst = 0.0;
    uint8_t* was_broken = calloc(bonds, 1);
    for (int step = 0; step < 6000; step++) {
        uint32_t before = sb_solver_vertex_count(s);
        assert_int_equal(sb_solver_advance(s, 1e-4), SB_OK);
        sb_solver_get_positions(s, x);
        sb_solver_get_velocities(s, v);
        for (uint32_t b = 0; b < bonds; b++)
            if (sb_solver_bond_broken(s, b) && !was_broken[b]) {
                was_broken[b] = 1;
                released += bond_energy(s, b, x);
            }
        if (sb_solver_vertex_count(s) == before) continue;
        splits++;
        check_copies(s, x, v, before);
        worst = fmax(worst, check_pieces(s, v, released));
    }
    print_message(
        "%u steps split, %u copies, %g J released by %u bonds; a free piece's kinetic energy at most %g of it\n",
        splits, sb_solver_vertex_count(s) - SIDE * SIDE, released, sb_solver_broken_count(s), worst);
    assert_true(splits > 0);
    free(was_broken);
    free(x);
    free(v);
    ps_destroy(s, handles, model);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_splits_conserve),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
