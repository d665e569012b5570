/* softbond's static answer to a problem of the finite-element oracle
 * (bench/fem_oracle.h), shared by tests/test_fem.c and
 * bench/bench_materials.c: the tissue built from the oracle's very box
 * mesh, the oracle's clamps, prescribed displacements and loads (the
 * traction's consistent nodal loads, gravity on the model's lumped masses),
 * and its static equilibrium by Newton on softbond's own reference forces,
 * each linear system solved by CG with the stiffness's products from
 * central differences of those forces. Failures come back as NAN (the
 * caller asserts or reports), never as an abort. */
#ifndef SB_FEM_STATIC_H
#define SB_FEM_STATIC_H

#include "bench/fem_oracle.h"
#include "softbond/softbond.h"

#include <sys/stat.h>

/* The problem's measurement: uz at the tip's centre for the cantilever,
 * ux at the centre of the face x = lx for the block. */
typedef struct fem_problem {
    const char* name;
    double lx, ly, lz;
    fem_case c;
    double probe[3];
    int probe_axis;
    bool undamped; /* the springs without the papers' damping rule (a dynamic run to rest); else the rule */
    double grade;  /* 0: uniform cells; else the cells at focus are grade times as wide (fem_mesh_grade) */
    double focus[3];
} fem_problem;

/* The box mesh of the problem at n cells across its thickness (z). */
static inline fem_mesh fem_problem_mesh(const fem_problem* pb, int n) {
    fem_mesh m = fem_box(pb->lx, pb->ly, pb->lz, n * (int)lround(pb->lx / pb->lz), n * (int)lround(pb->ly / pb->lz), n);
    const double lo[3] = {0.0, 0.0, 0.0}, hi[3] = {pb->lx, pb->ly, pb->lz};
    if (pb->grade > 0.0) fem_mesh_grade(&m, lo, hi, pb->focus, pb->grade);
    return m;
}

/* The point among count (3 a point) at p, or UINT32_MAX. */
static inline uint32_t fem_point_at(const double* x, uint32_t count, const double p[3]) {
    for (uint32_t i = 0; i < count; i++)
        if (fabs(x[3 * i] - p[0]) < 1e-9 && fabs(x[3 * i + 1] - p[1]) < 1e-9 && fabs(x[3 * i + 2] - p[2]) < 1e-9)
            return i;
    return UINT32_MAX;
}

/* ccx's answer (C3D10 when quadratic) at the probe, solved in dir (made
 * here); NAN when ccx fails. */
static inline double fem_oracle_probe(const fem_problem* pb, int n, bool quadratic, const char* dir) {
    fem_mesh m = fem_problem_mesh(pb, n);
    double* u = calloc(3 * (size_t)m.nodes, sizeof *u);
    uint32_t probe = fem_point_at(m.x, m.nodes, pb->probe);
    mkdir(dir, 0700);
    double v = probe != UINT32_MAX && fem_ccx(dir, &m, &pb->c, quadratic, u) == 0 ? u[3 * probe + pb->probe_axis] : NAN;
    free(u);
    fem_mesh_free(&m);
    return v;
}

typedef struct fem_static {
    const sb_model* model;
    const double* load; /* external, 3n */
    const uint8_t* held;
    size_t n3;
    double *f, *fp, *fm, *xp;
    bool failed; /* a force evaluation failed */
} fem_static;

/* The residual r = f(x) + load on free dofs. */
static inline void fem_residual(fem_static* s, const double* x, double* r) {
    sb_energies e;
    sb_error err = {0};
    s->failed |= sb_reference_forces(s->model, x, NULL, r, &e, &err) != SB_OK;
    for (size_t k = 0; k < s->n3; k++) r[k] = s->held[k / 3] ? 0.0 : r[k] + s->load[k];
}

/* K v = −(f(x + εv) − f(x − εv)) / 2ε on free dofs. */
static inline void fem_product(fem_static* s, const double* x, const double* v, double* out, double scale) {
    double vmax = 0.0;
    for (size_t k = 0; k < s->n3; k++) vmax = fmax(vmax, fabs(v[k]));
    if (vmax == 0.0) {
        memset(out, 0, s->n3 * sizeof *out);
        return;
    }
    double eps = 1e-6 * scale / vmax;
    sb_energies e;
    sb_error err = {0};
    for (size_t k = 0; k < s->n3; k++) s->xp[k] = x[k] + eps * v[k];
    s->failed |= sb_reference_forces(s->model, s->xp, NULL, s->fp, &e, &err) != SB_OK;
    for (size_t k = 0; k < s->n3; k++) s->xp[k] = x[k] - eps * v[k];
    s->failed |= sb_reference_forces(s->model, s->xp, NULL, s->fm, &e, &err) != SB_OK;
    for (size_t k = 0; k < s->n3; k++) out[k] = s->held[k / 3] ? 0.0 : -(s->fp[k] - s->fm[k]) / (2.0 * eps);
}

