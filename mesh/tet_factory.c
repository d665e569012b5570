/* The volumetric mass-spring factory (Sudhamani & Merriliance 2019, after
 * Lloyd, Székely & Harders 2007): masses from the density, spring
 * stiffness from Young's modulus, damping from the documented rule and
 * Rayleigh's stiffness-proportional β. See
 * include/softbond/volume.h for the formulas and the materials. */
#include "mesh/builder_internal.h"
#include "common/edge_map.h"
#include "softbond/volume.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SB_LIVER_E 3500.0        /* Pa, Sudhamani & Merriliance (2019) */
#define SB_GALLBLADDER_E 1500.0  /* Pa, same source */
#define SB_TISSUE_DENSITY 1060.0 /* kg/m³, ICRU Report 46: adult liver 1.06 g/cm³ */

sb_tissue_def sb_default_tissue_def(void) {
    return (sb_tissue_def){.young_modulus = SB_LIVER_E,
                           .density = SB_TISSUE_DENSITY,
                           .damping = 1.0,
                           .poisson_ratio = 0.45,
                           .model = SB_TISSUE_SPRINGS};
}

bool sb_tissue_from_name(const char* name, sb_tissue_def* out) {
    sb_tissue_def def = sb_default_tissue_def();
    if (!name) return false;
    if (strcmp(name, "gallbladder") == 0)
        def.young_modulus = SB_GALLBLADDER_E;
    else if (strcmp(name, "liver") != 0)
        return false;
    *out = def;
    return true;
}

typedef struct sb_tet_edge {
    uint32_t i, j;
    double k;
} sb_tet_edge;

