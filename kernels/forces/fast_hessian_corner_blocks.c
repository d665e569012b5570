/* The triangles' diagonal blocks of K + damping D in closed form
 * (kernels/forces/fast_hessian.h's diagonal pass for the triangle group): six dual
 * runs a triangle cost about five times this.
 *
 * Corner c (kernels/forces/fast_corners.c's notation: vertex i = c, neighbours
 * j = c+1, k = c+2, a = x_j − x_i, b = x_k − x_i, â, b̂, A, B, cos θ = â·b̂)
 * has the energy ½ kθ (c − c0)² + ksb (c − c0) S, S the two edges' stretch.
 * Its Hessian in (a, b), with g = kθ (c − c0) + ksb S and h = ksb (c − c0),
 * is kθ ∇c ∇cᵀ + ksb (∇c ∇Sᵀ + ∇S ∇cᵀ) + g ∇²c + h ∇²S, where
 *   ∇_a c = (b̂ − c â)/A,  ∇_a S = â,  ∇²_aa S = (I − â âᵀ)/A,
 *   ∇²_aa c = −(â b̂ᵀ + b̂ âᵀ + c I − 3 c â âᵀ)/A²,
 *   ∇²_ab c = ((I − b̂ b̂ᵀ) − â (â − c b̂)ᵀ)/(A B),  ∇²_ab S = 0,
 * and b's alike (kernels/forces/hessian_corners.c derives them); then
 * K_jj = H_aa, K_kk = H_bb, K_ii = H_aa + H_ab + H_abᵀ + H_bb. A bond that
 * edge c owns adds k (u uᵀ + (1 − r0/r)(I − u uᵀ)) + damping d u uᵀ to both
 * of its ends. */
#include "kernels/forces/fast_hessian_corner_blocks.h"
#include "kernels/forces/fast_hessian.h"

/* A symmetric 3 × 3 block per lane: its upper triangle, xx xy xz yy yz zz
 * (SB_BLOCK_SIZE, kernels/forces/fast_hessian.h). Every term below is symmetric or
 * comes with its transpose, so six entries carry it: two thirds of the
 * arithmetic of a full block. */
typedef struct sb_wsym3 {
    sb_wide m[SB_BLOCK_SIZE];
} sb_wsym3;

static const int sb_sym_row[SB_BLOCK_SIZE] = {0, 0, 0, 1, 1, 2}, sb_sym_column[SB_BLOCK_SIZE] = {0, 1, 2, 1, 2, 2};

static inline sb_wide sb_wv_at(sb_wvec3 p, int axis) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; }

/* out += s (p qᵀ + q pᵀ) */
static inline void sb_ws_pair(sb_wsym3* out, sb_wide s, sb_wvec3 p, sb_wvec3 q) {
    for (int e = 0; e < SB_BLOCK_SIZE; e++) {
        int r = sb_sym_row[e], c = sb_sym_column[e];
        sb_wide pq = sb_w_add(sb_w_mul(sb_wv_at(p, r), sb_wv_at(q, c)), sb_w_mul(sb_wv_at(q, r), sb_wv_at(p, c)));
        out->m[e] = sb_w_add(out->m[e], sb_w_mul(s, pq));
    }
}

/* out += s p pᵀ */
static inline void sb_ws_outer(sb_wsym3* out, sb_wide s, sb_wvec3 p) {
    sb_wvec3 sp = sb_wv_scale(p, s);
    for (int e = 0; e < SB_BLOCK_SIZE; e++)
        out->m[e] = sb_w_add(out->m[e], sb_w_mul(sb_wv_at(sp, sb_sym_row[e]), sb_wv_at(p, sb_sym_column[e])));
}

/* out += s I */
static inline void sb_ws_identity(sb_wsym3* out, sb_wide s) {
    static const int diagonal[3] = {0, 3, 5};
    for (int d = 0; d < 3; d++) out->m[diagonal[d]] = sb_w_add(out->m[diagonal[d]], s);
}

