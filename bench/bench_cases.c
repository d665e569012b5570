/* The benchmark cases: meshes, constants and time step (see bench_cases.h).
 *
 * Constants, with h the mean rest edge length:
 *   bond_k = 100 N/m, angle_k = 0.5 bond_k h² J, stretch_bend_k = 0.1 bond_k h J/m
 *   (ksb² < kθ kb / 2, so the energy stays convex near rest);
 *   --all-terms adds spring_k = bond_k, spring_damping = 0.02 √(kb m) and
 *   bend_k = 0.1 bond_k h² J/rad².
 * Mass: 0.1 kg/m² spread evenly over the vertices (one mass for all, so the
 * LAMMPS peer needs one atom type).
 * Time step: a Gershgorin bound on the stiffest vertex's Hessian. A vertex of
 * degree D sees at most 2 D kb from its bonds, 18 corners each adding at most
 * 4 kθ / h_min² (|∇c|² ≤ 4/h_min²) and 18 · 6 ksb / h_min from stretch-bend;
 * the springs and hinges of --all-terms add 2 D ks and 18 · 4 kbend / h_min².
 * dt = 0.8 · 2/ω with ω² = that bound / m: Verlet is stable for ω dt < 2,
 * and the bound is above the true highest frequency, so dt is at most 80 %
 * of the limit (far less in practice). 20 000 steps of the 10k cases stay
 * stable with the fast kernels and gravity. */
#include "bench/bench_cases.h"
#include "common/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define SB_BENCH_BOND_K 100.0
#define SB_BENCH_DENSITY 0.1       /* kg/m² */
#define SB_BENCH_SHEET_SIZE 1.0    /* m */
#define SB_BENCH_SPHERE_RADIUS 0.5 /* m */

/* Sheets keep the generator's row-major order, already local. Icospheres
 * are Morton-renumbered; the _unordered and _shuffled variants of the
 * largest keep the generator's numbering (each subdivision's midpoints
 * after the previous level's, triangles in subdivision order) or a random
 * one, to measure what the renumbering gains. */
const sb_bench_case sb_bench_cases[] = {
    {"sheet_10k", SB_BENCH_SHEET, 100, true, SB_BENCH_GENERATED},                   /* 10 000 vertices */
    {"icosphere_10k", SB_BENCH_ICOSPHERE, 5, true, SB_BENCH_MORTON},                /* 10 242 */
    {"sheet_100k", SB_BENCH_SHEET, 316, false, SB_BENCH_GENERATED},                 /* 99 856 */
    {"icosphere_164k", SB_BENCH_ICOSPHERE, 7, false, SB_BENCH_MORTON},              /* 163 842 (s = 6: 40 962) */
    {"sheet_1m", SB_BENCH_SHEET, 1000, false, SB_BENCH_GENERATED},                  /* 1 000 000 */
    {"icosphere_655k", SB_BENCH_ICOSPHERE, 8, false, SB_BENCH_MORTON},              /* 655 362 (s = 9: 2.6 M) */
    {"icosphere_655k_unordered", SB_BENCH_ICOSPHERE, 8, false, SB_BENCH_GENERATED}, /* generator numbering */
    {"icosphere_655k_shuffled", SB_BENCH_ICOSPHERE, 8, false, SB_BENCH_SHUFFLED},   /* random numbering */
};
const size_t sb_bench_case_count = sizeof sb_bench_cases / sizeof *sb_bench_cases;

const sb_bench_case* sb_bench_find_case(const char* name) {
    for (size_t i = 0; i < sb_bench_case_count; i++)
        if (strcmp(sb_bench_cases[i].name, name) == 0) return &sb_bench_cases[i];
    return NULL;
}

static double sb_distance(const double* p, const double* q) {
    double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* Mean and shortest edge over the triangles' edges (interior edges count
 * twice in the mean, which does not matter for a scale). Returns the area. */
static double sb_mesh_scales(const sb_mesh* m, double* mean, double* shortest) {
    double sum = 0.0, lo = INFINITY, area = 0.0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t* v = m->triangles + 3 * t;
        const double *p0 = m->positions + 3 * v[0], *p1 = m->positions + 3 * v[1], *p2 = m->positions + 3 * v[2];
        double l[3] = {sb_distance(p0, p1), sb_distance(p1, p2), sb_distance(p2, p0)};
        for (int c = 0; c < 3; c++) {
            sum += l[c];
            lo = fmin(lo, l[c]);
        }
        double s = 0.5 * (l[0] + l[1] + l[2]);
        area += sqrt(fmax(0.0, s * (s - l[0]) * (s - l[1]) * (s - l[2])));
    }
    *mean = sum / (3.0 * m->triangle_count);
    *shortest = lo;
    return area;
}

static uint32_t sb_max_degree(const sb_mesh* m) {
    uint32_t* count = calloc(m->vertex_count, sizeof *count);
    uint32_t best = 6;
    if (!count) return 12;
    for (size_t i = 0; i < 3 * (size_t)m->triangle_count; i++) count[m->triangles[i]]++;
    for (uint32_t i = 0; i < m->vertex_count; i++)
        if (count[i] > best) best = count[i]; /* triangles at a vertex ≥ its interior degree */
    free(count);
    return best + 1;
}

