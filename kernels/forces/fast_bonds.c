/* Fast per-bond kernel: bond stretch (Eq. 3) and the damped spring (Eq. 2)
 * in one pass, sharing the bond vector and its length. */
#include "kernels/forces/fast_bonds.h"
#include "kernels/forces/fast_block.h"
#include "kernels/forces/reference_terms.h"

int sb_fast_bonds(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                  double energy[2]) {
    uint32_t step = sb_block_step(serial);
    const sb_wide half = sb_w_set((sb_real)0.5), ratio = sb_w_set((sb_real)SB_COLLAPSE_RATIO);
    sb_wide bond_sum = sb_w_set(0), spring_sum = sb_w_set(0);
    bool collapsed = false, near = false;
    for (uint32_t s = begin; s < end; s += step) {
        int count = sb_block_count(s, end, step);
        sb_windex i = sb_w_index(m->bond_i + s), j = sb_w_index(m->bond_j + s);
        sb_worigin origin;
        sb_wvec3 xi = sb_wv_origin_at(fr, m->bond_i + s, &origin);
        sb_wvec3 d = sb_wv_sub(sb_wv_vertex_at(fr, m->bond_j + s, &origin), xi);
        sb_wide squared = sb_wv_dot(d, d), inv_r = sb_w_rsqrt(squared);
        sb_wide r = sb_w_mul(squared, inv_r), r0 = sb_w_load(m->bond_r0 + s);
        collapsed |= sb_w_any(sb_w_less(r, sb_w_mul(ratio, r0)), count);
        if (m->bond_near_max2) near |= sb_near_limit(m->bond_near_max2, m->bond_near_min2, s, squared, count);
        sb_wide stretch = sb_w_sub(r, r0);
        sb_wide kb = sb_w_constant(m->bond_k, s), ks = sb_w_constant(m->spring_k, s);
        sb_wide magnitude = sb_w_mul(sb_w_add(kb, ks), stretch);
        if (m->has_damping) {
            sb_wvec3 dv = sb_wv_sub(sb_wv_load4(fr->velocities4, j), sb_wv_load4(fr->velocities4, i));
            sb_wide closing = sb_w_mul(sb_wv_dot(dv, d), inv_r);
            magnitude = sb_w_add(magnitude, sb_w_mul(sb_w_constant(m->spring_damping, s), closing));
        }
        sb_wvec3 f = sb_wv_scale(d, sb_w_mul(magnitude, inv_r));
        sb_wv_add4(fr->forces4, i, f, count);
        sb_wv_add4(fr->forces4, j, sb_wv_neg(f), count);
        sb_wide strain_energy = sb_w_mul(half, sb_w_mul(stretch, stretch));
        bond_sum = sb_w_add(bond_sum, sb_w_keep(sb_w_mul(kb, strain_energy), count));
        spring_sum = sb_w_add(spring_sum, sb_w_keep(sb_w_mul(ks, strain_energy), count));
    }
    energy[0] += sb_w_sum(bond_sum, SB_WIDTH);
    energy[1] += sb_w_sum(spring_sum, SB_WIDTH);
    return (collapsed ? SB_KERNEL_COLLAPSED : 0) | (near ? SB_KERNEL_NEAR_LIMIT : 0);
}
