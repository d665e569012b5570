/* Private: the "wide" real — one SIMD register of sb_real lanes — behind a
 * few inline functions, so that every fast kernel is written once and runs
 * as AVX-512, AVX2 or plain scalar code (SB_WIDTH lanes of 16/8/1 in float,
 * 8/4/1 in double), chosen by the compiler flags of the SB_SIMD build
 * option. The scalar variant is the same kernel code with one lane, not a
 * separate implementation.
 *
 * Elements are processed in blocks of SB_WIDTH. The element arrays are
 * padded to a multiple of SB_WIDTH with copies of a real element, so loads
 * and gathers of a block are always in bounds and finite; `count` (the
 * number of real lanes in the block) masks what is written and summed.
 * Energies are summed lane-wise over a chunk (sb_w_keep drops the padding
 * lanes of a last block) and reduced across lanes once per chunk.
 *
 * Lane-wise choices without branches: sb_w_pick_greater(a, b, x, y) is
 * a > b ? x : y, sb_w_pick_negative(s, x, y) is x where s has its sign bit
 * set (−0 included), else y. */
#ifndef SB_WIDE_H
#define SB_WIDE_H

#include "softbond/types.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#if defined(__AVX512F__) || defined(__AVX2__)
#include <immintrin.h>
#endif

#if defined(__AVX512F__) && !SB_DOUBLE
/* ---- AVX-512, float: 16 lanes ------------------------------------------ */
#define SB_WIDTH 16
#define SB_SIMD_NAME "avx512"
typedef __m512 sb_wide;
typedef __m512i sb_windex;
typedef __mmask16 sb_wmask;
static inline sb_wide sb_w_set(sb_real s) { return _mm512_set1_ps(s); }
static inline sb_wide sb_w_load(const sb_real* p) { return _mm512_loadu_ps(p); }
static inline sb_windex sb_w_index(const uint32_t* p) { return _mm512_loadu_si512((const void*)p); }
static inline sb_wide sb_w_gather(const sb_real* base, sb_windex i) { return _mm512_i32gather_ps(i, base, 4); }
static inline sb_wmask sb_w_lanes(int count) { return (sb_wmask)((1u << count) - 1u); }
static inline sb_wide sb_w_add(sb_wide a, sb_wide b) { return _mm512_add_ps(a, b); }
static inline sb_wide sb_w_sub(sb_wide a, sb_wide b) { return _mm512_sub_ps(a, b); }
static inline sb_wide sb_w_mul(sb_wide a, sb_wide b) { return _mm512_mul_ps(a, b); }
static inline sb_wide sb_w_div(sb_wide a, sb_wide b) { return _mm512_div_ps(a, b); }
static inline sb_wide sb_w_sqrt(sb_wide a) { return _mm512_sqrt_ps(a); }
/* 14-bit estimate, one Newton step: ~1 ulp, without a division */
static inline sb_wide sb_w_rsqrt(sb_wide a) {
    __m512 y = _mm512_rsqrt14_ps(a);
    __m512 t = _mm512_mul_ps(_mm512_mul_ps(a, y), y);
    return _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(0.5f), y), _mm512_sub_ps(_mm512_set1_ps(3.0f), t));
}
/* 1/a: 14-bit estimate, one Newton step (~1 ulp), without a division */
static inline sb_wide sb_w_recip(sb_wide a) {
    __m512 y = _mm512_rcp14_ps(a);
    return _mm512_fmadd_ps(y, _mm512_fnmadd_ps(a, y, _mm512_set1_ps(1.0f)), y);
}
static inline sb_wmask sb_w_less(sb_wide a, sb_wide b) { return _mm512_cmp_ps_mask(a, b, _CMP_NGE_UQ); }
static inline bool sb_w_any(sb_wmask m, int count) { return (m & sb_w_lanes(count)) != 0; }
static inline double sb_w_sum(sb_wide v, int count) { return _mm512_mask_reduce_add_ps(sb_w_lanes(count), v); }
static inline sb_wide sb_w_keep(sb_wide v, int count) { return _mm512_maskz_mov_ps(sb_w_lanes(count), v); }
static inline sb_wide sb_w_min(sb_wide a, sb_wide b) { return _mm512_min_ps(a, b); }
static inline sb_wide sb_w_max(sb_wide a, sb_wide b) { return _mm512_max_ps(a, b); }
static inline void sb_w_store(sb_real* p, sb_wide v) { _mm512_storeu_ps(p, v); }
static inline sb_wide sb_w_abs(sb_wide a) { return _mm512_abs_ps(a); }
static inline sb_wide sb_w_pick_greater(sb_wide a, sb_wide b, sb_wide x, sb_wide y) {
    return _mm512_mask_blend_ps(_mm512_cmp_ps_mask(a, b, _CMP_GT_OQ), y, x);
}
static inline sb_wide sb_w_pick_negative(sb_wide s, sb_wide x, sb_wide y) {
    return _mm512_mask_blend_ps(_mm512_cmplt_epi32_mask(_mm512_castps_si512(s), _mm512_setzero_si512()), y, x);
}

