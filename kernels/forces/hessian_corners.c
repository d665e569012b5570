/* A triangle's three corners (kernels/forces/hessian.h): angle bend and
 * stretch-bend, the formulas of kernels/forces/reference_corners.c, on dual numbers
 * and, for the stiffness matrix, in closed form. Corner c sits at local
 * vertex c with neighbours c + 1 and c + 2 (mod 3).
 *
 * Closed form: with a = x_j − x_i, b = x_k − x_i, c = â·b̂, S the stretch and
 * g, h as in reference_corners.c, the corner's Hessian in (a, b) is
 *   kθ ∇c ∇cᵀ + ksb (∇c ∇Sᵀ + ∇S ∇cᵀ) + g ∇²c + h ∇²S,
 * ∇_a c = (b̂ − c â)/A, ∇_a S = â, ∇²_aa S = (I − â âᵀ)/A,
 * ∇²_aa c = −(â b̂ᵀ + b̂ âᵀ + c I − 3 c â âᵀ)/A²,
 * ∇²_ab c = ((I − b̂ b̂ᵀ) − â (â − c b̂)ᵀ)/(A B), and b's alike; then
 * K_jj = H_aa, K_kk = H_bb, K_jk = H_ab, K_ij = −(H_aa + H_ba),
 * K_ik = −(H_ab + H_bb), K_ii = H_aa + H_ab + H_ba + H_bb. Tested against
 * differences of the reference forces and against the dual product. */
#include "kernels/forces/hessian_corners.h"
#include "kernels/forces/hessian.h"
#include "kernels/forces/reference_terms.h"

#include <string.h>

/* The triangle's angle and stretch-bend stiffnesses, 0 for a term turned
 * off; false when both are 0 (the corners add nothing). */
static bool sb_corner_stiffness(const sb_model* m, uint32_t t, double* k_angle, double* k_sb) {
    *k_angle = m->term_enabled[SB_TERM_ANGLE] ? m->angle_k[t] : 0.0;
    *k_sb = m->term_enabled[SB_TERM_STRETCH_BEND] ? m->stretch_bend_k[t] : 0.0;
    return *k_angle != 0.0 || *k_sb != 0.0;
}

/* Adds one corner's forces to f (local vertices i, j, k). */
static void sb_corner_dual(double k_angle, double k_sb, double cos0, double a0, double b0, const sb_dvec3* x, int i,
                           int j, int k, sb_dvec3* f, bool* collapsed) {
    sb_dvec3 a = sb_dv3_sub(x[j], x[i]), b = sb_dv3_sub(x[k], x[i]);
    sb_dual A = sb_dv3_length(a), B = sb_dv3_length(b);
    if (!(A.v >= SB_COLLAPSE_RATIO * a0) || !(B.v >= SB_COLLAPSE_RATIO * b0)) {
        *collapsed = true;
        return;
    }
    sb_dual inv_a = sb_d_div(sb_d_const(1.0), A), inv_b = sb_d_div(sb_d_const(1.0), B);
    sb_dvec3 ua = sb_dv3_scale(a, inv_a), ub = sb_dv3_scale(b, inv_b);
    sb_dual c = sb_dv3_dot(ua, ub), dc = sb_d_sub(c, sb_d_const(cos0));
    sb_dual S = sb_d_add(sb_d_sub(A, sb_d_const(a0)), sb_d_sub(B, sb_d_const(b0)));
    sb_dual g = sb_d_add(sb_d_scale(dc, k_angle), sb_d_scale(S, k_sb)), h = sb_d_scale(dc, k_sb);
    sb_dual minus_h = sb_d_scale(h, -1.0);
    sb_dvec3 fj = sb_dv3_add(sb_dv3_scale(sb_dv3_sub(ub, sb_dv3_scale(ua, c)), sb_d_scale(sb_d_mul(g, inv_a), -1.0)),
                             sb_dv3_scale(ua, minus_h));
    sb_dvec3 fk = sb_dv3_add(sb_dv3_scale(sb_dv3_sub(ua, sb_dv3_scale(ub, c)), sb_d_scale(sb_d_mul(g, inv_b), -1.0)),
                             sb_dv3_scale(ub, minus_h));
    f[j] = sb_dv3_add(f[j], fj);
    f[k] = sb_dv3_add(f[k], fk);
    f[i] = sb_dv3_sub(f[i], sb_dv3_add(fj, fk));
}

