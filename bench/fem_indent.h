/* The indentation problem (tests/test_fem_indent.c, bench/bench_materials.c):
 * a block lx × ly × lz clamped on its bottom face (z = 0), pressed by a
 * rigid frictionless sphere of radius R above its top's centre to a depth
 * d; the measurement is the force on the sphere, the haptic quantity.
 *
 * The oracle: CalculiX's linear elements (C3D10 on a finer mesh) with the
 * contact solved by an active set (Signorini's conditions at the top
 * face's nodes, in small displacements). A node in the set has its
 * vertical displacement prescribed to the sphere's surface above its rest
 * point (no node may rise above it), uz = (lz + R − d − √(R² − r²)) − lz, and is free sideways
 * (frictionless); each ccx solve adds the top nodes that went through the
 * sphere and drops those whose reaction pulls (adhesion), until the set
 * stops changing. The force is the sum of the set's vertical reactions.
 * On a fine mesh this is the continuum's answer, whatever the contact's
 * discretisation; the converged mesh is checked against a coarser one.
 *
 * softbond's answer is what a program gets: its solver, the tissue model,
 * and the built-in sphere collider driven down on a smooth path, the run
 * damped (drag) to rest; the force is the collider's contact force
 * (sb_solver_contact_force) averaged over the last stretch of the hold,
 * with the contact by vertices as the oracle's is by nodes
 * (sb_solver_def.vertex_contact_only): with face contact the sphere also
 * presses the flat quarter faces between the nodes, which the oracle's
 * nodal contact does not (+19 % at 3 cells across, E 1 MPa; a surface-to-
 * surface oracle is not built). Symplectic Euler at a fifth of the
 * element's wave-crossing time. */
#ifndef SB_FEM_INDENT_H
#define SB_FEM_INDENT_H

#include "bench/fem_static.h"

typedef struct fem_indent {
    double lx, ly, lz;    /* m */
    double radius, depth; /* m */
    double young_modulus; /* Pa */
    double poisson_ratio; /* ν */
    double density;       /* kg/m³ */
    double grade;         /* 0: uniform cells; else graded toward the top's centre (fem_mesh_grade) */
} fem_indent;

/* The 20 × 20 × 10 mm block under a 5 mm sphere, 1 mm deep. */
static inline fem_indent fem_indent_case(double young, double nu, double depth) {
    return (fem_indent){.lx = 0.02,
                        .ly = 0.02,
                        .lz = 0.01,
                        .radius = 0.005,
                        .depth = depth,
                        .young_modulus = young,
                        .poisson_ratio = nu,
                        .density = FEM_RHO};
}

/* The block as a clamped problem of fem_static.h (no load: the sphere is
 * the load), the springs undamped: their dashpots (the papers' rule) do
 * not change the force at rest and would need a far smaller explicit step. */
static inline fem_problem fem_indent_problem(const fem_indent* in) {
    fem_problem pb = {.name = "indentation",
                      .lx = in->lx,
                      .ly = in->ly,
                      .lz = in->lz,
                      .undamped = true,
                      .grade = in->grade,
                      .focus = {0.5 * in->lx, 0.5 * in->ly, in->lz}};
    pb.c = (fem_case){.young_modulus = in->young_modulus,
                      .poisson_ratio = in->poisson_ratio,
                      .density = in->density,
                      .clamp_axis = 2,
                      .clamp_at = 0.0,
                      .move_axis = -1,
                      .traction_axis = -1};
    return pb;
}

/* Where the sphere's surface lies below the top face at rest point p (m,
 * negative), or +INFINITY where the sphere is not above p. */
static inline double fem_indent_gap(const fem_indent* in, const double* p) {
    double dx = p[0] - 0.5 * in->lx, dy = p[1] - 0.5 * in->ly, r2 = dx * dx + dy * dy;
    if (r2 >= in->radius * in->radius) return INFINITY;
    return in->radius - in->depth - sqrt(in->radius * in->radius - r2);
}