#elif defined(__AVX512F__) && SB_DOUBLE
/* ---- AVX-512, double: 8 lanes ------------------------------------------ */
#define SB_WIDTH 8
#define SB_SIMD_NAME "avx512"
typedef __m512d sb_wide;
typedef __m256i sb_windex;
typedef __mmask8 sb_wmask;
static inline sb_wide sb_w_set(sb_real s) { return _mm512_set1_pd(s); }
static inline sb_wide sb_w_load(const sb_real* p) { return _mm512_loadu_pd(p); }
static inline sb_windex sb_w_index(const uint32_t* p) { return _mm256_loadu_si256((const void*)p); }
static inline sb_wide sb_w_gather(const sb_real* base, sb_windex i) { return _mm512_i32gather_pd(i, base, 8); }
static inline sb_wmask sb_w_lanes(int count) { return (sb_wmask)((1u << count) - 1u); }
static inline sb_wide sb_w_add(sb_wide a, sb_wide b) { return _mm512_add_pd(a, b); }
static inline sb_wide sb_w_sub(sb_wide a, sb_wide b) { return _mm512_sub_pd(a, b); }
static inline sb_wide sb_w_mul(sb_wide a, sb_wide b) { return _mm512_mul_pd(a, b); }
static inline sb_wide sb_w_div(sb_wide a, sb_wide b) { return _mm512_div_pd(a, b); }
static inline sb_wide sb_w_sqrt(sb_wide a) { return _mm512_sqrt_pd(a); }
/* 14-bit estimate, two Newton steps */
static inline sb_wide sb_w_rsqrt(sb_wide a) {
    __m512d y = _mm512_rsqrt14_pd(a);
    for (int step = 0; step < 2; step++) {
        __m512d t = _mm512_mul_pd(_mm512_mul_pd(a, y), y);
        y = _mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(0.5), y), _mm512_sub_pd(_mm512_set1_pd(3.0), t));
    }
    return y;
}
/* 1/a: 14-bit estimate, two Newton steps */
static inline sb_wide sb_w_recip(sb_wide a) {
    __m512d y = _mm512_rcp14_pd(a);
    for (int step = 0; step < 2; step++) y = _mm512_fmadd_pd(y, _mm512_fnmadd_pd(a, y, _mm512_set1_pd(1.0)), y);
    return y;
}
static inline sb_wmask sb_w_less(sb_wide a, sb_wide b) { return _mm512_cmp_pd_mask(a, b, _CMP_NGE_UQ); }
static inline bool sb_w_any(sb_wmask m, int count) { return (m & sb_w_lanes(count)) != 0; }
static inline double sb_w_sum(sb_wide v, int count) { return _mm512_mask_reduce_add_pd(sb_w_lanes(count), v); }
static inline sb_wide sb_w_keep(sb_wide v, int count) { return _mm512_maskz_mov_pd(sb_w_lanes(count), v); }
static inline sb_wide sb_w_min(sb_wide a, sb_wide b) { return _mm512_min_pd(a, b); }
static inline sb_wide sb_w_max(sb_wide a, sb_wide b) { return _mm512_max_pd(a, b); }
static inline void sb_w_store(sb_real* p, sb_wide v) { _mm512_storeu_pd(p, v); }
static inline sb_wide sb_w_abs(sb_wide a) { return _mm512_abs_pd(a); }
static inline sb_wide sb_w_pick_greater(sb_wide a, sb_wide b, sb_wide x, sb_wide y) {
    return _mm512_mask_blend_pd(_mm512_cmp_pd_mask(a, b, _CMP_GT_OQ), y, x);
}
static inline sb_wide sb_w_pick_negative(sb_wide s, sb_wide x, sb_wide y) {
    return _mm512_mask_blend_pd(_mm512_cmplt_epi64_mask(_mm512_castpd_si512(s), _mm512_setzero_si512()), y, x);
}