void sb_triangle_forces_dual(const sb_model* m, uint32_t t, const sb_dvec3* x, sb_dvec3* f, bool* collapsed) {
    double k_angle, k_sb;
    *collapsed = false;
    for (int c = 0; c < 3; c++) f[c] = (sb_dvec3){{0, 0, 0}, {0, 0, 0}};
    if (!sb_corner_stiffness(m, t, &k_angle, &k_sb)) return;
    for (int c = 0; c < 3; c++)
        sb_corner_dual(k_angle, k_sb, m->tri_cos0[c][t], m->tri_len0[c][t], m->tri_len0[(c + 2) % 3][t], x, c,
                       (c + 1) % 3, (c + 2) % 3, f, collapsed);
}

/* A corner at local vertex i (neighbours j, l): a = x_j − x_i, b = x_l − x_i,
 * their lengths and unit vectors, and c = â·b̂. */
typedef struct sb_corner_frame {
    sb_vec3 ua, ub;
    double A, B, c;
} sb_corner_frame;

static sb_corner_frame sb_corner_frame_at(const sb_vec3* x, int i, int j, int l) {
    sb_vec3 a = sb_v3_sub(x[j], x[i]), b = sb_v3_sub(x[l], x[i]);
    sb_corner_frame f = {.A = sb_v3_length(a), .B = sb_v3_length(b)};
    f.ua = sb_v3_scale(a, 1.0 / f.A), f.ub = sb_v3_scale(b, 1.0 / f.B);
    f.c = sb_v3_dot(f.ua, f.ub);
    return f;
}

/* One corner's λ w wᵀ (kernels/forces/hessian.h): λ, and w on i, j, l in parts. */
static double sb_corner_definite_parts(double k_angle, double k_sb, const sb_vec3* x, int i, int j, int l,
                                       sb_vec3* parts) {
    sb_corner_frame f = sb_corner_frame_at(x, i, j, l);
    sb_vec3 ua = f.ua, ub = f.ub;
    double A = f.A, B = f.B, c = f.c;
    double lambda = 0.5 * (k_angle + sqrt(k_angle * k_angle + 4.0 * k_sb * k_sb));
    double p = k_sb != 0.0 ? k_sb : 1.0, q = k_sb != 0.0 ? lambda - k_angle : 0.0, norm = sqrt(p * p + q * q);
    p /= norm, q /= norm;
    /* w on j and l: p ∇c + q ∇S; on i minus their sum */
    parts[1] = sb_v3_add(sb_v3_scale(sb_v3_sub(ub, sb_v3_scale(ua, c)), p / A), sb_v3_scale(ua, q));
    parts[2] = sb_v3_add(sb_v3_scale(sb_v3_sub(ua, sb_v3_scale(ub, c)), p / B), sb_v3_scale(ub, q));
    parts[0] = sb_v3_scale(sb_v3_add(parts[1], parts[2]), -1.0);
    return lambda;
}

/* One corner's λ w wᵀ added to the triangle's 9 × 9 k. */
static void sb_corner_definite(double k_angle, double k_sb, const sb_vec3* x, int i, int j, int l, double* k) {
    sb_vec3 parts[3];
    double lambda = sb_corner_definite_parts(k_angle, k_sb, x, i, j, l, parts), w[9];
    const int at[3] = {i, j, l};
    for (int v = 0; v < 3; v++) w[3 * at[v]] = parts[v].x, w[3 * at[v] + 1] = parts[v].y, w[3 * at[v] + 2] = parts[v].z;
    sb_add_outer(k, 9, w, lambda);
}

void sb_triangle_definite(const sb_model* m, uint32_t t, const sb_vec3* x, double* k) {
    double k_angle, k_sb;
    if (!sb_corner_stiffness(m, t, &k_angle, &k_sb)) return;
    for (int c = 0; c < 3; c++) sb_corner_definite(k_angle, k_sb, x, c, (c + 1) % 3, (c + 2) % 3, k);
}

/* out += s u vᵀ (3 × 3 row-major). */
static void sb_add_uv(double* out, sb_vec3 u, sb_vec3 v, double s) {
    const double uu[3] = {u.x, u.y, u.z}, vv[3] = {v.x, v.y, v.z};
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) out[3 * r + c] += s * uu[r] * vv[c];
}

static void sb_add_identity(double* out, double s) { out[0] += s, out[4] += s, out[8] += s; }

/* k (size × size) block (row, col) += s m, or s mᵀ. */
static void sb_add_block(double* k, int size, int row, int col, const double* m, bool transpose, double s) {
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            k[(3 * row + r) * size + 3 * col + c] += s * (transpose ? m[3 * c + r] : m[3 * r + c]);
}