static inline double fem_dot(const double* a, const double* b, size_t n) {
    double s = 0.0;
    for (size_t k = 0; k < n; k++) s += a[k] * b[k];
    return s;
}

/* Newton with CG: x starts at the given positions (held vertices placed). */
static inline void fem_solve_static(fem_static* s, double* x, double scale) {
    size_t n = s->n3;
    double *r = calloc(n, 8), *d = calloc(n, 8), *p = calloc(n, 8), *q = calloc(n, 8), *z = calloc(n, 8);
    s->fp = calloc(n, 8), s->fm = calloc(n, 8), s->xp = calloc(n, 8);
    double first = 0.0;
    for (int newton = 0; newton < 4; newton++) {
        fem_residual(s, x, r);
        double rr = fem_dot(r, r, n);
        if (newton == 0) first = sqrt(rr);
        if (sqrt(rr) <= 1e-9 * first) break;
        memset(d, 0, n * 8);
        memcpy(p, r, n * 8);
        memcpy(z, r, n * 8);
        double zz = rr;
        for (int it = 0; it < 20000 && sqrt(zz) > 1e-10 * sqrt(rr); it++) {
            fem_product(s, x, p, q, scale);
            double alpha = zz / fem_dot(p, q, n);
            for (size_t k = 0; k < n; k++) d[k] += alpha * p[k], z[k] -= alpha * q[k];
            double next = fem_dot(z, z, n);
            for (size_t k = 0; k < n; k++) p[k] = z[k] + next / zz * p[k];
            zz = next;
        }
        for (size_t k = 0; k < n; k++) x[k] += d[k];
    }
    free(r), free(d), free(p), free(q), free(z), free(s->fp), free(s->fm), free(s->xp);
}

/* The quadratic model's middle vertex of each edge (C3D10's slots, as
 * fem_traction_loads reads them) of the tetrahedra with a face on the
 * traction's plane, found by position: independent of the factory's
 * numbering. NULL when one is missing. */
static inline uint32_t* fem_traction_middles(const fem_mesh* m, const fem_case* c, const double* rest, uint32_t count) {
    static const int ends[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};
    uint32_t* mid = calloc(6 * (size_t)m->tets, sizeof *mid);
    for (uint32_t t = 0; t < m->tets; t++) {
        int on = 0;
        for (int q = 0; q < 4; q++) on += fem_on(m->x + 3 * m->tet[4 * t + q], c->traction_axis, c->traction_at);
        if (on < 3) continue;
        for (int e = 0; e < 6; e++) {
            const double *a = m->x + 3 * m->tet[4 * t + ends[e][0]], *b = m->x + 3 * m->tet[4 * t + ends[e][1]];
            double p[3] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
            mid[6 * t + e] = fem_point_at(rest, count, p);
            if (mid[6 * t + e] == UINT32_MAX) {
                free(mid);
                return NULL;
            }
        }
    }
    return mid;
}

/* The problem's tissue at n cells across: the compiled model (NULL on
 * failure), each vertex's rest position, whether it is held, where it
 * starts (held vertices moved by the prescribed displacement) and its
 * external load (traction and gravity). */
typedef struct fem_body {
    sb_model* model;
    uint32_t count; /* the mesh's vertices, and a quadratic model's middles */
    double *rest, *x, *load;
    uint8_t* held;
} fem_body;

static inline void fem_body_free(fem_body* body) {
    sb_model_destroy(body->model);
    free(body->rest), free(body->x), free(body->load), free(body->held);
}