#elif defined(__AVX2__)
/* ---- AVX2: 8 float or 4 double lanes; scatter is done lane by lane ----- */
#if SB_DOUBLE
#define SB_WIDTH 4
typedef __m256d sb_wide;
typedef __m128i sb_windex;
static inline sb_wide sb_w_set(sb_real s) { return _mm256_set1_pd(s); }
static inline sb_wide sb_w_load(const sb_real* p) { return _mm256_loadu_pd(p); }
static inline sb_windex sb_w_index(const uint32_t* p) { return _mm_loadu_si128((const void*)p); }
static inline sb_wide sb_w_gather(const sb_real* base, sb_windex i) { return _mm256_i32gather_pd(base, i, 8); }
static inline sb_wide sb_w_add(sb_wide a, sb_wide b) { return _mm256_add_pd(a, b); }
static inline sb_wide sb_w_sub(sb_wide a, sb_wide b) { return _mm256_sub_pd(a, b); }
static inline sb_wide sb_w_mul(sb_wide a, sb_wide b) { return _mm256_mul_pd(a, b); }
static inline sb_wide sb_w_div(sb_wide a, sb_wide b) { return _mm256_div_pd(a, b); }
static inline sb_wide sb_w_sqrt(sb_wide a) { return _mm256_sqrt_pd(a); }
static inline sb_wide sb_w_rsqrt(sb_wide a) { return _mm256_div_pd(_mm256_set1_pd(1.0), _mm256_sqrt_pd(a)); }
static inline sb_wide sb_w_recip(sb_wide a) { return _mm256_div_pd(_mm256_set1_pd(1.0), a); }
static inline int sb_w_less(sb_wide a, sb_wide b) { return _mm256_movemask_pd(_mm256_cmp_pd(a, b, _CMP_NGE_UQ)); }
static inline sb_wide sb_w_min(sb_wide a, sb_wide b) { return _mm256_min_pd(a, b); }
static inline sb_wide sb_w_max(sb_wide a, sb_wide b) { return _mm256_max_pd(a, b); }
static inline void sb_w_store(sb_real* p, sb_wide v) { _mm256_storeu_pd(p, v); }
static inline sb_wide sb_w_abs(sb_wide a) { return _mm256_andnot_pd(_mm256_set1_pd(-0.0), a); }
static inline sb_wide sb_w_pick_greater(sb_wide a, sb_wide b, sb_wide x, sb_wide y) {
    return _mm256_blendv_pd(y, x, _mm256_cmp_pd(a, b, _CMP_GT_OQ));
}
static inline sb_wide sb_w_pick_negative(sb_wide s, sb_wide x, sb_wide y) { return _mm256_blendv_pd(y, x, s); }
#else
#define SB_WIDTH 8
typedef __m256 sb_wide;
typedef __m256i sb_windex;
static inline sb_wide sb_w_set(sb_real s) { return _mm256_set1_ps(s); }
static inline sb_wide sb_w_load(const sb_real* p) { return _mm256_loadu_ps(p); }
static inline sb_windex sb_w_index(const uint32_t* p) { return _mm256_loadu_si256((const void*)p); }
static inline sb_wide sb_w_gather(const sb_real* base, sb_windex i) { return _mm256_i32gather_ps(base, i, 4); }
static inline sb_wide sb_w_add(sb_wide a, sb_wide b) { return _mm256_add_ps(a, b); }
static inline sb_wide sb_w_sub(sb_wide a, sb_wide b) { return _mm256_sub_ps(a, b); }
static inline sb_wide sb_w_mul(sb_wide a, sb_wide b) { return _mm256_mul_ps(a, b); }
static inline sb_wide sb_w_div(sb_wide a, sb_wide b) { return _mm256_div_ps(a, b); }
static inline sb_wide sb_w_sqrt(sb_wide a) { return _mm256_sqrt_ps(a); }
/* 12-bit estimate, one Newton step: ~23 bits */
static inline sb_wide sb_w_rsqrt(sb_wide a) {
    __m256 y = _mm256_rsqrt_ps(a);
    __m256 t = _mm256_mul_ps(_mm256_mul_ps(a, y), y);
    return _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(0.5f), y), _mm256_sub_ps(_mm256_set1_ps(3.0f), t));
}
/* 1/a: 12-bit estimate, one Newton step: ~23 bits */
static inline sb_wide sb_w_recip(sb_wide a) {
    __m256 y = _mm256_rcp_ps(a);
    return _mm256_add_ps(y, _mm256_mul_ps(y, _mm256_sub_ps(_mm256_set1_ps(1.0f), _mm256_mul_ps(a, y))));
}
static inline int sb_w_less(sb_wide a, sb_wide b) { return _mm256_movemask_ps(_mm256_cmp_ps(a, b, _CMP_NGE_UQ)); }
static inline sb_wide sb_w_min(sb_wide a, sb_wide b) { return _mm256_min_ps(a, b); }
static inline sb_wide sb_w_max(sb_wide a, sb_wide b) { return _mm256_max_ps(a, b); }
static inline void sb_w_store(sb_real* p, sb_wide v) { _mm256_storeu_ps(p, v); }
static inline sb_wide sb_w_abs(sb_wide a) { return _mm256_andnot_ps(_mm256_set1_ps(-0.0f), a); }
static inline sb_wide sb_w_pick_greater(sb_wide a, sb_wide b, sb_wide x, sb_wide y) {
    return _mm256_blendv_ps(y, x, _mm256_cmp_ps(a, b, _CMP_GT_OQ));
}
static inline sb_wide sb_w_pick_negative(sb_wide s, sb_wide x, sb_wide y) { return _mm256_blendv_ps(y, x, s); }
#endif
#define SB_SIMD_NAME "avx2"
typedef int sb_wmask;
static inline bool sb_w_any(sb_wmask m, int count) { return (m & ((1 << count) - 1)) != 0; }
static inline double sb_w_sum(sb_wide v, int count) {
    sb_real lanes[SB_WIDTH];
    memcpy(lanes, &v, sizeof lanes);
    double sum = 0.0;
    for (int l = 0; l < count; l++) sum += lanes[l];
    return sum;
}
static inline sb_wide sb_w_keep(sb_wide v, int count) {
    sb_real lanes[SB_WIDTH];
    memcpy(lanes, &v, sizeof lanes);
    for (int l = count; l < SB_WIDTH; l++) lanes[l] = 0;
    memcpy(&v, lanes, sizeof lanes);
    return v;
}

