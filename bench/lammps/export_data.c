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
 * has no LAMMPS style and is left out of the peer's step.
 *
 * --all-terms (sb_bench's: the damped spring and the hinge bend, and the
 * time step that comes with them) writes an atom_style molecular file:
 * the spring's elastic part ½ ks (r − r0)² joins the harmonic bond
 * (K = (kb + ks)/2; its damping has no bond style and is left out), and
 * every interior edge is a dihedral o0 e0 e1 o1 of dihedral_style table,
 * DIR/CASE.hinge.table tabulating ½ k_bend (φ − φ0)² in LAMMPS' angle. LAMMPS
 * measures φ_L = 180° when the two wings lie flat on opposite sides of the
 * edge (trans) and 0 when folded onto each other, so softbond's
 * |φ| = 180° − |φ_L| and, with φ0 = 0 (a flat rest, the only one this
 * exporter accepts), E = ½ k_bend (π − |φ_L|)², whatever the sign
 * conventions. It also writes DIR/CASE.bent.data, the same file with the
 * sheet bent (a wave across it and a random fold at every vertex), and
 * prints softbond's reference energies of that state for bench/lammps/run.sh
 * to compare with LAMMPS' before it times anything. */
#include "bench/bench_cases.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SB_PI 3.14159265358979323846

/* An edge a < b, as a side of triangle `opposite`'s vertex. */
typedef struct sb_edge {
    uint32_t a, b;
    uint32_t opposite;
} sb_edge;

static int sb_edge_compare(const void* p, const void* q) {
    const sb_edge *x = p, *y = q;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    return (x->b > y->b) - (x->b < y->b);
}

/* Every triangle's three sides, sorted by edge: an interior edge appears
 * twice in a row, with the two wings' opposite vertices. */
static sb_edge* sb_sorted_sides(const sb_mesh* m) {
    size_t n = 3 * (size_t)m->triangle_count;
    sb_edge* e = malloc(n * sizeof *e);
    if (!e) return NULL;
    for (size_t t = 0; t < m->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            const uint32_t* v = m->triangles + 3 * t;
            uint32_t p = v[c], q = v[(c + 1) % 3];
            e[3 * t + c] = (sb_edge){p < q ? p : q, p < q ? q : p, v[(c + 2) % 3]};
        }
    qsort(e, n, sizeof *e, sb_edge_compare);
    return e;
}

/* Unique edges from the sorted sides, each with a < b. */
static sb_edge* sb_unique_edges(const sb_edge* sides, size_t n, size_t* count) {
    size_t u = 0;
    sb_edge* e = malloc(n * sizeof *e);
    if (!e) return NULL;
    for (size_t i = 0; i < n; i++)
        if (u == 0 || sb_edge_compare(&e[u - 1], &sides[i]) != 0) e[u++] = sides[i];
    *count = u;
    return e;
}

/* Hinges (o0, e0, e1, o1), LAMMPS' dihedral order, from the sorted sides. */
static uint32_t* sb_hinges(const sb_edge* sides, size_t n, size_t* count) {
    uint32_t* h = malloc(2 * n * sizeof *h);
    size_t k = 0;
    if (!h) return NULL;
    for (size_t i = 0; i + 1 < n; i++)
        if (sb_edge_compare(&sides[i], &sides[i + 1]) == 0) {
            uint32_t* d = h + 4 * k++;
            d[0] = sides[i].opposite, d[1] = sides[i].a, d[2] = sides[i].b, d[3] = sides[i + 1].opposite;
        }
    *count = k;
    return h;
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

static void sb_write_box(FILE* f, const double* positions, uint32_t count, double margin) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < count; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], positions[3 * i + c]);
            hi[c] = fmax(hi[c], positions[3 * i + c]);
        }
    const char* axis[3] = {"x", "y", "z"};
    for (int c = 0; c < 3; c++) fprintf(f, "%.17g %.17g %slo %shi\n", lo[c] - margin, hi[c] + margin, axis[c], axis[c]);
}

typedef struct sb_export {
    const sb_bench_setup* s;
    bool all_terms;
    sb_edge* edges;
    size_t edge_count;
    uint32_t* hinges; /* 4 per hinge, with all_terms */
    size_t hinge_count;
    uint32_t *bond_type, *angle_type;
    double *bond_r0, *angle_cos0; /* per type */
    size_t bond_types, angle_types;
} sb_export;

/* The data file, with the atoms at `positions` (the rest values, and so
 * the types, are always the mesh's). */
