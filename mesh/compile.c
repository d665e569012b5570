/* sb_builder_compile: validate every element, then lay the model out as
 * structure-of-arrays with its rest values. Validation runs completely
 * before anything is allocated for the model, and reports the first bad
 * element by kind and index. */
#include "mesh/builder_internal.h"
#include "mesh/model_internal.h"
#include "common/error.h"
#include "common/geometry.h"
#include "mesh/sort_key.h"

#include <math.h>
#include <string.h>
#include <stdlib.h>

/* A triangle whose area is below this fraction of its longest edge squared
 * is degenerate: its corner angles are then meaningless. */
#define SB_MIN_AREA_RATIO 1e-12

static bool sb_constant_ok(double k) { return isfinite(k) && k >= 0.0; }

static sb_status sb_check_vertices(const sb_builder* b, sb_error* err) {
    const sb_vertex_def* v = SB_ITEMS(b->vertices, sb_vertex_def);
    for (size_t i = 0; i < b->vertices.count; i++) {
        if (!sb_finite3(v[i].position) || !sb_finite3(v[i].velocity) || !isfinite(v[i].mass))
            return sb_error_set(err, SB_ERR_INVALID, "vertex %zu: non-finite position, velocity or mass", i);
        if (v[i].mass < 0.0 || (!v[i].fixed && v[i].mass == 0.0))
            return sb_error_set(err, SB_ERR_INVALID, "vertex %zu: mass %g kg (a free vertex needs a positive mass)", i,
                                v[i].mass);
    }
    return SB_OK;
}

static double sb_distance(const sb_builder* b, uint32_t i, uint32_t j) {
    const sb_vertex_def* v = SB_ITEMS(b->vertices, sb_vertex_def);
    return sb_v3_length(sb_v3_sub(sb_v3(v[i].position), sb_v3(v[j].position)));
}

/* The maximum break length: 0 means never, like +inf. */
static double sb_break_max(const sb_bond_def* d) { return d->break_max == 0.0 ? INFINITY : d->break_max; }

static sb_status sb_check_break_limits(const sb_bond_def* d, size_t index, double r0, sb_error* err) {
    double lo = d->break_min, hi = sb_break_max(d);
    if (isnan(lo) || isnan(hi) || lo < 0.0 || hi < 0.0 || isinf(lo))
        return sb_error_set(
            err, SB_ERR_INVALID,
            "bond %zu (%u, %u): break lengths must be >= 0 (min finite, max finite or +inf; got %g, %g)", index, d->i,
            d->j, d->break_min, d->break_max);
    if (!(lo < r0 && r0 < hi))
        return sb_error_set(err, SB_ERR_INVALID,
                            "bond %zu (%u, %u): rest length %g m is not between the break lengths %g and %g m", index,
                            d->i, d->j, r0, lo, hi);
    return SB_OK;
}

static sb_status sb_check_bond(const sb_builder* b, size_t index, sb_error* err) {
    const sb_bond_def* d = SB_ITEMS(b->bonds, sb_bond_def) + index;
    uint32_t n = (uint32_t)b->vertices.count;
    if (d->i >= n || d->j >= n)
        return sb_error_set(err, SB_ERR_INVALID, "bond %zu: vertex index %u out of range (%u vertices)", index,
                            d->i >= n ? d->i : d->j, n);
    if (d->i == d->j) return sb_error_set(err, SB_ERR_INVALID, "bond %zu: joins vertex %u to itself", index, d->i);
    if (!sb_constant_ok(d->k) || !sb_constant_ok(d->spring_k) || !sb_constant_ok(d->spring_damping))
        return sb_error_set(err, SB_ERR_INVALID, "bond %zu: constants must be finite and >= 0", index);
    double r0 = d->rest_length < 0.0 ? sb_distance(b, d->i, d->j) : d->rest_length;
    if (!isfinite(r0) || r0 <= 0.0)
        return sb_error_set(err, SB_ERR_INVALID, "bond %zu (%u, %u): rest length %g m must be positive", index, d->i,
                            d->j, r0);
    return sb_check_break_limits(d, index, r0, err);
}

/* Duplicates are rejected, never merged: which constants should win is
 * the caller's decision, not ours. */