#else
/* ---- scalar: one lane, the same kernels ------------------------------- */
#define SB_WIDTH 1
#define SB_SIMD_NAME "scalar"
typedef sb_real sb_wide;
typedef uint32_t sb_windex;
typedef int sb_wmask;
static inline sb_wide sb_w_set(sb_real s) { return s; }
static inline sb_wide sb_w_load(const sb_real* p) { return *p; }
static inline sb_windex sb_w_index(const uint32_t* p) { return *p; }
static inline sb_wide sb_w_gather(const sb_real* base, sb_windex i) { return base[i]; }
static inline sb_wide sb_w_add(sb_wide a, sb_wide b) { return a + b; }
static inline sb_wide sb_w_sub(sb_wide a, sb_wide b) { return a - b; }
static inline sb_wide sb_w_mul(sb_wide a, sb_wide b) { return a * b; }
static inline sb_wide sb_w_div(sb_wide a, sb_wide b) { return a / b; }
static inline sb_wide sb_w_sqrt(sb_wide a) { return (sb_wide)sqrt(a); }
static inline sb_wide sb_w_rsqrt(sb_wide a) { return (sb_wide)(1.0 / sqrt(a)); }
static inline sb_wide sb_w_recip(sb_wide a) { return (sb_wide)1 / a; }
static inline sb_wmask sb_w_less(sb_wide a, sb_wide b) { return !(a >= b); }
static inline bool sb_w_any(sb_wmask m, int count) { return m && count; }
static inline double sb_w_sum(sb_wide v, int count) { return count ? v : 0.0; }
static inline sb_wide sb_w_keep(sb_wide v, int count) { return count ? v : 0; }
static inline sb_wide sb_w_min(sb_wide a, sb_wide b) { return a < b ? a : b; }
static inline sb_wide sb_w_max(sb_wide a, sb_wide b) { return a > b ? a : b; }
static inline void sb_w_store(sb_real* p, sb_wide v) { *p = v; }
static inline sb_wide sb_w_abs(sb_wide a) { return (sb_wide)fabs(a); }
static inline sb_wide sb_w_pick_greater(sb_wide a, sb_wide b, sb_wide x, sb_wide y) { return a > b ? x : y; }
static inline sb_wide sb_w_pick_negative(sb_wide s, sb_wide x, sb_wide y) { return signbit(s) ? x : y; }
#endif

/* One real per vertex spread over that vertex's packed x y z lanes, its w
 * lane 0: lane l of the packed reals [q, q + SB_WIDTH) gets per_vertex[(q +
 * l) / 4], or 0 where q + l is a w lane; q a multiple of SB_WIDTH. So a
 * per-vertex constant (a mass) streams 1 real a vertex, not 4. */
static inline sb_real sb_packed_lane(const sb_real* per_vertex, size_t q) {
    return (q & 3) < 3 ? per_vertex[q >> 2] : 0;
}
#if defined(__AVX512F__) && !SB_DOUBLE
static inline sb_wide sb_w_spread4(const sb_real* per_vertex, size_t q) {
    const __m512i lane = _mm512_set_epi32(3, 3, 3, 3, 2, 2, 2, 2, 1, 1, 1, 1, 0, 0, 0, 0);
    return _mm512_maskz_permutexvar_ps(0x7777, lane, _mm512_castps128_ps512(_mm_loadu_ps(per_vertex + q / 4)));
}
#elif defined(__AVX512F__) && SB_DOUBLE
static inline sb_wide sb_w_spread4(const sb_real* per_vertex, size_t q) {
    const __m512i lane = _mm512_set_epi64(1, 1, 1, 1, 0, 0, 0, 0);
    return _mm512_maskz_permutexvar_pd(0x77, lane, _mm512_castpd128_pd512(_mm_loadu_pd(per_vertex + q / 4)));
}
#elif defined(__AVX2__) && SB_DOUBLE
static inline sb_wide sb_w_spread4(const sb_real* per_vertex, size_t q) {
    return _mm256_blend_pd(_mm256_broadcast_sd(per_vertex + q / 4), _mm256_setzero_pd(), 0x8);
}
#elif defined(__AVX2__)
static inline sb_wide sb_w_spread4(const sb_real* per_vertex, size_t q) {
    __m256 two = _mm256_castps128_ps256(_mm_castsi128_ps(_mm_loadl_epi64((const __m128i*)(per_vertex + q / 4))));
    __m256 spread = _mm256_permutevar8x32_ps(two, _mm256_set_epi32(1, 1, 1, 1, 0, 0, 0, 0));
    return _mm256_blend_ps(spread, _mm256_setzero_ps(), 0x88);
}
#else
static inline sb_wide sb_w_spread4(const sb_real* per_vertex, size_t q) { return sb_packed_lane(per_vertex, q); }
#endif

