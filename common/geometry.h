/* Private: small double-precision vector helpers, the dihedral angle and a
 * 3 × 3 inverse, shared by the builder (rest values), the reference kernels
 * and the implicit solvers' preconditioners. */
#ifndef SB_GEOMETRY_H
#define SB_GEOMETRY_H

#include <math.h>
#include <stdbool.h>

#define SB_PI 3.14159265358979323846

typedef struct sb_vec3 {
    double x, y, z;
} sb_vec3;

/* Whether all three components of v are finite. */
static inline bool sb_finite3(const double v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

static inline sb_vec3 sb_v3(const double* p) { return (sb_vec3){p[0], p[1], p[2]}; }
static inline sb_vec3 sb_v3_sub(sb_vec3 a, sb_vec3 b) { return (sb_vec3){a.x - b.x, a.y - b.y, a.z - b.z}; }
static inline sb_vec3 sb_v3_add(sb_vec3 a, sb_vec3 b) { return (sb_vec3){a.x + b.x, a.y + b.y, a.z + b.z}; }
static inline sb_vec3 sb_v3_scale(sb_vec3 a, double s) { return (sb_vec3){a.x * s, a.y * s, a.z * s}; }
static inline double sb_v3_dot(sb_vec3 a, sb_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline double sb_v3_length(sb_vec3 a) { return sqrt(sb_v3_dot(a, a)); }
static inline sb_vec3 sb_v3_cross(sb_vec3 a, sb_vec3 b) {
    return (sb_vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/* out[0..2] += s * a */
static inline void sb_v3_add_to(double* out, sb_vec3 a, double s) {
    out[0] += s * a.x;
    out[1] += s * a.y;
    out[2] += s * a.z;
}

/* The hinge (e0, e1; o0, o1): n0 = (o0 − e0) × (o0 − e1) and
 * n1 = (o1 − e1) × (o1 − e0) are the normals of the two wings, both pointing
 * the same way when the sheet is flat. The signed dihedral angle is
 * φ = atan2((n0 × n1)·ê, n0·n1), ê along e1 − e0: 0 when flat, ±π when
 * folded shut. */
typedef struct sb_hinge_geometry {
    sb_vec3 edge; /* e1 − e0 */
    sb_vec3 n0, n1;
    double edge_length;
    double phi;
} sb_hinge_geometry;

/* The edge and the normals; phi left 0 (sb_hinge_measure gives it). */
static inline sb_hinge_geometry sb_hinge_shape(sb_vec3 e0, sb_vec3 e1, sb_vec3 o0, sb_vec3 o1) {
    sb_hinge_geometry h;
    h.edge = sb_v3_sub(e1, e0);
    h.edge_length = sb_v3_length(h.edge);
    h.n0 = sb_v3_cross(sb_v3_sub(o0, e0), sb_v3_sub(o0, e1));
    h.n1 = sb_v3_cross(sb_v3_sub(o1, e1), sb_v3_sub(o1, e0));
    h.phi = 0.0;
    return h;
}

static inline sb_hinge_geometry sb_hinge_measure(sb_vec3 e0, sb_vec3 e1, sb_vec3 o0, sb_vec3 o1) {
    sb_hinge_geometry h = sb_hinge_shape(e0, e1, o0, o1);
    double sine = sb_v3_dot(sb_v3_cross(h.n0, h.n1), h.edge) / h.edge_length;
    h.phi = atan2(sine, sb_v3_dot(h.n0, h.n1));
    return h;
}

/* A hinge's wing has collapsed when its height is below this fraction of
 * its edge. */
#define SB_MIN_WING_RATIO 1e-12

/* The hinge's angle φ and u = −∇φ on e0, e1, o0, o1 (the gradient derived
 * in kernels/forces/reference_hinges.c); false when a wing collapsed. phi may be
 * NULL: u alone, without the atan2. */
static inline bool sb_hinge_gradient(const sb_vec3 x[4], double* phi, sb_vec3 u[4]) {
    sb_hinge_geometry g = phi ? sb_hinge_measure(x[0], x[1], x[2], x[3]) : sb_hinge_shape(x[0], x[1], x[2], x[3]);
    double n0_sq = sb_v3_dot(g.n0, g.n0), n1_sq = sb_v3_dot(g.n1, g.n1);
    double limit = SB_MIN_WING_RATIO * g.edge_length * g.edge_length;
    if (!(g.edge_length > 0.0) || !(n0_sq > limit * limit) || !(n1_sq > limit * limit)) return false;
    sb_vec3 w0 = sb_v3_scale(g.n0, 1.0 / n0_sq), w1 = sb_v3_scale(g.n1, 1.0 / n1_sq);
    sb_vec3 unit_edge = sb_v3_scale(g.edge, 1.0 / g.edge_length);
    u[0] = sb_v3_add(sb_v3_scale(w0, sb_v3_dot(sb_v3_sub(x[2], x[1]), unit_edge)),
                     sb_v3_scale(w1, sb_v3_dot(sb_v3_sub(x[3], x[1]), unit_edge)));
    u[1] = sb_v3_add(sb_v3_scale(w0, -sb_v3_dot(sb_v3_sub(x[2], x[0]), unit_edge)),
                     sb_v3_scale(w1, -sb_v3_dot(sb_v3_sub(x[3], x[0]), unit_edge)));
    u[2] = sb_v3_scale(w0, g.edge_length);
    u[3] = sb_v3_scale(w1, g.edge_length);
    if (phi) *phi = g.phi;
    return true;
}

/* φ − φ0 wrapped into (−π, π]. */
static inline double sb_angle_difference(double phi, double phi0) {
    double d = phi - phi0;
    if (d > SB_PI) d -= 2.0 * SB_PI;
    if (d <= -SB_PI) d += 2.0 * SB_PI;
    return d;
}

/* out = a⁻¹ for a 3 × 3 row-major matrix, by its adjugate; false (out
 * untouched) when a is singular or not finite. */
static inline bool sb_m3_invert(const double* a, double* out) {
    double c0 = a[4] * a[8] - a[5] * a[7], c1 = a[5] * a[6] - a[3] * a[8], c2 = a[3] * a[7] - a[4] * a[6];
    double det = a[0] * c0 + a[1] * c1 + a[2] * c2;
    if (!(fabs(det) > 0.0) || !isfinite(det)) return false;
    double inv = 1.0 / det;
    double adjugate[9] = {c0, a[2] * a[7] - a[1] * a[8], a[1] * a[5] - a[2] * a[4],
                          c1, a[0] * a[8] - a[2] * a[6], a[2] * a[3] - a[0] * a[5],
                          c2, a[1] * a[6] - a[0] * a[7], a[0] * a[4] - a[1] * a[3]};
    for (int k = 0; k < 9; k++) out[k] = adjugate[k] * inv;
    return true;
}

#endif
