/* The indentation against the finite-element oracle (bench/fem_indent.h):
 * a block 20 × 20 × 10 mm clamped on its bottom, pressed 1 mm deep by a
 * rigid frictionless sphere of radius 5 mm; the force on the sphere, the
 * haptic quantity. The reference is CalculiX's C3D10 on the quarter block
 * at 10 cells across the thickness with the contact as Signorini's active
 * set, checked against 6 cells across (within 2 %: measured 0.6 % at ν 0.45,
 * 1.5 % at ν 0.49) and against Hertz's
 * half-space (the thin bonded block is stiffer, by less than half).
 * softbond's answer is its solver with the built-in sphere collider driven
 * down and damped to rest.
 *
 * Held for the quadratic co-rotated element (corotated_quadratic): within
 * 10 % at 1 183 and 2 601 vertices (3 and 4 cells across) at E 1 kPa,
 * ν 0.45 (measured −4.9 %, −4.6 %) and at 3 across at E 1 MPa, ν 0.49
 * (−6.9 %). At 405 vertices (2 cells across, the issue's "few hundred")
 * on uniform cells it misses by −39.5 %: the contact patch (radius about
 * 2.2 mm) spans a single spacing of the vertices (2.5 mm), and ccx's own
 * C3D10 on that mesh misses by −35.5 %; held there is that softbond is
 * within 10 % of that same-mesh C3D10 (measured −6.2 %). The same 405
 * vertices graded toward the tool (bench/fem_oracle.h fem_mesh_grade: the
 * cells under it 0.4 times as wide, those at the block's sides 1.6 times)
 * put four nodes in the patch: held within 10 % (measured −5.3 %; ccx's
 * C3D10 on that mesh +1.2 %). The
 * linear co-rotated element and the papers' springs are reported, not
 * held. */
#define _POSIX_C_SOURCE 200809L
#include "tests/test_util.h"
#include "tests/test_files.h"
#include "bench/fem_indent.h"

#define REFERENCE_CELLS 10
#define COARSE_CELLS 6

/* ccx's force at n cells across (C3D10), in the test's temporary folder. */
static double oracle(const fem_indent* in, int n, const char* name) {
    char dir[300];
    snprintf(dir, sizeof dir, "%s/%s_%d", tu_tmp_dir, name, n);
    int nodes = 0;
    double f = fem_indent_oracle(in, n, true, dir, &nodes);
    assert_false(isnan(f));
    print_message("  C3D10 quarter at %d across: %.6g N (%d nodes in contact)\n", n, f, nodes);
    return f;
}

/* The converged reference, checked against the coarser mesh and Hertz. */
static double reference(const fem_indent* in, const char* name) {
    double f = oracle(in, REFERENCE_CELLS, name), coarse = oracle(in, COARSE_CELLS, name), hertz = fem_indent_hertz(in);
    print_message("%s (E %g Pa, nu %.2f, depth %g m): %.6g N, coarser %+.2f %%, Hertz %.6g N\n", name,
                  in->young_modulus, in->poisson_ratio, in->depth, f, 100.0 * (coarse / f - 1.0), hertz);
    TU_ASSERT_LE(fabs(coarse / f - 1.0), 0.02);
    TU_ASSERT_LE(hertz, f);
    TU_ASSERT_LE(f, 1.5 * hertz);
    return f;
}

/* softbond's force with the model at n cells across, and its error. */
static double softbond_error(const fem_indent* in, int n, sb_tissue_model model, const char* label, double ref) {
    long steps = 0;
    double f = fem_indent_softbond(in, n, model, &steps);
    assert_false(isnan(f));
    print_message("  %-19s %d across: %.6g N, %+.1f %% (%ld steps)\n", label, n, f, 100.0 * (f / ref - 1.0), steps);
    return fabs(f / ref - 1.0);
}

static void test_indentation_soft(void** state) {
    (void)state;
    fem_indent in = fem_indent_case(1e3, 0.45, 1e-3);
    double ref = reference(&in, "soft");
    /* the coarse mesh: ccx's C3D10 on it, softbond against that */
    double same = oracle(&in, 2, "soft"), coarse = fem_indent_softbond(&in, 2, SB_TISSUE_COROTATED_QUADRATIC, NULL);
    print_message(
        "  corotated_quadratic 2 across: %+.1f %% (C3D10 on the same mesh %+.1f %%, the two %+.1f %% apart)\n",
        100.0 * (coarse / ref - 1.0), 100.0 * (same / ref - 1.0), 100.0 * (coarse / same - 1.0));
    TU_ASSERT_LE(fabs(coarse / same - 1.0), 0.10);
    double e3 = softbond_error(&in, 3, SB_TISSUE_COROTATED_QUADRATIC, "corotated_quadratic", ref);
    double e4 = softbond_error(&in, 4, SB_TISSUE_COROTATED_QUADRATIC, "corotated_quadratic", ref);
    TU_ASSERT_LE(e3, 0.10);
    TU_ASSERT_LE(e4, 0.10);
    /* the same 405 vertices graded toward the tool: the cells under it 0.4 × as wide */
    fem_indent graded = in;
    graded.grade = 0.4;
    double graded_same = oracle(&graded, 2, "graded");
    print_message("  C3D10 on the graded mesh of 2 across: %+.1f %%\n", 100.0 * (graded_same / ref - 1.0));
    TU_ASSERT_LE(softbond_error(&graded, 2, SB_TISSUE_COROTATED_QUADRATIC, "quadratic, graded", ref), 0.10);
    /* reported beside */
    for (int n = 4; n <= 6; n += 2) softbond_error(&in, n, SB_TISSUE_COROTATED, "corotated", ref);
    for (int n = 4; n <= 8; n += 4) softbond_error(&in, n, SB_TISSUE_SPRINGS, "springs", ref);
}

static void test_indentation_stiff(void** state) {
    (void)state;
    fem_indent in = fem_indent_case(1e6, 0.49, 1e-3);
    double ref = reference(&in, "stiff");
    TU_ASSERT_LE(softbond_error(&in, 3, SB_TISSUE_COROTATED_QUADRATIC, "corotated_quadratic", ref), 0.10);
}

static int setup(void** state) {
    (void)state;
    return tu_make_tmp_dir("softbond_fem_indent");
}

static int teardown(void** state) {
    (void)state;
    return getenv("SB_FEM_KEEP") ? 0 : tu_remove_tmp_dir();
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_indentation_soft),
        cmocka_unit_test(test_indentation_stiff),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
