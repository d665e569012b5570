/* Private: the fast kernels' second derivatives, for implicit
 * Euler on the fast kernels (kernels/integrators/implicit_fast.c): what the
 * families share. Each family's passes are declared in its own header
 * (kernels/forces/fast_hessian_bonds.h, _corners.h, _hinges.h, and
 * _corner_blocks.h for the triangles' closed form).
 *
 * Design. Each term family's force formula is run on wide dual numbers
 * (common/dual.h's scalar duals, one SIMD lane per element): seeded with
 * positions x + ε p it gives, in the derivative parts, ∂f/∂x · p exactly
 * (to rounding). One function per family (kernels/fast_hessian_*.c) thus
 * serves both passes, with a different seed:
 *   product:  out += scale (K p + damping D p), p packed x y z w like the
 *             positions (one seed per element);
 *   diagonal: each vertex's 3 × 3 block of K + damping D (seeds: the three
 *             axes of each of the element's vertices but the last, whose
 *             block the others give), the block-Jacobi preconditioner's.
 * Hand-derived closed forms would be a second copy of every term's
 * derivative to keep true; a product on duals costs about 1.4 force passes
 * (the gathers and scatters, which bound those, are the same). The one
 * closed form is the triangles' diagonal blocks
 * (kernels/forces/fast_hessian_corner_blocks.c): six dual runs a triangle cost
 * five times as much, and its tests hold it against the reference's
 * element matrices as they do the duals. The passes run over the fast
 * model's blocked coloring like the force kernels (kernels/forces/fast_model.h):
 * deterministic for any thread count, no atomics.
 *
 * K is the exact Hessian of the elastic energy, as kernels/forces/hessian.h's
 * (indefinite where a bond is compressed, a corner loaded, a hinge bent);
 * D = d u uᵀ per damped spring, exact; the damped spring's dependence on x
 * through its direction is left out as there. */
#ifndef SB_FAST_HESSIAN_H
#define SB_FAST_HESSIAN_H

#include "kernels/forces/fast_kernels.h"
#include "kernels/forces/fast_block.h"

/* A vertex's diagonal block is symmetric: its upper triangle is kept,
 * SB_BLOCK_SIZE numbers xx xy xz yy yz zz, in SB_BLOCK_STRIDE reals as two
 * packed vectors xx xy xz 0, yy yz zz 0 (the kernels' packed scatter adds
 * them; the array is aligned like the positions). */
enum { SB_BLOCK_SIZE = 6, SB_BLOCK_STRIDE = 8 };
static const int sb_block_offset[SB_BLOCK_SIZE] = {0, 1, 2, 4, 5, 6};

/* What the passes read and write. They have the force kernels' signature
 * (sb_fast_kernel, kernels/forces/fast_kernels.h) and receive this frame's first
 * member: `base` holds the positions, the direction p (velocities4's place;
 * NULL for the diagonal pass) and out (forces4's place). */
typedef struct sb_hessian_frame {
    sb_fast_frame base;
    sb_real scale;   /* out += scale (K p + damping D p), and the blocks alike */
    sb_real damping; /* D's weight against K's (1 / dt in J = M + dt D + dt² K) */
    sb_real* blocks; /* diagonal pass: SB_BLOCK_STRIDE per vertex, added to */
} sb_hessian_frame;

/* ---- wide dual numbers ------------------------------------------------- */

typedef struct sb_wdual {
    sb_wide v, d;
} sb_wdual;

typedef struct sb_wdvec3 {
    sb_wvec3 v, d;
} sb_wdvec3;