static sb_status sb_check_duplicate_bonds(const sb_builder* b, sb_error* err) {
    size_t count = b->bonds.count;
    if (count < 2) return SB_OK;
    sb_sort_key* keys = malloc(count * sizeof *keys);
    if (!keys) return sb_error_set(err, SB_ERR_NOMEM, "out of memory checking %zu bonds", count);
    const sb_bond_def* d = SB_ITEMS(b->bonds, sb_bond_def);
    for (size_t i = 0; i < count; i++) {
        uint64_t lo = d[i].i < d[i].j ? d[i].i : d[i].j, hi = d[i].i ^ d[i].j ^ lo;
        keys[i] = (sb_sort_key){lo << 32 | hi, (uint32_t)i};
    }
    qsort(keys, count, sizeof *keys, sb_sort_key_compare);
    sb_status status = SB_OK;
    for (size_t i = 1; i < count && status == SB_OK; i++)
        if (keys[i].key == keys[i - 1].key)
            status = sb_error_set(err, SB_ERR_INVALID, "bond %u: duplicates bond %u (vertices %u and %u)",
                                  keys[i].index, keys[i - 1].index, d[keys[i].index].i, d[keys[i].index].j);
    free(keys);
    return status;
}

/* Twice the area of (i, j, k) against its longest edge: false if degenerate. */
static bool sb_triangle_proper(const sb_builder* b, uint32_t i, uint32_t j, uint32_t k) {
    const sb_vertex_def* v = SB_ITEMS(b->vertices, sb_vertex_def);
    sb_vec3 a = sb_v3_sub(sb_v3(v[j].position), sb_v3(v[i].position));
    sb_vec3 c = sb_v3_sub(sb_v3(v[k].position), sb_v3(v[i].position));
    sb_vec3 e = sb_v3_sub(sb_v3(v[k].position), sb_v3(v[j].position));
    double longest = fmax(sb_v3_dot(a, a), fmax(sb_v3_dot(c, c), sb_v3_dot(e, e)));
    return sb_v3_length(sb_v3_cross(a, c)) > SB_MIN_AREA_RATIO * longest && longest > 0.0;
}

static sb_status sb_check_indices(const char* kind, size_t index, const uint32_t* ids, int count, uint32_t n,
                                  sb_error* err) {
    for (int a = 0; a < count; a++) {
        if (ids[a] >= n)
            return sb_error_set(err, SB_ERR_INVALID, "%s %zu: vertex index %u out of range (%u vertices)", kind, index,
                                ids[a], n);
        for (int c = 0; c < a; c++)
            if (ids[a] == ids[c])
                return sb_error_set(err, SB_ERR_INVALID, "%s %zu: vertex %u repeated", kind, index, ids[a]);
    }
    return SB_OK;
}

static sb_status sb_check_triangle(const sb_builder* b, size_t index, sb_error* err) {
    const sb_triangle_def* t = SB_ITEMS(b->triangles, sb_triangle_def) + index;
    uint32_t ids[3] = {t->i, t->j, t->k};
    sb_status status = sb_check_indices("triangle", index, ids, 3, (uint32_t)b->vertices.count, err);
    if (status != SB_OK) return status;
    if (!sb_constant_ok(t->angle_k) || !sb_constant_ok(t->stretch_bend_k))
        return sb_error_set(err, SB_ERR_INVALID, "triangle %zu: constants must be finite and >= 0", index);
    if (!sb_triangle_proper(b, t->i, t->j, t->k))
        return sb_error_set(err, SB_ERR_INVALID, "triangle %zu (%u, %u, %u): zero area", index, t->i, t->j, t->k);
    return SB_OK;
}

static sb_status sb_check_hinge(const sb_builder* b, size_t index, sb_error* err) {
    const sb_hinge_def* h = SB_ITEMS(b->hinges, sb_hinge_def) + index;
    uint32_t ids[4] = {h->e0, h->e1, h->o0, h->o1};
    sb_status status = sb_check_indices("hinge", index, ids, 4, (uint32_t)b->vertices.count, err);
    if (status != SB_OK) return status;
    if (!sb_constant_ok(h->k))
        return sb_error_set(err, SB_ERR_INVALID, "hinge %zu: constant must be finite and >= 0", index);
    if (!sb_triangle_proper(b, h->e0, h->e1, h->o0) || !sb_triangle_proper(b, h->e1, h->e0, h->o1))
        return sb_error_set(err, SB_ERR_INVALID, "hinge %zu (edge %u-%u): a wing has zero area", index, h->e0, h->e1);
    return SB_OK;
}

