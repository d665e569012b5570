/* One co-rotated quadratic tetrahedron: see corotated_quadratic.h. */
#include "kernels/forces/corotated_quadratic.h"
#include "kernels/forces/corotated.h"

#include <math.h>
#include <stddef.h>

static const int sb_quad_edges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

/* The four-point rule, exact to degree 2: barycentric (a, b, b, b) and its
 * permutations, weight ¼ each. */
#define SB_GAUSS_A 0.58541019662496845446
#define SB_GAUSS_B 0.13819660112501051518

/* The linear element's gradients g[4][3] from D_m⁻¹ (row c of D_m⁻¹ is
 * g_{c+1}, g_0 = −Σ g_{c+1}). */
static void sb_linear_gradients(const double dm_inv[9], double g[4][3]) {
    for (int q = 0; q < 3; q++) {
        g[0][q] = 0.0;
        for (int c = 0; c < 3; c++) {
            g[c + 1][q] = dm_inv[3 * c + q];
            g[0][q] -= dm_inv[3 * c + q];
        }
    }
}

/* The ten shape functions' gradients at Gauss point `point`. */
static void sb_quad_gradients(const double g[4][3], int point, double G[SB_QUAD_NODES][3]) {
    double L[4];
    for (int i = 0; i < 4; i++) L[i] = i == point ? SB_GAUSS_A : SB_GAUSS_B;
    for (int i = 0; i < 4; i++)
        for (int q = 0; q < 3; q++) G[i][q] = (4.0 * L[i] - 1.0) * g[i][q];
    for (int e = 0; e < 6; e++) {
        int i = sb_quad_edges[e][0], j = sb_quad_edges[e][1];
        for (int q = 0; q < 3; q++) G[4 + e][q] = 4.0 * (L[i] * g[j][q] + L[j] * g[i][q]);
    }
}

/* F of the corners and R of it; false when F is not finite. */
static bool sb_quad_rotation(const double p[SB_QUAD_NODES][3], const double dm_inv[9], double R[9]) {
    double F[9];
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) {
            double s = 0.0;
            for (int c = 0; c < 3; c++) s += (p[c + 1][r] - p[0][r]) * dm_inv[3 * c + k];
            F[3 * r + k] = s;
        }
    for (int k = 0; k < 9; k++)
        if (!isfinite(F[k])) return false;
    sb_corotated_rotation(F, R);
    return true;
}

/* D_m = (D_m⁻¹)⁻¹, row-major. */
static void sb_invert3(const double a[9], double out[9]) {
    double det =
        a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) + a[2] * (a[3] * a[7] - a[4] * a[6]);
    out[0] = (a[4] * a[8] - a[5] * a[7]) / det;
    out[1] = (a[2] * a[7] - a[1] * a[8]) / det;
    out[2] = (a[1] * a[5] - a[2] * a[4]) / det;
    out[3] = (a[5] * a[6] - a[3] * a[8]) / det;
    out[4] = (a[0] * a[8] - a[2] * a[6]) / det;
    out[5] = (a[2] * a[3] - a[0] * a[5]) / det;
    out[6] = (a[3] * a[7] - a[4] * a[6]) / det;
    out[7] = (a[1] * a[6] - a[0] * a[7]) / det;
    out[8] = (a[0] * a[4] - a[1] * a[3]) / det;
}

/* u'_a = Rᵀ(x_a − x_0) − (X_a − X_0), X_a − X_0 = D_m ξ_a (ξ: the node's
 * place in the reference element, a middle halfway between its corners). */
static void sb_quad_unrotated(const double p[SB_QUAD_NODES][3], const double dm_inv[9], const double R[9],
                              double u[SB_QUAD_NODES][3]) {
    double dm[9], xi[SB_QUAD_NODES][3] = {{0.0}};
    sb_invert3(dm_inv, dm);
    for (int c = 0; c < 3; c++) xi[c + 1][c] = 1.0;
    for (int e = 0; e < 6; e++)
        for (int q = 0; q < 3; q++) xi[4 + e][q] = 0.5 * (xi[sb_quad_edges[e][0]][q] + xi[sb_quad_edges[e][1]][q]);
    for (int a = 0; a < SB_QUAD_NODES; a++) {
        double d[3] = {p[a][0] - p[0][0], p[a][1] - p[0][1], p[a][2] - p[0][2]};
        for (int r = 0; r < 3; r++)
            u[a][r] = R[r] * d[0] + R[3 + r] * d[1] + R[6 + r] * d[2] -
                      (dm[3 * r] * xi[a][0] + dm[3 * r + 1] * xi[a][1] + dm[3 * r + 2] * xi[a][2]);
    }
}

/* Adds −K0 u to fr (u, fr in the element's unrotated frame): at each Gauss
 * point the strain ε of u, the stress σ = 2μ ε + λ tr(ε) I, and
 * fr_a −= w V σ ∇N_a; returns ½ uᵀ K0 u. */