static inline void sb_ws_add(sb_wsym3* out, const sb_wsym3* a) {
    for (int e = 0; e < SB_BLOCK_SIZE; e++) out->m[e] = sb_w_add(out->m[e], a->m[e]);
}

typedef struct sb_wgeometry {
    sb_wvec3 unit[3];   /* u_c: unit vector of edge c → c+1 */
    sb_wide inverse[3]; /* 1 / L_c */
    sb_wide length[3];
} sb_wgeometry;

/* The second derivatives of the part of one side (â, A) that does not
 * involve the other: kθ ∇c ∇cᵀ + ksb (∇c âᵀ + â ∇cᵀ) + g ∇²_aa c + h ∇²_aa S. */
static inline void sb_corner_side(sb_wsym3* h_aa, sb_wvec3 ua, sb_wvec3 ub, sb_wvec3 grad, sb_wide inv, sb_wide cosine,
                                  sb_wide ka, sb_wide ksb, sb_wide g, sb_wide h) {
    const sb_wide minus_g = sb_w_mul(sb_w_mul(sb_w_set(-1), g), sb_w_mul(inv, inv)), h_inv = sb_w_mul(h, inv);
    sb_ws_outer(h_aa, ka, grad);
    sb_ws_pair(h_aa, ksb, grad, ua);
    sb_ws_pair(h_aa, minus_g, ua, ub);
    sb_ws_identity(h_aa, sb_w_add(sb_w_mul(minus_g, cosine), h_inv));
    sb_ws_outer(h_aa, sb_w_sub(sb_w_mul(sb_w_set(-3), sb_w_mul(minus_g, cosine)), h_inv), ua);
}

/* Adds corner c's blocks to block[i], block[j], block[k]. */
static inline void sb_corner_blocks(const sb_wgeometry* t, int c, sb_wide cos0, sb_wide len0_a, sb_wide len0_b,
                                    sb_wide ka, sb_wide ksb, sb_wsym3* block) {
    const sb_wide zero = sb_w_set(0);
    int j = (c + 1) % 3, k = (c + 2) % 3;
    sb_wvec3 ua = t->unit[c], ub = sb_wv_neg(t->unit[k]);
    sb_wide ia = t->inverse[c], ib = t->inverse[k], cosine = sb_wv_dot(ua, ub), dc = sb_w_sub(cosine, cos0);
    sb_wide s = sb_w_add(sb_w_sub(t->length[c], len0_a), sb_w_sub(t->length[k], len0_b));
    sb_wide g = sb_w_add(sb_w_mul(ka, dc), sb_w_mul(ksb, s)), h = sb_w_mul(ksb, dc);
    sb_wvec3 ga = sb_wv_scale(sb_wv_sub(ub, sb_wv_scale(ua, cosine)), ia);
    sb_wvec3 gb = sb_wv_scale(sb_wv_sub(ua, sb_wv_scale(ub, cosine)), ib);
    sb_wsym3 h_aa, h_bb, h_ab;
    for (int e = 0; e < SB_BLOCK_SIZE; e++) h_aa.m[e] = h_bb.m[e] = h_ab.m[e] = zero;
    sb_corner_side(&h_aa, ua, ub, ga, ia, cosine, ka, ksb, g, h);
    sb_corner_side(&h_bb, ub, ua, gb, ib, cosine, ka, ksb, g, h);
    /* h_ab = H_ab + H_abᵀ, H_ab = kθ ∇_a c ∇_b cᵀ + ksb (∇_a c b̂ᵀ + â ∇_b cᵀ) + g ∇²_ab c */
    sb_wide g_ab = sb_w_mul(g, sb_w_mul(ia, ib)), minus_g_ab = sb_w_sub(zero, g_ab);
    sb_ws_pair(&h_ab, ka, ga, gb);
    sb_ws_pair(&h_ab, ksb, ga, ub);
    sb_ws_pair(&h_ab, ksb, ua, gb);
    sb_ws_identity(&h_ab, sb_w_add(g_ab, g_ab));
    sb_ws_outer(&h_ab, sb_w_add(minus_g_ab, minus_g_ab), ub);
    sb_ws_pair(&h_ab, minus_g_ab, ua, sb_wv_sub(ua, sb_wv_scale(ub, cosine)));
    sb_ws_add(&block[j], &h_aa);
    sb_ws_add(&block[k], &h_bb);
    sb_ws_add(&h_ab, &h_aa);
    sb_ws_add(&h_ab, &h_bb);
    sb_ws_add(&block[c], &h_ab);
}