/* A corner's Hessian in (a, b), blocks aa, ab, bb (H_ba = abᵀ), and its
 * forces on i, j, l. */
typedef struct sb_corner_hessian {
    double aa[9], ab[9], bb[9];
    sb_vec3 force[3]; /* on i, j, l */
} sb_corner_hessian;

/* A corner of triangle t at local vertex i (neighbours j, l): its frame and
 * stiffnesses, and g = ∂E/∂c, h = ∂E/∂S (reference_corners.c). */
typedef struct sb_corner {
    sb_corner_frame f;
    double k_angle, k_sb, g, h;
} sb_corner;

/* False when an edge collapsed. */
static bool sb_corner_at(const sb_model* m, uint32_t t, double k_angle, double k_sb, const sb_vec3* x, int i, int j,
                         int l, sb_corner* out) {
    double a0 = m->tri_len0[i][t], b0 = m->tri_len0[l][t];
    out->f = sb_corner_frame_at(x, i, j, l);
    if (!(out->f.A >= SB_COLLAPSE_RATIO * a0) || !(out->f.B >= SB_COLLAPSE_RATIO * b0)) return false;
    double dc = out->f.c - m->tri_cos0[i][t], S = (out->f.A - a0) + (out->f.B - b0);
    out->k_angle = k_angle, out->k_sb = k_sb;
    out->g = k_angle * dc + k_sb * S, out->h = k_sb * dc;
    return true;
}

static void sb_corner_hessian_at(const sb_corner* corner, sb_corner_hessian* out) {
    sb_vec3 ua = corner->f.ua, ub = corner->f.ub;
    double A = corner->f.A, B = corner->f.B, c = corner->f.c, g = corner->g, h = corner->h;
    double k_angle = corner->k_angle, k_sb = corner->k_sb;
    sb_vec3 ca = sb_v3_scale(sb_v3_sub(ub, sb_v3_scale(ua, c)), 1.0 / A);
    sb_vec3 cb = sb_v3_scale(sb_v3_sub(ua, sb_v3_scale(ub, c)), 1.0 / B);
    double *aa = out->aa, *ab = out->ab, *bb = out->bb;
    memset(out, 0, sizeof *out);
    /* kθ ∇c ∇cᵀ + ksb (∇c ∇Sᵀ + ∇S ∇cᵀ) */
    sb_add_uv(aa, ca, ca, k_angle), sb_add_uv(aa, ca, ua, k_sb), sb_add_uv(aa, ua, ca, k_sb);
    sb_add_uv(ab, ca, cb, k_angle), sb_add_uv(ab, ca, ub, k_sb), sb_add_uv(ab, ua, cb, k_sb);
    sb_add_uv(bb, cb, cb, k_angle), sb_add_uv(bb, cb, ub, k_sb), sb_add_uv(bb, ub, cb, k_sb);
    /* g ∇²c */
    double saa = -g / (A * A), sbb = -g / (B * B), sab = g / (A * B);
    sb_add_uv(aa, ua, ub, saa), sb_add_uv(aa, ub, ua, saa), sb_add_identity(aa, saa * c);
    sb_add_uv(aa, ua, ua, -3.0 * c * saa);
    sb_add_uv(bb, ub, ua, sbb), sb_add_uv(bb, ua, ub, sbb), sb_add_identity(bb, sbb * c);
    sb_add_uv(bb, ub, ub, -3.0 * c * sbb);
    sb_add_identity(ab, sab), sb_add_uv(ab, ub, ub, -sab), sb_add_uv(ab, ua, ua, -sab), sb_add_uv(ab, ua, ub, c * sab);
    /* h ∇²S */
    sb_add_identity(aa, h / A), sb_add_uv(aa, ua, ua, -h / A);
    sb_add_identity(bb, h / B), sb_add_uv(bb, ub, ub, -h / B);
    /* −∇E: F_j = −(g ∇_a c + h â), F_l = −(g ∇_b c + h b̂), F_i = −F_j − F_l */
    out->force[1] = sb_v3_scale(sb_v3_add(sb_v3_scale(ca, g), sb_v3_scale(ua, h)), -1.0);
    out->force[2] = sb_v3_scale(sb_v3_add(sb_v3_scale(cb, g), sb_v3_scale(ub, h)), -1.0);
    out->force[0] = sb_v3_scale(sb_v3_add(out->force[1], out->force[2]), -1.0);
}

/* The triangle's corners one by one; false when an edge collapsed. */
typedef void (*sb_corner_visit)(const sb_corner_hessian* h, int i, int j, int l, void* context);

