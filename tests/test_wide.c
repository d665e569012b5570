/* kernels/runtime/wide.h's vector atan2 against libm's atan2 (in double, of the same
 * sb_real arguments) over the whole circle, in every lane; its reciprocal
 * and inverse square root (estimates refined by Newton steps) against
 * double's; its spread of one real a vertex over the packed x y z w lanes;
 * its packed loads and scatter-adds with the lanes' vertices read from
 * memory. */
#include "test_util.h"

#include "kernels/runtime/wide.h"

/* The bounds stated in kernels/runtime/wide.h: 1.1 units in the last place of π. */
#define ATAN2_BOUND (sizeof(sb_real) == sizeof(float) ? 2.6e-7 : 5e-16)

/* Evaluates sb_w_atan2 on n (y, x) pairs, SB_WIDTH at a time (n a multiple
 * of SB_WIDTH); returns the largest difference from libm, and checks that
 * every result has libm's sign. */
static double worst_error(const sb_real* y, const sb_real* x, size_t n) {
    double worst = 0.0;
    for (size_t i = 0; i < n; i += SB_WIDTH) {
        sb_real out[SB_WIDTH];
        sb_w_store(out, sb_w_atan2(sb_w_load(y + i), sb_w_load(x + i)));
        for (int l = 0; l < SB_WIDTH; l++) {
            double expected = atan2((double)y[i + l], (double)x[i + l]);
            if (!signbit(out[l]) != !signbit(expected))
                fail_msg("atan2(%.9g, %.9g): %.9g, libm %.9g", (double)y[i + l], (double)x[i + l], (double)out[l],
                         expected);
            worst = fmax(worst, fabs(out[l] - expected));
        }
    }
    return worst;
}

/* Round n up to a whole number of blocks by repeating the first pair. */
static size_t pad(sb_real* y, sb_real* x, size_t n) {
    while (n % SB_WIDTH) {
        y[n] = y[0];
        x[n] = x[0];
        n++;
    }
    return n;
}

/* Points on circles of radius 1e-20 to 1e20, evenly around, then the same
 * angles with each coordinate's last bits jittered by the rounding to sb_real. */
static void test_whole_circle(void** state) {
    (void)state;
    enum { angles = 1 << 16, radii = 5 };
    const double radius[radii] = {1e-20, 1e-3, 1.0, 7.5e3, 1e20};
    size_t capacity = (size_t)angles * radii + SB_WIDTH;
    sb_real *y = malloc(capacity * sizeof *y), *x = malloc(capacity * sizeof *x);
    size_t n = 0;
    for (int r = 0; r < radii; r++)
        for (int a = 0; a < angles; a++) {
            double theta = -M_PI + 2.0 * M_PI * (a + 0.37) / angles;
            y[n] = (sb_real)(radius[r] * sin(theta));
            x[n] = (sb_real)(radius[r] * cos(theta));
            n++;
        }
    double worst = worst_error(y, x, pad(y, x, n));
    print_message("whole circle: largest error %.3g rad against libm (bound %.3g)\n", worst, ATAN2_BOUND);
    TU_ASSERT_LE(worst, ATAN2_BOUND);
    free(y);
    free(x);
}

/* Random pairs in a box, where the reduction's branches meet: |y| = |x|,
 * |y| = tan(π/8) |x| and their neighbours. */
static void test_branch_edges(void** state) {
    (void)state;
    enum { count = 1 << 14 };
    sb_real y[count + SB_WIDTH], x[count + SB_WIDTH];
    tu_rng rng = {11};
    const double ratios[] = {1.0, 0.41421356237309504880, 2.41421356237309504880};
    for (int i = 0; i < count; i++) {
        double u = tu_uniform(&rng, -1.0, 1.0), ratio = ratios[i % 3];
        double wiggle = 1.0 + (i % 7 - 3) * TU_REAL_EPS;
        x[i] = (sb_real)u;
        y[i] = (sb_real)(i % 2 ? -1.0 : 1.0) * (sb_real)(fabs(u) * ratio * wiggle);
    }
    double worst = worst_error(y, x, pad(y, x, count));
    print_message("branch edges: largest error %.3g rad\n", worst);
    TU_ASSERT_LE(worst, ATAN2_BOUND);
}

/* Zeros and the axes: libm's values and signs (±0, ±π/2, ±π). */
static void test_axes_and_zeros(void** state) {
    (void)state;
    const sb_real values[] = {0.0f, -0.0f, 1.0f, -1.0f, 3e-30f};
    enum { n = sizeof values / sizeof values[0] };
    sb_real y[n * n + SB_WIDTH], x[n * n + SB_WIDTH];
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            y[i * n + j] = values[i];
            x[i * n + j] = values[j];
        }
    TU_ASSERT_LE(worst_error(y, x, pad(y, x, n * n)), ATAN2_BOUND);
}

/* sb_w_spread4 and sb_packed_lane: packed real q + l gets vertex (q + l) / 4's
 * value in its x, y and z lanes and 0 in its w lane, at every block start. */
