/* The scalar reference force terms (include/softbond/reference.h): each
 * term's forces are the exact negative gradient of its energy (checked by
 * finite differences on random, nearly straight, nearly collapsed, nearly
 * flat and strongly folded geometry), internal forces carry no net force or
 * torque, everything is invariant under rigid motions, forces vanish at rest,
 * damping dissipates at the rate of Eq. 2, collapsed edges are reported, and
 * a few values are checked against numbers worked out by hand. */
#include "tests/test_util.h"

#include <stdio.h>

/* ---- the test patch ---------------------------------------------------------
 * Four vertices, two triangles (0,1,2) and (1,0,3) sharing the edge 0-1, five
 * bonds (every edge) and one hinge across 0-1: every term has elements. */

enum { PATCH_N = 4, PATCH_DOF = 3 * PATCH_N };

typedef struct consts {
    double bond_k, spring_k, damping, angle_k, sb_k, bend_k;
} consts;

static const uint32_t patch_edges[5][2] = {{0, 1}, {1, 2}, {2, 0}, {0, 3}, {3, 1}};

/* A well-shaped rest patch with edges of about L and a non-flat hinge. */
static void canonical_patch(double L, double out[PATCH_DOF]) {
    const double p[PATCH_DOF] = {0, 0, 0, 1, 0, 0, 0.4, 0.9, 0, 0.6, -0.8, 0.3};
    for (int i = 0; i < PATCH_DOF; ++i) out[i] = L * p[i];
}

