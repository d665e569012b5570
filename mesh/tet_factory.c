/* The volumetric mass-spring factory (Sudhamani & Merriliance 2019, after
 * Lloyd, Székely & Harders 2007): masses from the density, spring
 * stiffness from Young's modulus, damping from the documented rule and
 * Rayleigh's stiffness-proportional β. See
 * include/softbond/volume.h for the formulas and the materials. */
#include "mesh/builder_internal.h"
#include "mesh/tet_edges.h"
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

static double sb_distance3(const double* p, const double* q) {
    double dx = q[0] - p[0], dy = q[1] - p[1], dz = q[2] - p[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static double sb_tet_mesh_volume(const sb_tet_mesh* m, uint32_t t) {
    const uint32_t* v = m->tets + 4 * (size_t)t;
    const double* p = m->positions;
    return fabs(sb_tet_volume(p + 3 * (size_t)v[0], p + 3 * (size_t)v[1], p + 3 * (size_t)v[2], p + 3 * (size_t)v[3]));
}

/* Σ over tetrahedra of (√2/25) l_t E per unique edge (numbered as edges). */
static double* sb_tet_spring_constants(const sb_tet_mesh* m, const sb_tet_edge_set* edges, double modulus) {
    double* k = calloc(edges->count ? edges->count : 1, sizeof *k);
    for (uint32_t t = 0; k && t < m->tet_count; t++) {
        double length = cbrt(6.0 * sqrt(2.0) * sb_tet_mesh_volume(m, t)); /* the regular tetrahedron's edge */
        for (int e = 0; e < 6; e++) k[edges->of_tet[6 * (size_t)t + e]] += sqrt(2.0) / 25.0 * length * modulus;
    }
    return k;
}

/* The lumped masses: ρ V / 4 to each corner (linear: the springs' and the
 * linear elements'), or the quadratic element's HRZ lumping (Hinton, Rock
 * & Zienkiewicz 1976: the consistent mass matrix's diagonal, 6/420 ρV at a
 * corner and 32/420 ρV at a middle, scaled to the element's mass): ρ V / 36
 * to each corner and 4 ρ V / 27 to each middle, all positive. mass has the
 * corners, then (quadratic) the middles; none may be left at 0. */
static sb_status sb_tet_masses(const sb_tet_mesh* m, const sb_tet_edge_set* edges, double density, double** out,
                               sb_error* err) {
    size_t count = (size_t)m->vertex_count + (edges ? edges->count : 0);
    double* mass = calloc(count ? count : 1, sizeof *mass);
    if (!mass) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    double corner_share = edges ? 1.0 / 36.0 : 0.25, middle_share = 4.0 / 27.0;
    for (uint32_t t = 0; t < m->tet_count; t++) {
        double element = density * sb_tet_mesh_volume(m, t);
        for (int c = 0; c < 4; c++) mass[m->tets[4 * (size_t)t + c]] += corner_share * element;
        for (int e = 0; edges && e < 6; e++)
            mass[m->vertex_count + edges->of_tet[6 * (size_t)t + e]] += middle_share * element;
    }
    for (uint32_t i = 0; i < m->vertex_count; i++)
        if (mass[i] <= 0.0) {
            free(mass);
            return sb_error_set(err, SB_ERR_INVALID, "vertex %u belongs to no tetrahedron: it would have no mass", i);
        }
    *out = mass;
    return SB_OK;
}

/* A vertex per mesh vertex, then (quadratic) one at each edge's middle. */
static sb_status sb_tet_vertices(sb_builder* b, const sb_tet_mesh* m, const sb_tet_edge_set* edges, const double* mass,
                                 sb_error* err) {
    uint32_t count = m->vertex_count + (edges ? edges->count : 0);
    for (uint32_t i = 0; i < count; i++) {
        sb_vertex_def def = sb_default_vertex_def();
        if (i < m->vertex_count) {
            memcpy(def.position, m->positions + 3 * (size_t)i, sizeof def.position);
        } else {
            const uint32_t* ends = edges->ends + 2 * (size_t)(i - m->vertex_count);
            for (int k = 0; k < 3; k++)
                def.position[k] = 0.5 * (m->positions[3 * (size_t)ends[0] + k] + m->positions[3 * (size_t)ends[1] + k]);
        }
        def.mass = mass[i];
        if (sb_builder_add_vertex(b, &def) < 0) return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding vertices");
    }
    return SB_OK;
}

static sb_status sb_tet_springs(sb_builder* b, uint32_t first, const sb_tet_mesh* m, const sb_tet_edge_set* edges,
                                const double* mass, const sb_tissue_def* tissue, sb_error* err) {
    double* k = sb_tet_spring_constants(m, edges, tissue->young_modulus);
    if (!k) return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding springs");
    sb_status status = SB_OK;
    for (uint32_t e = 0; e < edges->count && status == SB_OK; e++) {
        uint32_t a = edges->ends[2 * (size_t)e], c = edges->ends[2 * (size_t)e + 1];
        double l0 = sb_distance3(m->positions + 3 * (size_t)a, m->positions + 3 * (size_t)c);
        sb_bond_def def = sb_default_bond_def();
        def.i = first + a;
        def.j = first + c;
        def.rest_length = -1.0;
        def.k = 0.0;
        def.spring_k = k[e];
        def.spring_damping = tissue->damping * sqrt(k[e] * (mass[a] + mass[c])) / l0 + tissue->stiffness_damping * k[e];
        if (sb_builder_add_bond(b, &def) < 0) status = sb_error_set(err, SB_ERR_NOMEM, "out of memory adding springs");
    }
    free(k);
    return status;
}

/* The finite elements; quadratic when edges is given (its middles numbered
 * after the mesh's vertices). */
static sb_status sb_tet_elements(sb_builder* b, uint32_t first, const sb_tet_mesh* m, const sb_tet_edge_set* edges,
                                 const sb_tissue_def* tissue, sb_error* err) {
    for (uint32_t t = 0; t < m->tet_count; t++) {
        const uint32_t* v = m->tets + 4 * (size_t)t;
        sb_tet_def def = {.v = {first + v[0], first + v[1], first + v[2], first + v[3]},
                          .young_modulus = tissue->young_modulus,
                          .poisson_ratio = tissue->poisson_ratio,
                          .stiffness_damping = tissue->stiffness_damping,
                          .quadratic = edges != NULL};
        for (int e = 0; edges && e < 6; e++) def.mid[e] = first + m->vertex_count + edges->of_tet[6 * (size_t)t + e];
        if (sb_builder_add_tet(b, &def) < 0) return sb_error_set(err, SB_ERR_NOMEM, "out of memory adding tetrahedra");
    }
    return SB_OK;
}

/* The mesh's boundary as faces (the quadratic tissue's split at its
 * edges' middle vertices), so that the colliders stop at its surface
 * between vertices. */
static sb_status sb_tet_faces_add(sb_builder* b, uint32_t first, const sb_tet_mesh* m, bool quadratic, sb_error* err) {
    sb_mesh surface;
    sb_status status =
        quadratic ? sb_tet_mesh_quadratic_surface(m, &surface, err) : sb_tet_mesh_surface(m, &surface, err);
    for (uint32_t t = 0; status == SB_OK && t < surface.triangle_count; t++) {
        uint32_t v[3];
        for (int c = 0; c < 3; c++) v[c] = first + surface.triangles[3 * (size_t)t + c];
        if (sb_builder_add_face(b, v) < 0) status = sb_error_set(err, SB_ERR_NOMEM, "out of memory adding the surface");
    }
    sb_mesh_free(&surface);
    return status;
}

static bool sb_tissue_elements(sb_tissue_model model) {
    return model == SB_TISSUE_COROTATED || model == SB_TISSUE_COROTATED_QUADRATIC;
}

sb_status sb_builder_add_tet_mesh(sb_builder* b, const sb_tet_mesh* m, const sb_tissue_def* tissue, sb_error* err) {
    if (!isfinite(tissue->young_modulus) || tissue->young_modulus < 0.0 || !isfinite(tissue->density) ||
        tissue->density <= 0.0 || !isfinite(tissue->damping) || tissue->damping < 0.0 ||
        !isfinite(tissue->stiffness_damping) || tissue->stiffness_damping < 0.0)
        return sb_error_set(err, SB_ERR_INVALID,
                            "tissue: Young's modulus, damping and stiffness damping must be finite and >= 0, density "
                            "finite and > 0");
    if (tissue->model != SB_TISSUE_SPRINGS && !sb_tissue_elements(tissue->model))
        return sb_error_set(err, SB_ERR_INVALID, "tissue: unknown model %d", (int)tissue->model);
    if (sb_tissue_elements(tissue->model) && !(tissue->poisson_ratio > -1.0 && tissue->poisson_ratio < 0.5))
        return sb_error_set(err, SB_ERR_INVALID, "tissue: Poisson's ratio %g is not in (-1, 0.5)",
                            tissue->poisson_ratio);
    sb_status status = sb_tet_mesh_check(m, err);
    if (status != SB_OK) return status;
    uint32_t first = sb_builder_vertex_count(b);
    bool quadratic = tissue->model == SB_TISSUE_COROTATED_QUADRATIC;
    sb_tet_edge_set edges;
    status = sb_tet_edge_set_find(m, &edges, err);
    double* mass = NULL;
    if (status == SB_OK) status = sb_tet_masses(m, quadratic ? &edges : NULL, tissue->density, &mass, err);
    if (status == SB_OK) status = sb_tet_vertices(b, m, quadratic ? &edges : NULL, mass, err);
    if (status == SB_OK)
        status = sb_tissue_elements(tissue->model)
                     ? sb_tet_elements(b, first, m, quadratic ? &edges : NULL, tissue, err)
                     : sb_tet_springs(b, first, m, &edges, mass, tissue, err);
    if (status == SB_OK) status = sb_tet_faces_add(b, first, m, quadratic, err);
    free(mass);
    sb_tet_edge_set_free(&edges);
    return status;
}
