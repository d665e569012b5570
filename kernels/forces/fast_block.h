/* Private: iterating a color's elements in SIMD blocks, shared by the fast
 * kernels. */
#ifndef SB_FAST_BLOCK_H
#define SB_FAST_BLOCK_H

#include "kernels/forces/fast_kernels.h"
#include "kernels/forces/fast_model.h"
#include "kernels/runtime/wide.h"
#include "common/geometry.h"

#include <float.h>

/* Lanes per block: SB_WIDTH, or 1 for the serial overflow color. */
static inline uint32_t sb_block_step(bool serial) { return serial ? 1u : SB_WIDTH; }

/* Real elements in the block starting at s. */
static inline int sb_block_count(uint32_t s, uint32_t end, uint32_t step) {
    return (int)(end - s < step ? end - s : step);
}

/* An element's vertices as its kernel reads them. In float a position is
 * 24 bits, and the compensated drifts keep what its rounding left out in a
 * carry (kernels/state/vertex_state.h); a force evaluated at the rounded
 * positions carries their noise, which heats an undamped body (+46 %
 * energy over 4 × 10⁵ Verlet steps, tests/test_long_run_energy.c, against
 * +0.03 % with the carries). So in float each element is placed about its
 * first vertex x_0: vertex c at (x_c − x_0) + (carry_c − carry_0), where
 * the first difference is exact or rounded to the element's size, not to
 * the coordinates', and the carries add back the rest; vertex 0 sits at
 * the origin. The force formulas depend only on differences of positions,
 * so the translation changes nothing else. In a double build there are no
 * carries and each vertex is x_c itself, as before. */
typedef struct sb_worigin {
    sb_wvec3 x, carry; /* vertex 0's position and carry (float) */
} sb_worigin;

/* Vertex 0 of each lane's element, which sets *origin. */
static inline sb_wvec3 sb_wv_origin_at(const sb_fast_frame* fr, const uint32_t* id, sb_worigin* origin) {
    sb_wvec3 x = sb_wv_load4_at(fr->positions4, id);
#if SB_DOUBLE
    (void)origin;
    return x;
#else
    *origin = (sb_worigin){x, sb_wv_load4_at(fr->carries4, id)};
    const sb_wide zero = sb_w_set(0);
    return (sb_wvec3){zero, zero, zero};
#endif
}

/* Another vertex of each lane's element, about its origin. */
static inline sb_wvec3 sb_wv_vertex_at(const sb_fast_frame* fr, const uint32_t* id, const sb_worigin* origin) {
    sb_wvec3 x = sb_wv_load4_at(fr->positions4, id);
#if SB_DOUBLE
    (void)origin;
    return x;
#else
    return sb_wv_add(sb_wv_sub(x, origin->x), sb_wv_sub(sb_wv_load4_at(fr->carries4, id), origin->carry));
#endif
}

/* The scalar kernels' (in double) position of vertex v, component k:
 * x + carry, exact in double. */
static inline double sb_fast_position(const sb_fast_frame* fr, uint32_t v, int k) {
    size_t at = 4 * (size_t)v + (size_t)k;
    return SB_DOUBLE ? (double)fr->positions4[at] : (double)fr->positions4[at] + (double)fr->carries4[at];
}

/* Whether a lane's squared length is at or past the margin of its break
 * limits (min2 may be NULL: no bond has a min). */
static inline bool sb_near_limit(const sb_real* max2, const sb_real* min2, uint32_t s, sb_wide squared, int count) {
    return sb_w_any(sb_w_less(sb_w_load(max2 + s), squared), count) ||
           (min2 && sb_w_any(sb_w_less(squared, sb_w_load(min2 + s)), count));
}

/* The bits (flag >> shift) & mask of each lane's flag byte (flags padded
 * like the slots), as a real: the compiler turns the loop into a byte load
 * and a widening. */
static inline sb_wide sb_w_field(const uint8_t* flags, int shift, unsigned mask) {
    sb_real lanes[SB_WIDTH];
    for (int l = 0; l < SB_WIDTH; l++) lanes[l] = (sb_real)(flags[l] >> shift & mask);
    return sb_w_load(lanes);
}

static inline sb_wide sb_w_constant(sb_fast_constant c, uint32_t s) {
    return c.values ? sb_w_load(c.values + s) : sb_w_set(c.uniform);
}

/* Bit `bit` of each lane's flag byte, as 1 or 0. */
static inline sb_wide sb_w_bit(const uint8_t* flags, int bit) { return sb_w_field(flags, bit, 1u); }

/* A triangle slot's angle and stretch-bend constants: zero for a triangle
 * a breakable model dropped (sb_fast_model.mortal_triangles). */
static inline void sb_w_corner_constants(const sb_fast_model* m, uint32_t s, sb_wide* ka, sb_wide* ksb) {
    *ka = sb_w_constant(m->angle_k, s);
    *ksb = sb_w_constant(m->stretch_bend_k, s);
    if (!m->mortal_triangles) return;
    sb_wide live = sb_w_bit(m->tri_owned + s, SB_TRIANGLE_LIVE);
    *ka = sb_w_mul(live, *ka);
    *ksb = sb_w_mul(live, *ksb);
}

/* φ − φ0 per lane, wrapped into (−π, π] as sb_angle_difference does
 * (the hinge kernel, the fused hinges, vbd's fast sweep, the hinges' second
 * derivatives). */
static inline sb_wide sb_w_angle_delta(sb_wide sine, sb_wide cosine, sb_wide phi0) {
    const sb_wide pi = sb_w_set((sb_real)SB_PI), two_pi = sb_w_set((sb_real)(2.0 * SB_PI));
    sb_wide d = sb_w_sub(sb_w_atan2(sine, cosine), phi0);
    d = sb_w_pick_greater(d, pi, sb_w_sub(d, two_pi), d);
    return sb_w_pick_greater(d, sb_w_sub(sb_w_set(0), pi), d, sb_w_add(d, two_pi));
}

#if SB_DOUBLE
#define SB_REAL_MIN DBL_MIN
#else
#define SB_REAL_MIN FLT_MIN
#endif

/* The lanes where one of the n values is not finite: their absolute values'
 * sum keeps a NaN or an infinity (a max would drop a NaN). */
static inline sb_wmask sb_w_not_finite(const sb_wide* values, int n) {
    sb_wide sum = sb_w_set(0);
    for (int k = 0; k < n; k++) sum = sb_w_add(sum, sb_w_abs(values[k]));
    return sb_w_less(sb_w_set(SB_DOUBLE ? (sb_real)DBL_MAX : (sb_real)FLT_MAX), sum);
}

/* A hinge's wing has collapsed when its height is below SB_MIN_WING_RATIO
 * of the edge (common/geometry.h): |n|² below this, from the squared edge
 * length; the smallest normal number keeps a zero-length edge caught. */
static inline sb_wide sb_w_wing_limit(sb_wide edge_sq) {
    const sb_wide ratio = sb_w_set((sb_real)(SB_MIN_WING_RATIO * SB_MIN_WING_RATIO));
    return sb_w_add(sb_w_mul(ratio, sb_w_mul(edge_sq, edge_sq)), sb_w_set(SB_REAL_MIN));
}

#endif