/* A 3-vector of wide reals: one lane per element. */
typedef struct sb_wvec3 {
    sb_wide x, y, z;
} sb_wvec3;

static inline sb_wvec3 sb_wv_gather(const sb_real* x, const sb_real* y, const sb_real* z, sb_windex i) {
    return (sb_wvec3){sb_w_gather(x, i), sb_w_gather(y, i), sb_w_gather(z, i)};
}

/* Packed vertex data: x y z w per vertex (w unused), 4·sizeof(sb_real)
 * bytes apart. Loading a block's positions from it, and adding its forces to
 * it, is where a step spends its time: 16 float gathers of 3 components
 * cost far more than 16 loads of one packed vertex each. The _at forms take
 * the lanes' vertex indices from memory (a kernel's slot array): the
 * sb_windex forms store theirs and call them, and a kernel that has its
 * indices in memory saves moving them out of a vector lane by lane (a few
 * % of pbd's triangle sweep: bench/results/notes/xpbd.md). */
#if defined(__AVX512F__) && !SB_DOUBLE
/* The 4x4 transpose inside each 128-bit lane: four registers of packed
 * vertices (x y z w) in, x, y, z and w out (lane 4 L + j of the output is
 * 128-bit lane L of register j), and back. */
static inline sb_wvec3 sb_w_lanes_of_packed(const __m512 r[4], sb_wide* w) {
    __m512 t0 = _mm512_unpacklo_ps(r[0], r[1]), t1 = _mm512_unpackhi_ps(r[0], r[1]);
    __m512 t2 = _mm512_unpacklo_ps(r[2], r[3]), t3 = _mm512_unpackhi_ps(r[2], r[3]);
    __m512d d0 = _mm512_castps_pd(t0), d1 = _mm512_castps_pd(t1), d2 = _mm512_castps_pd(t2), d3 = _mm512_castps_pd(t3);
    *w = _mm512_castpd_ps(_mm512_unpackhi_pd(d1, d3));
    return (sb_wvec3){_mm512_castpd_ps(_mm512_unpacklo_pd(d0, d2)), _mm512_castpd_ps(_mm512_unpackhi_pd(d0, d2)),
                      _mm512_castpd_ps(_mm512_unpacklo_pd(d1, d3))};
}
static inline void sb_w_packed_of_lanes(sb_wvec3 v, sb_wide w, __m512 r[4]) {
    __m512d t0 = _mm512_castps_pd(_mm512_unpacklo_ps(v.x, v.y)), t1 = _mm512_castps_pd(_mm512_unpackhi_ps(v.x, v.y));
    __m512d t2 = _mm512_castps_pd(_mm512_unpacklo_ps(v.z, w)), t3 = _mm512_castps_pd(_mm512_unpackhi_ps(v.z, w));
    r[0] = _mm512_castpd_ps(_mm512_unpacklo_pd(t0, t2));
    r[1] = _mm512_castpd_ps(_mm512_unpackhi_pd(t0, t2));
    r[2] = _mm512_castpd_ps(_mm512_unpacklo_pd(t1, t3));
    r[3] = _mm512_castpd_ps(_mm512_unpackhi_pd(t1, t3));
}

/* Lanes are loaded four per register in the order (0,4,8,12), (1,5,9,13),
 * (2,6,10,14), (3,7,11,15), so that a 4x4 transpose inside each 128-bit
 * lane leaves x, y, z and w in natural lane order. */
static inline sb_wvec3 sb_wv_load4w_at(const sb_real* p4, const uint32_t* id, sb_wide* w) {
    __m512 r[4];
    for (int j = 0; j < 4; j++) {
        r[j] = _mm512_castps128_ps512(_mm_load_ps(p4 + 4 * (size_t)id[j]));
        r[j] = _mm512_insertf32x4(r[j], _mm_load_ps(p4 + 4 * (size_t)id[4 + j]), 1);
        r[j] = _mm512_insertf32x4(r[j], _mm_load_ps(p4 + 4 * (size_t)id[8 + j]), 2);
        r[j] = _mm512_insertf32x4(r[j], _mm_load_ps(p4 + 4 * (size_t)id[12 + j]), 3);
    }
    return sb_w_lanes_of_packed(r, w);
}