static inline sb_wdual sb_wd_add(sb_wdual a, sb_wdual b) { return (sb_wdual){sb_w_add(a.v, b.v), sb_w_add(a.d, b.d)}; }
static inline sb_wdual sb_wd_sub(sb_wdual a, sb_wdual b) { return (sb_wdual){sb_w_sub(a.v, b.v), sb_w_sub(a.d, b.d)}; }
static inline sb_wdual sb_wd_mul(sb_wdual a, sb_wdual b) {
    return (sb_wdual){sb_w_mul(a.v, b.v), sb_w_add(sb_w_mul(a.d, b.v), sb_w_mul(a.v, b.d))};
}
static inline sb_wdual sb_wd_scale(sb_wdual a, sb_wide s) { return (sb_wdual){sb_w_mul(a.v, s), sb_w_mul(a.d, s)}; }
/* 1 / a */
static inline sb_wdual sb_wd_inverse(sb_wdual a) {
    sb_wide inv = sb_w_div(sb_w_set(1), a.v);
    return (sb_wdual){inv, sb_w_mul(sb_w_sub(sb_w_set(0), a.d), sb_w_mul(inv, inv))};
}
/* 1 / √a */
static inline sb_wdual sb_wd_rsqrt(sb_wdual a) {
    sb_wide r = sb_w_rsqrt(a.v);
    return (sb_wdual){r, sb_w_mul(sb_w_mul(sb_w_set((sb_real)-0.5), a.d), sb_w_mul(r, sb_w_mul(r, r)))};
}
static inline sb_wdvec3 sb_wdv_add(sb_wdvec3 a, sb_wdvec3 b) {
    return (sb_wdvec3){sb_wv_add(a.v, b.v), sb_wv_add(a.d, b.d)};
}
static inline sb_wdvec3 sb_wdv_sub(sb_wdvec3 a, sb_wdvec3 b) {
    return (sb_wdvec3){sb_wv_sub(a.v, b.v), sb_wv_sub(a.d, b.d)};
}
static inline sb_wdvec3 sb_wdv_scale(sb_wdvec3 a, sb_wdual s) {
    return (sb_wdvec3){sb_wv_scale(a.v, s.v), sb_wv_add(sb_wv_scale(a.d, s.v), sb_wv_scale(a.v, s.d))};
}
static inline sb_wdual sb_wdv_dot(sb_wdvec3 a, sb_wdvec3 b) {
    return (sb_wdual){sb_wv_dot(a.v, b.v), sb_w_add(sb_wv_dot(a.d, b.v), sb_wv_dot(a.v, b.d))};
}
static inline sb_wdvec3 sb_wdv_cross(sb_wdvec3 a, sb_wdvec3 b) {
    return (sb_wdvec3){sb_wv_cross(a.v, b.v), sb_wv_add(sb_wv_cross(a.d, b.v), sb_wv_cross(a.v, b.d))};
}
static inline sb_wdvec3 sb_wdv_neg(sb_wdvec3 a) { return (sb_wdvec3){sb_wv_neg(a.v), sb_wv_neg(a.d)}; }

/* The edge force of a bond of stiffness k and rest length r0 at the dual
 * positions a → b, with its damping c: the force on a (−it on b). The bond
 * pass's and the fused bonds' (kernels/forces/fast_hessian_corners.c). */
static inline sb_wdvec3 sb_wdual_bond_force(sb_wdvec3 a, sb_wdvec3 b, sb_wide k, sb_wide r0, sb_wide c,
                                            sb_wide damping) {
    sb_wdvec3 delta = sb_wdv_sub(b, a);
    sb_wdual squared = sb_wdv_dot(delta, delta), inv_r = sb_wd_rsqrt(squared);
    sb_wdual r = sb_wd_mul(squared, inv_r);
    sb_wdvec3 u = sb_wdv_scale(delta, inv_r);
    sb_wdual magnitude = {sb_w_mul(k, sb_w_sub(r.v, r0)), sb_w_mul(k, r.d)};
    sb_wdvec3 f = sb_wdv_scale(u, magnitude);
    sb_wide closing = sb_w_mul(sb_w_mul(c, damping), sb_wv_dot(delta.d, u.v)); /* c (Δẋ·u), weighted */
    f.d = sb_wv_add(f.d, sb_wv_scale(u.v, closing));
    return f;
}

/* ---- the two passes, shared by the families ----------------------------- */

/* A family's forces at the dual positions x[0..vertices) of the block at
 * slot s: f's derivative parts ∂f/∂x · ẋ − damping D ẋ (the damping force's
 * derivative in the velocities, seeded with the same ẋ); values as the
 * force kernel's. */
typedef void (*sb_wdual_forces)(const sb_fast_model* m, uint32_t s, sb_wide damping, const sb_wdvec3* x, sb_wdvec3* f);

enum { SB_HESSIAN_MAX_VERTICES = 4 };

