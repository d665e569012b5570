/* A sheet membrane's stiffness: the co-rotated K of
 * kernels/forces/membrane.c (symmetric, positive semi-definite, the
 * energy's exact Hessian at rest and at any rotation of it, R's derivative
 * left out under strain), and the helpers that serve any element whose
 * stiffness is one such matrix to kernels/forces/hessian.c's functions. */
#include "kernels/forces/hessian_membranes.h"
#include "kernels/forces/membrane.h"

bool sb_membrane_element_stiffness(const sb_model* m, uint32_t t, const sb_vec3* x, double* f, double* k) {
    double p[3][3], dm_inv[4], forces[3][3], energy;
    for (int c = 0; c < 3; c++) {
        p[c][0] = x[c].x;
        p[c][1] = x[c].y;
        p[c][2] = x[c].z;
    }
    for (int q = 0; q < 4; q++) dm_inv[q] = m->membrane_dm_inv[q][t];
    double volume = m->membrane_volume[t], mu = m->membrane_mu[t], lambda = m->membrane_lambda[t];
    if (f) {
        if (!sb_membrane_triangle(p, dm_inv, volume, mu, lambda, forces, &energy)) return false;
        for (int c = 0; c < 3; c++)
            for (int q = 0; q < 3; q++) f[3 * c + q] = forces[c][q];
    }
    return !k || sb_membrane_stiffness(p, dm_inv, volume, mu, lambda, k);
}

void sb_matrix_forces_dual(int count, const double* forces, const double* k, const sb_dvec3* x, sb_dvec3* f) {
    int size = 3 * count;
    for (int a = 0; a < count; a++) {
        double d[3];
        for (int i = 0; i < 3; i++) {
            double s = 0.0;
            for (int b = 0; b < count; b++) {
                const double* row = k + (3 * a + i) * size + 3 * b;
                s -= row[0] * x[b].d.x + row[1] * x[b].d.y + row[2] * x[b].d.z;
            }
            d[i] = s;
        }
        f[a].v = (sb_vec3){forces[3 * a], forces[3 * a + 1], forces[3 * a + 2]};
        f[a].d = (sb_vec3){d[0], d[1], d[2]};
    }
}

void sb_matrix_vertex_share(int count, const double* forces, const double* k, int place, double* f, double* block) {
    int size = 3 * count;
    for (int i = 0; i < 3; i++) {
        f[i] += forces[3 * place + i];
        for (int j = 0; j < 3; j++) block[3 * i + j] += k[(3 * place + i) * size + 3 * place + j];
    }
}

void sb_matrix_blocks(int count, const double* k, double scale, double* blocks) {
    int size = 3 * count;
    for (int r = 0; r < count; r++)
        for (int c = 0; c < count; c++)
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++)
                    blocks[9 * (count * r + c) + 3 * a + b] = scale * k[(3 * r + a) * size + 3 * c + b];
}