static void test_spread_over_packed_lanes(void** state) {
    (void)state;
    enum { vertices = 12 };
    const sb_real per_vertex[vertices] = {1.5f,  -2.25f, 3.0f, 4e-30f, 5.5f,  6.0f,
                                          -7.0f, 8.125f, 9.0f, 1e30f,  11.0f, 12.5f};
    for (size_t q = 0; q + SB_WIDTH <= 4 * vertices; q += SB_WIDTH) {
        sb_real out[SB_WIDTH];
        sb_w_store(out, sb_w_spread4(per_vertex, q));
        for (int l = 0; l < SB_WIDTH; l++) {
            size_t k = q + (size_t)l;
            sb_real expected = k % 4 == 3 ? 0 : per_vertex[k / 4];
            if (out[l] != expected || sb_packed_lane(per_vertex, k) != expected)
                fail_msg("packed real %zu: spread %g, lane %g, expected %g", k, (double)out[l],
                         (double)sb_packed_lane(per_vertex, k), (double)expected);
        }
    }
}

/* sb_w_recip and sb_w_rsqrt within 2 units of sb_real's epsilon of 1/a
 * and 1/sqrt(a) (computed in double) for a over 1e-30 to 1e30, every lane
 * (recip also of −a). */
static void test_reciprocals(void** state) {
    (void)state;
    const double eps = sizeof(sb_real) == sizeof(float) ? FLT_EPSILON : DBL_EPSILON;
    double worst_recip = 0.0, worst_rsqrt = 0.0;
    enum { count = 4096 };
    for (int i = 0; i < count; i += SB_WIDTH) {
        sb_real a[SB_WIDTH], recip[SB_WIDTH], negative[SB_WIDTH], rsqrt[SB_WIDTH];
        for (int l = 0; l < SB_WIDTH; l++) a[l] = (sb_real)pow(10.0, -30.0 + 60.0 * (i + l) / (count - 1.0));
        sb_wide w = sb_w_load(a);
        sb_w_store(recip, sb_w_recip(w));
        sb_w_store(negative, sb_w_recip(sb_w_sub(sb_w_set(0), w)));
        sb_w_store(rsqrt, sb_w_rsqrt(w));
        for (int l = 0; l < SB_WIDTH; l++) {
            double x = a[l];
            worst_recip = fmax(worst_recip, fabs(recip[l] * x - 1.0));
            worst_recip = fmax(worst_recip, fabs(negative[l] * x + 1.0));
            worst_rsqrt = fmax(worst_rsqrt, fabs(rsqrt[l] * sqrt(x) - 1.0));
        }
    }
    print_message("recip %.3g, rsqrt %.3g of epsilon\n", worst_recip / eps, worst_rsqrt / eps);
    TU_ASSERT_LE(worst_recip, 2 * eps);
    TU_ASSERT_LE(worst_rsqrt, 2 * eps);
}

/* sb_wv_load4_at gives each lane its vertex's x y z; sb_wv_add4_at adds
 * each of the first `count` lanes' vectors to its vertex and nothing else
 * anywhere (the full block, count = SB_WIDTH, takes its own path). */
static void test_packed_load_and_add_at(void** state) {
    (void)state;
    enum { vertices = 3 * SB_WIDTH };
    sb_real p4[4 * vertices] __attribute__((aligned(64))), before[4 * vertices];
    for (int i = 0; i < 4 * vertices; i++) p4[i] = (sb_real)(i % 4 == 3 ? -1 : 0.5 * i + 1);
    uint32_t id[SB_WIDTH];
    for (int l = 0; l < SB_WIDTH; l++) id[l] = (uint32_t)((7 * l + 5) % vertices); /* distinct, scattered */
    for (int count = 1; count <= SB_WIDTH; count++) {
        memcpy(before, p4, sizeof p4);
        sb_wvec3 v = sb_wv_load4_at(p4, id);
        sb_real x[SB_WIDTH], y[SB_WIDTH], z[SB_WIDTH];
        memcpy(x, &v.x, sizeof x);
        memcpy(y, &v.y, sizeof y);
        memcpy(z, &v.z, sizeof z);
        for (int l = 0; l < SB_WIDTH; l++)
            if (x[l] != p4[4 * id[l]] || y[l] != p4[4 * id[l] + 1] || z[l] != p4[4 * id[l] + 2])
                fail_msg("lane %d loaded (%g, %g, %g), vertex %u", l, (double)x[l], (double)y[l], (double)z[l], id[l]);
        sb_real add[SB_WIDTH];
        for (int l = 0; l < SB_WIDTH; l++) add[l] = (sb_real)(l + 1);
        sb_wide a = sb_w_load(add);
        sb_wv_add4_at(p4, id, (sb_wvec3){a, sb_w_mul(a, sb_w_set(2)), sb_w_mul(a, sb_w_set(-4))}, count);
        for (int i = 0; i < vertices; i++) {
            int lane = -1;
            for (int l = 0; l < count; l++)
                if (id[l] == (uint32_t)i) lane = l;
            sb_real d[4] = {0, 0, 0, 0};
            if (lane >= 0) {
                d[0] = add[lane];
                d[1] = 2 * add[lane];
                d[2] = -4 * add[lane];
            }
            for (int k = 0; k < 4; k++)
                if (p4[4 * i + k] != before[4 * i + k] + d[k])
                    fail_msg("count %d, vertex %d, component %d: %g, expected %g", count, i, k, (double)p4[4 * i + k],
                             (double)(before[4 * i + k] + d[k]));
        }
    }
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_whole_circle),   cmocka_unit_test(test_branch_edges),
        cmocka_unit_test(test_axes_and_zeros), cmocka_unit_test(test_spread_over_packed_lanes),
        cmocka_unit_test(test_reciprocals),    cmocka_unit_test(test_packed_load_and_add_at),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