static inline sb_wvec3 sb_wv_load4w(const sb_real* p4, sb_windex i, sb_wide* w) {
    uint32_t id[16];
    _mm512_storeu_si512((void*)id, i);
    return sb_wv_load4w_at(p4, id, w);
}

static inline void sb_add_packed(sb_real* p4, uint32_t id, __m128 v) {
    sb_real* p = p4 + 4 * (size_t)id;
    _mm_store_ps(p, _mm_add_ps(_mm_load_ps(p), v));
}

/* The inverse transpose; then each of the first `count` lanes adds its
 * packed vector to its vertex (lanes of a block never share one). */
static inline void sb_wv_add4_at(sb_real* p4, const uint32_t* id, sb_wvec3 v, int count) {
    __m512 r[4];
    sb_w_packed_of_lanes(v, _mm512_setzero_ps(), r);
    if (count == 16) { /* a full block: no lane tests */
        for (int j = 0; j < 4; j++) {
            sb_add_packed(p4, id[j], _mm512_castps512_ps128(r[j]));
            sb_add_packed(p4, id[4 + j], _mm512_extractf32x4_ps(r[j], 1));
            sb_add_packed(p4, id[8 + j], _mm512_extractf32x4_ps(r[j], 2));
            sb_add_packed(p4, id[12 + j], _mm512_extractf32x4_ps(r[j], 3));
        }
        return;
    }
    for (int j = 0; j < 4; j++) {
        if (j < count) sb_add_packed(p4, id[j], _mm512_castps512_ps128(r[j]));
        if (4 + j < count) sb_add_packed(p4, id[4 + j], _mm512_extractf32x4_ps(r[j], 1));
        if (8 + j < count) sb_add_packed(p4, id[8 + j], _mm512_extractf32x4_ps(r[j], 2));
        if (12 + j < count) sb_add_packed(p4, id[12 + j], _mm512_extractf32x4_ps(r[j], 3));
    }
}

static inline void sb_wv_add4(sb_real* p4, sb_windex i, sb_wvec3 v, int count) {
    uint32_t id[16];
    _mm512_storeu_si512((void*)id, i);
    sb_wv_add4_at(p4, id, v, count);
}

/* The inverse of sb_wv_load4w: the first `count` lanes store x y z w to
 * their vertices (no read: for a kernel that loaded them and owns them). */
static inline void sb_wv_store4w_at(sb_real* p4, const uint32_t* id, sb_wvec3 v, sb_wide w, int count) {
    __m512 r[4];
    sb_w_packed_of_lanes(v, w, r);
    for (int j = 0; j < 4; j++) {
        if (j < count) _mm_store_ps(p4 + 4 * (size_t)id[j], _mm512_castps512_ps128(r[j]));
        if (4 + j < count) _mm_store_ps(p4 + 4 * (size_t)id[4 + j], _mm512_extractf32x4_ps(r[j], 1));
        if (8 + j < count) _mm_store_ps(p4 + 4 * (size_t)id[8 + j], _mm512_extractf32x4_ps(r[j], 2));
        if (12 + j < count) _mm_store_ps(p4 + 4 * (size_t)id[12 + j], _mm512_extractf32x4_ps(r[j], 3));
    }
}

static inline void sb_wv_store4w(sb_real* p4, sb_windex i, sb_wvec3 v, sb_wide w, int count) {
    uint32_t id[16];
    _mm512_storeu_si512((void*)id, i);
    sb_wv_store4w_at(p4, id, v, w, count);
}

/* A run of SB_WIDTH consecutive packed vertices, one a lane: four whole
 * registers transposed in their 128-bit lanes, which leaves lane l holding
 * vertex sb_w_run_vertex(l) of the run; sb_w_load_run reads one real a
 * vertex into the same lanes. */
static inline int sb_w_run_vertex(int l) { return 4 * (l & 3) + (l >> 2); }
static inline sb_wvec3 sb_wv_load4_run(const sb_real* p4, sb_wide* w) {
    const __m512 r[4] = {_mm512_loadu_ps(p4), _mm512_loadu_ps(p4 + 16), _mm512_loadu_ps(p4 + 32),
                         _mm512_loadu_ps(p4 + 48)};
    return sb_w_lanes_of_packed(r, w);
}
static inline void sb_wv_store4_run(sb_real* p4, sb_wvec3 v, sb_wide w) {
    __m512 r[4];
    sb_w_packed_of_lanes(v, w, r);
    for (int j = 0; j < 4; j++) _mm512_storeu_ps(p4 + 16 * j, r[j]);
}
static inline sb_wide sb_w_load_run(const sb_real* per_vertex) {
    const __m512i order = _mm512_set_epi32(15, 11, 7, 3, 14, 10, 6, 2, 13, 9, 5, 1, 12, 8, 4, 0);
    return _mm512_permutexvar_ps(order, _mm512_loadu_ps(per_vertex));
}
#else
/* Elsewhere: the components of each lane's vertex, one lane at a time. */
static inline sb_wvec3 sb_wv_load4w_at(const sb_real* p4, const uint32_t* id, sb_wide* w) {
    sb_real x[SB_WIDTH], y[SB_WIDTH], z[SB_WIDTH], ws[SB_WIDTH];
    for (int l = 0; l < SB_WIDTH; l++) {
        const sb_real* p = p4 + 4 * (size_t)id[l];
        x[l] = p[0];
        y[l] = p[1];
        z[l] = p[2];
        ws[l] = p[3];
    }
    sb_wvec3 v;
    memcpy(&v.x, x, sizeof x);
    memcpy(&v.y, y, sizeof y);
    memcpy(&v.z, z, sizeof z);
    memcpy(w, ws, sizeof ws);
    return v;
}

