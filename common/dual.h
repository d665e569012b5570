/* Private: dual numbers with many seeds, a value and its derivatives along
 * up to SB_DUAL_SEEDS directions at once.
 *
 * The second derivatives of the force terms (kernels/hessian_*.c) come from
 * running each term's exact force formula on dual numbers: seeding the
 * positions with directions p_1 … p_s gives, in the derivative parts, the
 * force's directional derivatives ∂f/∂x · p_k exactly (to rounding, no step
 * size). One run seeded with the 3 n unit vectors of an element's n ≤ 4
 * vertices gives its whole stiffness matrix; seeded with one vertex's three
 * axes, that vertex's diagonal block; seeded with p, a Hessian-vector
 * product. The value part is computed once for all seeds, and the seeds'
 * loops have a fixed length the compiler vectorises: one run of twelve seeds
 * costs about what three single-seed runs did. */
#ifndef SB_DUAL_H
#define SB_DUAL_H

#include "common/geometry.h"

#include <math.h>

/* The operations pass 100-byte structs by value: inlined, they become
 * vector registers; called, they would be copies through memory. */
#define SB_DUAL_INLINE static inline __attribute__((always_inline))

enum { SB_DUAL_SEEDS = 12 }; /* 3 × the most vertices an element has */

typedef struct sb_dual {
    double v;                /* value */
    double d[SB_DUAL_SEEDS]; /* derivative along each seed */
} sb_dual;

typedef struct sb_dvec3 {
    sb_dual x, y, z;
} sb_dvec3;

#define SB_DUAL_EACH(k) for (int k = 0; k < SB_DUAL_SEEDS; k++)

SB_DUAL_INLINE sb_dual sb_d_const(double v) { return (sb_dual){.v = v}; }
SB_DUAL_INLINE sb_dual sb_d_add(sb_dual a, sb_dual b) {
    sb_dual r = {.v = a.v + b.v};
    SB_DUAL_EACH(k) r.d[k] = a.d[k] + b.d[k];
    return r;
}
SB_DUAL_INLINE sb_dual sb_d_sub(sb_dual a, sb_dual b) {
    sb_dual r = {.v = a.v - b.v};
    SB_DUAL_EACH(k) r.d[k] = a.d[k] - b.d[k];
    return r;
}
SB_DUAL_INLINE sb_dual sb_d_mul(sb_dual a, sb_dual b) {
    sb_dual r = {.v = a.v * b.v};
    SB_DUAL_EACH(k) r.d[k] = a.d[k] * b.v + a.v * b.d[k];
    return r;
}
SB_DUAL_INLINE sb_dual sb_d_scale(sb_dual a, double s) {
    sb_dual r = {.v = a.v * s};
    SB_DUAL_EACH(k) r.d[k] = a.d[k] * s;
    return r;
}
/* f(a) by the chain rule, given value = f(a.v) and slope = f'(a.v). */
SB_DUAL_INLINE sb_dual sb_d_chain(double value, sb_dual a, double slope) {
    sb_dual r = {.v = value};
    SB_DUAL_EACH(k) r.d[k] = a.d[k] * slope;
    return r;
}
SB_DUAL_INLINE sb_dual sb_d_div(sb_dual a, sb_dual b) {
    double inv = 1.0 / b.v, q = a.v * inv;
    sb_dual r = {.v = q};
    SB_DUAL_EACH(k) r.d[k] = (a.d[k] - q * b.d[k]) * inv;
    return r;
}
SB_DUAL_INLINE sb_dual sb_d_sqrt(sb_dual a) {
    double root = sqrt(a.v);
    return sb_d_chain(root, a, 0.5 / root);
}
/* atan2(y, x): d = (x dy − y dx) / (x² + y²). */
SB_DUAL_INLINE sb_dual sb_d_atan2(sb_dual y, sb_dual x) {
    double inv = 1.0 / (x.v * x.v + y.v * y.v);
    sb_dual r = {.v = atan2(y.v, x.v)};
    SB_DUAL_EACH(k) r.d[k] = (x.v * y.d[k] - y.v * x.d[k]) * inv;
    return r;
}

/* The point x with no derivative; sb_dv3_seed gives it one. */
SB_DUAL_INLINE sb_dvec3 sb_dv3_at(const double* x) {
    return (sb_dvec3){sb_d_const(x[0]), sb_d_const(x[1]), sb_d_const(x[2])};
}
/* Adds direction p (3 doubles) to seed k of a. */
SB_DUAL_INLINE void sb_dv3_seed(sb_dvec3* a, int k, const double* p) {
    a->x.d[k] = p[0], a->y.d[k] = p[1], a->z.d[k] = p[2];
}
/* Seed k moves a along one axis (0, 1, 2: x, y, z). */
SB_DUAL_INLINE void sb_dv3_seed_axis(sb_dvec3* a, int k, int axis) {
    (axis == 0 ? &a->x : axis == 1 ? &a->y : &a->z)->d[k] = 1.0;
}
SB_DUAL_INLINE sb_vec3 sb_dv3_value(sb_dvec3 a) { return (sb_vec3){a.x.v, a.y.v, a.z.v}; }
/* The derivative along seed k. */
SB_DUAL_INLINE sb_vec3 sb_dv3_derivative(sb_dvec3 a, int k) { return (sb_vec3){a.x.d[k], a.y.d[k], a.z.d[k]}; }

SB_DUAL_INLINE sb_dvec3 sb_dv3_add(sb_dvec3 a, sb_dvec3 b) {
    return (sb_dvec3){sb_d_add(a.x, b.x), sb_d_add(a.y, b.y), sb_d_add(a.z, b.z)};
}
SB_DUAL_INLINE sb_dvec3 sb_dv3_sub(sb_dvec3 a, sb_dvec3 b) {
    return (sb_dvec3){sb_d_sub(a.x, b.x), sb_d_sub(a.y, b.y), sb_d_sub(a.z, b.z)};
}
SB_DUAL_INLINE sb_dvec3 sb_dv3_scale(sb_dvec3 a, sb_dual s) {
    return (sb_dvec3){sb_d_mul(a.x, s), sb_d_mul(a.y, s), sb_d_mul(a.z, s)};
}
SB_DUAL_INLINE sb_dual sb_dv3_dot(sb_dvec3 a, sb_dvec3 b) {
    return sb_d_add(sb_d_add(sb_d_mul(a.x, b.x), sb_d_mul(a.y, b.y)), sb_d_mul(a.z, b.z));
}
SB_DUAL_INLINE sb_dvec3 sb_dv3_cross(sb_dvec3 a, sb_dvec3 b) {
    return (sb_dvec3){sb_d_sub(sb_d_mul(a.y, b.z), sb_d_mul(a.z, b.y)),
                      sb_d_sub(sb_d_mul(a.z, b.x), sb_d_mul(a.x, b.z)),
                      sb_d_sub(sb_d_mul(a.x, b.y), sb_d_mul(a.y, b.x))};
}
SB_DUAL_INLINE sb_dual sb_dv3_length(sb_dvec3 a) { return sb_d_sqrt(sb_dv3_dot(a, a)); }

#endif
