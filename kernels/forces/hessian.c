/* Element stiffness matrices and products from the terms' dual forces, and
 * their positive semi-definite stand-ins (kernels/forces/hessian.h). */
#include "kernels/forces/hessian.h"
#include "kernels/forces/hessian_edges.h"
#include "kernels/forces/hessian_corners.h"
#include "kernels/forces/hessian_hinges.h"
#include "kernels/forces/hessian_tets.h"
#include "kernels/forces/hessian_membranes.h"
#include "kernels/forces/plate.h"

#include <string.h>

uint64_t sb_element_count(const sb_model* m) {
    return (uint64_t)m->bond_count + m->triangle_count + m->hinge_count + m->tet_count + m->membrane_count +
           m->plate_count;
}

sb_element sb_element_at(const sb_model* m, uint64_t e) {
    if (e < m->bond_count) return (sb_element){SB_ELEMENT_BOND, (uint32_t)e, 2, {m->bond_i[e], m->bond_j[e]}};
    e -= m->bond_count;
    if (e < m->triangle_count)
        return (sb_element){SB_ELEMENT_TRIANGLE, (uint32_t)e, 3, {m->tri_v[0][e], m->tri_v[1][e], m->tri_v[2][e]}};
    e -= m->triangle_count;
    if (e < m->hinge_count)
        return (sb_element){
            SB_ELEMENT_HINGE, (uint32_t)e, 4, {m->hinge_e0[e], m->hinge_e1[e], m->hinge_o0[e], m->hinge_o1[e]}};
    e -= m->hinge_count;
    if (e < m->tet_count) {
        sb_element tet = {SB_ELEMENT_TET, (uint32_t)e, m->tet_nodes[e], {0}};
        for (int a = 0; a < tet.count; a++) tet.vertex[a] = m->tet_v[a][e];
        return tet;
    }
    e -= m->tet_count;
    if (e < m->membrane_count)
        return (sb_element){
            SB_ELEMENT_MEMBRANE, (uint32_t)e, 3, {m->membrane_v[0][e], m->membrane_v[1][e], m->membrane_v[2][e]}};
    e -= m->membrane_count;
    sb_element plate = {SB_ELEMENT_PLATE, (uint32_t)e, m->plate_nodes[e], {0}};
    for (int a = 0; a < plate.count; a++) plate.vertex[a] = m->plate_v[SB_PLATE_NODES * e + (size_t)a];
    return plate;
}

/* A plate's forces and its constant matrix (kernels/forces/plate.c). */
static bool sb_plate_matrix(const sb_model* m, uint32_t t, const sb_vec3* x, double* forces, double* k) {
    sb_plate_element(m, t, x, forces, k);
    return true;
}

/* A membrane's exact forces and K as sb_tet_forces_dual's; false when it
 * collapsed. */
static bool sb_membrane_forces_dual(const sb_model* m, uint32_t tri, const sb_dvec3* x, sb_dvec3* f) {
    sb_vec3 at[3] = {x[0].v, x[1].v, x[2].v};
    double forces[9], k[81];
    if (!sb_membrane_element_stiffness(m, tri, at, forces, k)) return false;
    sb_matrix_forces_dual(3, forces, k, x, f);
    return true;
}

/* A tetrahedron's exact forces at x.v, and −R K0 Rᵀ x.d as their
 * derivative part (hessian.h). */
static bool sb_tet_forces_dual(const sb_model* m, uint32_t tet, const sb_dvec3* x, sb_dvec3* f) {
    int nodes = m->tet_nodes[tet], size = 3 * nodes;
    sb_vec3 at[SB_ELEMENT_MAX] = {{0.0, 0.0, 0.0}};
    double forces[3 * SB_ELEMENT_MAX], k[SB_ELEMENT_MATRIX], p[3 * SB_ELEMENT_MAX];
    for (int a = 0; a < nodes; a++) {
        at[a] = x[a].v;
        p[3 * a] = x[a].d.x, p[3 * a + 1] = x[a].d.y, p[3 * a + 2] = x[a].d.z;
    }
    if (!sb_tet_stiffness(m, tet, at, forces, k)) return false;
    for (int a = 0; a < nodes; a++) {
        double d[3];
        for (int i = 0; i < 3; i++) {
            double s = 0.0;
            for (int c = 0; c < size; c++) s -= k[(3 * a + i) * size + c] * p[c];
            d[i] = s;
        }
        f[a].v = (sb_vec3){forces[3 * a], forces[3 * a + 1], forces[3 * a + 2]};
        f[a].d = (sb_vec3){d[0], d[1], d[2]};
    }
    return true;
}