static sb_model* build_patch(const double rest[PATCH_DOF], consts c) {
    sb_builder* b = sb_builder_create();
    assert_non_null(b);
    for (int v = 0; v < PATCH_N; ++v)
        assert_int_equal(tu_vertex(b, rest[3 * v], rest[3 * v + 1], rest[3 * v + 2], 1.0, false), v);
    for (int e = 0; e < 5; ++e)
        assert_int_equal(tu_bond(b, patch_edges[e][0], patch_edges[e][1], -1.0, c.bond_k, c.spring_k, c.damping), e);
    assert_int_equal(tu_triangle(b, 0, 1, 2, c.angle_k, c.sb_k), 0);
    assert_int_equal(tu_triangle(b, 1, 0, 3, c.angle_k, c.sb_k), 1);
    assert_int_equal(tu_hinge(b, 0, 1, 2, 3, c.bend_k), 0);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

/* Random rotation matrix (axis-angle, Rodrigues). */
static void random_rotation(tu_rng* r, double R[3][3]) {
    double a[3] = {tu_uniform(r, -1, 1), tu_uniform(r, -1, 1), tu_uniform(r, -1, 1)};
    double n = tu_norm(a);
    for (int i = 0; i < 3; ++i) a[i] /= n;
    double t = tu_uniform(r, 0.3, 3.0), c = cos(t), s = sin(t), C = 1 - c;
    R[0][0] = c + a[0] * a[0] * C;
    R[0][1] = a[0] * a[1] * C - a[2] * s;
    R[0][2] = a[0] * a[2] * C + a[1] * s;
    R[1][0] = a[1] * a[0] * C + a[2] * s;
    R[1][1] = c + a[1] * a[1] * C;
    R[1][2] = a[1] * a[2] * C - a[0] * s;
    R[2][0] = a[2] * a[0] * C - a[1] * s;
    R[2][1] = a[2] * a[1] * C + a[0] * s;
    R[2][2] = c + a[2] * a[2] * C;
}

static void rotate(const double R[3][3], const double* in, double* out, int n, const double t[3]) {
    for (int v = 0; v < n; ++v)
        for (int i = 0; i < 3; ++i)
            out[3 * v + i] = R[i][0] * in[3 * v] + R[i][1] * in[3 * v + 1] + R[i][2] * in[3 * v + 2] + (t ? t[i] : 0.0);
}

/* A random rest patch of scale L (the canonical one perturbed by 15 % and
 * rigidly moved) and a current state perturbed from it by up to 20 %. */
static void random_patch(uint64_t seed, double rest[PATCH_DOF], double cur[PATCH_DOF]) {
    tu_rng r = {seed * 7919u + 17u};
    double L = tu_uniform(&r, 0.05, 3.0), base[PATCH_DOF], R[3][3];
    canonical_patch(L, base);
    for (int i = 0; i < PATCH_DOF; ++i) base[i] += L * tu_uniform(&r, -0.15, 0.15);
    random_rotation(&r, R);
    double t[3] = {tu_uniform(&r, -2, 2), tu_uniform(&r, -2, 2), tu_uniform(&r, -2, 2)};
    rotate(R, base, rest, PATCH_N, t);
    for (int i = 0; i < PATCH_DOF; ++i) cur[i] = rest[i] + L * tu_uniform(&r, -0.2, 0.2);
}

/* The smallest length scale of the patch: shortest edge or triangle height. */
static double smallest_length(const double x[PATCH_DOF]) {
    double m = INFINITY;
    for (int e = 0; e < 5; ++e) {
        double d = tu_dist(x + 3 * patch_edges[e][0], x + 3 * patch_edges[e][1]);
        if (d < m) m = d;
    }
    const uint32_t tri[2][3] = {{0, 1, 2}, {1, 0, 3}};
    for (int t = 0; t < 2; ++t) {
        const double *a = x + 3 * tri[t][0], *b = x + 3 * tri[t][1], *c = x + 3 * tri[t][2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, n[3];
        tu_cross(u, v, n);
        double longest = fmax(tu_dist(a, b), fmax(tu_dist(b, c), tu_dist(c, a)));
        double h = tu_norm(n) / longest;
        if (h < m) m = h;
    }
    return m;
}

/* One term's energy and forces (forces zeroed first); fails on error. */
static double eval_term(const sb_model* m, sb_term term, const double* x, const double* v, double* f, size_t dof) {
    sb_error err;
    double e = NAN;
    memset(&err, 0, sizeof err);
    for (size_t i = 0; i < dof; ++i) f[i] = 0.0;
    sb_status s = sb_reference_term(m, term, x, v, f, &e, &err);
    if (s != SB_OK)
        fail_msg("sb_reference_term(%s) failed: %s: %s", sb_term_name(term), sb_status_name(s), err.message);
    return e;
}

/* max |f + ∇E| / max |f| with a fourth-order central difference
 * (−E(x+2h) + 8E(x+h) − 8E(x−h) + E(x−2h)) / 12h.
 * h = 1e-3 × the smallest length of the geometry (edge or triangle height,
 * the scale on which the energy varies): the truncation error is then about
 * (1e-3)^4 = 1e-12 relative and the rounding error about ε·E/h, at most
 * ~1e-8 of the largest force even where forces are small (they scale with
 * sin θ near a straight angle). Measured worst case: 9e-9 (179.9°, angle
 * term). So a correct gradient passes the 1e-6 bound with a margin of 100,
 * while a wrong one (a missing term, the paper's inexact Eq. 8–10) is off by
 * O(1). */
static double gradient_error(const sb_model* m, sb_term term, const double x[PATCH_DOF]) {
    double f[PATCH_DOF], tmp[PATCH_DOF], xp[PATCH_DOF];
    eval_term(m, term, x, NULL, f, PATCH_DOF);
    assert_true(tu_all_finite(f, PATCH_DOF));
    double fscale = tu_max_abs(f, PATCH_DOF);
    if (fscale == 0.0) fail_msg("%s: all forces are zero, nothing to check", sb_term_name(term));
    double h = 1e-3 * smallest_length(x), worst = 0.0;
    for (int i = 0; i < PATCH_DOF; ++i) {
        double e[4];
        const double steps[4] = {2, 1, -1, -2};
        for (int s = 0; s < 4; ++s) {
            memcpy(xp, x, sizeof xp);
            xp[i] += steps[s] * h;
            e[s] = eval_term(m, term, xp, NULL, tmp, PATCH_DOF);
        }
        double g = (-e[0] + 8 * e[1] - 8 * e[2] + e[3]) / (12 * h);
        double d = fabs(f[i] + g);
        if (d > worst) worst = d;
    }
    return worst / fscale;
}

static const sb_term all_terms[5] = {SB_TERM_BOND, SB_TERM_ANGLE, SB_TERM_STRETCH_BEND, SB_TERM_SPRING, SB_TERM_BEND};

/* Only `term`'s constant is nonzero (the values are arbitrary, not 1). */
static consts only(sb_term term) {
    consts c = {0, 0, 0, 0, 0, 0};
    switch (term) {
    case SB_TERM_BOND: c.bond_k = 37.0; break;
    case SB_TERM_ANGLE: c.angle_k = 2.3; break;
    case SB_TERM_STRETCH_BEND: c.sb_k = 5.1; break;
    case SB_TERM_SPRING:
        c.spring_k = 11.0;
        c.damping = 0.7;
        break;
    case SB_TERM_BEND: c.bend_k = 0.9; break;
    default: break;
    }
    return c;
}

static void check_gradient(const char* what, const double rest[PATCH_DOF], const double cur[PATCH_DOF]) {
    for (int t = 0; t < 5; ++t) {
        sb_model* m = build_patch(rest, only(all_terms[t]));
        assert_true(sb_model_term_enabled(m, all_terms[t]));
        double rel = gradient_error(m, all_terms[t], cur);
        sb_model_destroy(m);
        if (!(rel <= 1e-6))
            fail_msg("%s, term %s: forces differ from −∇E by %.3g of the largest force (bound "
                     "1e-6)",
                     what, sb_term_name(all_terms[t]), rel);
    }
}

static void test_gradient_random(void** state) {
    (void)state;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        double rest[PATCH_DOF], cur[PATCH_DOF];
        char what[64];
        random_patch(seed, rest, cur);
        snprintf(what, sizeof what, "random patch, seed %u", (unsigned)seed);
        check_gradient(what, rest, cur);
    }
}

/* A current patch with edge 0-1 along x from 0 to 1 and vertex 2 (o0) and
 * vertex 3 (o1) placed as given. */
static void make_current(const double p2[3], const double p3[3], double cur[PATCH_DOF]) {
    const double base[6] = {0, 0, 0, 1, 0, 0};
    memcpy(cur, base, sizeof base);
    memcpy(cur + 6, p2, 3 * sizeof(double));
    memcpy(cur + 9, p3, 3 * sizeof(double));
}

static void test_gradient_special(void** state) {
    (void)state;
    const double deg = M_PI / 180.0;
    double rest[PATCH_DOF], cur[PATCH_DOF];
    canonical_patch(1.0, rest);
    const double p3_generic[3] = {0.45, -0.7, 0.35};

    /* θ ≈ 179.9° at vertex 2: it sits just off the middle of edge 0-1. */
    double h179 = 0.5 * tan(0.05 * deg);
    double p2a[3] = {0.5, h179, 0};
    make_current(p2a, p3_generic, cur);
    check_gradient("179.9 degrees at vertex 2", rest, cur);

    /* θ ≈ 179.9° at vertex 0. */
    double p2b[3] = {-0.9 * cos(0.1 * deg), 0.9 * sin(0.1 * deg), 0};
    make_current(p2b, p3_generic, cur);
    check_gradient("179.9 degrees at vertex 0", rest, cur);

    /* θ ≈ 0.1° at vertex 0: edges 0-1 and 0-2 nearly parallel. */
    double p2c[3] = {0.9 * cos(0.1 * deg), 0.9 * sin(0.1 * deg), 0};
    make_current(p2c, p3_generic, cur);
    check_gradient("0.1 degrees at vertex 0", rest, cur);

    /* One edge 1e-4 of the other: |0-2| = 1e-4, |0-1| = 1. */
    double p2d[3] = {1e-4 * cos(60 * deg), 1e-4 * sin(60 * deg), 0};
    make_current(p2d, p3_generic, cur);
    check_gradient("edge 0-2 1e-4 of edge 0-1", rest, cur);

    /* Hinge nearly flat: the wing of vertex 3 out of plane by 1e-3 rad. */
    double p2e[3] = {0.4, 0.9, 0}, p3e[3] = {0.6, -0.8 * cos(1e-3), 0.8 * sin(1e-3)};
    make_current(p2e, p3e, cur);
    check_gradient("hinge folded 1e-3 rad", rest, cur);

    /* Hinge exactly flat (the rest is folded, so forces are not zero). */
    double p3f[3] = {0.6, -0.8, 0};
    make_current(p2e, p3f, cur);
    check_gradient("hinge flat", rest, cur);

    /* Hinge folded by 90° and strongly folded by 170° (wings nearly closed). */
    double p3g[3] = {0.6, -0.8 * cos(90 * deg), 0.8 * sin(90 * deg)};
    make_current(p2e, p3g, cur);
    check_gradient("hinge folded 90 degrees", rest, cur);
    double p3h[3] = {0.6, -0.8 * cos(170 * deg), 0.8 * sin(170 * deg)};
    make_current(p2e, p3h, cur);
    check_gradient("hinge folded 170 degrees", rest, cur);
    double p3i[3] = {0.6, -0.8 * cos(-170 * deg), 0.8 * sin(-170 * deg)};
    make_current(p2e, p3i, cur);
    check_gradient("hinge folded -170 degrees", rest, cur);
}

/* ---- conservation and invariance ------------------------------------------- */

static const consts all_on = {37.0, 11.0, 0.7, 2.3, 5.1, 0.9};

/* All terms through sb_reference_forces; fails on error. */
static double eval_all(const sb_model* m, const double* x, const double* v, double* f) {
    sb_energies en;
    sb_error err;
    memset(&err, 0, sizeof err);
    sb_status s = sb_reference_forces(m, x, v, f, &en, &err);
    if (s != SB_OK) fail_msg("sb_reference_forces failed: %s", err.message);
    return sb_energies_internal(&en);
}

static void test_net_force_and_torque(void** state) {
    (void)state;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        double rest[PATCH_DOF], cur[PATCH_DOF], vel[PATCH_DOF], f[PATCH_DOF];
        random_patch(seed, rest, cur);
        tu_rng r = {seed + 1000};
        for (int i = 0; i < PATCH_DOF; ++i) vel[i] = tu_uniform(&r, -2, 2);
        sb_model* m = build_patch(rest, all_on);
        for (int t = 0; t < 5; ++t) assert_true(sb_model_term_enabled(m, all_terms[t]));
        eval_all(m, cur, vel, f);
        sb_model_destroy(m);
        double sum[3] = {0, 0, 0}, torque[3] = {0, 0, 0}, xmax = tu_max_abs(cur, PATCH_DOF);
        for (int v = 0; v < PATCH_N; ++v) {
            double c[3];
            tu_cross(cur + 3 * v, f + 3 * v, c);
            for (int i = 0; i < 3; ++i) {
                sum[i] += f[3 * v + i];
                torque[i] += c[i];
            }
        }
        /* Cancellation of O(1) terms in double: 1e-12 of the scale is ~1e4 ε. */
        double fscale = tu_max_abs(f, PATCH_DOF);
        assert_true(fscale > 0);
        TU_ASSERT_LE(tu_max_abs(sum, 3), 1e-12 * fscale);
        TU_ASSERT_LE(tu_max_abs(torque, 3), 1e-12 * fscale * xmax);
    }
}

