/* sb_builder_compile's part for the membranes: each checked (indices, E ≥ 0,
 * ν in (−1, ½), thickness > 0, Rayleigh's β ≥ 0, a proper triangle), then laid out with its
 * rest edges in the triangle's own plane and the plane-stress constants
 * μ = E / 2(1 + ν), λ = E ν / (1 − ν²) (kernels/forces/membrane.c). */
#include "mesh/builder_internal.h"
#include "mesh/model_internal.h"
#include "common/error.h"
#include "common/geometry.h"

#include <math.h>
#include <stdlib.h>

/* The rest triangle's edges x1 − x0, x2 − x0 and its area. */
static double sb_rest_edges(const sb_builder* b, const uint32_t v[3], sb_vec3* e1, sb_vec3* e2) {
    const sb_vertex_def* vertex = SB_ITEMS(b->vertices, sb_vertex_def);
    sb_vec3 p0 = sb_v3(vertex[v[0]].position);
    *e1 = sb_v3_sub(sb_v3(vertex[v[1]].position), p0);
    *e2 = sb_v3_sub(sb_v3(vertex[v[2]].position), p0);
    return 0.5 * sb_v3_length(sb_v3_cross(*e1, *e2));
}

static sb_status sb_check_membrane(const sb_builder* b, size_t index, sb_error* err) {
    const sb_membrane_def* d = SB_ITEMS(b->membranes, sb_membrane_def) + index;
    uint32_t n = (uint32_t)b->vertices.count;
    for (int a = 0; a < 3; a++) {
        if (d->v[a] >= n)
            return sb_error_set(err, SB_ERR_INVALID, "membrane %zu: vertex index %u out of range (%u vertices)", index,
                                d->v[a], n);
        if (d->v[a] == d->v[(a + 1) % 3])
            return sb_error_set(err, SB_ERR_INVALID, "membrane %zu: vertex %u repeated", index, d->v[a]);
    }
    if (!isfinite(d->young_modulus) || d->young_modulus < 0.0 || !(d->poisson_ratio > -1.0) ||
        !(d->poisson_ratio < 0.5) || !isfinite(d->thickness) || !(d->thickness > 0.0) ||
        !isfinite(d->stiffness_damping) || d->stiffness_damping < 0.0)
        return sb_error_set(err, SB_ERR_INVALID,
                            "membrane %zu: Young's modulus and stiffness damping must be finite and >= 0, Poisson's "
                            "ratio in (-1, 0.5), the thickness finite and > 0",
                            index);
    sb_vec3 e1, e2;
    double area = sb_rest_edges(b, d->v, &e1, &e2);
    double longest = fmax(sb_v3_dot(e1, e1), fmax(sb_v3_dot(e2, e2), sb_v3_dot(sb_v3_sub(e2, e1), sb_v3_sub(e2, e1))));
    if (!(area > 1e-12 * longest))
        return sb_error_set(err, SB_ERR_INVALID, "membrane %zu (%u, %u, %u): zero area", index, d->v[0], d->v[1],
                            d->v[2]);
    return SB_OK;
}

sb_status sb_check_membranes(const sb_builder* b, sb_error* err) {
    sb_status status = SB_OK;
    for (size_t i = 0; i < b->membranes.count && status == SB_OK; i++) status = sb_check_membrane(b, i, err);
    return status;
}

static void* sb_membrane_array(size_t count, size_t size, bool* ok) {
    void* p = calloc(count ? count : 1, size);
    if (!p) *ok = false;
    return p;
}

/* D_m⁻¹ of the rest edges in the frame u = e1/|e1|, w ⟂ u in the plane:
 * D_m = [[|e1|, e2·u], [0, e2·w]]. */
static void sb_rest_inverse(sb_vec3 e1, sb_vec3 e2, double area, double inv[4]) {
    double l1 = sb_v3_length(e1), along = sb_v3_dot(e2, e1) / l1, across = 2.0 * area / l1;
    double det = l1 * across;
    inv[0] = across / det, inv[1] = -along / det;
    inv[2] = 0.0, inv[3] = l1 / det;
}

bool sb_fill_membranes(sb_model* m, const sb_builder* b) {
    size_t count = b->membranes.count;
    bool ok = true;
    m->membrane_count = (uint32_t)count;
    for (int c = 0; c < 3; c++) m->membrane_v[c] = sb_membrane_array(count, sizeof(uint32_t), &ok);
    for (int c = 0; c < 4; c++) m->membrane_dm_inv[c] = sb_membrane_array(count, sizeof(double), &ok);
    m->membrane_volume = sb_membrane_array(count, sizeof(double), &ok);
    m->membrane_mu = sb_membrane_array(count, sizeof(double), &ok);
    m->membrane_lambda = sb_membrane_array(count, sizeof(double), &ok);
    m->membrane_beta = sb_membrane_array(count, sizeof(double), &ok);
    if (!ok) return false;
    const sb_membrane_def* d = SB_ITEMS(b->membranes, sb_membrane_def);
    for (size_t t = 0; t < count; t++) {
        sb_vec3 e1, e2;
        double area = sb_rest_edges(b, d[t].v, &e1, &e2), inv[4];
        sb_rest_inverse(e1, e2, area, inv);
        for (int c = 0; c < 3; c++) m->membrane_v[c][t] = d[t].v[c];
        for (int c = 0; c < 4; c++) m->membrane_dm_inv[c][t] = inv[c];
        m->membrane_volume[t] = area * d[t].thickness;
        double e = d[t].young_modulus, nu = d[t].poisson_ratio;
        m->membrane_mu[t] = e / (2.0 * (1.0 + nu));
        m->membrane_lambda[t] = e * nu / (1.0 - nu * nu);
        m->membrane_beta[t] = d[t].stiffness_damping;
        m->membrane_damped |= e > 0.0 && d[t].stiffness_damping > 0.0;
        m->term_enabled[SB_TERM_MEMBRANE] |= d[t].young_modulus > 0.0;
    }
    return true;
}
