/* The per-triangle half of the self-contact hierarchy's refit
 * (kernels/contact/triangle_bvh.c), SB_WIDTH triangles at a time: each triangle's
 * box around its corners at the start and the end of the step, and its
 * unit normal at the end. The same code runs as AVX-512, AVX2 or one lane
 * (kernels/runtime/wide.h); tests/test_self_contact.c checks the refitted boxes and
 * normal boxes against every triangle computed in double. */
#include "kernels/contact/fast_triangle_bounds.h"
#include "kernels/runtime/wide.h"

/* Writes lanes [0, count) of v to out (count < SB_WIDTH: a block's tail,
 * whose other lanes belong to another worker's range). */
static void sb_put(sb_real* out, sb_wide v, int count) {
    if (count == SB_WIDTH) {
        sb_w_store(out, v);
        return;
    }
    sb_real lanes[SB_WIDTH];
    sb_w_store(lanes, v);
    memcpy(out, lanes, (size_t)count * sizeof *lanes);
}

void sb_fast_triangle_bounds(const sb_triangle_corners* t, const sb_real* from4, const sb_real* to4, uint32_t first,
                             uint32_t last, const sb_triangle_bounds* out) {
    /* a degenerate triangle's normal comes out zero (its box of normals then
     * holds 0, so no node containing it counts as flat) */
    const sb_wide tiny = sb_w_set((sb_real)1e-30);
    for (uint32_t k = first; k < last; k += SB_WIDTH) {
        int count = last - k < SB_WIDTH ? (int)(last - k) : SB_WIDTH;
        sb_wvec3 p[2][3];
        for (int c = 0; c < 3; c++) {
            sb_windex index = sb_w_index(t->corner[c] + k);
            p[0][c] = sb_wv_load4(from4, index);
            p[1][c] = sb_wv_load4(to4, index);
        }
        sb_wvec3 lo = p[0][0], hi = p[0][0];
        for (int e = 0; e < 2; e++)
            for (int c = 0; c < 3; c++) {
                lo = (sb_wvec3){sb_w_min(lo.x, p[e][c].x), sb_w_min(lo.y, p[e][c].y), sb_w_min(lo.z, p[e][c].z)};
                hi = (sb_wvec3){sb_w_max(hi.x, p[e][c].x), sb_w_max(hi.y, p[e][c].y), sb_w_max(hi.z, p[e][c].z)};
            }
        sb_wvec3 u = {sb_w_sub(p[1][1].x, p[1][0].x), sb_w_sub(p[1][1].y, p[1][0].y), sb_w_sub(p[1][1].z, p[1][0].z)};
        sb_wvec3 v = {sb_w_sub(p[1][2].x, p[1][0].x), sb_w_sub(p[1][2].y, p[1][0].y), sb_w_sub(p[1][2].z, p[1][0].z)};
        sb_wvec3 n = {sb_w_sub(sb_w_mul(u.y, v.z), sb_w_mul(u.z, v.y)),
                      sb_w_sub(sb_w_mul(u.z, v.x), sb_w_mul(u.x, v.z)),
                      sb_w_sub(sb_w_mul(u.x, v.y), sb_w_mul(u.y, v.x))};
        sb_wide length2 = sb_w_add(sb_w_add(sb_w_mul(n.x, n.x), sb_w_mul(n.y, n.y)), sb_w_mul(n.z, n.z));
        sb_wide scale = sb_w_rsqrt(sb_w_add(length2, tiny));
        sb_wide values[9] = {
            lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, sb_w_mul(n.x, scale), sb_w_mul(n.y, scale), sb_w_mul(n.z, scale)};
        for (int j = 0; j < 9; j++) sb_put(out->value[j] + k, values[j], count);
    }
}
