/* sb_lammps_export: writes one benchmark case (bench/bench_cases.c: the same
 * generator, constants and time step as sb_bench) as a LAMMPS data file for
 * atom_style angle, plus LAMMPS commands (time step, cutoffs, the pinned
 * atoms' group) that the input script includes after read_data.
 *
 *   sb_lammps_export [--jitter J] CASE DIR   →  DIR/CASE.data, DIR/CASE.settings
 *
 * Atoms are the vertices (ID = vertex + 1, one molecule, one atom type with
 * the case's uniform mass); bonds are the unique edges; angles are the three
 * corners of every triangle, the corner vertex in the middle.
 *
 * Rest values. LAMMPS' bond_style harmonic and angle_style cosine/squared
 * take r0 and θ0 per type, not per bond, so bonds (and angles) are grouped
 * into types by rest value: values within 1e-9 of the mean edge length (or
 * 1e-9 in cos θ) share a type. An unjittered sheet then has 2 bond types
 * (spacing and diagonal) and 2 angle types (45° and 90°), an icosphere one
 * type per symmetry orbit (about edges / 60); a jittered sheet would need a
 * type per bond, which LAMMPS accepts but reads slowly, so run.sh exports
 * sheets without jitter (--jitter 0). The per-step cost depends on the
 * topology and not on the values, so the comparison stays like for like.
 *
 * Coefficients (DESIGN.md): bond K = kb/2 (E = K (r − r0)²), angle
 * K = kθ/2 (E = K (cos θ − cos θ0)², θ0 in degrees). The stretch-bend term
 * has no LAMMPS style and is left out of the peer's step. */
#include "bench/bench_cases.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SB_PI 3.14159265358979323846

typedef struct sb_edge {
    uint32_t a, b;
} sb_edge;

static int sb_edge_compare(const void* p, const void* q) {
    const sb_edge *x = p, *y = q;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    return (x->b > y->b) - (x->b < y->b);
}

/* Unique edges of the mesh, each with a < b. */
static sb_edge* sb_unique_edges(const sb_mesh* m, size_t* count) {
    size_t n = 3 * (size_t)m->triangle_count, u = 0;
    sb_edge* e = malloc(n * sizeof *e);
    if (!e) return NULL;
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            uint32_t p = m->triangles[3 * t + c], q = m->triangles[3 * t + (c + 1) % 3];
            e[3 * t + c] = (sb_edge){p < q ? p : q, p < q ? q : p};
        }
    qsort(e, n, sizeof *e, sb_edge_compare);
    for (size_t i = 0; i < n; i++)
        if (u == 0 || sb_edge_compare(&e[u - 1], &e[i]) != 0) e[u++] = e[i];
    *count = u;
    return e;
}

static const double* sb_sort_values;
static int sb_index_compare(const void* p, const void* q) {
    double x = sb_sort_values[*(const size_t*)p], y = sb_sort_values[*(const size_t*)q];
    return (x > y) - (x < y);
}

/* Groups values into types: type[i] in 1..*type_count, type_value[t - 1]
 * the first (smallest) value of type t. */
static double* sb_assign_types(const double* values, size_t n, double tolerance, uint32_t* type, size_t* type_count) {
    size_t* order = malloc(n * sizeof *order);
    double* type_value = malloc(n * sizeof *type_value);
    if (!order || !type_value) {
        free(order);
        free(type_value);
        return NULL;
    }
    for (size_t i = 0; i < n; i++) order[i] = i;
    sb_sort_values = values;
    qsort(order, n, sizeof *order, sb_index_compare);
    size_t types = 0;
    for (size_t k = 0; k < n; k++) {
        double v = values[order[k]];
        if (types == 0 || v - type_value[types - 1] > tolerance) type_value[types++] = v;
        type[order[k]] = (uint32_t)types;
    }
    free(order);
    *type_count = types;
    return type_value;
}

