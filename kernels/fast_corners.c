/* Fast per-triangle kernel: the three corners' angle bend (Eq. 4) and
 * stretch-bend (Eq. 5) together. The triangle's three edge vectors, lengths
 * and unit vectors are computed once and shared by the corners: corner c
 * sits at vertex c with â = u_c (edge c → c+1) and b̂ = −u_{c+2}
 * (edge c+2 → c, reversed), A = L_c, B = L_{c+2}. The forces on the three
 * vertices are summed in registers and scattered once. */
#include "kernels/fast_kernels.h"
#include "kernels/fast_block.h"
#include "kernels/reference_terms.h"

typedef struct sb_wtriangle {
    sb_wvec3 unit[3];  /* u_c: unit vector of edge c → c+1 */
    sb_wide length[3]; /* L_c */
    sb_wide strain[3]; /* L_c − L_c0 */
} sb_wtriangle;

typedef struct sb_wcorner_out {
    sb_wvec3 force[3]; /* on vertices 0, 1, 2 */
    sb_wide angle_energy, stretch_bend_energy;
} sb_wcorner_out;

/* Adds corner c's forces and energies to out. */
static inline void sb_fast_corner(const sb_wtriangle* t, int c, sb_wide cos0, sb_wide ka, sb_wide ksb,
                                  sb_wcorner_out* out) {
    int j = (c + 1) % 3, k = (c + 2) % 3;
    sb_wvec3 ua = t->unit[c], ub = sb_wv_neg(t->unit[k]);
    sb_wide cosine = sb_wv_dot(ua, ub), dc = sb_w_sub(cosine, cos0);
    sb_wide s = sb_w_add(t->strain[c], t->strain[k]);
    sb_wide g = sb_w_add(sb_w_mul(ka, dc), sb_w_mul(ksb, s)), h = sb_w_mul(ksb, dc);
    /* F_j = −(g/A)(b̂ − c â) − h â ;  F_k = −(g/B)(â − c b̂) − h b̂ */
    sb_wide ga = sb_w_div(g, t->length[c]), gb = sb_w_div(g, t->length[k]);
    sb_wvec3 fj = sb_wv_add(sb_wv_scale(sb_wv_sub(ub, sb_wv_scale(ua, cosine)), ga), sb_wv_scale(ua, h));
    sb_wvec3 fk = sb_wv_add(sb_wv_scale(sb_wv_sub(ua, sb_wv_scale(ub, cosine)), gb), sb_wv_scale(ub, h));
    out->force[j] = sb_wv_sub(out->force[j], fj);
    out->force[k] = sb_wv_sub(out->force[k], fk);
    out->force[c] = sb_wv_add(out->force[c], sb_wv_add(fj, fk));
    out->angle_energy = sb_w_add(out->angle_energy, sb_w_mul(sb_w_mul(sb_w_set((sb_real)0.5), ka), sb_w_mul(dc, dc)));
    out->stretch_bend_energy = sb_w_add(out->stretch_bend_energy, sb_w_mul(sb_w_mul(ksb, dc), s));
}

bool sb_fast_corners(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                     double energy[2]) {
    uint32_t step = sb_block_step(serial);
    const sb_wide ratio = sb_w_set((sb_real)SB_COLLAPSE_RATIO), zero = sb_w_set(0);
    bool collapsed = false;
    for (uint32_t s = begin; s < end; s += step) {
        int count = sb_block_count(s, end, step);
        sb_windex v[3];
        sb_wvec3 p[3];
        for (int c = 0; c < 3; c++) {
            v[c] = sb_w_index(m->tri_v[c] + s);
            p[c] = sb_wv_gather(fr->x, fr->y, fr->z, v[c]);
        }
        sb_wtriangle t;
        for (int c = 0; c < 3; c++) {
            sb_wvec3 e = sb_wv_sub(p[(c + 1) % 3], p[c]);
            sb_wide rest = sb_w_load(m->tri_len0[c] + s);
            t.length[c] = sb_w_sqrt(sb_wv_dot(e, e));
            t.unit[c] = sb_wv_scale(e, sb_w_div(sb_w_set(1), t.length[c]));
            t.strain[c] = sb_w_sub(t.length[c], rest);
            collapsed |= sb_w_any(sb_w_less(t.length[c], sb_w_mul(ratio, rest)), count);
        }
        sb_wide ka = sb_w_constant(m->angle_k, s), ksb = sb_w_constant(m->stretch_bend_k, s);
        sb_wcorner_out out = {{{zero, zero, zero}, {zero, zero, zero}, {zero, zero, zero}}, zero, zero};
        for (int c = 0; c < 3; c++) sb_fast_corner(&t, c, sb_w_load(m->tri_cos0[c] + s), ka, ksb, &out);
        for (int c = 0; c < 3; c++) sb_wv_scatter_add(fr->fx, fr->fy, fr->fz, v[c], out.force[c], count);
        energy[0] += sb_w_sum(out.angle_energy, count);
        energy[1] += sb_w_sum(out.stretch_bend_energy, count);
    }
    return collapsed;
}