static inline sb_wvec3 sb_wv_load4w(const sb_real* p4, sb_windex i, sb_wide* w) {
    uint32_t id[SB_WIDTH];
    memcpy(id, &i, sizeof id);
    return sb_wv_load4w_at(p4, id, w);
}

static inline void sb_wv_add4_at(sb_real* p4, const uint32_t* id, sb_wvec3 v, int count) {
    sb_real x[SB_WIDTH], y[SB_WIDTH], z[SB_WIDTH];
    memcpy(x, &v.x, sizeof x);
    memcpy(y, &v.y, sizeof y);
    memcpy(z, &v.z, sizeof z);
    for (int l = 0; l < count; l++) {
        sb_real* p = p4 + 4 * (size_t)id[l];
        p[0] += x[l];
        p[1] += y[l];
        p[2] += z[l];
    }
}

static inline void sb_wv_add4(sb_real* p4, sb_windex i, sb_wvec3 v, int count) {
    uint32_t id[SB_WIDTH];
    memcpy(id, &i, sizeof id);
    sb_wv_add4_at(p4, id, v, count);
}

static inline void sb_wv_store4w_at(sb_real* p4, const uint32_t* id, sb_wvec3 v, sb_wide w, int count) {
    sb_real x[SB_WIDTH], y[SB_WIDTH], z[SB_WIDTH], ws[SB_WIDTH];
    memcpy(x, &v.x, sizeof x);
    memcpy(y, &v.y, sizeof y);
    memcpy(z, &v.z, sizeof z);
    memcpy(ws, &w, sizeof ws);
    for (int l = 0; l < count; l++) {
        sb_real* p = p4 + 4 * (size_t)id[l];
        p[0] = x[l];
        p[1] = y[l];
        p[2] = z[l];
        p[3] = ws[l];
    }
}

static inline void sb_wv_store4w(sb_real* p4, sb_windex i, sb_wvec3 v, sb_wide w, int count) {
    uint32_t id[SB_WIDTH];
    memcpy(id, &i, sizeof id);
    sb_wv_store4w_at(p4, id, v, w, count);
}

/* A run of SB_WIDTH consecutive packed vertices, vertex l in lane l. */
static inline int sb_w_run_vertex(int l) { return l; }
static inline sb_wvec3 sb_wv_load4_run(const sb_real* p4, sb_wide* w) {
    uint32_t id[SB_WIDTH];
    for (int l = 0; l < SB_WIDTH; l++) id[l] = (uint32_t)l;
    return sb_wv_load4w_at(p4, id, w);
}
static inline void sb_wv_store4_run(sb_real* p4, sb_wvec3 v, sb_wide w) {
    uint32_t id[SB_WIDTH];
    for (int l = 0; l < SB_WIDTH; l++) id[l] = (uint32_t)l;
    sb_wv_store4w_at(p4, id, v, w, SB_WIDTH);
}
static inline sb_wide sb_w_load_run(const sb_real* per_vertex) { return sb_w_load(per_vertex); }
#endif

/* The x y z of each lane's packed vertex (sb_wv_load4w also gives w: a
 * kernel may keep a per-vertex value there, pbd the inverse mass). */
static inline sb_wvec3 sb_wv_load4(const sb_real* p4, sb_windex i) {
    sb_wide unused;
    return sb_wv_load4w(p4, i, &unused);
}
static inline sb_wvec3 sb_wv_load4_at(const sb_real* p4, const uint32_t* id) {
    sb_wide unused;
    return sb_wv_load4w_at(p4, id, &unused);
}