static void test_rigid_motion_invariance(void** state) {
    (void)state;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        double rest[PATCH_DOF], cur[PATCH_DOF], vel[PATCH_DOF];
        random_patch(seed, rest, cur);
        tu_rng r = {seed + 2000};
        for (int i = 0; i < PATCH_DOF; ++i) vel[i] = tu_uniform(&r, -2, 2);
        double R[3][3], t[3] = {tu_uniform(&r, -5, 5), tu_uniform(&r, -5, 5), tu_uniform(&r, -5, 5)};
        random_rotation(&r, R);
        double cur2[PATCH_DOF], vel2[PATCH_DOF], f[PATCH_DOF], f2[PATCH_DOF], fr[PATCH_DOF];
        rotate(R, cur, cur2, PATCH_N, t);
        rotate(R, vel, vel2, PATCH_N, NULL);
        sb_model* m = build_patch(rest, all_on);
        for (int term = 0; term < 5; ++term) {
            double e1 = eval_term(m, all_terms[term], cur, vel, f, PATCH_DOF);
            double e2 = eval_term(m, all_terms[term], cur2, vel2, f2, PATCH_DOF);
            rotate(R, f, fr, PATCH_N, NULL);
            /* Positions move by up to ~10 m, so rounding of coordinates costs
             * ~1e-15 relative; 1e-9 leaves room and still catches any
             * dependence on orientation or origin (O(1) errors). */
            double fscale = tu_max_abs(f, PATCH_DOF), dmax = 0;
            for (int i = 0; i < PATCH_DOF; ++i) dmax = fmax(dmax, fabs(fr[i] - f2[i]));
            if (!(fabs(e1 - e2) <= 1e-9 * fabs(e1)))
                fail_msg("seed %u, %s: energy %.17g changed to %.17g by a rigid motion", (unsigned)seed,
                         sb_term_name(all_terms[term]), e1, e2);
            if (!(dmax <= 1e-9 * fscale))
                fail_msg("seed %u, %s: forces not rotated with the body: max diff %.3g of %.3g", (unsigned)seed,
                         sb_term_name(all_terms[term]), dmax, fscale);
        }
        sb_model_destroy(m);
    }
}