static double sb_length(const double* p, const double* q) {
    double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

/* Cosine of the angle at p between p→q and p→r. */
static double sb_corner_cosine(const double* p, const double* q, const double* r) {
    double a[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, b[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    return (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) / (sb_length(p, q) * sb_length(p, r));
}

static void sb_write_box(FILE* f, const sb_mesh* m, double margin) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < m->vertex_count; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], m->positions[3 * i + c]);
            hi[c] = fmax(hi[c], m->positions[3 * i + c]);
        }
    const char* axis[3] = {"x", "y", "z"};
    for (int c = 0; c < 3; c++) fprintf(f, "%.17g %.17g %slo %shi\n", lo[c] - margin, hi[c] + margin, axis[c], axis[c]);
}

typedef struct sb_export {
    const sb_bench_setup* s;
    sb_edge* edges;
    size_t edge_count;
    uint32_t *bond_type, *angle_type;
    double *bond_r0, *angle_cos0; /* per type */
    size_t bond_types, angle_types;
} sb_export;

static int sb_write_data(const char* path, const char* name, const sb_export* x) {
    const sb_mesh* m = &x->s->mesh;
    FILE* f = fopen(path, "w");
    if (!f) return 1;
    fprintf(f, "LAMMPS data file: softbond benchmark case %s\n\n", name);
    fprintf(f, "%u atoms\n%zu bonds\n%zu angles\n1 atom types\n%zu bond types\n%zu angle types\n\n", m->vertex_count,
            x->edge_count, 3 * (size_t)m->triangle_count, x->bond_types, x->angle_types);
    sb_write_box(f, m, 2.0 * x->s->edge_length);
    fprintf(f, "\nMasses\n\n1 %.17g\n", x->s->material.mass);
    fprintf(f, "\nBond Coeffs # harmonic\n\n");
    for (size_t t = 0; t < x->bond_types; t++)
        fprintf(f, "%zu %.17g %.17g\n", t + 1, 0.5 * x->s->material.bond_k, x->bond_r0[t]);
    fprintf(f, "\nAngle Coeffs # cosine/squared\n\n");
    for (size_t t = 0; t < x->angle_types; t++)
        fprintf(f, "%zu %.17g %.17g\n", t + 1, 0.5 * x->s->material.angle_k,
                acos(fmax(-1.0, fmin(1.0, x->angle_cos0[t]))) * 180.0 / SB_PI);
    fprintf(f, "\nAtoms # angle\n\n");
    for (uint32_t i = 0; i < m->vertex_count; i++)
        fprintf(f, "%u 1 1 %.17g %.17g %.17g\n", i + 1, m->positions[3 * i], m->positions[3 * i + 1],
                m->positions[3 * i + 2]);
    fprintf(f, "\nBonds\n\n");
    for (size_t e = 0; e < x->edge_count; e++)
        fprintf(f, "%zu %u %u %u\n", e + 1, x->bond_type[e], x->edges[e].a + 1, x->edges[e].b + 1);
    fprintf(f, "\nAngles\n\n");
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            const uint32_t* v = m->triangles + 3 * t;
            fprintf(f, "%zu %u %u %u %u\n", 3 * t + c + 1, x->angle_type[3 * t + c], v[(c + 1) % 3] + 1, v[c] + 1,
                    v[(c + 2) % 3] + 1);
        }
    return fclose(f) != 0;
}

static double sb_max_edge(const sb_export* x) {
    double longest = 0.0;
    for (size_t t = 0; t < x->bond_types; t++) longest = fmax(longest, x->bond_r0[t]);
    return longest;
}

/* LAMMPS commands for after read_data: the time step, ghost cutoff and
 * skin as variables, and the groups "pins" and "mobile" (everything else). */
static int sb_write_settings(const char* path, const sb_export* x) {
    FILE* f = fopen(path, "w");
    if (!f) return 1;
    double longest = sb_max_edge(x);
    fprintf(f, "# generated by sb_lammps_export\n");
    fprintf(f, "variable sb_dt equal %.17g\n", x->s->dt);
    fprintf(f, "variable sb_cutoff equal %.17g\n", 3.0 * longest);
    fprintf(f, "variable sb_skin equal %.17g\n", longest);
    fprintf(f, "variable sb_gravity equal %.17g\n", SB_BENCH_GRAVITY);
    if (x->s->pin_count == 0) {
        fprintf(f, "group mobile union all\n");
        return fclose(f) != 0;
    }
    fprintf(f, "group pins id");
    for (uint32_t p = 0; p < x->s->pin_count; p++) fprintf(f, " %u", x->s->pins[p] + 1);
    fprintf(f, "\ngroup mobile subtract all pins\n");
    return fclose(f) != 0;
}

