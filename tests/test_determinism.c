/* Determinism against a fixed hash (as Box2D does): a fixed scene, advanced
 * 200 Verlet steps with the fast kernels, must end in exactly the state
 * recorded below for the running build (precision, SIMD level, optimized or
 * not), bit for bit, on 1, 2 and 3 threads alike. test_fast.c shows that
 * thread counts agree with each other; this test shows that the trajectory
 * itself has not moved: a change to a kernel, the coloring, the order of a
 * sum, the integrator, the builder or the compiler flags that changes one
 * bit of the state fails here. */
#include "test_util.h"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

enum { STEPS = 200 };
#define DT 2e-4 /* s */

/* The expected hashes: FNV-1a 64 over the bytes of the positions and then
 * the velocities, 3n doubles each from sb_solver_get_positions and
 * sb_solver_get_velocities (exact copies of the solver's sb_real values),
 * after STEPS steps on 2 threads, keyed by the precision (SB_DOUBLE), the
 * SIMD level (sb_runtime_simd()) and whether the build optimizes: the fast
 * kernels are compiled with -ffp-contract=fast (CMakeLists.txt), and gcc
 * fuses a*b+c into one FMA from -O1 on but not at -O0 (Debug), which moves
 * bits wherever the SIMD level has FMA (avx2, avx512). The tests are built
 * with the library's flags, so __OPTIMIZE__ here tells the library's too.
 *
 * Produced by this test's own message (it prints the hash of each run and,
 * when the table has no entry, the line to add) from every combination,
 * with gcc 12.2.0 (Debian 12), glibc 2.36, on an Intel Xeon with AVX-512:
 *     for d in OFF ON; do for s in native avx2 scalar; do for t in Release Debug; do
 *         cmake -S . -B b-$d-$s-$t -DCMAKE_BUILD_TYPE=$t -DSB_DOUBLE=$d -DSB_SIMD=$s
 *         cmake --build b-$d-$s-$t -j --target test_determinism && b-$d-$s-$t/tests/test_determinism
 *     done; done; done
 * SB_SIMD=native on that machine and SB_SIMD=avx512 give the same hashes
 * (both report "avx512"); so do Release, RelWithDebInfo, MinSizeRel and
 * RelWithDebInfo with SB_SANITIZE=ON (build-asan of `make test`).
 *
 * AVX2 in float also depends on the processor's maker: its sb_w_rsqrt
 * (kernels/runtime/wide.h) starts from vrsqrtps, whose 12-bit approximation each
 * vendor tabulates its own way (AVX-512's vrsqrt14ps, and every square root
 * and division, are specified to the bit), and one Newton step carries the
 * difference into the result. So those entries name the cpuid vendor; the
 * AuthenticAMD ones are from an AMD EPYC (Zen 5, the "Oxide Virtual
 * Turin-like Processor") on 2026-12-03, with the same gcc and glibc. That
 * build of a2efddb, the commit that made the table, already gives them:
 * no commit since moved AVX2's bits (a bisect over every commit since that
 * touched the kernels, mesh/, common/ or CMakeLists.txt found none); the
 * GenuineIntel ones were never checked on another machine since. Every
 * other entry was rechecked by the loop above on that AMD machine at commit
 * 4d991a1 (2026-12-03): all twelve builds gave their entries, on 1, 2 and
 * 3 threads alike.
 *
 * The float entries moved with the compensated drift (the position's
 * rounding carried to the next step, kernels/state/vertex_state.h); they
 * were remade by the loop above on an AMD EPYC on 2026-12-06, all but the
 * GenuineIntel AVX2 ones, which are still the old trajectory's and must be
 * remade on an Intel processor. The double entries did not move (a double
 * build's drift is not compensated).
 *
 * They moved again when the fast kernels began to evaluate their forces at
 * the compensated positions (each element about its first vertex, with the
 * carries: kernels/forces/fast_block.h); remade by the loop above (float
 * only) on an AMD EPYC on 2026-12-06, the same six, each the same on 1, 2
 * and 3 threads. The GenuineIntel AVX2 entries are still the trajectory
 * before both changes; the double entries did not move (a double build
 * reads no carries).
 *
 * A change that moves a bit must be noticed and decided on: if the new
 * trajectory is intended (a reordered sum, a new formula, a new compiler),
 * update every entry of the table in the same commit and say there why the
 * bits moved; if it is not intended, it is a bug. */
#ifdef __OPTIMIZE__
#define BUILD "optimized"
#else
#define BUILD "-O0"
#endif

typedef struct expected_hash {
    const char* precision; /* "float" or "double" */
    const char* simd;      /* sb_runtime_simd() */
    const char* build;     /* BUILD */
    uint64_t hash;
    const char* vendor; /* NULL: any processor; else cpu_vendor()'s (AVX2 in float, above) */
} expected_hash;

static const expected_hash expected[] = {
    {"float", "avx512", "optimized", 0xd45b89b67802402bull, NULL},
    {"float", "avx512", "-O0", 0xb4ecba6233a824a7ull, NULL},
    {"float", "avx2", "optimized", 0xc63084b25b656403ull, "GenuineIntel"},
    {"float", "avx2", "-O0", 0xa486048cf34a3536ull, "GenuineIntel"},
    {"float", "avx2", "optimized", 0xb53858c2556746e9ull, "AuthenticAMD"},
    {"float", "avx2", "-O0", 0xe4b25f37d5c537b9ull, "AuthenticAMD"},
    {"float", "scalar", "optimized", 0x694ab62e805cd0e4ull, NULL},
    {"float", "scalar", "-O0", 0x694ab62e805cd0e4ull, NULL},
    {"double", "avx512", "optimized", 0xfc68e9df845e4074ull, NULL},
    {"double", "avx512", "-O0", 0x960c8097c236410eull, NULL},
    {"double", "avx2", "optimized", 0x30a534aeb3dbdfb4ull, NULL},
    {"double", "avx2", "-O0", 0xc68872a620b3df37ull, NULL},
    {"double", "scalar", "optimized", 0xc68872a620b3df37ull, NULL},
    {"double", "scalar", "-O0", 0xc68872a620b3df37ull, NULL},
};