static void test_zero_at_rest(void** state) {
    (void)state;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        double rest[PATCH_DOF], cur[PATCH_DOF], f[PATCH_DOF];
        random_patch(seed, rest, cur);
        sb_model* m = build_patch(rest, all_on);
        double* x = tu_rest_positions(m);
        for (int i = 0; i < PATCH_DOF; ++i) assert_true(x[i] == rest[i]);
        double L = tu_dist(rest, rest + 3);
        for (int term = 0; term < 5; ++term) {
            /* The force scale of each term: k·L for the edge terms, k/L for
             * the angle and hinge terms (J per m), k for stretch-bend (J/m). */
            const double scale[5] = {all_on.bond_k * L, all_on.angle_k / L, all_on.sb_k, all_on.spring_k * L,
                                     all_on.bend_k / L};
            double e = eval_term(m, all_terms[term], x, NULL, f, PATCH_DOF);
            if (!(tu_max_abs(f, PATCH_DOF) <= 1e-12 * scale[term]))
                fail_msg("seed %u, %s: force %.3g at rest (scale %.3g)", (unsigned)seed, sb_term_name(all_terms[term]),
                         tu_max_abs(f, PATCH_DOF), scale[term]);
            if (!(fabs(e) <= 1e-24 * scale[term] * L))
                fail_msg("seed %u, %s: energy %.3g at rest", (unsigned)seed, sb_term_name(all_terms[term]), e);
        }
        free(x);
        sb_model_destroy(m);
    }
}

/* f_damp = forces(v) − forces(0) and its power Σ f_damp·v must equal
 * −Σ_bonds d ((v_b − v_a)·u)², computed here from the definition (Eq. 2). */
static void test_damping_power(void** state) {
    (void)state;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
        double rest[PATCH_DOF], cur[PATCH_DOF], vel[PATCH_DOF], f0[PATCH_DOF], fv[PATCH_DOF];
        random_patch(seed, rest, cur);
        tu_rng r = {seed + 3000};
        for (int i = 0; i < PATCH_DOF; ++i) vel[i] = tu_uniform(&r, -3, 3);
        consts c = {0, 11.0, 0.7, 0, 0, 0};
        sb_model* m = build_patch(rest, c);
        double e0 = eval_term(m, SB_TERM_SPRING, cur, NULL, f0, PATCH_DOF);
        double ev = eval_term(m, SB_TERM_SPRING, cur, vel, fv, PATCH_DOF);
        sb_model_destroy(m);
        /* Damping does not change the potential energy. */
        TU_ASSERT_NEAR(ev, e0, 1e-14 * fabs(e0));
        double power = 0, expected = 0;
        for (int i = 0; i < PATCH_DOF; ++i) power += (fv[i] - f0[i]) * vel[i];
        for (int e = 0; e < 5; ++e) {
            const double *a = cur + 3 * patch_edges[e][0], *b = cur + 3 * patch_edges[e][1];
            const double *va = vel + 3 * patch_edges[e][0], *vb = vel + 3 * patch_edges[e][1];
            double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, n = tu_norm(u);
            double dv[3] = {vb[0] - va[0], vb[1] - va[1], vb[2] - va[2]};
            double s = tu_dot(dv, u) / n;
            expected -= c.damping * s * s;
        }
        assert_true(expected < 0);
        /* A few roundings of O(1) numbers: 1e-12 relative. */
        TU_ASSERT_NEAR(power, expected, 1e-12 * fabs(expected));
    }
}

/* sb_reference_forces overwrites forces with the sum of the terms and fills
 * every term's energy; a term that is off adds nothing. */