/* Signed volume of a tetrahedron of builder vertices, and its longest edge. */
static double sb_tet_signed_volume(const sb_builder* b, const uint32_t* ids, double* longest) {
    const sb_vertex_def* v = SB_ITEMS(b->vertices, sb_vertex_def);
    sb_vec3 p0 = sb_v3(v[ids[0]].position);
    sb_vec3 e[3];
    for (int c = 0; c < 3; c++) e[c] = sb_v3_sub(sb_v3(v[ids[c + 1]].position), p0);
    *longest = 0.0;
    for (int a = 0; a < 4; a++)
        for (int c = a + 1; c < 4; c++)
            *longest = fmax(*longest, sb_v3_length(sb_v3_sub(sb_v3(v[ids[a]].position), sb_v3(v[ids[c]].position))));
    return sb_v3_dot(e[0], sb_v3_cross(e[1], e[2])) / 6.0;
}

static sb_status sb_check_tet(const sb_builder* b, size_t index, sb_error* err) {
    const sb_tet_def* t = SB_ITEMS(b->tets, sb_tet_def) + index;
    uint32_t ids[SB_TET_NODES];
    memcpy(ids, t->v, sizeof t->v);
    memcpy(ids + 4, t->mid, sizeof t->mid);
    sb_status status =
        sb_check_indices("tetrahedron", index, ids, t->quadratic ? SB_TET_NODES : 4, (uint32_t)b->vertices.count, err);
    if (status != SB_OK) return status;
    if (!sb_constant_ok(t->young_modulus) || !sb_constant_ok(t->stiffness_damping) || !isfinite(t->poisson_ratio) ||
        !(t->poisson_ratio > -1.0) || !(t->poisson_ratio < 0.5))
        return sb_error_set(err, SB_ERR_INVALID,
                            "tetrahedron %zu: Young's modulus and stiffness damping must be finite and >= 0, Poisson's "
                            "ratio in (-1, 0.5)",
                            index);
    double longest;
    double volume = sb_tet_signed_volume(b, t->v, &longest);
    if (!(fabs(volume) > 1e-12 * longest * longest * longest))
        return sb_error_set(err, SB_ERR_INVALID, "tetrahedron %zu (%u, %u, %u, %u): zero volume", index, t->v[0],
                            t->v[1], t->v[2], t->v[3]);
    return SB_OK;
}

static sb_status sb_validate(const sb_builder* b, sb_error* err) {
    if (b->vertices.count == 0) return sb_error_set(err, SB_ERR_INVALID, "the model has no vertices");
    sb_status status = sb_check_vertices(b, err);
    for (size_t i = 0; i < b->bonds.count && status == SB_OK; i++) status = sb_check_bond(b, i, err);
    if (status == SB_OK) status = sb_check_duplicate_bonds(b, err);
    for (size_t i = 0; i < b->triangles.count && status == SB_OK; i++) status = sb_check_triangle(b, i, err);
    for (size_t i = 0; i < b->hinges.count && status == SB_OK; i++) status = sb_check_hinge(b, i, err);
    for (size_t i = 0; i < b->tets.count && status == SB_OK; i++) status = sb_check_tet(b, i, err);
    for (size_t i = 0; i < b->faces.count && status == SB_OK; i++)
        status = sb_check_indices("face", i, SB_ITEMS(b->faces, uint32_t) + 3 * i, 3, (uint32_t)b->vertices.count, err);
    if (status == SB_OK) status = sb_check_membranes(b, err);
    if (status == SB_OK) status = sb_check_plates(b, err);
    return status;
}

/* ---- layout ------------------------------------------------------------ */

static void* sb_alloc_array(size_t count, size_t size, bool* ok) {
    void* p = calloc(count ? count : 1, size);
    if (!p) *ok = false;
    return p;
}

