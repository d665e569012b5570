/* Cutting through triangles (sb_solver_def.cut_through,
 * kernels/interaction/cut_mesh.c) of a loaded sheet at its own step: the
 * hanging sheet of scenes/blade_cut.yaml, stretched by gravity, cut from
 * its bottom edge to its top by the blade carried up its middle, at the
 * scene's 0.2 ms step, pinned along its top edge and (the scene's own) at
 * its two top corners. Every step stays finite with no vertex faster than
 * 10 times the blade (the oracle: the blade and gravity are the only
 * drives, and neither moves tissue that fast); no step that cuts raises
 * the sheet's energy (its terms, the kinetic energy and gravity's
 * potential of every vertex, pinned ones included, so the work of gravity
 * is in it) by more than three times the most a step that does not cut
 * does (Verlet's energy wobbles step to step; the new inner bonds of a
 * strained triangle add a little); at the end the sheet is exactly two
 * pieces, and, pinned along its top so that it does not move sideways
 * under the blade, its cut edges lie at rest within 5 % of a cell of the
 * blade's line x = 0.15 m (the oracle: the blade's path, not the mesh);
 * on the reference kernels and on the fast ones. */
#include "test_util.h"
#include "softbond/scene.h"
#include "softbond/reference.h"
#include "kernels/state/solver_data.h"
#include "mesh/model_internal.h"

#define SCENE SB_SOURCE_DIR "/scenes/blade_cut.yaml"
#define BLADE_X 0.15    /* m: the blade's line across the sheet at rest */
#define BLADE_SPEED 0.5 /* m/s: 0.4 m in 0.8 s */
#define CELL (0.3 / 23) /* m: 24 × 24 vertices over 0.3 m */

static uint32_t find(uint32_t* parent, uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

/* The sheet's energy: its terms, and the kinetic energy and gravity's
 * potential of every vertex (the solver's own count leaves pinned ones out). */
static double sheet_energy(const sb_solver* s, double* x, double* v, double* mass) {
    sb_energies e = sb_solver_energies(s);
    double total = sb_energies_internal(&e);
    sb_solver_get_positions(s, x);
    sb_solver_get_velocities(s, v);
    sb_solver_get_masses(s, mass);
    for (uint32_t i = 0; i < sb_solver_vertex_count(s); i++) {
        const double* u = v + 3 * (size_t)i;
        total += 0.5 * mass[i] * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) + mass[i] * 9.81 * x[3 * (size_t)i + 1];
    }
    return total;
}

/* The pieces (the triangles' vertices joined); checks the cut edges (those
 * of one triangle only, off the sheet's outline) at rest against the line. */
static void check_pieces(const sb_solver* s, bool along_line) {
    const sb_model* m = s->model;
    uint32_t n = sb_solver_vertex_count(s), triangles = sb_solver_triangle_count(s), pieces = 0;
    uint32_t* parent = malloc(n * sizeof *parent);
    for (uint32_t i = 0; i < n; i++) parent[i] = i;
    for (uint32_t t = 0; t < triangles; t++) {
        uint32_t v[3];
        sb_solver_triangle(s, t, v);
        for (int c = 1; c < 3; c++) parent[find(parent, v[c])] = find(parent, v[0]);
    }
    double worst = 0.0, length = 0.0;
    for (uint32_t t = 0; t < triangles; t++) {
        uint32_t v[3], w[3];
        sb_solver_triangle(s, t, v);
        for (int c = 0; c < 3; c++) {
            uint32_t i = v[c], j = v[(c + 1) % 3];
            bool shared = false;
            for (uint32_t u = 0; u < triangles && !shared; u++) {
                sb_solver_triangle(s, u, w);
                for (int k = 0; k < 3; k++) shared |= u != t && w[k] == j && w[(k + 1) % 3] == i;
            }
            double xi = m->rest_x[i], xj = m->rest_x[j], yi = m->rest_y[i], yj = m->rest_y[j];
            bool outline = (fabs(yi - yj) < 1e-9 && (fabs(yi) < 1e-9 || fabs(yi - 0.3) < 1e-9)) ||
                           (fabs(xi - xj) < 1e-9 && (fabs(xi) < 1e-9 || fabs(xi - 0.3) < 1e-9));
            if (shared || outline) continue;
            worst = fmax(worst, fmax(fabs(xi - BLADE_X), fabs(xj - BLADE_X)));
            length += hypot(xi - xj, yi - yj);
        }
    }
    for (uint32_t i = 0; i < n; i++) pieces += find(parent, i) == i;
    free(parent);
    print_message("%u pieces; cut edges %.4g m long in all, at most %.3g cells off the blade's line at rest\n", pieces,
                  length, worst / CELL);
    assert_int_equal(pieces, 2);
    if (!along_line) return;
    TU_ASSERT_LE(worst, 0.05 * CELL);
    TU_ASSERT_NEAR(length, 2 * 0.3, 1e-3); /* both sides, the sheet's whole height */
}

