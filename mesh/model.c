/* The compiled model: accessors and release. */
#include "mesh/model_internal.h"

#include <stdlib.h>

const char* sb_term_name(sb_term term) {
    static const char* const names[SB_TERM_COUNT] = {"bond", "angle",     "stretch_bend", "spring",
                                                     "bend", "corotated", "membrane"};
    return (unsigned)term < SB_TERM_COUNT ? names[term] : "unknown";
}

void sb_model_destroy(sb_model* m) {
    if (!m) return;
    void* arrays[] = {m->rest_x,   m->rest_y,         m->rest_z,   m->vel_x,          m->vel_y,
                      m->vel_z,    m->mass,           m->inv_mass, m->fixed,          m->bond_i,
                      m->bond_j,   m->bond_r0,        m->bond_k,   m->spring_k,       m->spring_damping,
                      m->angle_k,  m->stretch_bend_k, m->hinge_e0, m->hinge_e1,       m->hinge_o0,
                      m->hinge_o1, m->hinge_phi0,     m->hinge_k,  m->bond_break_min, m->bond_break_max};
    for (size_t a = 0; a < sizeof arrays / sizeof *arrays; a++) free(arrays[a]);
    for (int c = 0; c < 3; c++) {
        free(m->tri_v[c]);
        free(m->tri_cos0[c]);
        free(m->tri_len0[c]);
        free(m->face_v[c]);
    }
    for (int c = 0; c < SB_TET_NODES; c++) free(m->tet_v[c]);
    free(m->tet_nodes);
    for (int c = 0; c < 9; c++) free(m->tet_dm_inv[c]);
    free(m->tet_volume);
    free(m->tet_mu);
    free(m->tet_lambda);
    for (int c = 0; c < 3; c++) free(m->membrane_v[c]);
    for (int c = 0; c < 4; c++) free(m->membrane_dm_inv[c]);
    free(m->membrane_volume);
    free(m->membrane_mu);
    free(m->membrane_lambda);
    free(m->membrane_beta);
    free(m->plate_nodes);
    free(m->plate_v);
    free(m->plate_c);
    free(m->plate_a);
    free(m->plate_b);
    free(m->tet_beta);
    free(m);
}

uint32_t sb_model_vertex_count(const sb_model* m) { return m->vertex_count; }
uint32_t sb_model_bond_count(const sb_model* m) { return m->bond_count; }
uint32_t sb_model_triangle_count(const sb_model* m) { return m->triangle_count; }
uint32_t sb_model_hinge_count(const sb_model* m) { return m->hinge_count; }
uint32_t sb_model_tet_count(const sb_model* m) { return m->tet_count; }
uint32_t sb_model_membrane_count(const sb_model* m) { return m->membrane_count; }

bool sb_model_term_enabled(const sb_model* m, sb_term term) {
    return (unsigned)term < SB_TERM_COUNT && m->term_enabled[term];
}

void sb_model_rest_position(const sb_model* m, uint32_t v, double out[3]) {
    out[0] = m->rest_x[v];
    out[1] = m->rest_y[v];
    out[2] = m->rest_z[v];
}

void sb_model_initial_velocity(const sb_model* m, uint32_t v, double out[3]) {
    out[0] = m->vel_x[v];
    out[1] = m->vel_y[v];
    out[2] = m->vel_z[v];
}

double sb_model_mass(const sb_model* m, uint32_t v) { return m->mass[v]; }
bool sb_model_is_fixed(const sb_model* m, uint32_t v) { return m->fixed[v] != 0; }

sb_bond_info sb_model_bond(const sb_model* m, uint32_t e) {
    return (sb_bond_info){m->bond_i[e], m->bond_j[e],   m->bond_r0[e],
                          m->bond_k[e], m->spring_k[e], m->spring_damping[e]};
}

void sb_model_triangle(const sb_model* m, uint32_t t, uint32_t out[3]) {
    for (int c = 0; c < 3; c++) out[c] = m->tri_v[c][t];
}
