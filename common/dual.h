/* Private: dual numbers, a value and its derivative along one direction.
 *
 * The second derivatives of the force terms (kernels/hessian_*.c) come from
 * running each term's exact force formula on dual numbers: seeding the
 * positions with a direction p gives, in the derivative parts, the force's
 * directional derivative ∂f/∂x · p exactly (to rounding, no step size), so a
 * Hessian column, a Hessian-vector product and a diagonal block are all the
 * same computation with a different seed. */
#ifndef SB_DUAL_H
#define SB_DUAL_H

#include "common/geometry.h"

#include <math.h>

typedef struct sb_dual {
    double v, d; /* value, derivative */
} sb_dual;

typedef struct sb_dvec3 {
    sb_vec3 v, d;
} sb_dvec3;

static inline sb_dual sb_d(double v, double d) { return (sb_dual){v, d}; }
static inline sb_dual sb_d_const(double v) { return (sb_dual){v, 0.0}; }
static inline sb_dual sb_d_add(sb_dual a, sb_dual b) { return (sb_dual){a.v + b.v, a.d + b.d}; }
static inline sb_dual sb_d_sub(sb_dual a, sb_dual b) { return (sb_dual){a.v - b.v, a.d - b.d}; }
static inline sb_dual sb_d_mul(sb_dual a, sb_dual b) { return (sb_dual){a.v * b.v, a.d * b.v + a.v * b.d}; }
static inline sb_dual sb_d_div(sb_dual a, sb_dual b) {
    return (sb_dual){a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v)};
}
static inline sb_dual sb_d_scale(sb_dual a, double s) { return (sb_dual){a.v * s, a.d * s}; }
static inline sb_dual sb_d_sqrt(sb_dual a) {
    double r = sqrt(a.v);
    return (sb_dual){r, a.d / (2.0 * r)};
}
/* The point at x + ε p, as a dual vector (both 3 doubles). */
static inline sb_dvec3 sb_dv3(const double* x, const double* p) { return (sb_dvec3){sb_v3(x), sb_v3(p)}; }
static inline sb_dvec3 sb_dv3_add(sb_dvec3 a, sb_dvec3 b) {
    return (sb_dvec3){sb_v3_add(a.v, b.v), sb_v3_add(a.d, b.d)};
}
static inline sb_dvec3 sb_dv3_sub(sb_dvec3 a, sb_dvec3 b) {
    return (sb_dvec3){sb_v3_sub(a.v, b.v), sb_v3_sub(a.d, b.d)};
}
static inline sb_dvec3 sb_dv3_scale(sb_dvec3 a, sb_dual s) {
    return (sb_dvec3){sb_v3_scale(a.v, s.v), sb_v3_add(sb_v3_scale(a.d, s.v), sb_v3_scale(a.v, s.d))};
}
static inline sb_dual sb_dv3_dot(sb_dvec3 a, sb_dvec3 b) {
    return (sb_dual){sb_v3_dot(a.v, b.v), sb_v3_dot(a.d, b.v) + sb_v3_dot(a.v, b.d)};
}
static inline sb_dvec3 sb_dv3_cross(sb_dvec3 a, sb_dvec3 b) {
    return (sb_dvec3){sb_v3_cross(a.v, b.v), sb_v3_add(sb_v3_cross(a.d, b.v), sb_v3_cross(a.v, b.d))};
}
static inline sb_dual sb_dv3_length(sb_dvec3 a) { return sb_d_sqrt(sb_dv3_dot(a, a)); }

#endif