static bool sb_model_allocate(sb_model* m) {
    bool ok = true;
    size_t n = m->vertex_count, nb = m->bond_count, nt = m->triangle_count, nh = m->hinge_count;
    double** vertex_arrays[] = {&m->rest_x, &m->rest_y, &m->rest_z, &m->vel_x,
                                &m->vel_y,  &m->vel_z,  &m->mass,   &m->inv_mass};
    for (size_t a = 0; a < sizeof vertex_arrays / sizeof *vertex_arrays; a++)
        *vertex_arrays[a] = sb_alloc_array(n, sizeof(double), &ok);
    m->fixed = sb_alloc_array(n, 1, &ok);
    m->bond_i = sb_alloc_array(nb, sizeof(uint32_t), &ok);
    m->bond_j = sb_alloc_array(nb, sizeof(uint32_t), &ok);
    double** bond_arrays[] = {&m->bond_r0,        &m->bond_k,         &m->spring_k,
                              &m->spring_damping, &m->bond_break_min, &m->bond_break_max};
    for (size_t a = 0; a < sizeof bond_arrays / sizeof *bond_arrays; a++)
        *bond_arrays[a] = sb_alloc_array(nb, sizeof(double), &ok);
    for (int c = 0; c < 3; c++) {
        m->tri_v[c] = sb_alloc_array(nt, sizeof(uint32_t), &ok);
        m->tri_cos0[c] = sb_alloc_array(nt, sizeof(double), &ok);
        m->tri_len0[c] = sb_alloc_array(nt, sizeof(double), &ok);
        m->face_v[c] = sb_alloc_array(m->face_count, sizeof(uint32_t), &ok);
    }
    m->angle_k = sb_alloc_array(nt, sizeof(double), &ok);
    m->stretch_bend_k = sb_alloc_array(nt, sizeof(double), &ok);
    uint32_t** hinge_ids[] = {&m->hinge_e0, &m->hinge_e1, &m->hinge_o0, &m->hinge_o1};
    for (size_t a = 0; a < 4; a++) *hinge_ids[a] = sb_alloc_array(nh, sizeof(uint32_t), &ok);
    m->hinge_phi0 = sb_alloc_array(nh, sizeof(double), &ok);
    m->hinge_k = sb_alloc_array(nh, sizeof(double), &ok);
    size_t nq = m->tet_count;
    for (int c = 0; c < SB_TET_NODES; c++) m->tet_v[c] = sb_alloc_array(nq, sizeof(uint32_t), &ok);
    m->tet_nodes = sb_alloc_array(nq, sizeof(uint8_t), &ok);
    for (int c = 0; c < 9; c++) m->tet_dm_inv[c] = sb_alloc_array(nq, sizeof(double), &ok);
    m->tet_volume = sb_alloc_array(nq, sizeof(double), &ok);
    m->tet_mu = sb_alloc_array(nq, sizeof(double), &ok);
    m->tet_lambda = sb_alloc_array(nq, sizeof(double), &ok);
    m->tet_beta = sb_alloc_array(nq, sizeof(double), &ok);
    return ok;
}

static void sb_fill_vertices(sb_model* m, const sb_builder* b) {
    const sb_vertex_def* v = SB_ITEMS(b->vertices, sb_vertex_def);
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        m->rest_x[i] = v[i].position[0];
        m->rest_y[i] = v[i].position[1];
        m->rest_z[i] = v[i].position[2];
        m->vel_x[i] = v[i].fixed ? 0.0 : v[i].velocity[0];
        m->vel_y[i] = v[i].fixed ? 0.0 : v[i].velocity[1];
        m->vel_z[i] = v[i].fixed ? 0.0 : v[i].velocity[2];
        m->mass[i] = v[i].mass;
        m->fixed[i] = v[i].fixed;
        m->inv_mass[i] = v[i].fixed ? 0.0 : 1.0 / v[i].mass;
    }
}