static void test_forces_sum_of_terms(void** state) {
    (void)state;
    double rest[PATCH_DOF], cur[PATCH_DOF], vel[PATCH_DOF], f[PATCH_DOF], ft[PATCH_DOF];
    double sum[PATCH_DOF] = {0};
    random_patch(42, rest, cur);
    tu_rng r = {4242};
    for (int i = 0; i < PATCH_DOF; ++i) vel[i] = tu_uniform(&r, -1, 1);
    sb_model* m = build_patch(rest, all_on);
    double eterm[5];
    for (int t = 0; t < 5; ++t) {
        eterm[t] = eval_term(m, all_terms[t], cur, vel, ft, PATCH_DOF);
        for (int i = 0; i < PATCH_DOF; ++i) sum[i] += ft[i];
    }
    for (int i = 0; i < PATCH_DOF; ++i) f[i] = 1e300; /* must be overwritten */
    sb_energies en;
    sb_error err;
    assert_int_equal(sb_reference_forces(m, cur, vel, f, &en, &err), SB_OK);
    double fscale = tu_max_abs(sum, PATCH_DOF), etot = 0;
    for (int i = 0; i < PATCH_DOF; ++i) TU_ASSERT_NEAR(f[i], sum[i], 1e-13 * fscale);
    for (int t = 0; t < 5; ++t) {
        TU_ASSERT_NEAR(en.term[all_terms[t]], eterm[t], 1e-14 * fabs(eterm[t]));
        etot += eterm[t];
    }
    TU_ASSERT_NEAR(sb_energies_internal(&en), etot, 1e-13 * fabs(etot));
    sb_model_destroy(m);

    /* Only the bond term on: the others are off, add nothing, energy 0. */
    consts c = {3.0, 0, 0, 0, 0, 0};
    m = build_patch(rest, c);
    assert_true(sb_model_term_enabled(m, SB_TERM_BOND));
    for (int t = 1; t < 5; ++t) {
        assert_false(sb_model_term_enabled(m, all_terms[t]));
        double e = 123.0;
        for (int i = 0; i < PATCH_DOF; ++i) ft[i] = 7.0;
        assert_int_equal(sb_reference_term(m, all_terms[t], cur, vel, ft, &e, &err), SB_OK);
        assert_true(e == 0.0);
        for (int i = 0; i < PATCH_DOF; ++i) assert_true(ft[i] == 7.0);
    }
    assert_int_equal(sb_reference_forces(m, cur, vel, f, &en, &err), SB_OK);
    for (int t = 1; t < 5; ++t) assert_true(en.term[all_terms[t]] == 0.0);
    sb_model_destroy(m);
}

/* ---- collapsed edges --------------------------------------------------------- */

/* Three separate triangles (0,1,2), (3,4,5), (6,7,8); bonds along their
 * edges in order, so the edge 7-8 is bond 7 and lies in triangle 2. */
static sb_model* build_three_triangles(consts c) {
    sb_builder* b = sb_builder_create();
    for (int t = 0; t < 3; ++t) {
        tu_vertex(b, 3.0 * t, 0, 0, 1, false);
        tu_vertex(b, 3.0 * t + 1, 0, 0, 1, false);
        tu_vertex(b, 3.0 * t + 0.3, 0.8, 0.1, 1, false);
    }
    for (uint32_t t = 0; t < 3; ++t) {
        tu_bond(b, 3 * t, 3 * t + 1, -1, c.bond_k, c.spring_k, c.damping);
        tu_bond(b, 3 * t + 1, 3 * t + 2, -1, c.bond_k, c.spring_k, c.damping);
        tu_bond(b, 3 * t + 2, 3 * t, -1, c.bond_k, c.spring_k, c.damping);
    }
    for (uint32_t t = 0; t < 3; ++t) tu_triangle(b, 3 * t, 3 * t + 1, 3 * t + 2, c.angle_k, c.sb_k);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    return m;
}

static void test_collapsed_edge(void** state) {
    (void)state;
    const sb_term terms[4] = {SB_TERM_BOND, SB_TERM_SPRING, SB_TERM_ANGLE, SB_TERM_STRETCH_BEND};
    for (int t = 0; t < 4; ++t) {
        sb_model* m = build_three_triangles(only(terms[t]));
        double* x = tu_rest_positions(m);
        double v[27] = {0}, f[27] = {0}, e = 0.0;
        for (int i = 0; i < 27; ++i) v[i] = 0.1 * i;
        memcpy(x + 24, x + 21, 3 * sizeof(double)); /* vertex 8 onto vertex 7 */
        sb_error err;
        memset(&err, 0, sizeof err);
        sb_status s = sb_reference_term(m, terms[t], x, v, f, &e, &err);
        if (s != SB_ERR_DEGENERATE)
            fail_msg("%s on a collapsed edge: status %s, expected degenerate", sb_term_name(terms[t]),
                     sb_status_name(s));
        if (terms[t] == SB_TERM_BOND || terms[t] == SB_TERM_SPRING) {
            TU_ASSERT_CONTAINS(err.message, "bond 7");
        } else if (!strstr(err.message, "triangle 2") && !strstr(err.message, "angle")) {
            fail_msg("%s: message does not name triangle 2 or its angle: \"%s\"", sb_term_name(terms[t]), err.message);
        }
        assert_true(tu_all_finite(f, 27));
        assert_true(isfinite(e));
        /* Through sb_reference_forces too. */
        sb_energies en;
        memset(&en, 0, sizeof en);
        assert_int_equal(sb_reference_forces(m, x, v, f, &en, &err), SB_ERR_DEGENERATE);
        assert_true(tu_all_finite(f, 27));

        /* 1e-6 of the rest length is short but not collapsed (the contract
         * says below 1e-9): it must evaluate, finitely. */
        for (int i = 0; i < 3; ++i) x[24 + i] = x[21 + i] + 1e-6 * (x[18 + i] - x[21 + i]);
        eval_term(m, terms[t], x, v, f, 27);
        assert_true(tu_all_finite(f, 27));
        free(x);
        sb_model_destroy(m);
    }
}

/* ---- values by hand ---------------------------------------------------------- */

