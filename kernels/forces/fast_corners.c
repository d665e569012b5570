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
 * Uniform constants are one value; non-uniform ones (or a breakable
 * model's) are carried per triangle slot and edge. The bond's rest length
 * is the triangle's own where they agree (no stream of its own).
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
 * exact zeros (to one of the triangle's own vertices).
 *
 * Triangle pairs (sb_fast_pairs, over sb_fast_model.paired): two triangles
 * sharing an edge with a hinge on it, A = (A0, A1, A2) and B = (A1, A0,
 * B2), run as one element: four gathers and four scatters for both, each
 * triangle's corners, owned bonds and carried hinges by the same code as
 * a lone triangle (sb_fast_triangle, on A's lanes and then B's), and the
 * shared edge's hinge by the carried hinges' formula
 * (sb_fast_hinge_forces) on the registers, with no index, gather,
 * scatter or lane pick of its own. */
#include "kernels/forces/fast_corners.h"
#include "kernels/forces/fast_block.h"
#include "kernels/forces/reference_terms.h"

typedef struct sb_wtriangle {
    sb_wvec3 unit[3];   /* u_c: unit vector of edge c → c+1 */
    sb_wide inverse[3]; /* 1 / L_c */
    sb_wide strain[3];  /* L_c − L_c0 */
} sb_wtriangle;

typedef struct sb_wtriangle_out {
    sb_wvec3 force[4]; /* on vertices 0, 1, 2 (3: a pair's B2) */
    sb_wide energy[5]; /* angle, stretch-bend, bond, spring, bend */
} sb_wtriangle_out;

static inline sb_wtriangle_out sb_wtriangle_out_zero(void) {
    const sb_wide zero = sb_w_set(0);
    const sb_wvec3 none = {zero, zero, zero};
    return (sb_wtriangle_out){{none, none, none, none}, {zero, zero, zero, zero, zero}};
}

/* Where corner c's force goes in the out: the same slot, or, for a pair's
 * B = (A1, A0, B2) (`mirrored`), A's slot of the same vertex. Constant
 * wherever the loops over corners are unrolled. */
static inline int sb_slot_of(int c, bool mirrored) { return !mirrored ? c : c == 2 ? 3 : 1 - c; }

/* Adds corner c's forces and energies to out. */
static inline __attribute__((always_inline)) void sb_fast_corner(const sb_wtriangle* t, int c, sb_wide cos0, sb_wide ka,
                                                                 sb_wide ksb, bool mirrored, sb_wtriangle_out* out) {
    int j = (c + 1) % 3, k = (c + 2) % 3;
    sb_wvec3 ua = t->unit[c], ub = sb_wv_neg(t->unit[k]);
    sb_wide cosine = sb_wv_dot(ua, ub), dc = sb_w_sub(cosine, cos0);
    sb_wide s = sb_w_add(t->strain[c], t->strain[k]);
    sb_wide g = sb_w_add(sb_w_mul(ka, dc), sb_w_mul(ksb, s)), h = sb_w_mul(ksb, dc);
    /* F_j = −(g/A)(b̂ − c â) − h â ;  F_k = −(g/B)(â − c b̂) − h b̂ */
    sb_wide ga = sb_w_mul(g, t->inverse[c]), gb = sb_w_mul(g, t->inverse[k]);
    sb_wvec3 fj = sb_wv_add(sb_wv_scale(sb_wv_sub(ub, sb_wv_scale(ua, cosine)), ga), sb_wv_scale(ua, h));
    sb_wvec3 fk = sb_wv_add(sb_wv_scale(sb_wv_sub(ua, sb_wv_scale(ub, cosine)), gb), sb_wv_scale(ub, h));
    int at_j = sb_slot_of(j, mirrored), at_k = sb_slot_of(k, mirrored), at_c = sb_slot_of(c, mirrored);
    out->force[at_j] = sb_wv_sub(out->force[at_j], fj);
    out->force[at_k] = sb_wv_sub(out->force[at_k], fk);
    out->force[at_c] = sb_wv_add(out->force[at_c], sb_wv_add(fj, fk));
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
static inline __attribute__((always_inline)) void sb_fast_owned_bond(const sb_fast_model* m, const sb_wtriangle* t,
                                                                     const sb_wfused* e, int c, sb_wide length,
                                                                     uint32_t s, bool damping, bool mirrored,
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
    int at_c = sb_slot_of(c, mirrored), at_j = sb_slot_of(j, mirrored);
    out->force[at_c] = sb_wv_add(out->force[at_c], f);
    out->force[at_j] = sb_wv_sub(out->force[at_j], f);
    sb_wide strain_energy = sb_w_mul(sb_w_set((sb_real)0.5), sb_w_mul(stretch, stretch));
    out->energy[2] = sb_w_add(out->energy[2], sb_w_mul(kb, strain_energy));
    out->energy[3] = sb_w_add(out->energy[3], sb_w_mul(ks, strain_energy));
}

/* What a triangle's hinges share: its vertices, its edges' lengths and
 * its normal n0 with 1 / |n0|². */
typedef struct sb_wwing {
    sb_wvec3 p[3], normal;
    sb_wide length[3], normal_sq, inverse_normal_sq;
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

/* The dihedral term of kernels/forces/fast_hinges.c on p = e0, e1, o0, o1,
 * for a hinge whose first wing is a triangle's (its normal n0 and 1 / |n0|²
 * from the triangle, the edge's unit vector and length too): the forces
 * on the four into f, the energy added to *energy. Returns whether a wing
 * of a live hinge (k ≠ 0) collapsed. */
static inline __attribute__((always_inline)) bool sb_fast_hinge_forces(const sb_wwing* w, const sb_wvec3 p[4],
                                                                       sb_wvec3 unit, sb_wide length, sb_wide k,
                                                                       sb_wide phi0, int count, sb_wvec3 f[4],
                                                                       sb_wide* energy) {
    const sb_wide zero = sb_w_set(0), tiny = sb_w_set(SB_REAL_MIN);
    sb_wvec3 n1 = sb_wv_cross(sb_wv_sub(p[3], p[1]), sb_wv_sub(p[3], p[0]));
    sb_wide n1_sq = sb_wv_dot(n1, n1);
    sb_wide sine = sb_wv_dot(sb_wv_cross(w->normal, n1), unit);
    sb_wide delta = sb_w_angle_delta(sine, sb_wv_dot(w->normal, n1), phi0);
    sb_wide kd = sb_w_mul(k, delta);
    sb_wide narrowest = sb_w_min(w->normal_sq, n1_sq);
    narrowest = sb_w_pick_greater(sb_w_abs(k), zero, narrowest, sb_w_set((sb_real)INFINITY));
    bool collapsed = sb_w_any(sb_w_less(narrowest, sb_w_wing_limit(sb_w_mul(length, length))), count);
    sb_wvec3 w0 = sb_wv_scale(w->normal, sb_w_mul(kd, w->inverse_normal_sq));
    sb_wvec3 w1 = sb_wv_scale(n1, sb_w_div(kd, sb_w_max(n1_sq, tiny)));
    f[2] = sb_wv_scale(w0, length);
    f[3] = sb_wv_scale(w1, length);
    f[0] = sb_wv_add(sb_wv_scale(w0, sb_wv_dot(sb_wv_sub(p[2], p[1]), unit)),
                     sb_wv_scale(w1, sb_wv_dot(sb_wv_sub(p[3], p[1]), unit)));
    f[1] = sb_wv_neg(sb_wv_add(f[2], sb_wv_add(f[3], f[0])));
    *energy = sb_w_add(*energy, sb_w_mul(sb_w_mul(sb_w_set((sb_real)0.5), kd), delta));
    return collapsed;
}

/* Adds the hinges of hinge slot j (e0, e1, o0 the corners c, c + 1, c + 2
 * of the lane's edge c): scatters the force on o1, adds the others to
 * out. Returns whether a wing of a live hinge collapsed. */
static inline __attribute__((always_inline)) bool sb_fast_carried_hinge(const sb_fast_model* m, const sb_fast_frame* fr,
                                                                        const sb_wtriangle* t, const sb_wwing* w,
                                                                        sb_wide field, int j, uint32_t s, int count,
                                                                        bool mirrored, sb_wtriangle_out* out) {
    sb_windex other = sb_w_index(m->tri_hinge_other[j] + s);
    sb_wvec3 p[4] = {sb_wv_pick3(field, w->p[0], w->p[1], w->p[2]), sb_wv_pick3(field, w->p[1], w->p[2], w->p[0]),
                     sb_wv_pick3(field, w->p[2], w->p[0], w->p[1]), sb_wv_load4(fr->positions4, other)};
    sb_wvec3 unit = sb_wv_pick3(field, t->unit[0], t->unit[1], t->unit[2]);
    sb_wide length = sb_w_pick3(field, w->length[0], w->length[1], w->length[2]);
    sb_wide k = sb_w_pick_greater(field, sb_w_set((sb_real)0.5), sb_w_constant(m->tri_hinge_k[j], s), sb_w_set(0));
    sb_wvec3 f[4];
    bool collapsed =
        sb_fast_hinge_forces(w, p, unit, length, k, sb_w_load(m->tri_hinge_phi0[j] + s), count, f, &out->energy[4]);
    sb_wv_add4(fr->forces4, other, f[3], count);
    int at[3] = {sb_slot_of(0, mirrored), sb_slot_of(1, mirrored), sb_slot_of(2, mirrored)};
    out->force[at[0]] = sb_wv_add(out->force[at[0]], sb_wv_pick3(field, f[0], f[2], f[1]));
    out->force[at[1]] = sb_wv_add(out->force[at[1]], sb_wv_pick3(field, f[1], f[0], f[2]));
    out->force[at[2]] = sb_wv_add(out->force[at[2]], sb_wv_pick3(field, f[2], f[1], f[0]));
    return collapsed;
}

/* The wing's normal n0 = e_0 × e_1 and its inverse square. */
static inline __attribute__((always_inline)) void sb_fast_wing_normal(sb_wwing* w, const sb_wvec3 edge[3]) {
    w->normal = sb_wv_cross(edge[0], edge[1]);
    w->normal_sq = sb_wv_dot(w->normal, w->normal);
    w->inverse_normal_sq = sb_w_div(sb_w_set(1), sb_w_max(w->normal_sq, sb_w_set(SB_REAL_MIN)));
}

/* Adds the hinges the lanes' triangles carry; returns whether a wing
 * collapsed. The wing's normal is computed here unless `normal_ready`. */
static inline __attribute__((always_inline)) bool sb_fast_carried_hinges(const sb_fast_model* m,
                                                                         const sb_fast_frame* fr, const sb_wtriangle* t,
                                                                         sb_wwing* w, const sb_wvec3 edge[3],
                                                                         bool normal_ready, uint32_t s, int count,
                                                                         bool mirrored, sb_wtriangle_out* out) {
    bool collapsed = false;
    for (int j = 0; j < 3; j++) {
        sb_wide field = sb_w_field(m->tri_hinge_edges + s, 2 * j, 3u);
        if (!sb_w_any(sb_w_less(sb_w_set((sb_real)0.5), field), count)) break; /* nor in the next slots */
        if (j == 0 && !normal_ready) sb_fast_wing_normal(w, edge);
        collapsed |= sb_fast_carried_hinge(m, fr, t, w, field, j, s, count, mirrored, out);
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

/* What a block's kernel has on: the fused damping and hinges (`extras`
 * false compiles them out for the default terms, so that their state
 * costs no registers or stack stores there), and the break limits. */
typedef struct sb_fast_options {
    bool damping, hinges, limits;
} sb_fast_options;

static inline sb_fast_options sb_fast_options_of(const sb_fast_model* m, bool extras) {
    return (sb_fast_options){extras && m->fused_damping, extras && m->fused_hinges,
                             m->fused_bonds && m->tri_edge_near_max2[0]};
}

/* Triangle slot s's block, its positions in wing->p: adds the corners,
 * the owned bonds and the carried hinges to out (at sb_slot_of's slots),
 * its edges' unit vectors into *t and lengths into the wing; the wing's
 * normal too when `normal` (a pair's shared hinge needs it). Returns
 * SB_KERNEL_* flags. */
static inline __attribute__((always_inline)) int sb_fast_triangle(const sb_fast_model* m, const sb_fast_frame* fr,
                                                                  sb_fast_options o, bool normal, bool mirrored,
                                                                  uint32_t s, int count, sb_wwing* wing,
                                                                  sb_wtriangle* t, sb_wtriangle_out* out) {
    const sb_wide ratio = sb_w_set((sb_real)SB_COLLAPSE_RATIO), zero = sb_w_set(0);
    bool collapsed = false, near = false;
    sb_wfused fused;
    sb_wvec3 edge[3];
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++) {
        edge[c] = sb_wv_sub(wing->p[(c + 1) % 3], wing->p[c]);
        sb_wide rest = sb_w_load(m->tri_len0[c] + s), squared = sb_wv_dot(edge[c], edge[c]);
        t->inverse[c] = sb_w_rsqrt(squared);
        wing->length[c] = sb_w_mul(squared, t->inverse[c]);
        t->unit[c] = sb_wv_scale(edge[c], t->inverse[c]);
        t->strain[c] = sb_w_sub(wing->length[c], rest);
        fused.rest[c] = rest;
        collapsed |= sb_w_any(sb_w_less(wing->length[c], sb_w_mul(ratio, rest)), count);
        if (o.limits) near |= sb_near_limit(m->tri_edge_near_max2[c], m->tri_edge_near_min2[c], s, squared, count);
    }
    sb_wide ka = sb_w_constant(m->angle_k, s), ksb = sb_w_constant(m->stretch_bend_k, s);
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++) sb_fast_corner(t, c, sb_w_load(m->tri_cos0[c] + s), ka, ksb, mirrored, out);
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++) /* read only with damping */
        fused.velocity[c] = o.damping ? sb_wv_load4_at(fr->velocities4, m->tri_v[c] + s) : (sb_wvec3){zero, zero, zero};
    if (m->fused_bonds)
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) sb_fast_owned_bond(m, t, &fused, c, wing->length[c], s, o.damping, mirrored, out);
    if (normal) sb_fast_wing_normal(wing, edge);
    if (o.hinges) collapsed |= sb_fast_carried_hinges(m, fr, t, wing, edge, normal, s, count, mirrored, out);
    return (collapsed ? SB_KERNEL_COLLAPSED : 0) | (near ? SB_KERNEL_NEAR_LIMIT : 0);
}

/* The kernel's loop, one triangle a lane. */
static inline __attribute__((always_inline)) int sb_fast_corners_loop(const sb_fast_model* m, const sb_fast_frame* fr,
                                                                      uint32_t begin, uint32_t end, bool serial,
                                                                      double energy[5], bool extras) {
    uint32_t step = sb_block_step(serial);
    const sb_wide zero = sb_w_set(0);
    sb_wide sums[5] = {zero, zero, zero, zero, zero};
    sb_fast_options o = sb_fast_options_of(m, extras);
    int flags = 0;
    for (uint32_t s = begin; s < end; s += step) {
        int count = sb_block_count(s, end, step);
        sb_fast_corners_prefetch(m, s + SB_PREFETCH_SLOTS);
        sb_wwing wing;
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) wing.p[c] = sb_wv_load4_at(fr->positions4, m->tri_v[c] + s);
        sb_wtriangle t;
        sb_wtriangle_out out = sb_wtriangle_out_zero();
        flags |= sb_fast_triangle(m, fr, o, false, false, s, count, &wing, &t, &out);
#pragma GCC unroll 3
        for (int c = 0; c < 3; c++) sb_wv_add4_at(fr->forces4, m->tri_v[c] + s, out.force[c], count);
#pragma GCC unroll 5
        for (int e = 0; e < 5; e++) sums[e] = sb_w_add(sums[e], sb_w_keep(out.energy[e], count));
    }
    for (int e = 0; e < 5; e++) energy[e] += sb_w_sum(sums[e], SB_WIDTH);
    return flags;
}

int sb_fast_corners(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                    double energy[5]) {
    if (m->fused_damping || m->fused_hinges) return sb_fast_corners_loop(m, fr, begin, end, serial, energy, true);
    return sb_fast_corners_loop(m, fr, begin, end, serial, energy, false);
}

/* One block of pairs (sb_fast_model.paired): triangle A in slots s, B in
 * s + SB_WIDTH, B = (A1, A0, B2). Four gathers and four scatters; the
 * shared edge's hinge from the two wings' registers. */
static inline __attribute__((always_inline)) int sb_fast_pair(const sb_fast_model* m, const sb_fast_frame* fr,
                                                              sb_fast_options o, uint32_t s, int count,
                                                              sb_wide sums[5]) {
    uint32_t b = s + SB_WIDTH;
    sb_wwing wa, wb;
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++) wa.p[c] = sb_wv_load4_at(fr->positions4, m->tri_v[c] + s);
    wb.p[0] = wa.p[1];
    wb.p[1] = wa.p[0];
    wb.p[2] = sb_wv_load4_at(fr->positions4, m->tri_v[2] + b);
    sb_wtriangle ta, tb;
    sb_wtriangle_out out = sb_wtriangle_out_zero(); /* on A0, A1, A2, B2 */
    int flags = sb_fast_triangle(m, fr, o, true, false, s, count, &wa, &ta, &out);
    flags |= sb_fast_triangle(m, fr, o, false, true, b, count, &wb, &tb, &out);
    const sb_wvec3 p[4] = {wa.p[0], wa.p[1], wa.p[2], wb.p[2]};
    sb_wvec3 f[4];
    if (sb_fast_hinge_forces(&wa, p, ta.unit[0], wa.length[0], sb_w_constant(m->pair_k, s), sb_w_load(m->pair_phi0 + s),
                             count, f, &out.energy[4]))
        flags |= SB_KERNEL_COLLAPSED;
    sb_wv_add4_at(fr->forces4, m->tri_v[0] + s, sb_wv_add(out.force[0], f[0]), count);
    sb_wv_add4_at(fr->forces4, m->tri_v[1] + s, sb_wv_add(out.force[1], f[1]), count);
    sb_wv_add4_at(fr->forces4, m->tri_v[2] + s, sb_wv_add(out.force[2], f[2]), count);
    sb_wv_add4_at(fr->forces4, m->tri_v[2] + b, sb_wv_add(out.force[3], f[3]), count);
#pragma GCC unroll 5
    for (int e = 0; e < 5; e++) sums[e] = sb_w_add(sums[e], sb_w_keep(out.energy[e], count));
    return flags;
}

int sb_fast_pairs(const sb_fast_model* m, const sb_fast_frame* fr, uint32_t begin, uint32_t end, bool serial,
                  double energy[5]) {
    const sb_wide zero = sb_w_set(0);
    sb_wide sums[5] = {zero, zero, zero, zero, zero};
    sb_fast_options o = sb_fast_options_of(m, true);
    int flags = 0;
    for (uint32_t s = begin; s < end; s += 2 * SB_WIDTH) {
        int lanes = sb_block_count(s, end, SB_WIDTH);
        sb_fast_corners_prefetch(m, s + SB_PREFETCH_SLOTS);
        if (!serial)
            flags |= sb_fast_pair(m, fr, o, s, lanes, sums);
        else
            for (int l = 0; l < lanes; l++) flags |= sb_fast_pair(m, fr, o, s + (uint32_t)l, 1, sums);
    }
    for (int e = 0; e < 5; e++) energy[e] += sb_w_sum(sums[e], SB_WIDTH);
    return flags;
}