static const int sb_tet_edge_corners[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

static double sb_distance3(const double* p, const double* q) {
    double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* Σ over tetrahedra of (√2/25) l_t E per unique edge, in order of first appearance. */
static sb_status sb_tet_edges(const sb_tet_mesh* m, double modulus, sb_tet_edge** out, uint32_t* count, sb_error* err) {
    size_t max_edges = 6 * (size_t)m->tet_count;
    sb_edge_map map;
    sb_tet_edge* edges = malloc(max_edges * sizeof *edges);
    if (!edges || !sb_edge_map_init(&map, max_edges)) {
        free(edges);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory finding the edges of %u tetrahedra", m->tet_count);
    }
    uint32_t n = 0;
    for (uint32_t t = 0; t < m->tet_count; t++) {
        const uint32_t* v = m->tets + 4 * (size_t)t;
        const double* p = m->positions;
        double volume =
            fabs(sb_tet_volume(p + 3 * (size_t)v[0], p + 3 * (size_t)v[1], p + 3 * (size_t)v[2], p + 3 * (size_t)v[3]));
        double length = cbrt(6.0 * sqrt(2.0) * volume); /* the regular tetrahedron's edge */
        double k = sqrt(2.0) / 25.0 * length * modulus;
        for (int e = 0; e < 6; e++) {
            uint32_t a = v[sb_tet_edge_corners[e][0]], b = v[sb_tet_edge_corners[e][1]];
            bool inserted;
            uint32_t id = *sb_edge_map_upsert(&map, a, b, n, &inserted);
            if (inserted) edges[n++] = (sb_tet_edge){a, b, 0.0};
            edges[id].k += k;
        }
    }
    sb_edge_map_free(&map);
    *out = edges;
    *count = n;
    return SB_OK;
}

/* m_i = Σ ρ V / 4 over the tetrahedra of vertex i; none may be left at 0. */
static sb_status sb_tet_masses(const sb_tet_mesh* m, double density, double** out, sb_error* err) {
    double* mass = calloc(m->vertex_count ? m->vertex_count : 1, sizeof *mass);
    if (!mass) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    for (uint32_t t = 0; t < m->tet_count; t++) {
        const uint32_t* v = m->tets + 4 * (size_t)t;
        const double* p = m->positions;
        double share = density *
                       fabs(sb_tet_volume(p + 3 * (size_t)v[0], p + 3 * (size_t)v[1], p + 3 * (size_t)v[2],
                                          p + 3 * (size_t)v[3])) /
                       4.0;
        for (int c = 0; c < 4; c++) mass[v[c]] += share;
    }
    for (uint32_t i = 0; i < m->vertex_count; i++)
        if (mass[i] <= 0.0) {
            free(mass);
            return sb_error_set(err, SB_ERR_INVALID, "vertex %u belongs to no tetrahedron: it would have no mass", i);
        }
    *out = mass;
    return SB_OK;
}

static sb_status sb_tet_vertices(sb_builder* b, const sb_tet_mesh* m, const double* mass, sb_error* err) {
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        sb_vertex_def def = sb_default_vertex_def();
        memcpy(def.position, m->positions + 3 * (size_t)i, sizeof def.position);
        def.mass = mass[i];
        if (sb_builder_add_vertex(b, &def) < 0) return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding vertices");
    }
    return SB_OK;
}

static sb_status sb_tet_springs(sb_builder* b, uint32_t first, const sb_tet_mesh* m, const double* mass,
                                const sb_tissue_def* tissue, sb_error* err) {
    sb_tet_edge* edges = NULL;
    uint32_t count = 0;
    sb_status status = sb_tet_edges(m, tissue->young_modulus, &edges, &count, err);
    for (uint32_t e = 0; e < count && status == SB_OK; e++) {
        uint32_t i = first + edges[e].i, j = first + edges[e].j;
        double l0 = sb_distance3(m->positions + 3 * (size_t)edges[e].i, m->positions + 3 * (size_t)edges[e].j);
        double pair_mass = mass[edges[e].i] + mass[edges[e].j];
        sb_bond_def def = sb_default_bond_def();
        def.i = i;
        def.j = j;
        def.rest_length = -1.0;
        def.k = 0.0;
        def.spring_k = edges[e].k;
        def.spring_damping =
            tissue->damping * sqrt(edges[e].k * pair_mass) / l0 + tissue->stiffness_damping * edges[e].k;
        if (sb_builder_add_bond(b, &def) < 0) status = sb_error_set(err, SB_ERR_NOMEM, "out of memory adding springs");
    }
    free(edges);
    return status;
}

static sb_status sb_tet_elements(sb_builder* b, uint32_t first, const sb_tet_mesh* m, const sb_tissue_def* tissue,
                                 sb_error* err) {
    for (uint32_t t = 0; t < m->tet_count; t++) {
        const uint32_t* v = m->tets + 4 * (size_t)t;
        sb_tet_def def = {.v = {first + v[0], first + v[1], first + v[2], first + v[3]},
                          .young_modulus = tissue->young_modulus,
                          .poisson_ratio = tissue->poisson_ratio,
                          .stiffness_damping = tissue->stiffness_damping};
        if (sb_builder_add_tet(b, &def) < 0)
            return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding tetrahedra");
    }
    return SB_OK;
}

sb_status sb_builder_add_tet_mesh(sb_builder* b, const sb_tet_mesh* m, const sb_tissue_def* tissue, sb_error* err) {
    if (!isfinite(tissue->young_modulus) || tissue->young_modulus < 0.0 || !isfinite(tissue->density) ||
        tissue->density <= 0.0 || !isfinite(tissue->damping) || tissue->damping < 0.0 ||
        !isfinite(tissue->stiffness_damping) || tissue->stiffness_damping < 0.0)
        return sb_error_set(err, SB_ERR_INVALID,
                            "tissue: Young's modulus, damping and stiffness damping must be finite and >= 0, density "
                            "finite and > 0");
    if (tissue->model == SB_TISSUE_COROTATED && !(tissue->poisson_ratio > -1.0 && tissue->poisson_ratio < 0.5))
        return sb_error_set(err, SB_ERR_INVALID, "tissue: Poisson's ratio %g is not in (-1, 0.5)", tissue->poisson_ratio);
    if (tissue->model != SB_TISSUE_SPRINGS && tissue->model != SB_TISSUE_COROTATED)
        return sb_error_set(err, SB_ERR_INVALID, "tissue: unknown model %d", (int)tissue->model);
    sb_status status = sb_tet_mesh_check(m, err);
    if (status != SB_OK) return status;
    uint32_t first = sb_builder_vertex_count(b);
    double* mass = NULL;
    status = sb_tet_masses(m, tissue->density, &mass, err);
    if (status == SB_OK) status = sb_tet_vertices(b, m, mass, err);
    if (status == SB_OK)
        status = tissue->model == SB_TISSUE_COROTATED ? sb_tet_elements(b, first, m, tissue, err)
                                                      : sb_tet_springs(b, first, m, mass, tissue, err);
    free(mass);
    return status;
}