bool sb_element_forces_dual(const sb_model* m, const sb_element* e, const sb_dvec3* x, sb_dvec3* f) {
    bool collapsed = false;
    switch (e->kind) {
    case SB_ELEMENT_BOND: sb_bond_forces_dual(m, e->index, x, f, &collapsed); break;
    case SB_ELEMENT_TRIANGLE: sb_triangle_forces_dual(m, e->index, x, f, &collapsed); break;
    case SB_ELEMENT_HINGE: sb_hinge_forces_dual(m, e->index, x, f, &collapsed); break;
    case SB_ELEMENT_TET: return sb_tet_forces_dual(m, e->index, x, f);
    case SB_ELEMENT_MEMBRANE: return sb_membrane_forces_dual(m, e->index, x, f);
    case SB_ELEMENT_PLATE: {
        sb_vec3 at[SB_ELEMENT_MAX];
        double forces[3 * SB_ELEMENT_MAX], k[SB_ELEMENT_MATRIX];
        for (int a = 0; a < e->count; a++) at[a] = x[a].v;
        sb_plate_matrix(m, e->index, at, forces, k);
        sb_matrix_forces_dual(e->count, forces, k, x, f);
        return true;
    }
    }
    return !collapsed;
}

/* The element's vertices at x, seeded with the element-local direction p
 * (3 count doubles, or NULL for none). */
static void sb_element_seed(const sb_element* e, const double* x, const double* p, sb_dvec3* out) {
    static const double zero[3] = {0, 0, 0};
    for (int a = 0; a < e->count; a++) out[a] = sb_dv3(x + 3 * (size_t)e->vertex[a], p ? p + 3 * a : zero);
}

/* The hinge's (or any element's) stiffness by one dual run per column. */
static bool sb_element_stiffness_dual(const sb_model* m, const sb_element* e, const double* x, double* k) {
    int size = 3 * e->count;
    double seed[3 * SB_ELEMENT_MAX];
    sb_dvec3 xs[SB_ELEMENT_MAX], f[SB_ELEMENT_MAX];
    for (int col = 0; col < size; col++) {
        memset(seed, 0, sizeof seed);
        seed[col] = 1.0;
        sb_element_seed(e, x, seed, xs);
        if (!sb_element_forces_dual(m, e, xs, f)) return false;
        for (int a = 0; a < e->count; a++) {
            k[(3 * a + 0) * size + col] = -f[a].d.x;
            k[(3 * a + 1) * size + col] = -f[a].d.y;
            k[(3 * a + 2) * size + col] = -f[a].d.z;
        }
    }
    return true;
}

bool sb_element_stiffness(const sb_model* m, const sb_element* e, const double* x, double* k) {
    sb_vec3 local[SB_ELEMENT_MAX];
    for (int a = 0; a < e->count; a++) local[a] = sb_v3(x + 3 * (size_t)e->vertex[a]);
    switch (e->kind) {
    case SB_ELEMENT_BOND: return sb_bond_stiffness_matrix(m, e->index, local, k);
    case SB_ELEMENT_TRIANGLE: return sb_triangle_stiffness(m, e->index, local, k);
    case SB_ELEMENT_TET: return sb_tet_stiffness(m, e->index, local, NULL, k);
    case SB_ELEMENT_MEMBRANE: return sb_membrane_element_stiffness(m, e->index, local, NULL, k);
    case SB_ELEMENT_PLATE: return sb_plate_matrix(m, e->index, local, NULL, k);
    case SB_ELEMENT_HINGE: break;
    }
    return sb_element_stiffness_dual(m, e, x, k);
}

/* The tetrahedron's vertex share: its exact force and its diagonal block
 * of R K0 Rᵀ (positive semi-definite, as every diagonal block of a
 * positive semi-definite matrix). */
static bool sb_tet_vertex_share(const sb_model* m, uint32_t tet, const sb_vec3* x, int place, double* f,
                                double* block) {
    int size = 3 * m->tet_nodes[tet];
    double forces[3 * SB_ELEMENT_MAX], k[SB_ELEMENT_MATRIX];
    if (!sb_tet_stiffness(m, tet, x, forces, k)) return false;
    for (int i = 0; i < 3; i++) {
        f[i] += forces[3 * place + i];
        for (int j = 0; j < 3; j++) block[3 * i + j] += k[(3 * place + i) * size + 3 * place + j];
    }
    return true;
}

bool sb_element_vertex_share(const sb_model* m, const sb_element* e, const double* x, int place, double* f,
                             double* block) {
    sb_vec3 local[SB_ELEMENT_MAX];
    for (int a = 0; a < e->count; a++) local[a] = sb_v3(x + 3 * (size_t)e->vertex[a]);
    switch (e->kind) {
    case SB_ELEMENT_BOND: return sb_bond_vertex_share(m, e->index, local, place, f, block);
    case SB_ELEMENT_TRIANGLE: return sb_triangle_vertex_share(m, e->index, local, place, f, block);
    case SB_ELEMENT_TET: return sb_tet_vertex_share(m, e->index, local, place, f, block);
    case SB_ELEMENT_MEMBRANE: {
        double forces[9], k[81];
        if (!sb_membrane_element_stiffness(m, e->index, local, forces, k)) return false;
        sb_matrix_vertex_share(3, forces, k, place, f, block);
        return true;
    }
    case SB_ELEMENT_PLATE: {
        double forces[3 * SB_ELEMENT_MAX], k[SB_ELEMENT_MATRIX];
        sb_plate_matrix(m, e->index, local, forces, k);
        sb_matrix_vertex_share(e->count, forces, k, place, f, block);
        return true;
    }
    case SB_ELEMENT_HINGE: break;
    }
    return sb_hinge_vertex_share(m, e->index, local, place, f, block);
}