static bool sb_triangle_corners(const sb_model* m, uint32_t t, const sb_vec3* x, sb_corner_visit visit, void* context) {
    double k_angle, k_sb;
    if (!sb_corner_stiffness(m, t, &k_angle, &k_sb)) return true;
    for (int c = 0; c < 3; c++) {
        sb_corner corner;
        sb_corner_hessian h;
        int j = (c + 1) % 3, l = (c + 2) % 3;
        if (!sb_corner_at(m, t, k_angle, k_sb, x, c, j, l, &corner)) return false;
        sb_corner_hessian_at(&corner, &h);
        visit(&h, c, j, l, context);
    }
    return true;
}

/* Adds a corner to the triangle's 9 × 9 k (a = x_j − x_i, b = x_l − x_i). */
static void sb_add_corner_matrix(const sb_corner_hessian* h, int i, int j, int l, void* context) {
    double* k = context;
    const double *aa = h->aa, *ab = h->ab, *bb = h->bb;
    sb_add_block(k, 9, j, j, aa, false, 1.0), sb_add_block(k, 9, l, l, bb, false, 1.0);
    sb_add_block(k, 9, j, l, ab, false, 1.0), sb_add_block(k, 9, l, j, ab, true, 1.0);
    sb_add_block(k, 9, i, j, aa, false, -1.0), sb_add_block(k, 9, i, j, ab, true, -1.0);
    sb_add_block(k, 9, j, i, aa, false, -1.0), sb_add_block(k, 9, j, i, ab, false, -1.0);
    sb_add_block(k, 9, i, l, ab, false, -1.0), sb_add_block(k, 9, i, l, bb, false, -1.0);
    sb_add_block(k, 9, l, i, ab, true, -1.0), sb_add_block(k, 9, l, i, bb, false, -1.0);
    sb_add_block(k, 9, i, i, aa, false, 1.0), sb_add_block(k, 9, i, i, bb, false, 1.0);
    sb_add_block(k, 9, i, i, ab, false, 1.0), sb_add_block(k, 9, i, i, ab, true, 1.0);
}

bool sb_triangle_stiffness(const sb_model* m, uint32_t t, const sb_vec3* x, double* k) {
    memset(k, 0, 81 * sizeof *k);
    return sb_triangle_corners(m, t, x, sb_add_corner_matrix, k);
}

/* M = α I + U C Uᵀ with U = [â b̂] (3 × 2) and C = [[c11, c12], [c21, c22]]
 * (row-major 3 × 3). */
static void sb_expand_in_plane(double alpha, const double* cc, sb_vec3 ua, sb_vec3 ub, double* out) {
    const double a[3] = {ua.x, ua.y, ua.z}, b[3] = {ub.x, ub.y, ub.z};
    for (int r = 0; r < 3; r++) {
        double left_a = cc[0] * a[r] + cc[2] * b[r], left_b = cc[1] * a[r] + cc[3] * b[r];
        for (int c = 0; c < 3; c++) out[3 * r + c] = left_a * a[c] + left_b * b[c];
        out[4 * r] += alpha;
    }
}

/* The corner at local vertex i (neighbours j, l) added to the triangle's
 * nine blocks (block-major, block (r, c) at 9 (3 r + c)), times scale:
 * sb_corner_hessian_at's matrices, each a multiple of I plus a form in the
 * plane of â and b̂ (∇c, ∇S and the second derivatives all lie there), so
 * that each is a 2 × 2 matrix C in that basis, expanded once. */