/* Adds the block of the bond edge c owns (zero constants where none) to
 * both of its ends. */
static inline void sb_owned_bond_blocks(const sb_fast_model* m, const sb_wgeometry* t, uint32_t s, int c,
                                        sb_wide damping, sb_wsym3* block) {
    sb_wide owned = sb_w_bit(m->tri_owned + s, c);
    sb_wide r0 = sb_w_load((m->tri_edge_r0[c] ? m->tri_edge_r0[c] : m->tri_len0[c]) + s);
    sb_wide k =
        sb_w_mul(owned, sb_w_add(sb_w_constant(m->tri_edge_bond_k[c], s), sb_w_constant(m->tri_edge_spring_k[c], s)));
    sb_wide d = m->fused_damping ? sb_w_mul(owned, sb_w_constant(m->tri_edge_damping[c], s)) : sb_w_set(0);
    sb_wide sideways = sb_w_mul(k, sb_w_sub(sb_w_set(1), sb_w_mul(r0, t->inverse[c]))); /* k (1 − r0/r) */
    sb_wsym3 b;
    for (int e = 0; e < SB_BLOCK_SIZE; e++) b.m[e] = sb_w_set(0);
    sb_ws_identity(&b, sideways);
    sb_ws_outer(&b, sb_w_add(sb_w_sub(k, sideways), sb_w_mul(damping, d)), t->unit[c]);
    sb_ws_add(&block[c], &b);
    sb_ws_add(&block[(c + 1) % 3], &b);
}

void sb_fast_corner_blocks(const sb_fast_model* m, const sb_hessian_frame* fr, uint32_t begin, uint32_t end,
                           bool serial) {
    const sb_wide zero = sb_w_set(0), damping = sb_w_set(fr->damping);
    uint32_t step = sb_block_step(serial);
    for (uint32_t s = begin; s < end; s += step) {
        int count = sb_block_count(s, end, step);
        sb_windex v[3];
        sb_wvec3 p[3];
        for (int c = 0; c < 3; c++) {
            v[c] = sb_w_index(m->tri_v[c] + s);
            p[c] = sb_wv_load4(fr->base.positions4, v[c]);
        }
        sb_wgeometry t;
        for (int c = 0; c < 3; c++) {
            sb_wvec3 e = sb_wv_sub(p[(c + 1) % 3], p[c]);
            sb_wide squared = sb_wv_dot(e, e);
            t.inverse[c] = sb_w_rsqrt(squared);
            t.length[c] = sb_w_mul(squared, t.inverse[c]);
            t.unit[c] = sb_wv_scale(e, t.inverse[c]);
        }
        sb_wsym3 block[3];
        for (int c = 0; c < 3; c++)
            for (int e = 0; e < SB_BLOCK_SIZE; e++) block[c].m[e] = zero;
        if (m->has_corners) {
            sb_wide ka, ksb;
            sb_w_corner_constants(m, s, &ka, &ksb);
            for (int c = 0; c < 3; c++)
                sb_corner_blocks(&t, c, sb_w_load(m->tri_cos0[c] + s), sb_w_load(m->tri_len0[c] + s),
                                 sb_w_load(m->tri_len0[(c + 2) % 3] + s), ka, ksb, block);
        }
        if (m->fused_bonds)
            for (int c = 0; c < 3; c++) sb_owned_bond_blocks(m, &t, s, c, damping, block);
        for (int c = 0; c < 3; c++) sb_hessian_add_blocks(fr->blocks, v[c], block[c].m, fr->scale, count);
    }
}