/* Hertz's force on a half-space, F = 4/3 E/(1 − ν²) √R d^{3/2}: the
 * sanity reference (the block is not a half-space). */
static inline double fem_indent_hertz(const fem_indent* in) {
    double e_star = in->young_modulus / (1.0 - in->poisson_ratio * in->poisson_ratio);
    return 4.0 / 3.0 * e_star * sqrt(in->radius) * pow(in->depth, 1.5);
}

/* The oracle's mesh: the quarter x, y <= l/2 of the block (the problem
 * is symmetric about x = lx/2 and y = ly/2), n cells across the
 * thickness, graded as the whole block's is. */
static inline fem_mesh fem_indent_quarter(const fem_indent* in, int n) {
    fem_mesh m = fem_box(0.5 * in->lx, 0.5 * in->ly, in->lz, (int)lround(n * 0.5 * in->lx / in->lz),
                         (int)lround(n * 0.5 * in->ly / in->lz), n);
    const double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {0.5 * in->lx, 0.5 * in->ly, in->lz},
                 focus[3] = {0.5 * in->lx, 0.5 * in->ly, in->lz};
    if (in->grade > 0.0) fem_mesh_grade(&m, lo, hi, focus, in->grade);
    return m;
}

/* Writes the active set's deck in dir: the bottom clamped, the planes of
 * symmetry held normal to themselves, the set's vertical displacements. */
static inline int fem_indent_deck(const char* dir, const fem_indent* in, const fem_mesh* m, const double* x,
                                  uint32_t total, const uint32_t* mid, const uint8_t* active) {
    char path[1200];
    snprintf(path, sizeof path, "%s/fem.inp", dir);
    FILE* f = fopen(path, "w");
    if (!f) return -1;
    fem_problem pb = fem_indent_problem(in);
    fem_write_model(f, m, x, total, mid, &pb.c);
    for (uint32_t i = 0; i < total; i++) {
        if (fem_on(x + 3 * i, 2, 0.0)) fprintf(f, "%u, 1, 3, 0\n", i + 1);
        if (fem_on(x + 3 * i, 0, 0.5 * in->lx)) fprintf(f, "%u, 1, 1, 0\n", i + 1);
        if (fem_on(x + 3 * i, 1, 0.5 * in->ly)) fprintf(f, "%u, 2, 2, 0\n", i + 1);
        if (active[i]) fprintf(f, "%u, 3, 3, %.12g\n", i + 1, fem_indent_gap(in, x + 3 * i));
    }
    fprintf(f, "*NODE PRINT, NSET=NALL\nU\n*NODE PRINT, NSET=NALL\nRF\n*END STEP\n");
    fclose(f);
    return 0;
}

/* ccx's force on the sphere (N, positive) on the quarter mesh at n cells
 * across the thickness (C3D10 when quadratic), solved in dir (made here);
 * NAN when ccx fails or the active set does not settle in 20 solves.
 * *nodes: the quarter's nodes in contact at the end (may be NULL). */