bool sb_stiffness_product(const sb_model* m, const double* x, const double* p, double* out) {
    memset(out, 0, 3 * (size_t)m->vertex_count * sizeof *out);
    uint64_t count = sb_element_count(m);
    for (uint64_t id = 0; id < count; id++) {
        sb_element e = sb_element_at(m, id);
        double local[3 * SB_ELEMENT_MAX];
        for (int a = 0; a < e.count; a++) memcpy(local + 3 * a, p + 3 * (size_t)e.vertex[a], 3 * sizeof(double));
        sb_dvec3 xs[SB_ELEMENT_MAX], f[SB_ELEMENT_MAX];
        sb_element_seed(&e, x, local, xs);
        if (!sb_element_forces_dual(m, &e, xs, f)) return false;
        for (int a = 0; a < e.count; a++) sb_v3_add_to(out + 3 * (size_t)e.vertex[a], f[a].d, -1.0);
    }
    return true;
}

bool sb_element_stiffness_definite(const sb_model* m, const sb_element* e, const double* x, double* k) {
    sb_vec3 local[SB_ELEMENT_MAX];
    for (int a = 0; a < e->count; a++) local[a] = sb_v3(x + 3 * (size_t)e->vertex[a]);
    memset(k, 0, 9 * (size_t)e->count * (size_t)e->count * sizeof *k);
    switch (e->kind) {
    case SB_ELEMENT_BOND: sb_bond_definite(m, e->index, local, k); break;
    case SB_ELEMENT_TRIANGLE: sb_triangle_definite(m, e->index, local, k); break;
    case SB_ELEMENT_HINGE: sb_hinge_definite(m, e->index, local, k); break;
    case SB_ELEMENT_TET:
        if (!sb_tet_stiffness(m, e->index, local, NULL, k)) return false;
        break;
    case SB_ELEMENT_MEMBRANE:
        if (!sb_membrane_element_stiffness(m, e->index, local, NULL, k)) return false;
        break;
    case SB_ELEMENT_PLATE: sb_plate_matrix(m, e->index, local, NULL, k); break; /* positive semi-definite */
    }
    for (int r = 0; r < 9 * e->count * e->count; r++)
        if (!isfinite(k[r])) return false;
    return true;
}

/* dt² R K0 Rᵀ in the blocks' layout (hessian.h), definite or not. */
static bool sb_tet_jacobian_blocks(const sb_model* m, uint32_t tet, const sb_vec3* x, double scale, double* blocks) {
    int nodes = m->tet_nodes[tet], size = 3 * nodes;
    double k[SB_ELEMENT_MATRIX];
    if (!sb_tet_stiffness(m, tet, x, NULL, k)) return false;
    for (int r = 0; r < nodes; r++)
        for (int c = 0; c < nodes; c++)
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++)
                    blocks[9 * (nodes * r + c) + 3 * a + b] = scale * k[(3 * r + a) * size + 3 * c + b];
    return true;
}

bool sb_element_jacobian_blocks(const sb_model* m, const sb_element* e, const double* x, bool definite, double dt,
                                double* blocks) {
    sb_vec3 local[SB_ELEMENT_MAX];
    for (int a = 0; a < e->count; a++) local[a] = sb_v3(x + 3 * (size_t)e->vertex[a]);
    double scale = dt * dt, k[81] = {0};
    switch (e->kind) {
    case SB_ELEMENT_BOND: return sb_bond_jacobian_blocks(m, e->index, local, definite, dt, blocks);
    case SB_ELEMENT_HINGE: return sb_hinge_definite_blocks(m, e->index, local, scale, blocks);
    case SB_ELEMENT_TET: /* dt D + dt² K with D = β K, the element's Rayleigh damping */
        return sb_tet_jacobian_blocks(m, e->index, local, scale + dt * m->tet_beta[e->index], blocks);
    case SB_ELEMENT_MEMBRANE: /* likewise dt D + dt² K */
        if (!sb_membrane_element_stiffness(m, e->index, local, NULL, k)) return false;
        sb_matrix_blocks(3, k, scale + dt * m->membrane_beta[e->index], blocks);
        return true;
    case SB_ELEMENT_PLATE: {
        double plate[SB_ELEMENT_MATRIX];
        sb_plate_matrix(m, e->index, local, NULL, plate);
        sb_matrix_blocks(e->count, plate, scale, blocks);
        return true;
    }
    case SB_ELEMENT_TRIANGLE: break;
    }
    if (!definite) return sb_triangle_stiffness_blocks(m, e->index, local, scale, blocks);
    sb_triangle_definite(m, e->index, local, k);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            for (int a = 0; a < 3; a++)
                for (int b = 0; b < 3; b++) {
                    double v = scale * k[(3 * r + a) * 9 + 3 * c + b];
                    if (!isfinite(v)) return false;
                    blocks[9 * (3 * r + c) + 3 * a + b] = v;
                }
    return true;
}