static bool sb_classify(sb_export* x) {
    const sb_mesh* m = &x->s->mesh;
    size_t angles = 3 * (size_t)m->triangle_count;
    double* r0 = malloc(x->edge_count * sizeof *r0);
    double* c0 = malloc(angles * sizeof *c0);
    x->bond_type = malloc(x->edge_count * sizeof *x->bond_type);
    x->angle_type = malloc(angles * sizeof *x->angle_type);
    bool ok = r0 && c0 && x->bond_type && x->angle_type;
    for (size_t e = 0; ok && e < x->edge_count; e++)
        r0[e] = sb_length(m->positions + 3 * x->edges[e].a, m->positions + 3 * x->edges[e].b);
    for (size_t t = 0; ok && t < m->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            const uint32_t* v = m->triangles + 3 * t;
            c0[3 * t + c] = sb_corner_cosine(m->positions + 3 * v[c], m->positions + 3 * v[(c + 1) % 3],
                                             m->positions + 3 * v[(c + 2) % 3]);
        }
    if (ok) x->bond_r0 = sb_assign_types(r0, x->edge_count, 1e-9 * x->s->edge_length, x->bond_type, &x->bond_types);
    if (ok) x->angle_cos0 = sb_assign_types(c0, angles, 1e-9, x->angle_type, &x->angle_types);
    free(r0);
    free(c0);
    return ok && x->bond_r0 && x->angle_cos0;
}

int main(int argc, char** argv) {
    sb_bench_options o = {.all_terms = false, .jitter = SB_BENCH_DEFAULT_JITTER};
    int a = 1;
    if (a + 1 < argc && strcmp(argv[a], "--jitter") == 0) {
        o.jitter = atof(argv[a + 1]);
        a += 2;
    }
    if (argc - a != 2) {
        fprintf(stderr, "usage: sb_lammps_export [--jitter J] CASE DIR\n");
        return 2;
    }
    const sb_bench_case* c = sb_bench_find_case(argv[a]);
    if (!c) {
        fprintf(stderr, "sb_lammps_export: unknown case '%s'\n", argv[a]);
        return 2;
    }
    sb_bench_setup s;
    sb_error err = {{0}};
    if (sb_bench_prepare(c, &o, &s, &err) != SB_OK) {
        fprintf(stderr, "sb_lammps_export: %s: %s\n", c->name, err.message);
        return 1;
    }
    sb_export x = {.s = &s};
    x.edges = sb_unique_edges(&s.mesh, &x.edge_count);
    if (!x.edges || !sb_classify(&x)) {
        fprintf(stderr, "sb_lammps_export: out of memory\n");
        return 1;
    }
    char data[4096], vars[4096];
    snprintf(data, sizeof data, "%s/%s.data", argv[a + 1], c->name);
    snprintf(vars, sizeof vars, "%s/%s.settings", argv[a + 1], c->name);
    if (sb_write_data(data, c->name, &x) || sb_write_settings(vars, &x)) {
        fprintf(stderr, "sb_lammps_export: cannot write %s or %s\n", data, vars);
        return 1;
    }
    printf("%s vertices=%u bonds=%zu angles=%zu bond_types=%zu angle_types=%zu dt=%.6g\n", c->name, s.mesh.vertex_count,
           x.edge_count, 3 * (size_t)s.mesh.triangle_count, x.bond_types, x.angle_types, s.dt);
    free(x.edges);
    free(x.bond_type);
    free(x.angle_type);
    free(x.bond_r0);
    free(x.angle_cos0);
    sb_bench_setup_free(&s);
    return 0;
}
