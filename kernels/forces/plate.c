/* A flat sheet's plate bending (mesh/sheet_factory.c says why this form).
 * With u = x − rest and h_ij = Σ_a c_ij[a] u_a (3-vectors, ij = 11, 12,
 * 22), a plate's energy is
 *     E = ½ [a (|h11|² + |h22|² + 2 |h12|²) + b |h11 + h22|²],
 * a quadratic form of u: its forces −∂E/∂u_a =
 * −[a (c11[a] h11 + c22[a] h22 + 2 c12[a] h12) + b (c11[a] + c22[a])(h11 + h22)]
 * and its Hessian H ⊗ I₃ with
 *     H_ab = a (c11[a] c11[b] + c22[a] c22[b] + 2 c12[a] c12[b]) + b s[a] s[b],
 * s = c11 + c22, the same at every x. The stencils annihilate constant and
 * linear fields, so that E is zero at the rest shape and after any rigid
 * motion or uniform stretch of it; u rather than x keeps the sums free of
 * the positions' offsets. */
#include "kernels/forces/plate.h"

#include <string.h>

/* Stencil coefficient ij of vertex a of plate t. */
static double sb_plate_c(const sb_model* m, uint32_t t, int ij, int a) {
    return m->plate_c[SB_PLATE_NODES * (3 * (size_t)t + (size_t)ij) + (size_t)a];
}

double sb_plate_element(const sb_model* m, uint32_t t, const sb_vec3* x, double* f, double* k) {
    int count = m->plate_nodes[t];
    double weight_a = m->plate_a[t], weight_b = m->plate_b[t];
    sb_vec3 h[3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
    for (int a = 0; a < count; a++) {
        uint32_t v = m->plate_v[SB_PLATE_NODES * (size_t)t + (size_t)a];
        sb_vec3 u = {x[a].x - m->rest_x[v], x[a].y - m->rest_y[v], x[a].z - m->rest_z[v]};
        for (int ij = 0; ij < 3; ij++) h[ij] = sb_v3_add(h[ij], sb_v3_scale(u, sb_plate_c(m, t, ij, a)));
    }
    sb_vec3 trace = sb_v3_add(h[0], h[2]);
    for (int a = 0; f && a < count; a++) {
        double c11 = sb_plate_c(m, t, 0, a), c12 = sb_plate_c(m, t, 1, a), c22 = sb_plate_c(m, t, 2, a);
        sb_vec3 g = sb_v3_add(sb_v3_scale(sb_v3_add(sb_v3_add(sb_v3_scale(h[0], c11), sb_v3_scale(h[2], c22)),
                                                    sb_v3_scale(h[1], 2.0 * c12)),
                                          weight_a),
                              sb_v3_scale(trace, weight_b * (c11 + c22)));
        f[3 * a] = -g.x, f[3 * a + 1] = -g.y, f[3 * a + 2] = -g.z;
    }
    if (k) {
        int size = 3 * count;
        memset(k, 0, (size_t)size * (size_t)size * sizeof *k);
        for (int a = 0; a < count; a++)
            for (int b = 0; b < count; b++) {
                double hab = weight_a * (sb_plate_c(m, t, 0, a) * sb_plate_c(m, t, 0, b) +
                                         sb_plate_c(m, t, 2, a) * sb_plate_c(m, t, 2, b) +
                                         2.0 * sb_plate_c(m, t, 1, a) * sb_plate_c(m, t, 1, b)) +
                             weight_b * (sb_plate_c(m, t, 0, a) + sb_plate_c(m, t, 2, a)) *
                                 (sb_plate_c(m, t, 0, b) + sb_plate_c(m, t, 2, b));
                for (int i = 0; i < 3; i++) k[(3 * a + i) * size + 3 * b + i] = hab;
            }
    }
    return 0.5 * (weight_a * (sb_v3_dot(h[0], h[0]) + sb_v3_dot(h[2], h[2]) + 2.0 * sb_v3_dot(h[1], h[1])) +
                  weight_b * sb_v3_dot(trace, trace));
}

double sb_reference_plates(const sb_model* m, const double* x, double* f) {
    double total = 0.0;
    for (uint32_t t = 0; t < m->plate_count; t++) {
        int count = m->plate_nodes[t];
        sb_vec3 local[SB_PLATE_NODES];
        double g[3 * SB_PLATE_NODES];
        for (int a = 0; a < count; a++) local[a] = sb_v3(x + 3 * (size_t)m->plate_v[SB_PLATE_NODES * (size_t)t + a]);
        total += sb_plate_element(m, t, local, g, NULL);
        for (int a = 0; a < count; a++)
            for (int i = 0; i < 3; i++) f[3 * (size_t)m->plate_v[SB_PLATE_NODES * (size_t)t + a] + i] += g[3 * a + i];
    }
    return total;
}
