/* Private: the answer every built-in shape's sweep gives.
 *
 * Each built-in shape has one sweep in its rest frame (the
 * def's geometry as given, in world coordinates; kernels/contact/colliders/<shape>.c):
 * the move from → to against the closed solid bounded by the surface
 * inflated by `thickness` (m). Its answer, shared by every shape
 * (sb_sweep_from_inside, sb_sweep_from_outside below):
 *
 *   from outside, the move enters the solid  → true, fraction of the first
 *       point of the move in the solid (in [0, 1]), depth 0, the outward
 *       normal there;
 *   from outside, `to` outside, and the move only grazes the surface (one
 *       point in common: a tangent move, a line through an edge) or misses
 *       → false;
 *   from inside or on the surface, `to` inside or on it (resting contact)
 *       → true, fraction 1 (the vertex keeps the move the integrator gave
 *       it), depth = how far `to` lies inside, normal = the outward
 *       direction of least penetration at `to`;
 *   from inside or on the surface, `to` outside: the move leaves. If it
 *       starts along the least-penetration normal at `from` or away from
 *       the body (d·n >= 0) → false; if it heads in (d·n < 0: it would cross
 *       the body, or it starts on the surface and goes in) → true, fraction
 *       0, depth = how far `from` lies inside, normal at `from`. So a vertex
 *       that rounding left a hair inside cannot tunnel through.
 *
 * A zero-length move is a point query: true (fraction 1, its depth) when the
 * point is inside or on the surface. */
#ifndef SB_SWEEP_H
#define SB_SWEEP_H

#include <stdbool.h>

/* One end of a move: whether it is in the closed inflated solid, how deep
 * (>= 0) and the outward normal of least penetration there. */
typedef struct sb_sweep_end {
    bool inside;
    double depth;
    double normal[3];
} sb_sweep_end;

/* The answer when `from` is inside or on the surface (above). */
bool sb_sweep_from_inside(const sb_sweep_end* from_end, const sb_sweep_end* to_end, const double from[3],
                          const double to[3], double* fraction, double* depth, double normal[3]);
/* The answer when `from` is outside, given the interval [lo, hi] of the
 * line from + s (to − from) in the solid (entered: false when the line
 * misses it or only touches it) and the outward normal at lo. */
bool sb_sweep_from_outside(bool entered, double lo, double hi, const double lo_normal[3], const sb_sweep_end* to_end,
                           double* fraction, double* depth, double normal[3]);

#endif
