/* One co-rotated linear tetrahedron: see corotated.h. */
#include "kernels/forces/corotated.h"

#include <math.h>

/* Eigenvectors (columns of v) and eigenvalues of the symmetric a, by cyclic
 * Jacobi rotations; a is destroyed. */
static void sb_jacobi3(double a[3][3], double v[3][3], double w[3]) {
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) v[r][c] = r == c ? 1.0 : 0.0;
    for (int sweep = 0; sweep < 16; sweep++) {
        double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        double diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (!(off > 1e-32 * diag)) break;
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                if (a[p][q] == 0.0) continue;
                double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                double t = (theta >= 0.0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
                for (int k = 0; k < 3; k++) { /* a = Jᵀ a J */
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; k++) {
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; k++) {
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                }
            }
    }
    for (int k = 0; k < 3; k++) w[k] = a[k][k];
}

static void sb_normalize(double u[3]) {
    double l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int k = 0; k < 3; k++) u[k] /= l;
}

static void sb_cross(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* A unit vector perpendicular to the unit u. */
static void sb_perpendicular(const double u[3], double out[3]) {
    double axis[3] = {0.0, 0.0, 0.0};
    int k = fabs(u[0]) <= fabs(u[1]) ? (fabs(u[0]) <= fabs(u[2]) ? 0 : 2) : (fabs(u[1]) <= fabs(u[2]) ? 1 : 2);
    axis[k] = 1.0;
    sb_cross(u, axis, out);
    sb_normalize(out);
}

void sb_corotated_rotation(const double F[9], double R[9]) {
    double c[3][3], v[3][3], w[3];
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) c[r][k] = F[r] * F[k] + F[3 + r] * F[3 + k] + F[6 + r] * F[6 + k];
    sb_jacobi3(c, v, w);
    int order[3] = {0, 1, 2}; /* eigenvalues descending */
    for (int a = 0; a < 3; a++)
        for (int b = a + 1; b < 3; b++)
            if (w[order[b]] > w[order[a]]) {
                int s = order[a];
                order[a] = order[b];
                order[b] = s;
            }
    double vs[3][3]; /* vs[k] = k-th right singular vector */
    for (int k = 0; k < 3; k++)
        for (int r = 0; r < 3; r++) vs[k][r] = v[r][order[k]];
    sb_cross(vs[0], vs[1], vs[2]); /* V a rotation */
    double u[3][3];
    for (int k = 0; k < 2; k++)
        for (int r = 0; r < 3; r++) u[k][r] = F[3 * r] * vs[k][0] + F[3 * r + 1] * vs[k][1] + F[3 * r + 2] * vs[k][2];
    double l0 = sqrt(u[0][0] * u[0][0] + u[0][1] * u[0][1] + u[0][2] * u[0][2]);
    if (l0 > 0.0) {
        for (int r = 0; r < 3; r++) u[0][r] /= l0;
    } else {
        u[0][0] = 1.0, u[0][1] = 0.0, u[0][2] = 0.0;
    }
    double d = u[1][0] * u[0][0] + u[1][1] * u[0][1] + u[1][2] * u[0][2];
    for (int r = 0; r < 3; r++) u[1][r] -= d * u[0][r];
    double l1 = sqrt(u[1][0] * u[1][0] + u[1][1] * u[1][1] + u[1][2] * u[1][2]);
    if (l1 > 1e-12 * (l0 > 0.0 ? l0 : 1.0)) {
        for (int r = 0; r < 3; r++) u[1][r] /= l1;
    } else {
        sb_perpendicular(u[0], u[1]);
    }
    sb_cross(u[0], u[1], u[2]);
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) R[3 * r + k] = u[0][r] * vs[0][k] + u[1][r] * vs[1][k] + u[2][r] * vs[2][k];
}

/* F = D_s D_m⁻¹ of the corners p (or their velocities: Ḟ); false when not
 * finite. */
static bool sb_deformation(const double p[4][3], const double dm_inv[9], double F[9]) {
    bool finite = true;
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) {
            double s = 0.0;
            for (int c = 0; c < 3; c++) s += (p[c + 1][r] - p[0][r]) * dm_inv[3 * c + k];
            F[3 * r + k] = s;
            finite &= isfinite(s) != 0;
        }
    return finite;
}

/* f_{c+1} = −scale X g_{c+1} (g_{c+1} row c of D_m⁻¹), f_0 = −Σ: the
 * corners' forces of the first Piola-Kirchhoff stress X; written, or added
 * when `add`. */