/* splitmix64: a fixed random sequence. */
static uint64_t sb_bench_random(uint64_t* state) {
    uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* Renumbers vertices and reorders triangles at random (Fisher-Yates). */
static sb_status sb_bench_shuffle(sb_mesh* mesh, sb_error* err) {
    uint32_t n = mesh->vertex_count, nt = mesh->triangle_count;
    uint32_t *perm = malloc(n * sizeof *perm), *inverse = malloc(n * sizeof *inverse);
    double* positions = malloc(3 * (size_t)n * sizeof *positions);
    if (!perm || !inverse || !positions) {
        free(perm);
        free(inverse);
        free(positions);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory shuffling %u vertices", n);
    }
    uint64_t state = 2024;
    for (uint32_t i = 0; i < n; i++) perm[i] = i;
    for (uint32_t i = n - 1; i > 0; i--) {
        uint32_t j = (uint32_t)(sb_bench_random(&state) % (i + 1)), t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
    for (uint32_t i = 0; i < n; i++) {
        memcpy(positions + 3 * (size_t)i, mesh->positions + 3 * (size_t)perm[i], 3 * sizeof *positions);
        inverse[perm[i]] = i;
    }
    memcpy(mesh->positions, positions, 3 * (size_t)n * sizeof *positions);
    for (size_t k = 0; k < 3 * (size_t)nt; k++) mesh->triangles[k] = inverse[mesh->triangles[k]];
    for (uint32_t i = nt - 1; nt > 1 && i > 0; i--) {
        uint32_t j = (uint32_t)(sb_bench_random(&state) % (i + 1));
        for (int c = 0; c < 3; c++) {
            uint32_t t = mesh->triangles[3 * (size_t)i + c];
            mesh->triangles[3 * (size_t)i + c] = mesh->triangles[3 * (size_t)j + c];
            mesh->triangles[3 * (size_t)j + c] = t;
        }
    }
    free(perm);
    free(inverse);
    free(positions);
    return SB_OK;
}

static sb_status sb_generate(const sb_bench_case* c, const sb_bench_options* o, sb_mesh* mesh, sb_error* err) {
    sb_status status;
    if (c->shape == SB_BENCH_ICOSPHERE) {
        status = sb_mesh_generate_icosphere(c->size, SB_BENCH_SPHERE_RADIUS, mesh, err);
    } else {
        sb_sheet_def def = sb_default_sheet_def();
        def.nx = def.ny = c->size;
        def.width = def.height = SB_BENCH_SHEET_SIZE;
        def.jitter = o->jitter;
        def.seed = 12345;
        status = sb_mesh_generate_sheet(&def, mesh, err);
    }
    /* sheets are never renumbered: their pins are found by row-major index */
    if (status == SB_OK && c->order == SB_BENCH_MORTON) status = sb_mesh_reorder(mesh, NULL, err);
    if (status == SB_OK && c->order == SB_BENCH_SHUFFLED) status = sb_bench_shuffle(mesh, err);
    return status;
}

sb_status sb_bench_prepare(const sb_bench_case* c, const sb_bench_options* o, sb_bench_setup* s, sb_error* err) {
    memset(s, 0, sizeof *s);
    sb_status status = sb_generate(c, o, &s->mesh, err);
    if (status != SB_OK) return status;
    double h, h_min, area = sb_mesh_scales(&s->mesh, &h, &h_min);
    double kb = SB_BENCH_BOND_K, m = SB_BENCH_DENSITY * area / s->mesh.vertex_count;
    sb_material_def mat = sb_default_material_def();
    mat.bond_k = kb;
    mat.angle_k = 0.5 * kb * h * h;
    mat.stretch_bend_k = 0.1 * kb * h;
    mat.spring_k = o->all_terms ? kb : 0.0;
    mat.spring_damping = o->all_terms ? 0.02 * sqrt(kb * m) : 0.0;
    mat.bend_k = o->all_terms ? 0.1 * kb * h * h : 0.0;
    mat.mass = m;
    mat.density = 0.0;
    double degree = sb_max_degree(&s->mesh), inv_h2 = 1.0 / (h_min * h_min);
    double bound = 2.0 * degree * (mat.bond_k + mat.spring_k) + 18.0 * 4.0 * (mat.angle_k + mat.bend_k) * inv_h2 +
                   18.0 * 6.0 * mat.stretch_bend_k / h_min;
    s->material = mat;
    s->edge_length = h;
    s->dt = 0.8 * 2.0 / sqrt(bound / m);
    if (c->shape == SB_BENCH_SHEET) { /* the two corners of the top row: the sheet hangs from them */
        s->pins[0] = (c->size - 1) * c->size;
        s->pins[1] = c->size * c->size - 1;
        s->pin_count = 2;
    }
    return SB_OK;
}

sb_status sb_bench_build(const sb_bench_case* c, const sb_bench_options* o, sb_bench_setup* s, sb_error* err) {
    sb_status status = sb_bench_prepare(c, o, s, err);
    if (status != SB_OK) return status;
    sb_builder* b = sb_builder_create();
    if (!b) return sb_error_set(err, SB_ERR_NOMEM, "out of memory creating a builder");
    status = sb_builder_add_mesh(b, &s->mesh, &s->material, err);
    for (uint32_t p = 0; status == SB_OK && p < s->pin_count; p++) sb_builder_vertex(b, s->pins[p])->fixed = true;
    if (status == SB_OK) {
        s->model = sb_builder_compile(b, err);
        if (!s->model) status = SB_ERR_INVALID;
    }
    sb_builder_destroy(b);
    return status;
}

void sb_bench_setup_free(sb_bench_setup* s) {
    sb_model_destroy(s->model);
    sb_mesh_free(&s->mesh);
    memset(s, 0, sizeof *s);
}