static inline fem_body fem_body_build(const fem_problem* pb, int n, sb_tissue_model model) {
    fem_body body = {0};
    fem_mesh m = fem_problem_mesh(pb, n);
    sb_tet_mesh tm = {.vertex_count = m.nodes, .positions = m.x, .tet_count = m.tets, .tets = m.tet};
    sb_tissue_def tissue = sb_default_tissue_def();
    tissue.young_modulus = pb->c.young_modulus;
    tissue.poisson_ratio = pb->c.poisson_ratio;
    tissue.density = pb->c.density;
    tissue.model = model;
    if (pb->undamped) tissue.damping = 0.0;
    sb_builder* b = sb_builder_create();
    sb_error err = {0};
    if (sb_builder_add_tet_mesh(b, &tm, &tissue, &err) != SB_OK) goto done;
    body.count = sb_builder_vertex_count(b);
    size_t n3 = 3 * (size_t)body.count;
    body.held = calloc(body.count, 1);
    body.x = malloc(n3 * 8), body.rest = malloc(n3 * 8), body.load = calloc(n3, 8);
    for (uint32_t i = 0; i < body.count; i++)
        memcpy(body.rest + 3 * i, sb_builder_vertex(b, i)->position, 3 * sizeof(double));
    memcpy(body.x, body.rest, n3 * 8);
    for (uint32_t i = 0; i < body.count; i++) {
        bool clamp = fem_on(body.rest + 3 * i, pb->c.clamp_axis, pb->c.clamp_at);
        bool move = fem_on(body.rest + 3 * i, pb->c.move_axis, pb->c.move_at);
        if (move)
            for (int k = 0; k < 3; k++) body.x[3 * i + k] += pb->c.move[k];
        body.held[i] = clamp || move;
        sb_builder_vertex(b, i)->fixed = body.held[i];
    }
    body.model = sb_builder_compile(b, &err);
    if (!body.model) goto done;
    bool quadratic = model == SB_TISSUE_COROTATED_QUADRATIC;
    uint32_t* mid =
        quadratic && pb->c.traction_axis >= 0 ? fem_traction_middles(&m, &pb->c, body.rest, body.count) : NULL;
    if (quadratic && pb->c.traction_axis >= 0 && !mid) {
        sb_model_destroy(body.model);
        body.model = NULL;
        goto done;
    }
    fem_traction_loads(&m, &pb->c, mid, body.load);
    for (uint32_t i = 0; i < body.count; i++)
        for (int k = 0; k < 3; k++) body.load[3 * i + k] += sb_model_mass(body.model, i) * pb->c.gravity[k];
    free(mid);
done:
    sb_builder_destroy(b);
    fem_mesh_free(&m);
    return body;
}

/* The body's static equilibrium (left in body->x) and its displacement
 * at the problem's probe; NAN on any failure. */
static inline double fem_body_static(fem_body* body, const fem_problem* pb) {
    uint32_t probe = body->model ? fem_point_at(body->rest, body->count, pb->probe) : UINT32_MAX;
    if (probe == UINT32_MAX) return NAN;
    fem_static s = {.model = body->model, .load = body->load, .held = body->held, .n3 = 3 * (size_t)body->count};
    fem_solve_static(&s, body->x, pb->lz);
    return s.failed ? NAN : body->x[3 * probe + pb->probe_axis] - body->rest[3 * probe + pb->probe_axis];
}

/* softbond's static displacement at the probe (NAN on any failure). */
static inline double fem_softbond(const fem_problem* pb, int n, sb_tissue_model model) {
    fem_body body = fem_body_build(pb, n, model);
    double v = fem_body_static(&body, pb);
    fem_body_free(&body);
    return v;
}

/* ---- the cases -------------------------------------------------------------- */

#define FEM_E 3500.0
#define FEM_RHO 1060.0

/* A cantilever 100 × 20 × 20 mm clamped at x = 0, E 3.5 kPa, under a
 * shear traction on the tip face or gravity (deflection about 0.1 mm,
 * linear); the probe: uz at the tip's centre. */
static inline fem_problem fem_cantilever(double nu, bool gravity) {
    fem_problem pb = {.name = gravity ? "cantilever_gravity" : "cantilever_tip", .lx = 0.1, .ly = 0.02, .lz = 0.02};
    pb.c = (fem_case){.young_modulus = FEM_E,
                      .poisson_ratio = nu,
                      .density = FEM_RHO,
                      .clamp_axis = 0,
                      .clamp_at = 0.0,
                      .move_axis = -1,
                      .traction_axis = -1};
    if (gravity) {
        pb.c.gravity[2] = -1e-3; /* tip deflection about 0.1 mm: linear */
    } else {
        pb.c.traction_axis = 0;
        pb.c.traction_at = 0.1;
        pb.c.traction[2] = -0.035; /* Pa: 1.4e-5 N, tip deflection about 0.1 mm */
    }
    pb.probe[0] = 0.1, pb.probe[1] = 0.01, pb.probe[2] = 0.01;
    pb.probe_axis = 2;
    return pb;
}

/* The cantilever with modulus E and Poisson's ratio ν, its load scaled
 * with E so that the deflection stays about 0.1 % of the length (linear);
 * measured at the tip's lower edge (a vertex at every resolution). */
static inline fem_problem fem_cantilever_of(double young, double nu, bool gravity) {
    fem_problem pb = fem_cantilever(nu, gravity);
    double scale = young / FEM_E;
    pb.c.young_modulus = young;
    pb.probe[1] = pb.probe[2] = 0.0;
    if (gravity)
        pb.c.density *= scale; /* the load ρ g, not g: ccx's GRAV stays a small acceleration */
    else
        pb.c.traction[2] *= scale;
    return pb;
}

#endif
