/* The finite-element oracle (tests/test_fem.c, bench/bench_materials.c): CalculiX (`ccx`, Debian's
 * calculix-ccx) run on the same tetrahedra softbond uses, written as C3D4
 * or converted to quadratic C3D10 (a node at each edge's middle), with the
 * same clamps, prescribed displacements and loads; its displacements read
 * back from the .dat file (*NODE PRINT). In C, beside the tests, so that
 * the mesh ccx solves is the very array softbond is built from and the
 * oracle needs nothing beyond ccx itself.
 *
 * Loads: a uniform traction on the faces at x = L becomes each face's
 * consistent nodal loads (linear face: a third of T A to each corner;
 * quadratic face: a third to each middle node, none to the corners); gravity
 * is ccx's GRAV load on the density (softbond: the lumped masses ρ V / 4).
 *
 * Thin plates (tests/test_sheets.c): ccx's S8R shells on a rectangle
 * clamped along one side under gravity (fem_ccx_plate). */
#ifndef SB_FEM_ORACLE_H
#define SB_FEM_ORACLE_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct fem_mesh {
    uint32_t nodes, tets;
    double* x;     /* 3 a node */
    uint32_t* tet; /* 4 a tetrahedron, positive volume */
} fem_mesh;

/* Grades mesh m's cells toward the point focus, axis by axis: on each
 * side of focus[k] within [lo[k], hi[k]] a coordinate at the fraction u
 * of the way out moves to a u + (1 − a) u², so that the cells at the focus
 * are a (0 < a <= 1) times as wide as before and those at the far end
 * 2 − a times. Each axis's map is monotone, so a box mesh's cells stay
 * boxes and its tetrahedra keep their orientation. */
static inline void fem_mesh_grade(fem_mesh* m, const double lo[3], const double hi[3], const double focus[3],
                                  double a) {
    for (uint32_t i = 0; i < m->nodes; i++)
        for (int k = 0; k < 3; k++) {
            double *x = m->x + 3 * i + k, end = *x >= focus[k] ? hi[k] : lo[k];
            if (end == focus[k]) continue;
            double u = (*x - focus[k]) / (end - focus[k]);
            *x = focus[k] + (end - focus[k]) * (a * u + (1.0 - a) * u * u);
        }
}

/* A box [0, lx] × [0, ly] × [0, lz] of nx × ny × nz cubes, each cut into
 * the six tetrahedra around its diagonal (Freudenthal/Kuhn: conforming). */
static inline fem_mesh fem_box(double lx, double ly, double lz, int nx, int ny, int nz) {
    fem_mesh m;
    m.nodes = (uint32_t)((nx + 1) * (ny + 1) * (nz + 1));
    m.tets = (uint32_t)(6 * nx * ny * nz);
    m.x = malloc(3 * sizeof(double) * m.nodes);
    m.tet = malloc(4 * sizeof(uint32_t) * m.tets);
#define FEM_ID(i, j, k) ((uint32_t)(((k) * (ny + 1) + (j)) * (nx + 1) + (i)))
    for (int k = 0; k <= nz; k++)
        for (int j = 0; j <= ny; j++)
            for (int i = 0; i <= nx; i++) {
                double* p = m.x + 3 * FEM_ID(i, j, k);
                p[0] = lx * i / nx;
                p[1] = ly * j / ny;
                p[2] = lz * k / nz;
            }
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    uint32_t t = 0;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++)
                for (int p = 0; p < 6; p++) {
                    int c[3] = {0, 0, 0};
                    uint32_t* v = m.tet + 4 * t++;
                    v[0] = FEM_ID(i, j, k);
                    for (int s = 0; s < 3; s++) {
                        c[perms[p][s]] = 1;
                        v[s + 1] = FEM_ID(i + c[0], j + c[1], k + c[2]);
                    }
                    const double *a = m.x + 3 * v[0], *b = m.x + 3 * v[1], *cc = m.x + 3 * v[2], *d = m.x + 3 * v[3];
                    double u[3], w[3], z[3];
                    for (int q = 0; q < 3; q++) u[q] = b[q] - a[q], w[q] = cc[q] - a[q], z[q] = d[q] - a[q];
                    double vol = u[0] * (w[1] * z[2] - w[2] * z[1]) - u[1] * (w[0] * z[2] - w[2] * z[0]) +
                                 u[2] * (w[0] * z[1] - w[1] * z[0]);
                    if (vol < 0) {
                        uint32_t s2 = v[2];
                        v[2] = v[3];
                        v[3] = s2;
                    }
                }
#undef FEM_ID
    return m;
}

static inline void fem_mesh_free(fem_mesh* m) {
    free(m->x);
    free(m->tet);
}

