/* Private: the narrow phase of self-contact (kernels/contact/proximity.c), in
 * double: closest points between a point and a triangle and between two
 * segments, and the continuous tests of a vertex against a triangle and of
 * an edge against an edge that both move linearly over a step. */
#ifndef SB_PROXIMITY_H
#define SB_PROXIMITY_H

#include "common/geometry.h"

#include <stdbool.h>

/* The closest point of triangle (a, b, c) to p, as barycentric weights w
 * (w[0] a + w[1] b + w[2] c); returns the squared distance. A degenerate
 * triangle is treated as its longest edge. */
double sb_point_triangle_closest(sb_vec3 p, sb_vec3 a, sb_vec3 b, sb_vec3 c, double w[3]);

/* The closest points p0 + s (p1 − p0) and q0 + u (q1 − q0), s and u in
 * [0, 1]; returns the squared distance. */
double sb_segments_closest(sb_vec3 p0, sb_vec3 p1, sb_vec3 q0, sb_vec3 q1, double* s, double* u);

/* The roots in [0, 1] of a3 t³ + a2 t² + a1 t + a0 where it changes sign
 * (or reaches zero at t = 1 from a nonzero value), ascending; returns how
 * many (at most 3). A polynomial that does not
 * change sign in [0, 1] (including one that is zero throughout) has none. */
int sb_cubic_sign_changes(double a3, double a2, double a1, double a0, double roots[3]);

/* Four points moving linearly over a step, from x0[k] (t = 0) to x1[k]
 * (t = 1). */
typedef struct sb_moving_quad {
    sb_vec3 x0[4], x1[4];
} sb_moving_quad;

/* The coefficients (a3, a2, a1, a0) of the cubic in t
 * (x1(t) − x0(t)) · ((x2(t) − x0(t)) × (x3(t) − x0(t))), which is zero
 * exactly when the four points are coplanar. */
void sb_coplanarity_cubic(const sb_moving_quad* q, double coefficients[4]);

/* Vertex 0 against triangle (1, 2, 3): the earliest time t in [0, 1] at
 * which the cubic changes sign with the vertex within `reach` of the
 * triangle; fills t and the weights of the triangle's closest point then.
 * False when there is none. */
bool sb_vertex_triangle_crossing(const sb_moving_quad* q, double reach, double* t, double w[3]);

/* Edge (0, 1) against edge (2, 3): the same with the two segments within
 * `reach` of each other; fills t and the closest points' parameters. */
bool sb_edge_edge_crossing(const sb_moving_quad* q, double reach, double* t, double* s, double* u);

/* Whether the pair could have come within `reach` at some time of the step,
 * given its distance at the end: no point of either feature moved further
 * than the largest move δ of the four points, so the distance never fell
 * below end_distance − 2δ. A cheap test before the continuous ones. */
bool sb_quad_may_cross(const sb_moving_quad* q, double end_distance, double reach);

/* Point k of the quad at time t. */
static inline sb_vec3 sb_quad_at(const sb_moving_quad* q, int k, double t) {
    return sb_v3_add(q->x0[k], sb_v3_scale(sb_v3_sub(q->x1[k], q->x0[k]), t));
}

#endif