static int sb_write_data(const char* path, const char* name, const sb_export* x, const double* positions) {
    const sb_mesh* m = &x->s->mesh;
    const sb_material_def* mat = &x->s->material;
    FILE* f = fopen(path, "w");
    if (!f) return 1;
    fprintf(f, "LAMMPS data file: softbond benchmark case %s\n\n", name);
    fprintf(f, "%u atoms\n%zu bonds\n%zu angles\n", m->vertex_count, x->edge_count, 3 * (size_t)m->triangle_count);
    if (x->all_terms) fprintf(f, "%zu dihedrals\n", x->hinge_count);
    fprintf(f, "1 atom types\n%zu bond types\n%zu angle types\n", x->bond_types, x->angle_types);
    if (x->all_terms) fprintf(f, "1 dihedral types\n");
    fprintf(f, "\n");
    sb_write_box(f, positions, m->vertex_count, 2.0 * x->s->edge_length);
    fprintf(f, "\nMasses\n\n1 %.17g\n", mat->mass);
    fprintf(f, "\nBond Coeffs # harmonic\n\n");
    for (size_t t = 0; t < x->bond_types; t++)
        fprintf(f, "%zu %.17g %.17g\n", t + 1, 0.5 * (mat->bond_k + mat->spring_k), x->bond_r0[t]);
    fprintf(f, "\nAngle Coeffs # cosine/squared\n\n");
    for (size_t t = 0; t < x->angle_types; t++)
        fprintf(f, "%zu %.17g %.17g\n", t + 1, 0.5 * mat->angle_k,
                acos(fmax(-1.0, fmin(1.0, x->angle_cos0[t]))) * 180.0 / SB_PI);
    fprintf(f, "\nAtoms # %s\n\n", x->all_terms ? "molecular" : "angle");
    for (uint32_t i = 0; i < m->vertex_count; i++)
        fprintf(f, "%u 1 1 %.17g %.17g %.17g\n", i + 1, positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
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
    if (x->all_terms) {
        fprintf(f, "\nDihedrals\n\n");
        for (size_t h = 0; h < x->hinge_count; h++) {
            const uint32_t* d = x->hinges + 4 * h;
            fprintf(f, "%zu 1 %u %u %u %u\n", h + 1, d[0] + 1, d[1] + 1, d[2] + 1, d[3] + 1);
        }
    }
    return fclose(f) != 0;
}

/* The hinge's ½ k (π − |φ_L|)² at every half degree of LAMMPS' angle
 * (−180° included, 180° not: the table is cyclic), energies only (NOF:
 * LAMMPS takes the derivative from its spline). */
#define SB_HINGE_TABLE_POINTS 720
static int sb_write_hinge_table(const char* path, double k) {
    FILE* f = fopen(path, "w");
    if (!f) return 1;
    fprintf(f, "# generated by sb_lammps_export: softbond's hinge 1/2 k (phi - phi0)^2, phi0 = 0, in LAMMPS' angle\n");
    fprintf(f, "HINGE\nN %d NOF DEGREES\n\n", SB_HINGE_TABLE_POINTS);
    for (int i = 0; i < SB_HINGE_TABLE_POINTS; i++) {
        double degrees = -180.0 + 360.0 * i / SB_HINGE_TABLE_POINTS, bend = SB_PI - fabs(degrees) * SB_PI / 180.0;
        fprintf(f, "%d %.17g %.17g\n", i + 1, degrees, 0.5 * k * bend * bend);
    }
    return fclose(f) != 0;
}

static double sb_max_edge(const sb_export* x) {
    double longest = 0.0;
    for (size_t t = 0; t < x->bond_types; t++) longest = fmax(longest, x->bond_r0[t]);
    return longest;
}

/* LAMMPS commands for after read_data: the hinge table (with all terms),
 * the time step, ghost cutoff and skin as variables, and the groups "pins"
 * and "mobile" (everything else). */
static int sb_write_settings(const char* path, const char* name, const sb_export* x) {
    FILE* f = fopen(path, "w");
    if (!f) return 1;
    double longest = sb_max_edge(x);
    fprintf(f, "# generated by sb_lammps_export\n");
    if (x->all_terms) fprintf(f, "dihedral_coeff 1 %s.hinge.table HINGE\n", name);
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

/* The sheet bent: a wave of 5 cm across it (z = 0.05 sin 4πx cos 2πy) and
 * at every vertex a random move of up to 0.2 h out of the plane and 0.05 h
 * in it, so that every bond, corner and hinge is strained. */
static double* sb_bent_positions(const sb_bench_setup* s) {
    const sb_mesh* m = &s->mesh;
    double* x = malloc(3 * (size_t)m->vertex_count * sizeof *x);
    if (!x) return NULL;
    uint64_t state = 0x9e3779b97f4a7c15ull;
    for (uint32_t i = 0; i < m->vertex_count; i++) {
        const double* p = m->positions + 3 * i;
        double u[3];
        for (int c = 0; c < 3; c++) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            u[c] = (double)(state >> 11) / 9007199254740992.0 * 2.0 - 1.0; /* [-1, 1) */
        }
        x[3 * i] = p[0] + 0.05 * s->edge_length * u[0];
        x[3 * i + 1] = p[1] + 0.05 * s->edge_length * u[1];
        x[3 * i + 2] = p[2] + 0.05 * sin(4.0 * SB_PI * p[0]) * cos(2.0 * SB_PI * p[1]) + 0.2 * s->edge_length * u[2];
    }
    return x;
}

/* Writes DIR/CASE.bent.data and prints softbond's reference energies of
 * that state, in LAMMPS' grouping: bond (stretch + the spring's elastic
 * part), angle, dihedral (the hinges). */
static int sb_write_bent(const char* path, const char* name, const sb_export* x) {
    const sb_bench_setup* s = x->s;
    size_t n = 3 * (size_t)s->mesh.vertex_count;
    double* bent = sb_bent_positions(s);
    double *velocities = calloc(n, sizeof *velocities), *forces = malloc(n * sizeof *forces);
    sb_energies e;
    sb_error err = {{0}};
    int failed = !bent || !velocities || !forces || sb_write_data(path, name, x, bent) ||
                 sb_reference_forces(s->model, bent, velocities, forces, &e, &err) != SB_OK;
    if (!failed)
        printf("bent %s: softbond energies bond=%.17g angle=%.17g dihedral=%.17g (stretch-bend %.6g J not in LAMMPS)\n",
               name, e.term[SB_TERM_BOND] + e.term[SB_TERM_SPRING], e.term[SB_TERM_ANGLE], e.term[SB_TERM_BEND],
               e.term[SB_TERM_STRETCH_BEND]);
    else if (err.message[0])
        fprintf(stderr, "sb_lammps_export: %s: %s\n", name, err.message);
    free(bent);
    free(velocities);
    free(forces);
    return failed;
}

/* Writes DIR/CASE.data, .settings and, with all terms, .hinge.table and
 * .bent.data. */
static int sb_write_files(const char* dir, const char* name, const sb_export* x) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.data", dir, name);
    if (sb_write_data(path, name, x, x->s->mesh.positions)) return 1;
    snprintf(path, sizeof path, "%s/%s.settings", dir, name);
    if (sb_write_settings(path, name, x)) return 1;
    if (!x->all_terms) return 0;
    snprintf(path, sizeof path, "%s/%s.hinge.table", dir, name);
    if (sb_write_hinge_table(path, x->s->material.bend_k)) return 1;
    snprintf(path, sizeof path, "%s/%s.bent.data", dir, name);
    return sb_write_bent(path, name, x);
}