/* A problem: which nodes are held (all of a node's x at `at` along `axis`,
 * within 1e-9), a prescribed displacement for another plane, a traction on
 * the faces of a plane, gravity. */
typedef struct fem_case {
    double young_modulus, poisson_ratio, density;
    int clamp_axis;
    double clamp_at;
    int move_axis; /* −1: none; else the nodes at move_at get displacement `move` (all three components) */
    double move_at, move[3];
    int traction_axis; /* −1: none */
    double traction_at, traction[3];
    double gravity[3];
} fem_case;

static inline bool fem_on(const double* p, int axis, double at) { return axis >= 0 && fabs(p[axis] - at) < 1e-9; }

/* The faces on the traction's plane: calls add(user, node, force) with the
 * consistent nodal loads of the linear (quadratic = false) or quadratic
 * face; mid[] gives each tetrahedron's six middle nodes for quadratic. */
static const int fem_faces[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
/* edge index of (a, b) in C3D10's order: 01 12 02 03 13 23 */
static inline int fem_edge_slot(int a, int b) {
    if (a > b) {
        int s = a;
        a = b;
        b = s;
    }
    static const int slot[4][4] = {{-1, 0, 2, 3}, {0, -1, 1, 4}, {2, 1, -1, 5}, {3, 4, 5, -1}};
    return slot[a][b];
}

static inline void fem_traction_loads(const fem_mesh* m, const fem_case* c, const uint32_t* mid, double* load) {
    if (c->traction_axis < 0) return;
    for (uint32_t t = 0; t < m->tets; t++)
        for (int f = 0; f < 4; f++) {
            const uint32_t* v = m->tet + 4 * t;
            bool on = true;
            for (int q = 0; q < 3; q++) on &= fem_on(m->x + 3 * v[fem_faces[f][q]], c->traction_axis, c->traction_at);
            if (!on) continue;
            const double *a = m->x + 3 * v[fem_faces[f][0]], *b = m->x + 3 * v[fem_faces[f][1]],
                         *d = m->x + 3 * v[fem_faces[f][2]];
            double u[3], w[3];
            for (int q = 0; q < 3; q++) u[q] = b[q] - a[q], w[q] = d[q] - a[q];
            double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
            double area = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (int q = 0; q < 3; q++) {
                uint32_t node;
                if (mid) {
                    int e = fem_edge_slot(fem_faces[f][q], fem_faces[f][(q + 1) % 3]);
                    node = mid[6 * t + e];
                } else {
                    node = v[fem_faces[f][q]];
                }
                for (int k = 0; k < 3; k++) load[3 * node + k] += c->traction[k] * area / 3.0;
            }
        }
}

typedef struct fem_edge {
    uint32_t a, b;
} fem_edge;
static int fem_edge_cmp(const void* p, const void* q) {
    const fem_edge *x = p, *y = q;
    if (x->a != y->a) return x->a < y->a ? -1 : 1;
    return x->b < y->b ? -1 : x->b > y->b;
}

/* Reads the section of dir/fem.dat whose header names `section`
 * ("displacements", "forces") into out (3 a node, nodes 1 to count); the
 * number of nodes read, or −3 without a .dat. */
static inline int fem_ccx_read(const char* dir, const char* section, uint32_t count, double* out) {
    char path[1200];
    snprintf(path, sizeof path, "%s/fem.dat", dir);
    FILE* f = fopen(path, "r");
    if (!f) return -3;
    char line[512];
    int read = 0;
    bool in = false;
    while (fgets(line, sizeof line, f)) {
        if (strstr(line, " for set ")) {
            in = strstr(line, section) != NULL;
            continue;
        }
        unsigned id;
        double a, b, d;
        if (in && sscanf(line, "%u %lf %lf %lf", &id, &a, &b, &d) == 4 && id >= 1 && id <= count) {
            out[3 * (id - 1)] = a;
            out[3 * (id - 1) + 1] = b;
            out[3 * (id - 1) + 2] = d;
            read++;
        }
    }
    fclose(f);
    return read;
}

/* Runs ccx on dir/fem.inp: 0, or −2 when it failed. */
static inline int fem_ccx_run(const char* dir) {
    char command[1300];
    snprintf(command, sizeof command, "cd '%s' && OMP_NUM_THREADS=2 ccx -i fem > ccx.log 2>&1", dir);
    return system(command) == 0 ? 0 : -2;
}

/* Runs ccx on dir/fem.inp and reads the displacements of nodes 1 to
 * `count` (*NODE PRINT U) from dir/fem.dat into u (3 count): 0, or −2 when
 * ccx failed, −3 without a .dat, −4 when nodes are missing from it. */
static inline int fem_ccx_solve(const char* dir, uint32_t count, double* u) {
    if (fem_ccx_run(dir) != 0) return -2;
    int read = fem_ccx_read(dir, "displacements", count, u);
    return read < 0 ? read : (uint32_t)read == count ? 0 : -4;
}

/* C3D10's nodes for the mesh: the corners, then a node at each unique
 * edge's middle; *xs (3 a node) and *mid (6 a tetrahedron, C3D10's edge
 * slots) allocated here. Returns the number of nodes. */
static inline uint32_t fem_quadratic_nodes(const fem_mesh* m, double** xs, uint32_t** mid) {
    fem_edge* edges = malloc(6 * sizeof(fem_edge) * m->tets);
    static const int ends[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};
    for (uint32_t t = 0; t < m->tets; t++)
        for (int e = 0; e < 6; e++) {
            uint32_t a = m->tet[4 * t + ends[e][0]], b = m->tet[4 * t + ends[e][1]];
            edges[6 * t + e] = (fem_edge){a < b ? a : b, a < b ? b : a};
        }
    size_t n = 6 * (size_t)m->tets, unique = 0;
    fem_edge* sorted = malloc(sizeof(fem_edge) * n);
    memcpy(sorted, edges, sizeof(fem_edge) * n);
    qsort(sorted, n, sizeof *sorted, fem_edge_cmp);
    for (size_t k = 0; k < n; k++)
        if (!unique || fem_edge_cmp(sorted + unique - 1, sorted + k)) sorted[unique++] = sorted[k];
    uint32_t total = m->nodes + (uint32_t)unique;
    *xs = malloc(3 * sizeof(double) * total);
    memcpy(*xs, m->x, 3 * sizeof(double) * m->nodes);
    for (size_t k = 0; k < unique; k++)
        for (int q = 0; q < 3; q++)
            (*xs)[3 * (m->nodes + k) + q] = 0.5 * (m->x[3 * sorted[k].a + q] + m->x[3 * sorted[k].b + q]);
    *mid = malloc(6 * sizeof(uint32_t) * m->tets);
    for (size_t k = 0; k < n; k++) {
        fem_edge* hit = bsearch(edges + k, sorted, unique, sizeof *sorted, fem_edge_cmp);
        (*mid)[k] = m->nodes + (uint32_t)(hit - sorted);
    }
    free(edges);
    free(sorted);
    return total;
}

/* The deck's nodes (x, total of them), elements (C3D10 with mid, else
 * C3D4), material and section, up to the step's *BOUNDARY line. */
static inline void fem_write_model(FILE* f, const fem_mesh* m, const double* x, uint32_t total, const uint32_t* mid,
                                   const fem_case* c) {
    fprintf(f, "*NODE, NSET=NALL\n");
    for (uint32_t i = 0; i < total; i++)
        fprintf(f, "%u, %.17g, %.17g, %.17g\n", i + 1, x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    fprintf(f, "*ELEMENT, TYPE=%s, ELSET=EALL\n", mid ? "C3D10" : "C3D4");
    for (uint32_t t = 0; t < m->tets; t++) {
        const uint32_t* v = m->tet + 4 * t;
        fprintf(f, "%u, %u, %u, %u, %u", t + 1, v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1);
        if (mid) /* C3D10: 12 23 31 14 24 34, our slots 0 1 2 3 4 5 */
            for (int e = 0; e < 6; e++) fprintf(f, ", %u", mid[6 * t + e] + 1);
        fprintf(f, "\n");
    }
    fprintf(f, "*MATERIAL, NAME=TISSUE\n*ELASTIC\n%.17g, %.17g\n*DENSITY\n%.17g\n", c->young_modulus, c->poisson_ratio,
            c->density);
    fprintf(f, "*SOLID SECTION, ELSET=EALL, MATERIAL=TISSUE\n*STEP\n*STATIC\n*BOUNDARY\n");
}

/* Runs ccx in dir on the mesh (C3D10 when quadratic) and fills u (3 a
 * corner node, the mesh's numbering) with its displacements. 0 on success. */
static inline int fem_ccx(const char* dir, const fem_mesh* m, const fem_case* c, bool quadratic, double* u) {
    uint32_t total = m->nodes;
    uint32_t* mid = NULL;
    double* xs = NULL;
    if (quadratic) total = fem_quadratic_nodes(m, &xs, &mid);
    const double* x = quadratic ? xs : m->x;
    double* load = calloc(3 * (size_t)total, sizeof(double));
    fem_traction_loads(m, c, mid, load);
    char path[1200];
    snprintf(path, sizeof path, "%s/fem.inp", dir);
    FILE* f = fopen(path, "w");
    if (!f) return -1;
    fem_write_model(f, m, x, total, mid, c);
    for (uint32_t i = 0; i < total; i++) {
        if (fem_on(x + 3 * i, c->clamp_axis, c->clamp_at)) fprintf(f, "%u, 1, 3, 0\n", i + 1);
        if (fem_on(x + 3 * i, c->move_axis, c->move_at))
            for (int k = 0; k < 3; k++) fprintf(f, "%u, %d, %d, %.12g\n", i + 1, k + 1, k + 1, c->move[k]);
    }
    bool any = false;
    for (uint32_t i = 0; i < total; i++)
        for (int k = 0; k < 3; k++)
            if (load[3 * i + k] != 0.0) {
                if (!any) fprintf(f, "*CLOAD\n");
                any = true;
                fprintf(f, "%u, %d, %.12g\n", i + 1, k + 1, load[3 * i + k]);
            }
    double g = sqrt(c->gravity[0] * c->gravity[0] + c->gravity[1] * c->gravity[1] + c->gravity[2] * c->gravity[2]);
    if (g > 0.0)
        fprintf(f, "*DLOAD\nEALL, GRAV, %.17g, %.17g, %.17g, %.17g\n", g, c->gravity[0] / g, c->gravity[1] / g,
                c->gravity[2] / g);
    fprintf(f, "*NODE PRINT, NSET=NALL\nU\n*END STEP\n");
    fclose(f);
    free(load);
    free(xs);
    free(mid);
    return fem_ccx_solve(dir, m->nodes, u);
}

/* A thin plate for the shell oracle: length (x) × width (y) in the z = 0
 * plane, clamped along x = 0 (every displacement and rotation), under
 * gravity `gravity` m/s² along −z. */
typedef struct fem_plate {
    double length, width, thickness;
    double young_modulus, poisson_ratio, density, gravity;
} fem_plate;

/* ccx's S8R shells (8-node quadratic, reduced integration) on nx × ny
 * quadrilaterals: writes dir/fem.inp, solves, and returns in *tip the mean
 * vertical displacement of the nodes on x = length; 0 or fem_ccx_solve's
 * code. Numbers in 12 digits (ccx reads a field of at most 20 characters). */
static inline int fem_ccx_plate(const char* dir, const fem_plate* p, int nx, int ny, double* tip) {
    int cols = 2 * nx + 1, rows = 2 * ny + 1; /* the quadratic grid; the cells' centres unused */
    uint32_t *id = calloc((size_t)cols * rows, sizeof *id), count = 0;
    for (int j = 0; j < rows; j++)
        for (int i = 0; i < cols; i++)
            if (i % 2 == 0 || j % 2 == 0) id[j * cols + i] = ++count;
    char path[1200];
    snprintf(path, sizeof path, "%s/fem.inp", dir);
    FILE* f = fopen(path, "w");
    if (!f) return -1;
    fprintf(f, "*NODE, NSET=NALL\n");
    for (int j = 0; j < rows; j++)
        for (int i = 0; i < cols; i++)
            if (id[j * cols + i])
                fprintf(f, "%u, %.12g, %.12g, 0\n", id[j * cols + i], p->length * i / (cols - 1),
                        p->width * j / (rows - 1));
    fprintf(f, "*ELEMENT, TYPE=S8R, ELSET=EALL\n");
    for (int ej = 0, e = 1; ej < ny; ej++)
        for (int ei = 0; ei < nx; ei++, e++) {
            int i = 2 * ei, j = 2 * ej; /* corners counter-clockwise, then the sides' middles */
            const int at[8][2] = {{i, j},     {i + 2, j},     {i + 2, j + 2}, {i, j + 2},
                                  {i + 1, j}, {i + 2, j + 1}, {i + 1, j + 2}, {i, j + 1}};
            fprintf(f, "%d", e);
            for (int k = 0; k < 8; k++) fprintf(f, ", %u", id[at[k][1] * cols + at[k][0]]);
            fprintf(f, "\n");
        }
    fprintf(f, "*MATERIAL, NAME=SHEET\n*ELASTIC\n%.12g, %.12g\n*DENSITY\n%.12g\n", p->young_modulus, p->poisson_ratio,
            p->density);
    fprintf(f, "*SHELL SECTION, ELSET=EALL, MATERIAL=SHEET\n%.12g\n*STEP\n*STATIC\n*BOUNDARY\n", p->thickness);
    for (int j = 0; j < rows; j++) fprintf(f, "%u, 1, 6, 0\n", id[j * cols]);
    fprintf(f, "*DLOAD\nEALL, GRAV, %.12g, 0, 0, -1\n*NODE PRINT, NSET=NALL\nU\n*END STEP\n", p->gravity);
    fclose(f);
    double* u = calloc(3 * (size_t)count, sizeof *u);
    int status = fem_ccx_solve(dir, count, u);
    *tip = 0.0;
    for (int j = 0; j < rows; j++) *tip += u[3 * (id[j * cols + cols - 1] - 1) + 2] / rows;
    free(u);
    free(id);
    return status;
}

#endif