static inline double fem_indent_oracle(const fem_indent* in, int n, bool quadratic, const char* dir, int* nodes) {
    fem_mesh m = fem_indent_quarter(in, n);
    double* xs = NULL;
    uint32_t* mid = NULL;
    uint32_t total = quadratic ? fem_quadratic_nodes(&m, &xs, &mid) : m.nodes;
    const double* x = quadratic ? xs : m.x;
    double *u = calloc(3 * (size_t)total, sizeof *u), *rf = calloc(3 * (size_t)total, sizeof *rf);
    uint8_t* active = calloc(total, 1);
    for (uint32_t i = 0; i < total; i++) active[i] = fem_on(x + 3 * i, 2, in->lz) && fem_indent_gap(in, x + 3 * i) < 0;
    mkdir(dir, 0700);
    double force = NAN;
    for (int solve = 0; solve < 20; solve++) {
        if (fem_indent_deck(dir, in, &m, x, total, mid, active) != 0 || fem_ccx_run(dir) != 0 ||
            fem_ccx_read(dir, "displacements", total, u) != (int)total || fem_ccx_read(dir, "forces", total, rf) < 0)
            break;
        bool changed = false;
        double sum = 0.0;
        int count = 0;
        for (uint32_t i = 0; i < total; i++) {
            if (!fem_on(x + 3 * i, 2, in->lz)) continue;
            double gap = fem_indent_gap(in, x + 3 * i);
            if (active[i] && rf[3 * i + 2] > 0.0)
                active[i] = 0, changed = true; /* it pulls: let go */
            else if (!active[i] && u[3 * i + 2] > gap + 1e-9 * in->depth)
                active[i] = 1, changed = true;
            if (active[i]) sum -= rf[3 * i + 2], count++;
        }
        if (!changed) {
            force = 4.0 * sum; /* the four quarters */
            if (nodes) *nodes = count;
            break;
        }
    }
    free(u), free(rf), free(active), free(xs), free(mid);
    fem_mesh_free(&m);
    return force;
}

/* The stable step's scale: the dilatational wave's time across the
 * smallest spacing of the model's vertices. */
static inline double fem_indent_wave_time(const fem_indent* in, int n, sb_tissue_model model) {
    double nu = in->poisson_ratio;
    double wave = sqrt(in->young_modulus * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu) * in->density));
    double spacing = in->lz / n / (model == SB_TISSUE_COROTATED_QUADRATIC ? 2.0 : 1.0);
    return (in->grade > 0.0 ? in->grade : 1.0) * spacing / wave;
}

/* softbond's force on the sphere (N, positive) with the model at n cells
 * across; NAN when the build or a step fails. *steps: the steps taken. */
static inline double fem_indent_softbond(const fem_indent* in, int n, sb_tissue_model model, long* steps) {
    fem_problem pb = fem_indent_problem(in);
    fem_body body = fem_body_build(&pb, n, model);
    if (!body.model) return NAN;
    /* the block's slowest motion: a shear wave down its thickness and back, four times */
    double shear = sqrt(in->young_modulus / (2.0 * (1.0 + in->poisson_ratio) * in->density));
    double period = 4.0 * in->lz / shear, dt = 0.2 * fem_indent_wave_time(in, n, model);
    sb_keyframe path[2] = {{.time = 0.0}, {.time = 2.0 * period, .translate = {0.0, 0.0, -in->depth}}};
    sb_collider_def c = sb_default_collider_def();
    c.shape = SB_COLLIDER_SPHERE;
    c.center[0] = 0.5 * in->lx, c.center[1] = 0.5 * in->ly, c.center[2] = in->lz + in->radius;
    c.radius = in->radius;
    c.path = path;
    c.path_count = 2;
    c.interpolation = SB_INTERPOLATION_SMOOTH;
    sb_error err = {0};
    sb_collider* sphere = sb_collider_create(&c, &err);
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_SYMPLECTIC_EULER;
    def.gravity[2] = 0.0;
    def.drag = 4.0 * acos(-1.0) / period; /* about critical for the slowest motion */
    def.colliders = &sphere;
    def.collider_count = 1;
    def.vertex_contact_only = true; /* the oracle's contact is by nodes: so is this */
    def.runtime.threads = 1;
    sb_solver* solver = sphere ? sb_solver_create(body.model, &def, &err) : NULL;
    double force = NAN, sum = 0.0;
    long total = solver ? (long)ceil(6.0 * period / dt) : 0, window = total / 12, k = 0;
    for (; k < total; k++) {
        if (sb_solver_advance(solver, dt) != SB_OK) break;
        double f[3];
        sb_solver_contact_force(solver, 0, f);
        if (k >= total - window) sum += f[2];
    }
    if (solver && k == total) force = sum / (double)window;
    if (steps) *steps = k;
    sb_solver_destroy(solver);
    sb_collider_destroy(sphere);
    fem_body_free(&body);
    return force;
}

#endif