static void test_known_bond_and_spring(void** state) {
    (void)state;
    for (int which = 0; which < 2; ++which) {
        sb_builder* b = sb_builder_create();
        tu_vertex(b, 0, 0, 0, 1, false);
        tu_vertex(b, 1, 0, 0, 1, false);
        if (which == 0)
            tu_bond(b, 0, 1, -1, 4.0, 0, 0);
        else
            tu_bond(b, 0, 1, -1, 0, 4.0, 0.5);
        sb_model* m = tu_compile(b);
        sb_builder_destroy(b);
        sb_term term = which == 0 ? SB_TERM_BOND : SB_TERM_SPRING;
        /* Stretched from 1 to 1.5 with k = 4: E = ½·4·0.5² = 0.5, |F| = 4·0.5
         * = 2, pulling the ends together. */
        double x[6] = {0, 0, 0, 1.5, 0, 0}, f[6];
        double e = eval_term(m, term, x, NULL, f, 6);
        TU_ASSERT_NEAR(e, 0.5, 1e-15);
        TU_ASSERT_NEAR(f[0], 2.0, 1e-14);
        TU_ASSERT_NEAR(f[3], -2.0, 1e-14);
        for (int i = 0; i < 6; ++i)
            if (i != 0 && i != 3) TU_ASSERT_NEAR(f[i], 0.0, 1e-15);
        /* Compressed to 0.75 along a diagonal: E = ½·4·0.25² = 0.125, |F| = 1
         * pushing apart along (1,1,1)/√3. */
        double s = 0.75 / sqrt(3.0), x2[6] = {1, 2, 3, 1 + s, 2 + s, 3 + s};
        e = eval_term(m, term, x2, NULL, f, 6);
        TU_ASSERT_NEAR(e, 0.125, 1e-14);
        for (int i = 0; i < 3; ++i) {
            TU_ASSERT_NEAR(f[i], -1.0 / sqrt(3.0), 1e-13);
            TU_ASSERT_NEAR(f[3 + i], 1.0 / sqrt(3.0), 1e-13);
        }
        if (term == SB_TERM_SPRING) {
            /* Ends separating at 1 m/s along the bond with d = 0.5: the damping
             * force is 0.5 N on each end, pulling them together. */
            double v[6] = {0, 0, 0, 1, 0, 0};
            double fd[6];
            e = eval_term(m, term, x, v, fd, 6);
            TU_ASSERT_NEAR(fd[0], 2.0 + 0.5, 1e-14);
            TU_ASSERT_NEAR(fd[3], -2.0 - 0.5, 1e-14);
            /* A velocity across the bond is not damped. */
            double vy[6] = {0, 0, 0, 0, 3, 0};
            e = eval_term(m, term, x, vy, fd, 6);
            TU_ASSERT_NEAR(fd[0], 2.0, 1e-14);
            TU_ASSERT_NEAR(fd[4], 0.0, 1e-14);
        }
        sb_model_destroy(m);
    }
}

/* The corner formula of DESIGN.md for one corner (vertex i, neighbours j, k),
 * added to f. */
static void corner_forces(const double* x, int i, int j, int k, double c0, double A0, double B0, double kt, double ksb,
                          double* f) {
    double a[3], b[3];
    for (int d = 0; d < 3; ++d) {
        a[d] = x[3 * j + d] - x[3 * i + d];
        b[d] = x[3 * k + d] - x[3 * i + d];
    }
    double A = tu_norm(a), B = tu_norm(b), ah[3], bh[3];
    for (int d = 0; d < 3; ++d) {
        ah[d] = a[d] / A;
        bh[d] = b[d] / B;
    }
    double c = tu_dot(ah, bh), S = (A - A0) + (B - B0);
    double g = kt * (c - c0) + ksb * S, h = ksb * (c - c0);
    for (int d = 0; d < 3; ++d) {
        double Fj = -(g / A) * (bh[d] - c * ah[d]) - h * ah[d];
        double Fk = -(g / B) * (ah[d] - c * bh[d]) - h * bh[d];
        f[3 * j + d] += Fj;
        f[3 * k + d] += Fk;
        f[3 * i + d] -= Fj + Fk;
    }
}

/* A right-angled triangle (0,0,0), (1,0,0), (0,1,0) — corners 90°, 45°, 45°,
 * edges 1, 1, √2 — closed to the equilateral triangle with side 1: the right
 * angle becomes 60° (vertex 2 moves to (½, √3/2, 0)). */
static void test_known_angle_and_stretch_bend(void** state) {
    (void)state;
    const double r2 = sqrt(0.5), s3 = sqrt(3.0);
    double x[9] = {0, 0, 0, 1, 0, 0, 0.5, s3 / 2, 0};
    for (int which = 0; which < 2; ++which) {
        double kt = which == 0 ? 2.0 : 0.0, ksb = which == 0 ? 0.0 : 3.0;
        sb_builder* b = sb_builder_create();
        tu_vertex(b, 0, 0, 0, 1, false);
        tu_vertex(b, 1, 0, 0, 1, false);
        tu_vertex(b, 0, 1, 0, 1, false);
        tu_triangle(b, 0, 1, 2, kt, ksb);
        sb_model* m = tu_compile(b);
        sb_builder_destroy(b);
        sb_term term = which == 0 ? SB_TERM_ANGLE : SB_TERM_STRETCH_BEND;
        double f[9], expected_f[9] = {0};
        double e = eval_term(m, term, x, NULL, f, 9);
        double expected_e;
        if (which == 0) {
            /* ½ kθ Σ (cos θ − cos θ0)² = ½·2·[(½ − 0)² + 2(½ − √½)²] */
            expected_e = 0.5 * kt * (0.25 + 2 * (0.5 - r2) * (0.5 - r2));
            TU_ASSERT_NEAR(expected_e, 0.33578643762690485, 1e-15);
            /* Corner 0 by hand: â = x̂, b̂ = (½, √3/2, 0), c = ½, g = kθ(½ − 0) = 1:
             * F_1 = −g(b̂ − c â) = (0, −√3/2, 0), F_2 = −g(â − c b̂) = (−¾, √3/4, 0). */
            double c0f[9] = {0};
            corner_forces(x, 0, 1, 2, 0.0, 1, 1, kt, 0, c0f);
            TU_ASSERT_NEAR(c0f[3], 0.0, 1e-15);
            TU_ASSERT_NEAR(c0f[4], -s3 / 2, 1e-15);
            TU_ASSERT_NEAR(c0f[6], -0.75, 1e-15);
            TU_ASSERT_NEAR(c0f[7], s3 / 4, 1e-15);
        } else {
            /* ksb Σ (cos θ − cos θ0)(ΔrA + ΔrB): corner 0 keeps both edges
             * (0); corners 1 and 2 each have c − c0 = ½ − √½ and one edge
             * shortened from √2 to 1. */
            expected_e = ksb * 2 * (0.5 - r2) * (1 - sqrt(2.0));
            TU_ASSERT_NEAR(expected_e, 0.51471862576142973, 1e-14);
        }
        corner_forces(x, 0, 1, 2, 0.0, 1, 1, kt, ksb, expected_f);
        corner_forces(x, 1, 2, 0, r2, sqrt(2.0), 1, kt, ksb, expected_f);
        corner_forces(x, 2, 0, 1, r2, 1, sqrt(2.0), kt, ksb, expected_f);
        TU_ASSERT_NEAR(e, expected_e, 1e-14);
        for (int i = 0; i < 9; ++i) TU_ASSERT_NEAR(f[i], expected_f[i], 1e-13);
        sb_model_destroy(m);
    }
}