static inline sb_wvec3 sb_wv_sub(sb_wvec3 a, sb_wvec3 b) {
    return (sb_wvec3){sb_w_sub(a.x, b.x), sb_w_sub(a.y, b.y), sb_w_sub(a.z, b.z)};
}
static inline sb_wvec3 sb_wv_add(sb_wvec3 a, sb_wvec3 b) {
    return (sb_wvec3){sb_w_add(a.x, b.x), sb_w_add(a.y, b.y), sb_w_add(a.z, b.z)};
}
static inline sb_wvec3 sb_wv_scale(sb_wvec3 a, sb_wide s) {
    return (sb_wvec3){sb_w_mul(a.x, s), sb_w_mul(a.y, s), sb_w_mul(a.z, s)};
}
static inline sb_wide sb_wv_dot(sb_wvec3 a, sb_wvec3 b) {
    return sb_w_add(sb_w_add(sb_w_mul(a.x, b.x), sb_w_mul(a.y, b.y)), sb_w_mul(a.z, b.z));
}
static inline sb_wvec3 sb_wv_cross(sb_wvec3 a, sb_wvec3 b) {
    return (sb_wvec3){sb_w_sub(sb_w_mul(a.y, b.z), sb_w_mul(a.z, b.y)),
                      sb_w_sub(sb_w_mul(a.z, b.x), sb_w_mul(a.x, b.z)),
                      sb_w_sub(sb_w_mul(a.x, b.y), sb_w_mul(a.y, b.x))};
}
static inline sb_wvec3 sb_wv_neg(sb_wvec3 a) { return sb_wv_scale(a, sb_w_set(-1)); }

/* atan2(y, x) per lane, for finite arguments, with libm's signs and
 * quadrants (atan2(±0, −0) = ±π, atan2(±0, +0) = ±0), in (−π, π].
 *
 * Reduction: a = min(|x|, |y|) / max(|x|, |y|) in [0, 1]; above tan(π/8)
 * atan a = π/4 + atan((a − 1)/(a + 1)), so the polynomial only sees
 * |t| <= tan(π/8) = 0.414; then the octant (π/2 − r where |y| > |x|), the
 * half plane (π − r where x is negative) and the sign of y. One division.
 *
 * atan t = t + t·z·P(z), z = t², P a Chebyshev fit (mpmath, 50 digits) to
 * (atan t − t)/(t z) on [0, tan²(π/8)]: degree 4 in float, 10 in double.
 * The fit's own error is below 1e-9 (float) and 2e-18 (double) radians;
 * with rounding, the largest error against libm's atan2 over the whole
 * circle is 2.6e-7 rad in float and 5e-16 in double, 1.1 units in the last
 * place of π (measured: 2.52e-7 and 4.44e-16 with AVX-512, AVX2 and scalar,
 * with and without FMA; tests/test_wide.c checks the bounds). */
static inline sb_wide sb_w_atan_poly(sb_wide t) {
#if SB_DOUBLE
    static const double c[] = {-0.33333333333333330160,  0.19999999999995520678,   -0.14285714284666542922,
                               0.11111111015256361727,   -0.090909045781239018905, 0.076921831908260865637,
                               -0.066645114473819480001, 0.058581489128022098816,  -0.050854497379402598613,
                               0.039231658295587191303,  -0.019176887119062258989};
#else
    static const float c[] = {-0.33333331761168519851f, 0.19999540483648963445f, -0.14263955597984639199f,
                              0.10743731490791083043f, -0.06451928208121748758f};
#endif
    enum { degree = sizeof c / sizeof c[0] - 1 };
    sb_wide z = sb_w_mul(t, t), p = sb_w_set(c[degree]);
    for (int i = degree - 1; i >= 0; i--) p = sb_w_add(sb_w_mul(p, z), sb_w_set(c[i]));
    return sb_w_add(t, sb_w_mul(sb_w_mul(t, z), p));
}

static inline sb_wide sb_w_atan2(sb_wide y, sb_wide x) {
    const sb_real pi = (sb_real)3.14159265358979323846, tan_pi_8 = (sb_real)0.41421356237309504880;
    sb_wide ax = sb_w_abs(x), ay = sb_w_abs(y);
    sb_wide small = sb_w_min(ax, ay), large = sb_w_max(ax, ay), zero = sb_w_set(0);
    sb_wide split = sb_w_mul(large, sb_w_set(tan_pi_8));
    sb_wide num = sb_w_pick_greater(small, split, sb_w_sub(small, large), small);
    sb_wide den = sb_w_pick_greater(small, split, sb_w_add(small, large), large);
    sb_wide base = sb_w_pick_greater(small, split, sb_w_set(pi / 4), zero);
    sb_wide t = sb_w_pick_greater(den, zero, sb_w_div(num, den), zero); /* atan2(±0, ±0): t = 0, not 0/0 */
    sb_wide r = sb_w_add(base, sb_w_atan_poly(t));
    r = sb_w_pick_greater(ay, ax, sb_w_sub(sb_w_set(pi / 2), r), r);
    r = sb_w_pick_negative(x, sb_w_sub(sb_w_set(pi), r), r);
    return sb_w_pick_negative(y, sb_w_mul(r, sb_w_set(-1)), r);
}

#endif