static void sb_fill_bonds(sb_model* m, const sb_builder* b) {
    const sb_bond_def* d = SB_ITEMS(b->bonds, sb_bond_def);
    for (uint32_t e = 0; e < m->bond_count; e++) {
        m->bond_i[e] = d[e].i;
        m->bond_j[e] = d[e].j;
        m->bond_r0[e] = d[e].rest_length < 0.0 ? sb_distance(b, d[e].i, d[e].j) : d[e].rest_length;
        m->bond_k[e] = d[e].k;
        m->spring_k[e] = d[e].spring_k;
        m->spring_damping[e] = d[e].spring_damping;
        m->bond_break_min[e] = d[e].break_min;
        m->bond_break_max[e] = sb_break_max(d + e);
        m->breakable |= d[e].break_min > 0.0 || isfinite(m->bond_break_max[e]);
        m->term_enabled[SB_TERM_BOND] |= d[e].k > 0.0;
        m->term_enabled[SB_TERM_SPRING] |= d[e].spring_k > 0.0 || d[e].spring_damping > 0.0;
    }
}

static void sb_fill_triangles(sb_model* m, const sb_builder* b) {
    const sb_triangle_def* d = SB_ITEMS(b->triangles, sb_triangle_def);
    const sb_vertex_def* v = SB_ITEMS(b->vertices, sb_vertex_def);
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        uint32_t ids[3] = {d[t].i, d[t].j, d[t].k};
        for (int c = 0; c < 3; c++) {
            sb_vec3 p = sb_v3(v[ids[c]].position);
            sb_vec3 a = sb_v3_sub(sb_v3(v[ids[(c + 1) % 3]].position), p);
            sb_vec3 e = sb_v3_sub(sb_v3(v[ids[(c + 2) % 3]].position), p);
            m->tri_v[c][t] = ids[c];
            m->tri_len0[c][t] = sb_v3_length(a);
            m->tri_cos0[c][t] = sb_v3_dot(a, e) / (sb_v3_length(a) * sb_v3_length(e));
        }
        m->angle_k[t] = d[t].angle_k;
        m->stretch_bend_k[t] = d[t].stretch_bend_k;
        m->term_enabled[SB_TERM_ANGLE] |= d[t].angle_k > 0.0;
        m->term_enabled[SB_TERM_STRETCH_BEND] |= d[t].stretch_bend_k > 0.0;
    }
}

static void sb_fill_faces(sb_model* m, const sb_builder* b) {
    const uint32_t* v = SB_ITEMS(b->faces, uint32_t);
    for (uint32_t f = 0; f < m->face_count; f++)
        for (int c = 0; c < 3; c++) m->face_v[c][f] = v[3 * (size_t)f + c];
}

static void sb_fill_hinges(sb_model* m, const sb_builder* b) {
    const sb_hinge_def* d = SB_ITEMS(b->hinges, sb_hinge_def);
    const sb_vertex_def* v = SB_ITEMS(b->vertices, sb_vertex_def);
    for (uint32_t h = 0; h < m->hinge_count; h++) {
        m->hinge_e0[h] = d[h].e0;
        m->hinge_e1[h] = d[h].e1;
        m->hinge_o0[h] = d[h].o0;
        m->hinge_o1[h] = d[h].o1;
        m->hinge_phi0[h] = sb_hinge_measure(sb_v3(v[d[h].e0].position), sb_v3(v[d[h].e1].position),
                                            sb_v3(v[d[h].o0].position), sb_v3(v[d[h].o1].position))
                               .phi;
        m->hinge_k[h] = d[h].k;
        m->term_enabled[SB_TERM_BEND] |= d[h].k > 0.0;
    }
}

/* Corners 2 and 3 swapped, and the middles of the edges that swaps: 02 with
 * 03, 12 with 13. */
static void sb_tet_swap_corners(uint32_t ids[SB_TET_NODES]) {
    static const int pairs[3][2] = {{2, 3}, {5, 6}, {7, 8}};
    for (int p = 0; p < 3; p++) {
        uint32_t swap = ids[pairs[p][0]];
        ids[pairs[p][0]] = ids[pairs[p][1]];
        ids[pairs[p][1]] = swap;
    }
}

/* Each tetrahedron with positive volume (corners 2 and 3 swapped where the
 * given order is negative), D_m⁻¹ and the Lamé constants
 * μ = E / (2 (1 + ν)), λ = E ν / ((1 + ν)(1 − 2ν)). */