/* Adds lane l's block (upper[0..SB_BLOCK_SIZE), scaled) to the block of
 * its vertex, for the first count lanes (they never share one). */
static inline void sb_hessian_add_blocks(sb_real* blocks, sb_windex index, const sb_wide* upper, sb_real scale,
                                         int count) {
    uint32_t id[SB_WIDTH];
    memcpy(id, &index, sizeof id);
    for (int l = 0; l < SB_WIDTH; l++) id[l] *= SB_BLOCK_STRIDE / 4; /* in packed vectors */
    sb_windex packed = sb_w_index(id);
    const sb_wide w = sb_w_set(scale);
    sb_wv_add4(blocks, packed, (sb_wvec3){sb_w_mul(w, upper[0]), sb_w_mul(w, upper[1]), sb_w_mul(w, upper[2])}, count);
    sb_wv_add4(blocks + 4, packed, (sb_wvec3){sb_w_mul(w, upper[3]), sb_w_mul(w, upper[4]), sb_w_mul(w, upper[5])},
               count);
}

/* The upper triangle of the block whose columns are col[0..3). */
static inline void sb_hessian_add_columns(sb_real* blocks, sb_windex index, const sb_wvec3* col, sb_real scale,
                                          int count) {
    const sb_wide upper[SB_BLOCK_SIZE] = {col[0].x, col[1].x, col[2].x, col[1].y, col[2].y, col[2].z};
    sb_hessian_add_blocks(blocks, index, upper, scale, count);
}

/* Runs `forces` over the color's slots [begin, end): the product pass when
 * the frame has a direction, else the diagonal pass. vertex[a] are the
 * family's index arrays. */
static inline void sb_hessian_pass(const sb_fast_model* m, const sb_fast_frame* base, uint32_t begin, uint32_t end,
                                   bool serial, int vertices, uint32_t* const* vertex, sb_wdual_forces forces) {
    const sb_hessian_frame* fr = (const sb_hessian_frame*)base;
    const sb_wide zero = sb_w_set(0), damping = sb_w_set(fr->damping), minus_scale = sb_w_set(-fr->scale);
    uint32_t step = sb_block_step(serial);
    for (uint32_t s = begin; s < end; s += step) {
        int count = sb_block_count(s, end, step);
        sb_windex v[SB_HESSIAN_MAX_VERTICES];
        sb_wdvec3 x[SB_HESSIAN_MAX_VERTICES], f[SB_HESSIAN_MAX_VERTICES];
        for (int a = 0; a < vertices; a++) {
            v[a] = sb_w_index(vertex[a] + s);
            x[a].v = sb_wv_load4(base->positions4, v[a]);
            x[a].d = base->velocities4 ? sb_wv_load4(base->velocities4, v[a]) : (sb_wvec3){zero, zero, zero};
        }
        if (base->velocities4) { /* out += scale (K p + damping D p) = −scale f' */
            forces(m, s, damping, x, f);
            for (int a = 0; a < vertices; a++) sb_wv_add4(base->forces4, v[a], sb_wv_scale(f[a].d, minus_scale), count);
            continue;
        }
        /* K_aa's columns, seeding each axis of vertex a, but the last
         * vertex's: an element's forces depend on differences of positions
         * only, so each block row of K sums to zero and
         * K_LL = −Σ_{b<L} K_Lb, whose columns the other seeds give in f[L] */
        const int last = vertices - 1;
        sb_wvec3 col[3], last_col[3];
        for (int axis = 0; axis < 3; axis++) last_col[axis] = (sb_wvec3){zero, zero, zero};
        for (int a = 0; a < last; a++) {
            for (int axis = 0; axis < 3; axis++) {
                sb_wide* seed = axis == 0 ? &x[a].d.x : axis == 1 ? &x[a].d.y : &x[a].d.z;
                *seed = sb_w_set(1);
                forces(m, s, damping, x, f);
                *seed = zero;
                col[axis] = f[a].d;
                last_col[axis] = sb_wv_sub(last_col[axis], f[last].d);
            }
            sb_hessian_add_columns(fr->blocks, v[a], col, -fr->scale, count);
        }
        sb_hessian_add_columns(fr->blocks, v[last], last_col, -fr->scale, count);
    }
}

#endif