static void sb_corner_blocks(const sb_corner* corner, int i, int j, int l, double scale, double* blocks) {
    sb_vec3 ua = corner->f.ua, ub = corner->f.ub;
    double A = corner->f.A, B = corner->f.B, c = corner->f.c, g = corner->g, h = corner->h;
    double k_angle = corner->k_angle, k_sb = corner->k_sb;
    /* ∇_a c = p1 â + p2 b̂, ∇_b c = q1 â + q2 b̂ */
    double p1 = -c / A, p2 = 1.0 / A, q1 = 1.0 / B, q2 = -c / B;
    double saa = -g / (A * A), sbb = -g / (B * B), sab = g / (A * B);
    const double caa[4] = {k_angle * p1 * p1 + 2.0 * k_sb * p1 - 3.0 * c * saa - h / A,
                           k_angle * p1 * p2 + k_sb * p2 + saa, k_angle * p2 * p1 + k_sb * p2 + saa, k_angle * p2 * p2};
    const double cab[4] = {k_angle * p1 * q1 + k_sb * q1 - sab, k_angle * p1 * q2 + k_sb * (p1 + q2) + c * sab,
                           k_angle * p2 * q1, k_angle * p2 * q2 + k_sb * p2 - sab};
    const double cbb[4] = {k_angle * q1 * q1, k_angle * q1 * q2 + k_sb * q1 + sbb, k_angle * q2 * q1 + k_sb * q1 + sbb,
                           k_angle * q2 * q2 + 2.0 * k_sb * q2 - 3.0 * c * sbb - h / B};
    double aa[9], ab[9], bb[9];
    double s_aa[4], s_ab[4], s_bb[4];
    for (int k = 0; k < 4; k++) s_aa[k] = scale * caa[k], s_ab[k] = scale * cab[k], s_bb[k] = scale * cbb[k];
    sb_expand_in_plane(scale * (saa * c + h / A), s_aa, ua, ub, aa);
    sb_expand_in_plane(scale * sab, s_ab, ua, ub, ab);
    sb_expand_in_plane(scale * (sbb * c + h / B), s_bb, ua, ub, bb);
    double *jj = blocks + 9 * (3 * j + j), *ll = blocks + 9 * (3 * l + l), *ii = blocks + 9 * (3 * i + i);
    double *jl = blocks + 9 * (3 * j + l), *lj = blocks + 9 * (3 * l + j);
    double *ij = blocks + 9 * (3 * i + j), *ji = blocks + 9 * (3 * j + i);
    double *il = blocks + 9 * (3 * i + l), *li = blocks + 9 * (3 * l + i);
    /* K_jj = H_aa, K_ll = H_bb, K_jl = H_ab, K_lj = H_ba = H_abᵀ, K_ij = −(H_aa + H_ba),
     * K_ji = −(H_aa + H_ab), K_il = −(H_ab + H_bb), K_li = −(H_ba + H_bb), K_ii the sum of all four */
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            int k = 3 * r + c;
            double haa = aa[k], hbb = bb[k], hab = ab[k], hba = ab[3 * c + r];
            jj[k] += haa, ll[k] += hbb, jl[k] += hab, lj[k] += hba;
            ij[k] -= haa + hba, ji[k] -= haa + hab, il[k] -= hab + hbb, li[k] -= hba + hbb;
            ii[k] += (haa + hab) + (hba + hbb);
        }
}

bool sb_triangle_stiffness_blocks(const sb_model* m, uint32_t t, const sb_vec3* x, double scale, double* blocks) {
    memset(blocks, 0, 81 * sizeof *blocks);
    double k_angle, k_sb;
    if (!sb_corner_stiffness(m, t, &k_angle, &k_sb)) return true;
    for (int c = 0; c < 3; c++) {
        sb_corner corner;
        int j = (c + 1) % 3, l = (c + 2) % 3;
        if (!sb_corner_at(m, t, k_angle, k_sb, x, c, j, l, &corner)) return false;
        sb_corner_blocks(&corner, c, j, l, scale, blocks);
    }
    return true;
}

/* One vertex's share: its force and diagonal block. */
typedef struct sb_vertex_share {
    int place;
    double* f;
    double* block;
} sb_vertex_share;

/* The corner's force on the share's vertex only (the definite share's block
 * comes from sb_corner_definite_parts). */
static void sb_add_corner_force(const sb_corner_hessian* h, int i, int j, int l, void* context) {
    sb_vertex_share* share = context;
    sb_vec3 force = h->force[share->place == i ? 0 : share->place == j ? 1 : 2];
    share->f[0] += force.x, share->f[1] += force.y, share->f[2] += force.z;
    (void)l;
}

bool sb_triangle_vertex_share(const sb_model* m, uint32_t t, const sb_vec3* x, int place, double* f, double* block) {
    sb_vertex_share share = {place, f, block};
    if (!sb_triangle_corners(m, t, x, sb_add_corner_force, &share)) return false;
    double k_angle, k_sb;
    if (!sb_corner_stiffness(m, t, &k_angle, &k_sb)) return true;
    for (int c = 0; c < 3; c++) {
        sb_vec3 parts[3];
        int j = (c + 1) % 3, l = (c + 2) % 3;
        double lambda = sb_corner_definite_parts(k_angle, k_sb, x, c, j, l, parts);
        sb_vec3 w = parts[place == c ? 0 : place == j ? 1 : 2];
        sb_add_uv(block, w, w, lambda);
    }
    return true;
}
