/* Fast per-triangle kernel: the three corners' angle bend (Eq. 4) and
 * stretch-bend (Eq. 5) together, and the bond stretch of the edges the
 * triangle owns.
 *
 * The triangle's three edge vectors, lengths and unit vectors are computed
 * once and shared by the corners: corner c sits at vertex c with
 * â = u_c (edge c → c+1) and b̂ = −u_{c+2} (edge c+2 → c, reversed),
 * A = L_c, B = L_{c+2}. The forces on the three vertices are summed in
 * registers and scattered once.
 *
 * Fused bonds: gathers and scatter-adds are what a step costs (measured on
 * the reference machine: 0.57 ns per gathered and 0.73 ns per scatter-added
 * element, against a few ns of arithmetic per triangle), and a bond on a
 * triangle's edge needs exactly the positions and the length the triangle
 * kernel already has. So each bond on a triangle's edge is owned by one
 * triangle (kernels/fast_model.c: a bit per edge in one byte per triangle)
 * and costs no index or scatter of its own: its stretch, its spring and,
 * when the model has damping, the spring's damping from the edge's
 * relative velocity (the same half-step velocity the bond kernel and the
 * reference read, gathered for the triangle's three vertices only then).
 * Uniform constants are one value; non-uniform ones (or a breakable
 * model's) are carried per triangle slot and edge. The bond's rest length
 * is the triangle's own where they agree (no stream of its own). */
#include "kernels/fast_kernels.h"
#include "kernels/fast_block.h"
#include "kernels/reference_terms.h"

typedef struct sb_wtriangle {
    sb_wvec3 unit[3];   /* u_c: unit vector of edge c → c+1 */
    sb_wide inverse[3]; /* 1 / L_c */
    sb_wide strain[3];  /* L_c − L_c0 */
} sb_wtriangle;

typedef struct sb_wtriangle_out {
    sb_wvec3 force[3]; /* on vertices 0, 1, 2 */
    sb_wide energy[4]; /* angle, stretch-bend, bond, spring */
} sb_wtriangle_out;

/* Adds corner c's forces and energies to out. */
static inline void sb_fast_corner(const sb_wtriangle* t, int c, sb_wide cos0, sb_wide ka, sb_wide ksb,
                                  sb_wtriangle_out* out) {
    int j = (c + 1) % 3, k = (c + 2) % 3;
    sb_wvec3 ua = t->unit[c], ub = sb_wv_neg(t->unit[k]);
    sb_wide cosine = sb_wv_dot(ua, ub), dc = sb_w_sub(cosine, cos0);
    sb_wide s = sb_w_add(t->strain[c], t->strain[k]);
    sb_wide g = sb_w_add(sb_w_mul(ka, dc), sb_w_mul(ksb, s)), h = sb_w_mul(ksb, dc);
    /* F_j = −(g/A)(b̂ − c â) − h â ;  F_k = −(g/B)(â − c b̂) − h b̂ */
    sb_wide ga = sb_w_mul(g, t->inverse[c]), gb = sb_w_mul(g, t->inverse[k]);
    sb_wvec3 fj = sb_wv_add(sb_wv_scale(sb_wv_sub(ub, sb_wv_scale(ua, cosine)), ga), sb_wv_scale(ua, h));
    sb_wvec3 fk = sb_wv_add(sb_wv_scale(sb_wv_sub(ua, sb_wv_scale(ub, cosine)), gb), sb_wv_scale(ub, h));
    out->force[j] = sb_wv_sub(out->force[j], fj);
    out->force[k] = sb_wv_sub(out->force[k], fk);
    out->force[c] = sb_wv_add(out->force[c], sb_wv_add(fj, fk));
    out->energy[0] = sb_w_add(out->energy[0], sb_w_mul(sb_w_mul(sb_w_set((sb_real)0.5), ka), sb_w_mul(dc, dc)));
    out->energy[1] = sb_w_add(out->energy[1], sb_w_mul(sb_w_mul(ksb, dc), s));
}

/* What the fused bonds of a block of triangles need besides the shared
 * edge geometry: the edge rest lengths and, with damping, the velocities. */
typedef struct sb_wfused {
    sb_wide rest[3]; /* the triangle's edge rest lengths tri_len0 */
    sb_wvec3 velocity[3];
} sb_wfused;

/* Adds the bond edge c owns (if it does; a lane's constants are zero
 * otherwise): stretch, spring and damping along the edge. */