int main(int argc, char** argv) {
    sb_bench_options o = {.all_terms = false, .jitter = SB_BENCH_DEFAULT_JITTER};
    int a = 1;
    for (; a < argc && strncmp(argv[a], "--", 2) == 0; a++) {
        if (strcmp(argv[a], "--all-terms") == 0)
            o.all_terms = true;
        else if (strcmp(argv[a], "--jitter") == 0 && a + 1 < argc)
            o.jitter = atof(argv[++a]);
        else
            break;
    }
    if (argc - a != 2) {
        fprintf(stderr, "usage: sb_lammps_export [--jitter J] [--all-terms] CASE DIR\n");
        return 2;
    }
    const sb_bench_case* c = sb_bench_find_case(argv[a]);
    if (!c) {
        fprintf(stderr, "sb_lammps_export: unknown case '%s'\n", argv[a]);
        return 2;
    }
    if (o.all_terms && (c->shape != SB_BENCH_SHEET || o.jitter != 0.0)) {
        fprintf(stderr,
                "sb_lammps_export: %s: --all-terms needs a flat rest (every hinge's phi0 = 0): a sheet, --jitter 0\n",
                c->name);
        return 2;
    }
    sb_bench_setup s;
    sb_error err = {{0}};
    sb_status status = o.all_terms ? sb_bench_build(c, &o, &s, &err) : sb_bench_prepare(c, &o, &s, &err);
    if (status != SB_OK) {
        fprintf(stderr, "sb_lammps_export: %s: %s\n", c->name, err.message);
        return 1;
    }
    sb_export x = {.s = &s, .all_terms = o.all_terms};
    size_t sides = 3 * (size_t)s.mesh.triangle_count;
    sb_edge* sorted = sb_sorted_sides(&s.mesh);
    x.edges = sorted ? sb_unique_edges(sorted, sides, &x.edge_count) : NULL;
    x.hinges = sorted && o.all_terms ? sb_hinges(sorted, sides, &x.hinge_count) : NULL;
    free(sorted);
    if (!x.edges || (o.all_terms && !x.hinges) || !sb_classify(&x)) {
        fprintf(stderr, "sb_lammps_export: out of memory\n");
        return 1;
    }
    if (sb_write_files(argv[a + 1], c->name, &x)) {
        fprintf(stderr, "sb_lammps_export: cannot write %s's files in %s\n", c->name, argv[a + 1]);
        return 1;
    }
    printf("%s vertices=%u bonds=%zu angles=%zu dihedrals=%zu bond_types=%zu angle_types=%zu dt=%.6g\n", c->name,
           s.mesh.vertex_count, x.edge_count, 3 * (size_t)s.mesh.triangle_count, x.hinge_count, x.bond_types,
           x.angle_types, s.dt);
    free(x.edges);
    free(x.hinges);
    free(x.bond_type);
    free(x.angle_type);
    free(x.bond_r0);
    free(x.angle_cos0);
    sb_bench_setup_free(&s);
    return 0;
}