/* The processor's cpuid vendor string ("GenuineIntel", "AuthenticAMD"; empty off x86). */
static void cpu_vendor(char out[13]) {
    out[0] = '\0';
#if defined(__x86_64__) || defined(__i386__)
    unsigned a, b, c, d;
    if (!__get_cpuid(0, &a, &b, &c, &d)) return;
    memcpy(out, &b, 4), memcpy(out + 4, &d, 4), memcpy(out + 8, &c, 4);
    out[12] = '\0';
#endif
}

static uint64_t fnv1a(uint64_t h, const void* data, size_t size) {
    const unsigned char* bytes = data;
    for (size_t b = 0; b < size; b++) h = (h ^ bytes[b]) * 1099511628211ull;
    return h;
}

/* A 24 × 20 jittered sheet (fixed seed) with bond stretch, angle bend and
 * stretch-bend, pinned at two opposite corners, falling under gravity. */
static sb_model* make_model(void) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = 24;
    sheet.ny = 20;
    sheet.jitter = 0.15;
    sheet.seed = 7;
    sb_mesh mesh = {0};
    sb_error err;
    if (sb_mesh_generate_sheet(&sheet, &mesh, &err) != SB_OK) fail_msg("%s", err.message);
    sb_material_def material = sb_default_material_def();
    material.bond_k = 50.0;
    material.angle_k = 0.3;
    material.stretch_bend_k = 2.0;
    sb_builder* builder = sb_builder_create();
    assert_non_null(builder);
    if (sb_builder_add_mesh(builder, &mesh, &material, &err) != SB_OK) fail_msg("%s", err.message);
    sb_builder_vertex(builder, 0)->fixed = true;
    sb_builder_vertex(builder, mesh.vertex_count - 1)->fixed = true;
    sb_model* model = tu_compile(builder);
    sb_builder_destroy(builder);
    sb_mesh_free(&mesh);
    return model;
}

/* The hash of the state after STEPS Verlet steps with the fast kernels. */
static uint64_t run(const sb_model* model, int threads) {
    sb_solver_def def = sb_default_solver_def();
    def.kernels = SB_KERNELS_FAST;
    def.integrator = SB_INTEGRATOR_VERLET;
    def.runtime.threads = threads;
    sb_solver* solver = tu_solver(model, &def);
    tu_advance(solver, DT, STEPS);
    size_t n = 3 * (size_t)sb_model_vertex_count(model);
    double* values = malloc(n * sizeof *values);
    assert_non_null(values);
    uint64_t h = 1469598103934665603ull; /* the FNV-1a 64 offset basis */
    sb_solver_get_positions(solver, values);
    h = fnv1a(h, values, n * sizeof *values);
    sb_solver_get_velocities(solver, values);
    h = fnv1a(h, values, n * sizeof *values);
    free(values);
    sb_solver_destroy(solver);
    return h;
}

static void test_state_hash_is_fixed(void** state) {
    (void)state;
    const char* precision = SB_DOUBLE ? "double" : "float";
    const char* simd = sb_runtime_simd();
    char vendor[13];
    cpu_vendor(vendor);
    sb_model* model = make_model();
    uint64_t one = run(model, 1), two = run(model, 2), three = run(model, 3);
    sb_model_destroy(model);
    print_message("%s, %s: state hash after %d steps %016llx (1 thread), %016llx (2), %016llx (3)\n", precision, simd,
                  STEPS, (unsigned long long)one, (unsigned long long)two, (unsigned long long)three);
    /* meaningful on its own: the thread count never changes a bit */
    if (one != two || one != three)
        fail_msg("the thread count changed the state: %016llx (1 thread), %016llx (2), %016llx (3)",
                 (unsigned long long)one, (unsigned long long)two, (unsigned long long)three);
    for (size_t i = 0; i < sizeof expected / sizeof expected[0]; i++) {
        const expected_hash* e = &expected[i];
        if (strcmp(e->precision, precision) != 0 || strcmp(e->simd, simd) != 0 || strcmp(e->build, BUILD) != 0 ||
            (e->vendor && strcmp(e->vendor, vendor) != 0))
            continue;
        if (two != e->hash)
            fail_msg("%s, %s, %s: state hash %016llx, expected %016llx: the trajectory moved. If that is intended, "
                     "update every entry of the table in tests/test_determinism.c (its comment says how) in the "
                     "same commit and say there why the bits moved; if not, it is a bug",
                     precision, simd, BUILD, (unsigned long long)two, (unsigned long long)e->hash);
        return;
    }
    fail_msg("no expected hash for %s, %s, %s: check that this build's state is right (test_fast and "
             "test_integrators pass), then add {\"%s\", \"%s\", \"%s\", 0x%016llxull, NULL} (or \"%s\" for NULL "
             "where the vendor matters) to the table `expected` in tests/test_determinism.c with the compiler and "
             "machine in its comment",
             precision, simd, BUILD, precision, simd, BUILD, (unsigned long long)two, vendor);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_state_hash_is_fixed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
