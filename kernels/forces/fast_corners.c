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
 * Fused bonds: gathers and scatter-adds are what a step costs (the
 * measured costs per element: bench/results/notes/fast_step.md), and a bond on a
 * triangle's edge needs exactly the positions and the length the triangle
 * kernel already has. So each bond on a triangle's edge is owned by one
 * triangle (kernels/forces/fast_model.c: a bit per edge in one byte per triangle)
 * and costs no index or scatter of its own: its stretch, its spring and,
 * when the model has damping, the spring's damping from the edge's
 * relative velocity (the same half-step velocity the bond kernel and the
 * reference read, gathered for the triangle's three vertices only then).
 * Uniform constants are one value; non-uniform ones are carried per
 * triangle slot and edge. The bond's rest length is the triangle's own
 * where they agree (no stream of its own).
 *
 * A breakable model costs the same streams: its triangles' and fused
 * bonds' constants are folded as a plain model's are, and what breaks is
 * a bit of the slot's byte (a bond's edge bit, the triangle's live bit,
 * which masks the corners' constants and, with the edge bit, the collapse
 * checks). Its break limits are tested on the squared lengths in hand
 * against (limit / r0)² times the squared rest length, one value for a
 * material's strain (sb_fused_near_limit): the quiet step of a breakable
 * sheet loads nothing a plain one does not (bench/results/tearing.md).
 *
 * Fused hinges, for the same reason: a hinge on a triangle's edge needs
 * the edge's two vertices and the triangle's opposite vertex, which the
 * triangle has in registers, and its fourth vertex. Carried by one of its
 * wings (kernels/forces/fast_model.h), it costs one gather and one scatter-add
 * instead of four of each (a third of the gathered bytes), and the wing's
 * normal n0 = e_0 × e_1 is the same for the triangle's three edges. The
 * hinge of slot j sits on a different edge per lane: its vertices, unit
 * vector and length are picked lane by lane (two blends each), and its
 * forces go back the same way. Each hinge slot runs only for blocks where
 * some lane carries one; a color's triangles carrying most come first, so
 * few blocks run a slot for a few lanes. Lanes without a hinge there (or
 * with a dropped one) have k = 0; their divisions see at least the
 * smallest normal number and their collapse checks +inf, so they add
 * exact zeros (to one of the triangle's own vertices). */
#include "kernels/forces/fast_corners.h"
#include "kernels/forces/fast_block.h"
#include "kernels/forces/reference_terms.h"

typedef struct sb_wtriangle {
    sb_wvec3 unit[3];   /* u_c: unit vector of edge c → c+1 */
    sb_wide inverse[3]; /* 1 / L_c */
    sb_wide strain[3];  /* L_c − L_c0 */
} sb_wtriangle;

typedef struct sb_wtriangle_out {
    sb_wvec3 force[3]; /* on vertices 0, 1, 2 */
    sb_wide energy[5]; /* angle, stretch-bend, bond, spring, bend */
} sb_wtriangle_out;

/* Adds corner c's forces and energies to out. */
static inline __attribute__((always_inline)) void sb_fast_corner(const sb_wtriangle* t, int c, sb_wide cos0, sb_wide ka,
                                                                 sb_wide ksb, sb_wtriangle_out* out) {
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
    sb_wide rest[3];    /* the triangle's edge rest lengths tri_len0 */
    sb_wide squared[3]; /* the edges' squared lengths */
    sb_wvec3 velocity[3];
} sb_wfused;

/* Whether a lane's owned bond (owned 1, else 0) is at or past the margins
 * of its limits, relative to its rest length r0: no load but the margins'
 * where they differ from bond to bond. */
static inline bool sb_fused_near_limit(const sb_fast_model* m, uint32_t s, int c, sb_wide owned, sb_wide r0,
                                       sb_wide squared, int count) {
    sb_wide rest2 = sb_w_mul(r0, r0);
    bool near = sb_w_any(
        sb_w_less(sb_w_mul(sb_w_constant(m->tri_edge_max_ratio2[c], s), rest2), sb_w_mul(owned, squared)), count);
    if (sb_constant_on(m->tri_edge_min_ratio2[c]))
        near |= sb_w_any(
            sb_w_less(squared, sb_w_mul(owned, sb_w_mul(sb_w_constant(m->tri_edge_min_ratio2[c], s), rest2))), count);
    return near;
}

/* Adds the bond edge c owns (if it does; a lane's constants are zero
 * otherwise): stretch, spring and damping along the edge. With `limits`,
 * returns whether it is near its break limits. */
static inline __attribute__((always_inline)) bool sb_fast_owned_bond(const sb_fast_model* m, const sb_wtriangle* t,
                                                                     const sb_wfused* e, int c, sb_wide length,
                                                                     uint32_t s, bool damping, bool limits, int count,
                                                                     sb_wtriangle_out* out) {
    int j = (c + 1) % 3;
    sb_wide owned = sb_w_bit(m->tri_owned + s, c);
    sb_wide r0 = m->tri_edge_r0[c] ? sb_w_load(m->tri_edge_r0[c] + s) : e->rest[c];
    sb_wide stretch = sb_w_sub(length, r0);
    sb_wide kb = sb_w_mul(owned, sb_w_constant(m->tri_edge_bond_k[c], s));
    sb_wide ks = sb_w_mul(owned, sb_w_constant(m->tri_edge_spring_k[c], s));
    sb_wide magnitude = sb_w_mul(sb_w_add(kb, ks), stretch);
    if (damping) {
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
    return limits && sb_fused_near_limit(m, s, c, owned, r0, e->squared[c], count);
}

/* Edge c's rest length for its collapse check: the triangle's, or 0 (no
 * check) where a breakable model dropped the triangle and broke the edge's
 * own bond (a bond owned by the other triangle on it is checked there). */
static inline sb_wide sb_collapse_rest(const sb_fast_model* m, uint32_t s, int c, sb_wide rest) {
    if (!m->mortal_triangles) return rest;
    return sb_w_mul(rest, sb_w_max(sb_w_bit(m->tri_owned + s, SB_TRIANGLE_LIVE), sb_w_bit(m->tri_owned + s, c)));
}

/* What a triangle's hinges share: its vertices, its edges' lengths and
 * its normal n0 with 1 / |n0|². */
typedef struct sb_wwing {
    sb_wvec3 p[3], normal;
    sb_wide length[3], normal_sq, inverse_normal_sq;
    sb_worigin origin; /* p[0]'s (fast_block.h): where the fourth vertices are placed */
} sb_wwing;

/* Per lane a[c] for the edge c whose field is c + 1 (any of them for 0). */
static inline sb_wide sb_w_pick3(sb_wide field, sb_wide a0, sb_wide a1, sb_wide a2) {
    return sb_w_pick_greater(field, sb_w_set((sb_real)2.5), a2,
                             sb_w_pick_greater(field, sb_w_set((sb_real)1.5), a1, a0));
}
static inline sb_wvec3 sb_wv_pick3(sb_wide field, sb_wvec3 a0, sb_wvec3 a1, sb_wvec3 a2) {
    return (sb_wvec3){sb_w_pick3(field, a0.x, a1.x, a2.x), sb_w_pick3(field, a0.y, a1.y, a2.y),
                      sb_w_pick3(field, a0.z, a1.z, a2.z)};
}

/* Adds the hinges of hinge slot j (kernels/forces/fast_hinges.c's term, with
 * e0, e1, o0 the corners c, c + 1, c + 2 of the lane's edge c): scatters
 * the force on o1, adds the others to out. Returns whether a wing of a
 * live hinge collapsed. */
static inline bool sb_fast_carried_hinge(const sb_fast_model* m, const sb_fast_frame* fr, const sb_wtriangle* t,
                                         const sb_wwing* w, sb_wide field, int j, uint32_t s, int count,
                                         sb_wtriangle_out* out) {
    const sb_wide zero = sb_w_set(0), tiny = sb_w_set(SB_REAL_MIN);
    sb_wvec3 e0 = sb_wv_pick3(field, w->p[0], w->p[1], w->p[2]), e1 = sb_wv_pick3(field, w->p[1], w->p[2], w->p[0]);
    sb_wvec3 o0 = sb_wv_pick3(field, w->p[2], w->p[0], w->p[1]);
    sb_wvec3 unit = sb_wv_pick3(field, t->unit[0], t->unit[1], t->unit[2]);
    sb_wide length = sb_w_pick3(field, w->length[0], w->length[1], w->length[2]);
    sb_windex other = sb_w_index(m->tri_hinge_other[j] + s);
    sb_wvec3 o1 = sb_wv_vertex_at(fr, m->tri_hinge_other[j] + s, &w->origin);
    sb_wvec3 n1 = sb_wv_cross(sb_wv_sub(o1, e1), sb_wv_sub(o1, e0));
    sb_wide n1_sq = sb_wv_dot(n1, n1);
    sb_wide sine = sb_wv_dot(sb_wv_cross(w->normal, n1), unit);
    sb_wide delta = sb_w_angle_delta(sine, sb_wv_dot(w->normal, n1), sb_w_load(m->tri_hinge_phi0[j] + s));
    sb_wide k = sb_w_pick_greater(field, sb_w_set((sb_real)0.5), sb_w_constant(m->tri_hinge_k[j], s), zero);
    sb_wide kd = sb_w_mul(k, delta);
    sb_wide narrowest = sb_w_min(w->normal_sq, n1_sq);
    narrowest = sb_w_pick_greater(sb_w_abs(k), zero, narrowest, sb_w_set((sb_real)INFINITY));
    bool collapsed = sb_w_any(sb_w_less(narrowest, sb_w_wing_limit(sb_w_mul(length, length))), count);
    sb_wvec3 w0 = sb_wv_scale(w->normal, sb_w_mul(kd, w->inverse_normal_sq));
    sb_wvec3 w1 = sb_wv_scale(n1, sb_w_div(kd, sb_w_max(n1_sq, tiny)));
    sb_wvec3 f_o0 = sb_wv_scale(w0, length), f_o1 = sb_wv_scale(w1, length);
    sb_wvec3 f_e0 = sb_wv_add(sb_wv_scale(w0, sb_wv_dot(sb_wv_sub(o0, e1), unit)),
                              sb_wv_scale(w1, sb_wv_dot(sb_wv_sub(o1, e1), unit)));
    sb_wvec3 f_e1 = sb_wv_neg(sb_wv_add(f_o0, sb_wv_add(f_o1, f_e0)));
    sb_wv_add4(fr->forces4, other, f_o1, count);
    out->force[0] = sb_wv_add(out->force[0], sb_wv_pick3(field, f_e0, f_o0, f_e1));
    out->force[1] = sb_wv_add(out->force[1], sb_wv_pick3(field, f_e1, f_e0, f_o0));
    out->force[2] = sb_wv_add(out->force[2], sb_wv_pick3(field, f_o0, f_e1, f_e0));
    out->energy[4] = sb_w_add(out->energy[4], sb_w_mul(sb_w_mul(sb_w_set((sb_real)0.5), kd), delta));
    return collapsed;
}

/* Adds the hinges the lanes' triangles carry; returns whether a wing
 * collapsed. */
static inline bool sb_fast_carried_hinges(const sb_fast_model* m, const sb_fast_frame* fr, const sb_wtriangle* t,
                                          sb_wwing* w, const sb_wvec3 edge[3], uint32_t s, int count,
                                          sb_wtriangle_out* out) {
    bool collapsed = false;
    for (int j = 0; j < 3; j++) {
        sb_wide field = sb_w_field(m->tri_hinge_edges + s, 2 * j, 3u);
        if (!sb_w_any(sb_w_less(sb_w_set((sb_real)0.5), field), count)) break; /* nor in the next slots */
        if (j == 0) {
            w->normal = sb_wv_cross(edge[0], edge[1]);
            w->normal_sq = sb_wv_dot(w->normal, w->normal);
            w->inverse_normal_sq = sb_w_div(sb_w_set(1), sb_w_max(w->normal_sq, sb_w_set(SB_REAL_MIN)));
        }
        collapsed |= sb_fast_carried_hinge(m, fr, t, w, field, j, s, count, out);
    }
    return collapsed;
}

/* The per-triangle streams of the block SB_PREFETCH_SLOTS slots ahead are
 * asked for now: the hardware prefetcher, with ten streams, left the 1M
 * sheet's kernel waiting on them (perf: about a third of its samples on the
 * instructions after these loads, against a flat profile at 100k). Slots
 * are laid out contiguously across a group's ranges and blocks, so the
 * block ahead is usually the next one this worker runs; a prefetch past the
 * arrays' end is harmless. */
#define SB_PREFETCH_SLOTS (8 * 16)
static inline void sb_fast_corners_prefetch(const sb_fast_model* m, uint32_t s) {
    for (int c = 0; c < 3; c++) {
        __builtin_prefetch(m->tri_v[c] + s);
        __builtin_prefetch(m->tri_len0[c] + s);
        __builtin_prefetch(m->tri_cos0[c] + s);
    }
    __builtin_prefetch(m->tri_owned + s);
}

/* The kernel's loop; `extras` false compiles it without the fused damping
 * and hinges (the default terms), so that their state costs no registers
 * or stack stores there. */
static inline __attribute__((always_inline)) int sb_fast_corners_loop(const sb_fast_model* m, const sb_fast_frame* fr,
                                                                      uint32_t begin, uint32_t end, bool serial,
                                                                      double energy[5], bool extras) {
    uint32_t step = sb_block_step(serial);
    const sb_wide ratio = sb_w_set((sb_real)SB_COLLAPSE_RATIO), zero = sb_w_set(0);
    sb_wide sums[5] = {zero, zero, zero, zero, zero};
    bool collapsed = false, near = false, limits = m->fused_limits;
    bool damping = extras && m->fused_damping, hinges = extras && m->fused_hinges;
    for (uint32_t s = begin; s < end; s += step) {
        int count = sb_block_count(s, end, step);
        sb_fast_corners_prefetch(m, s + SB_PREFETCH_SLOTS);
        sb_wwing wing;
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++)
            wing.p[c] = c == 0 ? sb_wv_origin_at(fr, m->tri_v[c] + s, &wing.origin)
                               : sb_wv_vertex_at(fr, m->tri_v[c] + s, &wing.origin);
        sb_wtriangle t;
        sb_wfused fused;
        sb_wvec3 edge[3];
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) {
            edge[c] = sb_wv_sub(wing.p[(c + 1) % 3], wing.p[c]);
            sb_wide rest = sb_w_load(m->tri_len0[c] + s), squared = sb_wv_dot(edge[c], edge[c]);
            t.inverse[c] = sb_w_rsqrt(squared);
            wing.length[c] = sb_w_mul(squared, t.inverse[c]);
            t.unit[c] = sb_wv_scale(edge[c], t.inverse[c]);
            t.strain[c] = sb_w_sub(wing.length[c], rest);
            fused.rest[c] = rest;
            fused.squared[c] = squared;
            collapsed |= sb_w_any(sb_w_less(wing.length[c], sb_w_mul(ratio, sb_collapse_rest(m, s, c, rest))), count);
        }
        sb_wide ka, ksb;
        sb_w_corner_constants(m, s, &ka, &ksb);
        sb_wtriangle_out out = {{{zero, zero, zero}, {zero, zero, zero}, {zero, zero, zero}},
                                {zero, zero, zero, zero, zero}};
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) sb_fast_corner(&t, c, sb_w_load(m->tri_cos0[c] + s), ka, ksb, &out);
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) /* read only with damping */
            fused.velocity[c] =
                damping ? sb_wv_load4_at(fr->velocities4, m->tri_v[c] + s) : (sb_wvec3){zero, zero, zero};
        if (m->fused_bonds)
#pragma GCC unroll 3
            for (int c = 0; c < 3; c++)
                near |= sb_fast_owned_bond(m, &t, &fused, c, wing.length[c], s, damping, limits, count, &out);
        if (hinges) collapsed |= sb_fast_carried_hinges(m, fr, &t, &wing, edge, s, count, &out);
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) sb_wv_add4_at(fr->forces4, m->tri_v[c] + s, out.force[c], count);
#pragma GCC unroll 5
        for (int e = 0; e < 5; e++) sums[e] = sb_w_add(sums[e], sb_w_keep(out.energy[e], count));
    }
    for (int e = 0; e < 5; e++) energy[e] += sb_w_sum(sums[e], SB_WIDTH);
    return (collapsed ? SB_KERNEL_COLLAPSED : 0) | (near ? SB_KERNEL_NEAR_LIMIT : 0);
}

int sb_fast_corners(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                    double energy[5]) {
    if (m->fused_damping || m->fused_hinges) return sb_fast_corners_loop(m, fr, begin, end, serial, energy, true);
    return sb_fast_corners_loop(m, fr, begin, end, serial, energy, false);
}