/* A flat hinge (0,0,0)-(1,0,0) with wings o0 = (½,1,0) and o1 = (½,−1,0),
 * folded by α = 60° (o1 rotated about the x axis): E = ½ k α², and the
 * restoring force on each wing tip is k α / (its distance to the axis = 1),
 * normal to its wing, turning it back towards flat. */
static void test_known_hinge(void** state) {
    (void)state;
    const double k = 2.0, alpha = M_PI / 3;
    sb_builder* b = sb_builder_create();
    tu_vertex(b, 0, 0, 0, 1, false);
    tu_vertex(b, 1, 0, 0, 1, false);
    tu_vertex(b, 0.5, 1, 0, 1, false);
    tu_vertex(b, 0.5, -1, 0, 1, false);
    tu_triangle(b, 0, 1, 2, 0, 0);
    tu_triangle(b, 1, 0, 3, 0, 0);
    tu_hinge(b, 0, 1, 2, 3, k);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    assert_true(sb_model_term_enabled(m, SB_TERM_BEND));
    assert_int_equal(sb_model_hinge_count(m), 1);
    for (int sign = -1; sign <= 1; sign += 2) {
        double x[12] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -cos(alpha), sign * sin(alpha)}, f[12];
        double e = eval_term(m, SB_TERM_BEND, x, NULL, f, 12);
        TU_ASSERT_NEAR(e, 0.5 * k * alpha * alpha, 1e-13);
        /* o0's force is along ±z (the normal of its wing), away from o1's
         * side: turning o0 away from o1 opens the hinge back towards flat. */
        TU_ASSERT_NEAR(f[6], 0.0, 1e-13);
        TU_ASSERT_NEAR(f[7], 0.0, 1e-13);
        TU_ASSERT_NEAR(f[8], -sign * k * alpha, 1e-12);
        /* o1's force is normal to its wing (-cos α, sign sin α) in the y-z
         * plane and points back towards the flat position (0.5, −1, 0). */
        double fo1[3] = {f[9], f[10], f[11]};
        TU_ASSERT_NEAR(tu_norm(fo1), k * alpha, 1e-12);
        TU_ASSERT_NEAR(fo1[0], 0.0, 1e-13);
        TU_ASSERT_NEAR(fo1[1] * -cos(alpha) + fo1[2] * sign * sin(alpha), 0.0, 1e-12);
        double back[3] = {0, -1 + cos(alpha), -sign * sin(alpha)};
        assert_true(tu_dot(fo1, back) > 0);
    }
    sb_model_destroy(m);
}

/* ---- the co-rotated tetrahedra ----------------------------------------------
 * A 2 × 1 × 1 block of cubes of side L cut into twelve tetrahedra
 * (tu_tet_block), E = 3.5 kPa, ν = 0.45. */

enum { TET_N = 12, TET_DOF = 3 * TET_N };

/* max |f + ∇E| / max |f| for the corotated term, the fourth-order central
 * difference of gradient_error with h = 1e-4 L (L the cubes' side; the
 * tetrahedra's heights are about L / 2 and vary with the strain on that
 * scale): truncation about (1e-4)^4 relative, rounding about ε E / h, near
 * 1e-10 of the largest force here. */
static double tet_gradient_error(const sb_model* m, const double* x, double L) {
    double f[TET_DOF], tmp[TET_DOF], xp[TET_DOF];
    eval_term(m, SB_TERM_COROTATED, x, NULL, f, TET_DOF);
    assert_true(tu_all_finite(f, TET_DOF));
    double fscale = tu_max_abs(f, TET_DOF), h = 1e-4 * L, worst = 0.0;
    assert_true(fscale > 0.0);
    for (int i = 0; i < TET_DOF; ++i) {
        double e[4];
        const double steps[4] = {2, 1, -1, -2};
        for (int s = 0; s < 4; ++s) {
            memcpy(xp, x, sizeof xp);
            xp[i] += steps[s] * h;
            e[s] = eval_term(m, SB_TERM_COROTATED, xp, NULL, tmp, TET_DOF);
        }
        double g = (-e[0] + 8 * e[1] - 8 * e[2] + e[3]) / (12 * h);
        worst = fmax(worst, fabs(f[i] + g));
    }
    return worst / fscale;
}