/* The scene's cut with the sheet pinned by `pin`; `along_line`: the sheet
 * does not move sideways under the blade, so the cut edges at rest lie on
 * its line (held at its corners the sheet sags inwards as it hangs and
 * the incision opens, and the blade meets the tissue where it is then). */
static void check_cut(const char* kernels, const char* pin, bool along_line) {
    const char* set[] = {"cut_through=true", kernels, pin};
    sb_scene_file* scene;
    sb_error err;
    if (sb_scene_file_load(SCENE, set, 3, &scene, &err) != SB_OK) fail_msg("%s", err.message);
    sb_solver* s = sb_solver_create(sb_scene_file_model(scene), sb_scene_file_solver_def(scene), &err);
    if (!s) fail_msg("%s", err.message);
    double dt = sb_scene_file_dt(scene);
    size_t cap = sb_solver_vertex_capacity(s);
    double *x = malloc(3 * cap * sizeof *x), *v = malloc(3 * cap * sizeof *v), *mass = malloc(cap * sizeof *mass);
    double energy = sheet_energy(s, x, v, mass), fastest = 0.0, worst_gain = -INFINITY, quiet_gain = -INFINITY;
    uint32_t cuts = 0, triangles = sb_solver_triangle_count(s);
    int steps = (int)lround(sb_scene_file_duration(scene) / dt);
    for (int k = 0; k < steps; k++) {
        if (sb_solver_advance(s, dt) != SB_OK) fail_msg("step %d (t = %g s): %s", k, (k + 1) * dt, sb_solver_error(s));
        double after = sheet_energy(s, x, v, mass);
        uint32_t at = 0;
        for (uint32_t i = 0; i < sb_solver_vertex_count(s); i++) {
            const double* u = v + 3 * (size_t)i;
            double speed = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            if (speed > fastest) fastest = speed, at = i;
        }
        if (!(fastest <= 10.0 * BLADE_SPEED))
            fail_msg("step %d: vertex %u (%.3g kg) at %g m/s", k, at, mass[at], fastest);
        if (sb_solver_triangle_count(s) != triangles) { /* a step that cut */
            cuts++;
            worst_gain = fmax(worst_gain, after - energy);
            triangles = sb_solver_triangle_count(s);
        } else
            quiet_gain = fmax(quiet_gain, after - energy);
        energy = after;
    }
    print_message(
        "%s, %s: %u steps cut, %u vertices made; fastest vertex %.3g m/s; a cut's largest energy change %.3g J "
        "(the sheet's energy %.4g J)\n",
        kernels, pin, cuts, sb_solver_vertex_count(s) - sb_model_vertex_count(sb_scene_file_model(scene)), fastest,
        worst_gain, energy);
    print_message("a step that does not cut: energy change at most %.3g J\n", quiet_gain);
    assert_true(cuts > 20);
    TU_ASSERT_LE(worst_gain, 3.0 * quiet_gain);
    check_pieces(s, along_line);
    free(x);
    free(v);
    free(mass);
    sb_solver_destroy(s);
    sb_scene_file_destroy(scene);
}

static void test_hanging_sheet_cuts_cleanly_at_its_step(void** state) {
    (void)state;
    const char* kernels[2] = {"kernels=reference", "kernels=fast"}; /* the fast model built again at each cut */
    for (int k = 0; k < 2; k++) {
        check_cut(kernels[k], "pin=top_edge", true);     /* its whole top edge held: the halves hang side by side */
        check_cut(kernels[k], "pin=top_corners", false); /* the scene's: the incision gapes, the halves swing apart */
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_hanging_sheet_cuts_cleanly_at_its_step)};
    return TU_RUN_TESTS(tests);
}