static inline void sb_fast_owned_bond(const sb_fast_model* m, const sb_wtriangle* t, const sb_wfused* e, int c,
                                      sb_wide length, uint32_t s, sb_wtriangle_out* out) {
    int j = (c + 1) % 3;
    sb_wide owned = sb_w_bit(m->tri_owned + s, c);
    sb_wide r0 = m->tri_edge_r0[c] ? sb_w_load(m->tri_edge_r0[c] + s) : e->rest[c];
    sb_wide stretch = sb_w_sub(length, r0);
    sb_wide kb = sb_w_mul(owned, sb_w_constant(m->tri_edge_bond_k[c], s));
    sb_wide ks = sb_w_mul(owned, sb_w_constant(m->tri_edge_spring_k[c], s));
    sb_wide magnitude = sb_w_mul(sb_w_add(kb, ks), stretch);
    if (m->fused_damping) {
        sb_wide opening = sb_wv_dot(sb_wv_sub(e->velocity[j], e->velocity[c]), t->unit[c]);
        sb_wide d = sb_w_mul(owned, sb_w_constant(m->tri_edge_damping[c], s));
        magnitude = sb_w_add(magnitude, sb_w_mul(d, opening));
    }
    sb_wvec3 f = sb_wv_scale(t->unit[c], magnitude);
    out->force[c] = sb_wv_add(out->force[c], f);
    out->force[j] = sb_wv_sub(out->force[j], f);
    sb_wide strain_energy = sb_w_mul(sb_w_set((sb_real)0.5), sb_w_mul(stretch, stretch));
    out->energy[2] = sb_w_add(out->energy[2], sb_w_mul(kb, strain_energy));
    out->energy[3] = sb_w_add(out->energy[3], sb_w_mul(ks, strain_energy));
}

int sb_fast_corners(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                    double energy[4]) {
    uint32_t step = sb_block_step(serial);
    const sb_wide ratio = sb_w_set((sb_real)SB_COLLAPSE_RATIO), zero = sb_w_set(0);
    sb_wide sums[4] = {zero, zero, zero, zero};
    bool collapsed = false, near = false, limits = m->fused_bonds && m->tri_edge_near_max2[0];
    for (uint32_t s = begin; s < end; s += step) {
        int count = sb_block_count(s, end, step);
        sb_windex v[3];
        sb_wvec3 p[3];
        for (int c = 0; c < 3; c++) {
            v[c] = sb_w_index(m->tri_v[c] + s);
            p[c] = sb_wv_load4(fr->positions4, v[c]);
        }
        sb_wtriangle t;
        sb_wfused fused;
        sb_wide length[3];
        for (int c = 0; c < 3; c++) {
            sb_wvec3 e = sb_wv_sub(p[(c + 1) % 3], p[c]);
            sb_wide rest = sb_w_load(m->tri_len0[c] + s), squared = sb_wv_dot(e, e);
            t.inverse[c] = sb_w_rsqrt(squared);
            length[c] = sb_w_mul(squared, t.inverse[c]);
            t.unit[c] = sb_wv_scale(e, t.inverse[c]);
            t.strain[c] = sb_w_sub(length[c], rest);
            fused.rest[c] = rest;
            collapsed |= sb_w_any(sb_w_less(length[c], sb_w_mul(ratio, rest)), count);
            if (limits) near |= sb_near_limit(m->tri_edge_near_max2[c], m->tri_edge_near_min2[c], s, squared, count);
        }
        sb_wide ka = sb_w_constant(m->angle_k, s), ksb = sb_w_constant(m->stretch_bend_k, s);
        sb_wtriangle_out out = {{{zero, zero, zero}, {zero, zero, zero}, {zero, zero, zero}}, {zero, zero, zero, zero}};
        for (int c = 0; c < 3; c++) sb_fast_corner(&t, c, sb_w_load(m->tri_cos0[c] + s), ka, ksb, &out);
        for (int c = 0; c < 3 && m->fused_damping; c++) fused.velocity[c] = sb_wv_load4(fr->velocities4, v[c]);
        if (m->fused_bonds)
            for (int c = 0; c < 3; c++) sb_fast_owned_bond(m, &t, &fused, c, length[c], s, &out);
        for (int c = 0; c < 3; c++) sb_wv_add4(fr->forces4, v[c], out.force[c], count);
        for (int e = 0; e < 4; e++) sums[e] = sb_w_add(sums[e], sb_w_keep(out.energy[e], count));
    }
    for (int e = 0; e < 4; e++) energy[e] += sb_w_sum(sums[e], SB_WIDTH);
    return (collapsed ? SB_KERNEL_COLLAPSED : 0) | (near ? SB_KERNEL_NEAR_LIMIT : 0);
}
