/* The triangles' second derivatives (kernels/forces/fast_hessian.h): the three
 * corners' angle bend and stretch-bend of kernels/forces/fast_corners.c (its
 * notation: corner c at vertex c, â = u_c, b̂ = −u_{c+2}, A = L_c,
 * B = L_{c+2}) and the bonds the triangle's edges own, on wide duals; the
 * diagonal pass in closed form (kernels/forces/fast_hessian_corner_blocks.c). */
#include "kernels/forces/fast_hessian_corners.h"
#include "kernels/forces/fast_hessian_corner_blocks.h"
#include "kernels/forces/fast_hessian.h"

typedef struct sb_wdtriangle {
    sb_wdvec3 unit[3];   /* u_c: unit vector of edge c → c+1 */
    sb_wdual inverse[3]; /* 1 / L_c */
    sb_wdual strain[3];  /* L_c − L_c0 */
} sb_wdtriangle;

/* Adds corner c's forces to f. */
static inline void sb_wdual_corner(const sb_wdtriangle* t, int c, sb_wide cos0, sb_wide ka, sb_wide ksb, sb_wdvec3* f) {
    int j = (c + 1) % 3, k = (c + 2) % 3;
    sb_wdvec3 ua = t->unit[c], ub = sb_wdv_neg(t->unit[k]);
    sb_wdual cosine = sb_wdv_dot(ua, ub), dc = {sb_w_sub(cosine.v, cos0), cosine.d};
    sb_wdual s = sb_wd_add(t->strain[c], t->strain[k]);
    sb_wdual g = sb_wd_add(sb_wd_scale(dc, ka), sb_wd_scale(s, ksb)), h = sb_wd_scale(dc, ksb);
    /* F_j = −(g/A)(b̂ − c â) − h â ;  F_k = −(g/B)(â − c b̂) − h b̂ */
    sb_wdual ga = sb_wd_mul(g, t->inverse[c]), gb = sb_wd_mul(g, t->inverse[k]);
    sb_wdvec3 fj = sb_wdv_add(sb_wdv_scale(sb_wdv_sub(ub, sb_wdv_scale(ua, cosine)), ga), sb_wdv_scale(ua, h));
    sb_wdvec3 fk = sb_wdv_add(sb_wdv_scale(sb_wdv_sub(ua, sb_wdv_scale(ub, cosine)), gb), sb_wdv_scale(ub, h));
    f[j] = sb_wdv_sub(f[j], fj);
    f[k] = sb_wdv_sub(f[k], fk);
    f[c] = sb_wdv_add(f[c], sb_wdv_add(fj, fk));
}

/* Adds the bond edge c owns (a lane's constants are zero otherwise). */
static inline void sb_wdual_owned_bond(const sb_fast_model* m, uint32_t s, int c, sb_wide damping, const sb_wdvec3* x,
                                       sb_wdvec3* f) {
    int j = (c + 1) % 3;
    sb_wide owned = sb_w_bit(m->tri_owned + s, c);
    sb_wide r0 = sb_w_load((m->tri_edge_r0[c] ? m->tri_edge_r0[c] : m->tri_len0[c]) + s);
    sb_wide k =
        sb_w_mul(owned, sb_w_add(sb_w_constant(m->tri_edge_bond_k[c], s), sb_w_constant(m->tri_edge_spring_k[c], s)));
    sb_wide d = m->fused_damping ? sb_w_mul(owned, sb_w_constant(m->tri_edge_damping[c], s)) : sb_w_set(0);
    sb_wdvec3 force = sb_wdual_bond_force(x[c], x[j], k, r0, d, damping);
    f[c] = sb_wdv_add(f[c], force);
    f[j] = sb_wdv_sub(f[j], force);
}

static void sb_wdual_triangle(const sb_fast_model* m, uint32_t s, sb_wide damping, const sb_wdvec3* x, sb_wdvec3* f) {
    const sb_wide zero = sb_w_set(0);
    for (int c = 0; c < 3; c++) f[c] = (sb_wdvec3){{zero, zero, zero}, {zero, zero, zero}};
    if (m->has_corners) {
        sb_wdtriangle t;
        for (int c = 0; c < 3; c++) {
            sb_wdvec3 e = sb_wdv_sub(x[(c + 1) % 3], x[c]);
            sb_wdual squared = sb_wdv_dot(e, e);
            t.inverse[c] = sb_wd_rsqrt(squared);
            sb_wdual length = sb_wd_mul(squared, t.inverse[c]);
            t.unit[c] = sb_wdv_scale(e, t.inverse[c]);
            t.strain[c] = (sb_wdual){sb_w_sub(length.v, sb_w_load(m->tri_len0[c] + s)), length.d};
        }
        sb_wide ka, ksb;
        sb_w_corner_constants(m, s, &ka, &ksb);
        for (int c = 0; c < 3; c++) sb_wdual_corner(&t, c, sb_w_load(m->tri_cos0[c] + s), ka, ksb, f);
    }
    if (m->fused_bonds)
        for (int c = 0; c < 3; c++) sb_wdual_owned_bond(m, s, c, damping, x, f);
}

int sb_fast_corners_hessian(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end,
                            bool serial, double* unused) {
    (void)unused;
    if (!frame->velocities4) { /* the diagonal pass, in closed form */
        sb_fast_corner_blocks(m, (const sb_hessian_frame*)frame, begin, end, serial);
        return 0;
    }
    sb_hessian_pass(m, frame, begin, end, serial, 3, m->tri_v, sb_wdual_triangle);
    return 0;
}
