/* A hinge (kernels/forces/hessian.h): E = ½ k (φ − φ0)², the gradient of
 * kernels/forces/reference_hinges.c; local vertices e0, e1, o0, o1.
 *
 * On dual numbers for the stiffness matrix and its products: the dihedral
 * angle's derivative is ∇φ · ẋ with ∇φ = −u (the gradient the reference
 * derives), so atan2 runs on values only.
 *
 * In closed form for vbd's vertex share and the definite stand-in: the
 * Gauss-Newton block k ∇φ ∇φᵀ. The exact Hessian adds k (φ − φ0) ∇²φ,
 * indefinite and as large as the first term once the fold is a few degrees
 * from rest; vbd needs only a descent direction per vertex, the paper
 * itself approximates, and the share costs one evaluation of u where the
 * exact diagonal block took three dual runs (nearly half of vbd's step:
 * bench/results/notes/vbd.md). */
#include "kernels/forces/hessian_hinges.h"
#include "kernels/forces/hessian.h"
#include "common/geometry.h"

/* φ and u = −∇φ on each local vertex (e0, e1, o0, o1), on dual numbers;
 * false when a wing collapsed. */
static bool sb_hinge_angle_dual(const sb_dvec3* x, sb_dual* phi, sb_dvec3* u) {
    sb_dvec3 e0 = x[0], e1 = x[1], o0 = x[2], o1 = x[3];
    sb_dvec3 edge = sb_dv3_sub(e1, e0);
    sb_dvec3 n0 = sb_dv3_cross(sb_dv3_sub(o0, e0), sb_dv3_sub(o0, e1));
    sb_dvec3 n1 = sb_dv3_cross(sb_dv3_sub(o1, e1), sb_dv3_sub(o1, e0));
    sb_dual length = sb_dv3_length(edge), n0_sq = sb_dv3_dot(n0, n0), n1_sq = sb_dv3_dot(n1, n1);
    double limit = SB_MIN_WING_RATIO * length.v * length.v;
    if (!(length.v > 0.0) || !(n0_sq.v > limit * limit) || !(n1_sq.v > limit * limit)) return false;
    sb_dual inv_length = sb_d_div(sb_d_const(1.0), length);
    sb_dvec3 w0 = sb_dv3_scale(n0, sb_d_div(sb_d_const(1.0), n0_sq));
    sb_dvec3 w1 = sb_dv3_scale(n1, sb_d_div(sb_d_const(1.0), n1_sq));
    sb_dvec3 unit_edge = sb_dv3_scale(edge, inv_length);
    u[0] = sb_dv3_add(sb_dv3_scale(w0, sb_dv3_dot(sb_dv3_sub(o0, e1), unit_edge)),
                      sb_dv3_scale(w1, sb_dv3_dot(sb_dv3_sub(o1, e1), unit_edge)));
    u[1] = sb_dv3_add(sb_dv3_scale(w0, sb_d_scale(sb_dv3_dot(sb_dv3_sub(o0, e0), unit_edge), -1.0)),
                      sb_dv3_scale(w1, sb_d_scale(sb_dv3_dot(sb_dv3_sub(o1, e0), unit_edge), -1.0)));
    u[2] = sb_dv3_scale(w0, length);
    u[3] = sb_dv3_scale(w1, length);
    /* φ's value by atan2; its derivative is ∇φ · ẋ = −Σ u · ẋ, no dual atan2 */
    double sine = sb_v3_dot(sb_v3_cross(n0.v, n1.v), edge.v) / length.v;
    *phi = sb_d(atan2(sine, sb_v3_dot(n0.v, n1.v)), 0.0);
    for (int a = 0; a < 4; a++) phi->d -= sb_v3_dot(u[a].v, x[a].d);
    return true;
}

static double sb_hinge_stiffness(const sb_model* m, uint32_t h) {
    return m->term_enabled[SB_TERM_BEND] ? m->hinge_k[h] : 0.0;
}

void sb_hinge_forces_dual(const sb_model* m, uint32_t h, const sb_dvec3* x, sb_dvec3* f, bool* collapsed) {
    double k = sb_hinge_stiffness(m, h);
    sb_dual phi;
    sb_dvec3 u[4];
    *collapsed = !sb_hinge_angle_dual(x, &phi, u);
    if (*collapsed) return;
    /* the wrap of sb_angle_difference moves the value by 2π, not the slope */
    double delta = sb_angle_difference(phi.v, m->hinge_phi0[h]);
    sb_dual magnitude = sb_d(k * delta, k * phi.d);
    for (int a = 0; a < 4; a++) f[a] = sb_dv3_scale(u[a], magnitude);
}

void sb_hinge_definite(const sb_model* m, uint32_t h, const sb_vec3* x, double* k) {
    sb_vec3 u[4];
    if (!sb_hinge_gradient(x, NULL, u)) {
        k[0] = NAN;
        return;
    }
    double w[12];
    for (int a = 0; a < 4; a++) w[3 * a] = u[a].x, w[3 * a + 1] = u[a].y, w[3 * a + 2] = u[a].z;
    sb_add_outer(k, 12, w, sb_hinge_stiffness(m, h));
}

bool sb_hinge_definite_blocks(const sb_model* m, uint32_t h, const sb_vec3* x, double scale, double* blocks) {
    sb_vec3 u[4];
    if (!sb_hinge_gradient(x, NULL, u)) return false;
    double k = scale * sb_hinge_stiffness(m, h), w[12], kw[12];
    for (int a = 0; a < 4; a++) w[3 * a] = u[a].x, w[3 * a + 1] = u[a].y, w[3 * a + 2] = u[a].z;
    for (int r = 0; r < 12; r++) {
        if (!isfinite(w[r])) return false;
        kw[r] = k * w[r];
    }
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            double* block = blocks + 9 * (4 * r + c);
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++) block[3 * a + b] = kw[3 * r + a] * w[3 * c + b];
        }
    return true;
}

bool sb_hinge_vertex_share(const sb_model* m, uint32_t h, const sb_vec3* x, int place, double* f, double* block) {
    sb_vec3 u[4];
    double phi;
    if (!sb_hinge_gradient(x, &phi, u)) return false;
    double k = sb_hinge_stiffness(m, h), magnitude = k * sb_angle_difference(phi, m->hinge_phi0[h]);
    const double w[3] = {u[place].x, u[place].y, u[place].z};
    for (int r = 0; r < 3; r++) {
        f[r] += magnitude * w[r];
        for (int c = 0; c < 3; c++) block[3 * r + c] += k * w[r] * w[c];
    }
    return true;
}