static void sb_stress_forces(const double X[9], const double dm_inv[9], double scale, bool add, double f[4][3]) {
    for (int r = 0; r < 3; r++) {
        double sum = 0.0;
        for (int c = 0; c < 3; c++) {
            double h = 0.0;
            for (int k = 0; k < 3; k++) h += X[3 * r + k] * dm_inv[3 * c + k];
            h *= -scale;
            f[c + 1][r] = add ? f[c + 1][r] + h : h;
            sum += h;
        }
        f[0][r] = add ? f[0][r] - sum : -sum;
    }
}

/* The elastic forces −V P D_m⁻ᵀ and the energy V Ψ at F = R S. */
static void sb_corotated_elastic(const double F[9], const double R[9], const double dm_inv[9], double volume, double mu,
                                 double lambda, double f[4][3], double* energy) {
    double trace = 0.0, norm = 0.0;
    for (int k = 0; k < 9; k++) {
        trace += R[k] * F[k];
        norm += (F[k] - R[k]) * (F[k] - R[k]);
    }
    double t = trace - 3.0;
    *energy = volume * (mu * norm + 0.5 * lambda * t * t);
    double P[9];
    for (int k = 0; k < 9; k++) P[k] = 2.0 * mu * (F[k] - R[k]) + lambda * t * R[k];
    sb_stress_forces(P, dm_inv, volume, false, f);
}

/* (R K0 Rᵀ v)_a = V (μ (L + Lᵀ) + λ tr(L) I) R g_a with L = Ḟ Rᵀ
 * (kernels/forces/hessian_tets.c's blocks summed against v): the damping
 * force −β R K0 Rᵀ v is that of a Kelvin–Voigt viscous stress of the
 * rotated strain rate, shear viscosity β μ and β λ on the volume rate;
 * added to f. */
static void sb_corotated_viscous(const double Fdot[9], const double R[9], const double dm_inv[9], double volume,
                                 double mu, double lambda, double beta, double f[4][3]) {
    double L[9], trace = 0.0;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            L[3 * i + j] = Fdot[3 * i] * R[3 * j] + Fdot[3 * i + 1] * R[3 * j + 1] + Fdot[3 * i + 2] * R[3 * j + 2];
        trace += L[4 * i];
    }
    double stress[9]; /* σ R: the stress pulled back to the rest frame's gradients */
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) {
            double s = 0.0;
            for (int j = 0; j < 3; j++)
                s += (mu * (L[3 * i + j] + L[3 * j + i]) + (i == j ? lambda * trace : 0.0)) * R[3 * j + k];
            stress[3 * i + k] = s;
        }
    sb_stress_forces(stress, dm_inv, beta * volume, true, f);
}

bool sb_corotated_tet(const double p[4][3], const double dm_inv[9], double volume, double mu, double lambda,
                      double f[4][3], double* energy) {
    double F[9], R[9];
    if (!sb_deformation(p, dm_inv, F)) return false;
    sb_corotated_rotation(F, R);
    sb_corotated_elastic(F, R, dm_inv, volume, mu, lambda, f, energy);
    return true;
}

bool sb_corotated_tet_damped(const double p[4][3], const double v[4][3], const double dm_inv[9], double volume,
                             double mu, double lambda, double beta, double f[4][3], double* energy) {
    double F[9], R[9], Fdot[9];
    if (!sb_deformation(p, dm_inv, F) || !sb_deformation(v, dm_inv, Fdot)) return false;
    sb_corotated_rotation(F, R);
    sb_corotated_elastic(F, R, dm_inv, volume, mu, lambda, f, energy);
    sb_corotated_viscous(Fdot, R, dm_inv, volume, mu, lambda, beta, f);
    return true;
}

bool sb_corotated_stiffness(const double p[4][3], const double dm_inv[9], double volume, double mu, double lambda,
                            double k[144]) {
    double F[9], R[9];
    if (!sb_deformation(p, dm_inv, F)) return false;
    sb_corotated_rotation(F, R);
    double g[4][3], rg[4][3]; /* the shape functions' gradients, and turned by R */
    for (int q = 0; q < 3; q++) {
        g[0][q] = 0.0;
        for (int c = 0; c < 3; c++) {
            g[c + 1][q] = dm_inv[3 * c + q];
            g[0][q] -= dm_inv[3 * c + q];
        }
    }
    for (int a = 0; a < 4; a++)
        for (int r = 0; r < 3; r++) rg[a][r] = R[3 * r] * g[a][0] + R[3 * r + 1] * g[a][1] + R[3 * r + 2] * g[a][2];
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++) {
            double gg = g[a][0] * g[b][0] + g[a][1] * g[b][1] + g[a][2] * g[b][2];
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    k[(3 * a + i) * 12 + 3 * b + j] =
                        volume * (mu * ((i == j ? gg : 0.0) + rg[b][i] * rg[a][j]) + lambda * rg[a][i] * rg[b][j]);
        }
    for (int q = 0; q < 144; q++)
        if (!isfinite(k[q])) return false;
    return true;
}