static double sb_quad_k0_apply(const double g[4][3], double volume, double mu, double lambda,
                               const double u[SB_QUAD_NODES][3], double fr[SB_QUAD_NODES][3]) {
    double w = 0.25 * volume, e = 0.0;
    for (int point = 0; point < 4; point++) {
        double G[SB_QUAD_NODES][3], H[3][3] = {{0.0}}, eps[3][3], sigma[3][3];
        sb_quad_gradients(g, point, G);
        for (int a = 0; a < SB_QUAD_NODES; a++)
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++) H[r][c] += u[a][r] * G[a][c];
        double trace = H[0][0] + H[1][1] + H[2][2], norm = 0.0;
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                eps[r][c] = 0.5 * (H[r][c] + H[c][r]);
                norm += eps[r][c] * eps[r][c];
            }
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) sigma[r][c] = 2.0 * mu * eps[r][c] + (r == c ? lambda * trace : 0.0);
        e += w * (mu * norm + 0.5 * lambda * trace * trace);
        for (int a = 0; a < SB_QUAD_NODES; a++)
            for (int r = 0; r < 3; r++)
                fr[a][r] -= w * (sigma[r][0] * G[a][0] + sigma[r][1] * G[a][1] + sigma[r][2] * G[a][2]);
    }
    return e;
}

/* The forces −R K0 (Rᵀx − X) − β R K0 Rᵀ v (v NULL: no damping). */
static bool sb_quad_forces(const double p[SB_QUAD_NODES][3], const double v[SB_QUAD_NODES][3], const double dm_inv[9],
                           double volume, double mu, double lambda, double beta, double f[SB_QUAD_NODES][3],
                           double* energy) {
    double R[9], g[4][3], u[SB_QUAD_NODES][3], fr[SB_QUAD_NODES][3] = {{0.0}};
    if (!sb_quad_rotation(p, dm_inv, R)) return false;
    sb_linear_gradients(dm_inv, g);
    sb_quad_unrotated(p, dm_inv, R, u);
    double e = sb_quad_k0_apply(g, volume, mu, lambda, u, fr);
    if (v) {
        double rate[SB_QUAD_NODES][3]; /* β Rᵀ v */
        for (int a = 0; a < SB_QUAD_NODES; a++)
            for (int r = 0; r < 3; r++) rate[a][r] = beta * (R[r] * v[a][0] + R[3 + r] * v[a][1] + R[6 + r] * v[a][2]);
        sb_quad_k0_apply(g, volume, mu, lambda, rate, fr);
    }
    bool finite = isfinite(e) != 0;
    for (int a = 0; a < SB_QUAD_NODES; a++)
        for (int r = 0; r < 3; r++) {
            f[a][r] = R[3 * r] * fr[a][0] + R[3 * r + 1] * fr[a][1] + R[3 * r + 2] * fr[a][2];
            finite &= isfinite(f[a][r]) != 0;
        }
    *energy = e;
    return finite;
}

bool sb_corotated_quadratic_tet(const double p[SB_QUAD_NODES][3], const double dm_inv[9], double volume, double mu,
                                double lambda, double f[SB_QUAD_NODES][3], double* energy) {
    return sb_quad_forces(p, NULL, dm_inv, volume, mu, lambda, 0.0, f, energy);
}

bool sb_corotated_quadratic_tet_damped(const double p[SB_QUAD_NODES][3], const double v[SB_QUAD_NODES][3],
                                       const double dm_inv[9], double volume, double mu, double lambda, double beta,
                                       double f[SB_QUAD_NODES][3], double* energy) {
    return sb_quad_forces(p, v, dm_inv, volume, mu, lambda, beta, f, energy);
}

bool sb_corotated_quadratic_stiffness(const double p[SB_QUAD_NODES][3], const double dm_inv[9], double volume,
                                      double mu, double lambda, double k[SB_QUAD_DOFS * SB_QUAD_DOFS]) {
    double R[9], g[4][3];
    if (!sb_quad_rotation(p, dm_inv, R)) return false;
    sb_linear_gradients(dm_inv, g);
    for (int q = 0; q < SB_QUAD_DOFS * SB_QUAD_DOFS; q++) k[q] = 0.0;
    double w = 0.25 * volume;
    for (int point = 0; point < 4; point++) {
        double G[SB_QUAD_NODES][3], rg[SB_QUAD_NODES][3]; /* the gradients, and turned by R */
        sb_quad_gradients(g, point, G);
        for (int a = 0; a < SB_QUAD_NODES; a++)
            for (int r = 0; r < 3; r++) rg[a][r] = R[3 * r] * G[a][0] + R[3 * r + 1] * G[a][1] + R[3 * r + 2] * G[a][2];
        for (int a = 0; a < SB_QUAD_NODES; a++)
            for (int b = 0; b < SB_QUAD_NODES; b++) {
                double gg = G[a][0] * G[b][0] + G[a][1] * G[b][1] + G[a][2] * G[b][2];
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++)
                        k[(3 * a + i) * SB_QUAD_DOFS + 3 * b + j] +=
                            w * (mu * ((i == j ? gg : 0.0) + rg[b][i] * rg[a][j]) + lambda * rg[a][i] * rg[b][j]);
            }
    }
    for (int q = 0; q < SB_QUAD_DOFS * SB_QUAD_DOFS; q++)
        if (!isfinite(k[q])) return false;
    return true;
}