/* The rest block, strained by up to `strain` L per coordinate, then turned
 * by a random rotation (up to 3 rad) and moved. */
static void tet_current(const double* rest, double L, double strain, uint64_t seed, double* cur) {
    tu_rng r = {seed * 104729u + 3u};
    double R[3][3], strained[TET_DOF], t[3] = {tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1), tu_uniform(&r, -1, 1)};
    for (int i = 0; i < TET_DOF; ++i) strained[i] = rest[i] + strain * L * tu_uniform(&r, -1, 1);
    random_rotation(&r, R);
    rotate(R, strained, cur, TET_N, t);
}

/* The forces are −∇E under strain with large rotations: every coordinate
 * moved by up to 0.15 L, and on the last seeds 0.45 L, about the elements'
 * heights (distortions far beyond the linear range). Measured: below 1e-10
 * of the largest force. */
static void test_corotated_gradient(void** state) {
    (void)state;
    for (uint64_t seed = 1; seed <= 10; ++seed) {
        double L = 0.005 * (double)seed, strain = seed <= 7 ? 0.15 : 0.45;
        sb_model* m = tu_tet_block(2, 1, 1, L, 3500.0, 0.45, 0.1, seed, false);
        assert_int_equal(sb_model_vertex_count(m), TET_N);
        double* rest = tu_rest_positions(m);
        double cur[TET_DOF];
        tet_current(rest, L, strain, seed, cur);
        double rel = tet_gradient_error(m, cur, L);
        print_message("corotated, seed %llu (strain %.2f L): |f + ∇E| %.3g of the largest force\n",
                      (unsigned long long)seed, strain, rel);
        if (!(rel <= 1e-6))
            fail_msg("corotated, seed %llu: forces differ from −∇E by %.3g (bound 1e-6)", (unsigned long long)seed,
                     rel);
        free(rest);
        sb_model_destroy(m);
    }
}

/* At rest, and at rest turned by any rotation and moved, the energy is zero
 * and the forces vanish, within rounding: F = I (or a rotation) to about
 * ε, so the energy is about V E ε² and each force about E L² ε. Bounds:
 * 1e-20 E L³ and 1e-11 E L², with the rounding of positions up to 1 m
 * from the origin for 1 cm elements. A uniaxial
 * stretch ε has F = diag(1 + ε, 1, 1), R = I and the energy
 * V ε² (μ + λ / 2), whatever rotation follows. */
static void test_corotated_rest_and_stretch(void** state) {
    (void)state;
    const double E = 3500.0, nu = 0.45, mu = E / (2 * (1 + nu)), lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
    for (uint64_t seed = 1; seed <= 6; ++seed) {
        double L = 0.01 * (double)seed;
        sb_model* m = tu_tet_block(2, 1, 1, L, E, nu, 0.1, seed, false);
        double* rest = tu_rest_positions(m);
        double cur[TET_DOF], f[TET_DOF];
        tet_current(rest, L, 0.0, seed, cur);
        const double* states[2] = {rest, cur};
        for (int k = 0; k < 2; ++k) {
            double e = eval_term(m, SB_TERM_COROTATED, states[k], NULL, f, TET_DOF);
            TU_ASSERT_LE(fabs(e), 1e-20 * E * L * L * L);
            TU_ASSERT_LE(tu_max_abs(f, TET_DOF), 1e-11 * E * L * L);
        }
        double stretched[TET_DOF], turned[TET_DOF], R[3][3], eps = 0.01 * (double)seed;
        for (int i = 0; i < TET_DOF; ++i) stretched[i] = rest[i] * (i % 3 == 0 ? 1 + eps : 1.0);
        tu_rng r = {seed};
        random_rotation(&r, R);
        rotate(R, stretched, turned, TET_N, NULL);
        double e_turned = eval_term(m, SB_TERM_COROTATED, turned, NULL, f, TET_DOF);
        double e_stretched = eval_term(m, SB_TERM_COROTATED, stretched, NULL, f, TET_DOF);
        TU_ASSERT_NEAR(e_turned, e_stretched, 1e-10 * e_stretched);
        free(rest);
        sb_model_destroy(m);
    }
    /* without jitter the block's volume is 2 L³ and every element has F = diag(1 + ε, 1, 1) */
    double L = 0.02, eps = 0.03;
    sb_model* m = tu_tet_block(2, 1, 1, L, E, nu, 0.0, 1, false);
    double* rest = tu_rest_positions(m);
    double stretched[TET_DOF], f[TET_DOF];
    for (int i = 0; i < TET_DOF; ++i) stretched[i] = rest[i] * (i % 3 == 0 ? 1 + eps : 1.0);
    double e = eval_term(m, SB_TERM_COROTATED, stretched, NULL, f, TET_DOF);
    TU_ASSERT_NEAR(e, 2 * L * L * L * eps * eps * (mu + 0.5 * lambda), 1e-12 * e);
    free(rest);
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gradient_random),
        cmocka_unit_test(test_gradient_special),
        cmocka_unit_test(test_net_force_and_torque),
        cmocka_unit_test(test_rigid_motion_invariance),
        cmocka_unit_test(test_zero_at_rest),
        cmocka_unit_test(test_damping_power),
        cmocka_unit_test(test_forces_sum_of_terms),
        cmocka_unit_test(test_collapsed_edge),
        cmocka_unit_test(test_known_bond_and_spring),
        cmocka_unit_test(test_known_angle_and_stretch_bend),
        cmocka_unit_test(test_known_hinge),
        cmocka_unit_test(test_corotated_gradient),
        cmocka_unit_test(test_corotated_rest_and_stretch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