static void sb_fill_tets(sb_model* m, const sb_builder* b) {
    const sb_tet_def* d = SB_ITEMS(b->tets, sb_tet_def);
    const sb_vertex_def* v = SB_ITEMS(b->vertices, sb_vertex_def);
    for (uint32_t t = 0; t < m->tet_count; t++) {
        uint32_t ids[SB_TET_NODES];
        memcpy(ids, d[t].v, sizeof d[t].v);
        for (int e = 0; e < 6; e++) ids[4 + e] = d[t].quadratic ? d[t].mid[e] : ids[0];
        double longest;
        if (sb_tet_signed_volume(b, ids, &longest) < 0.0) sb_tet_swap_corners(ids);
        double dm[3][3]; /* columns: edges from vertex 0 */
        for (int c = 0; c < 3; c++)
            for (int r = 0; r < 3; r++) dm[r][c] = v[ids[c + 1]].position[r] - v[ids[0]].position[r];
        double det = dm[0][0] * (dm[1][1] * dm[2][2] - dm[1][2] * dm[2][1]) -
                     dm[0][1] * (dm[1][0] * dm[2][2] - dm[1][2] * dm[2][0]) +
                     dm[0][2] * (dm[1][0] * dm[2][1] - dm[1][1] * dm[2][0]);
        double inv[9] = {
            (dm[1][1] * dm[2][2] - dm[1][2] * dm[2][1]) / det, (dm[0][2] * dm[2][1] - dm[0][1] * dm[2][2]) / det,
            (dm[0][1] * dm[1][2] - dm[0][2] * dm[1][1]) / det, (dm[1][2] * dm[2][0] - dm[1][0] * dm[2][2]) / det,
            (dm[0][0] * dm[2][2] - dm[0][2] * dm[2][0]) / det, (dm[0][2] * dm[1][0] - dm[0][0] * dm[1][2]) / det,
            (dm[1][0] * dm[2][1] - dm[1][1] * dm[2][0]) / det, (dm[0][1] * dm[2][0] - dm[0][0] * dm[2][1]) / det,
            (dm[0][0] * dm[1][1] - dm[0][1] * dm[1][0]) / det};
        for (int c = 0; c < SB_TET_NODES; c++) m->tet_v[c][t] = ids[c];
        m->tet_nodes[t] = d[t].quadratic ? SB_TET_NODES : 4;
        for (int c = 0; c < 9; c++) m->tet_dm_inv[c][t] = inv[c];
        double e = d[t].young_modulus, nu = d[t].poisson_ratio;
        m->tet_volume[t] = det / 6.0;
        m->tet_mu[t] = e / (2.0 * (1.0 + nu));
        m->tet_lambda[t] = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        m->tet_beta[t] = d[t].stiffness_damping;
        m->tet_damped |= e > 0.0 && d[t].stiffness_damping > 0.0;
        m->term_enabled[SB_TERM_COROTATED] |= e > 0.0;
    }
}

sb_model* sb_builder_compile(const sb_builder* builder, sb_error* err) {
    if (sb_validate(builder, err) != SB_OK) return NULL;
    sb_model* m = calloc(1, sizeof *m);
    if (!m) {
        sb_error_set(err, SB_ERR_NOMEM, "out of memory compiling the model");
        return NULL;
    }
    m->vertex_count = (uint32_t)builder->vertices.count;
    m->bond_count = (uint32_t)builder->bonds.count;
    m->triangle_count = (uint32_t)builder->triangles.count;
    m->hinge_count = (uint32_t)builder->hinges.count;
    m->tet_count = (uint32_t)builder->tets.count;
    m->face_count = (uint32_t)builder->faces.count;
    if (!sb_model_allocate(m) || !sb_fill_membranes(m, builder) || !sb_fill_plates(m, builder)) {
        sb_model_destroy(m);
        sb_error_set(err, SB_ERR_NOMEM, "out of memory compiling a model of %u vertices", m->vertex_count);
        return NULL;
    }
    sb_fill_vertices(m, builder);
    sb_fill_bonds(m, builder);
    sb_fill_triangles(m, builder);
    sb_fill_hinges(m, builder);
    sb_fill_tets(m, builder);
    sb_fill_faces(m, builder);
    return m;
}
