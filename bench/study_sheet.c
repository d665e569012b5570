/* The study's sheet and the measurements every part of the study shares
 * (see study_sheet.h). */
#include "study_sheet.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

sb_material_def study_material(double k) {
    sb_material_def material = sb_default_material_def();
    material.bond_k = k;
    material.angle_k = 1e-3 * k;
    material.spring_damping = 0.0;
    return material;
}

static _Noreturn void study_fail(const char* message) {
    fprintf(stderr, "sb_study: %s\n", message);
    exit(1);
}

study_sheet study_sheet_make(uint32_t side, const sb_material_def* material) {
    study_sheet s = {.side = side, .middle = (side / 2) * side + side / 2, .corner = side - 1};
    sb_error err;
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = def.ny = side;
    if (sb_mesh_generate_sheet(&def, &s.mesh, &err) != SB_OK) study_fail(err.message);
    sb_material_def m = *material;
    m.mass = STUDY_MASS;
    m.density = 0.0;
    sb_builder* builder = sb_builder_create();
    if (sb_builder_add_mesh(builder, &s.mesh, &m, &err) != SB_OK) study_fail(err.message);
    for (uint32_t row = 0; row < side; row++) sb_builder_vertex(builder, row * side)->fixed = true;
    s.model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    if (!s.model) study_fail(err.message);
    return s;
}

void study_sheet_free(study_sheet* s) {
    sb_model_destroy(s->model);
    sb_mesh_free(&s->mesh);
}

/* K p by central differences of the reference forces at the rest shape,
 * free vertices only. */
static void stiffness_product(const study_sheet* s, const double* p, double* out, double* work) {
    uint32_t n3 = 3 * s->mesh.vertex_count;
    double *plus = work, *minus = work + n3, *x = work + 2 * n3, eps = 1e-7;
    sb_energies e;
    sb_error err;
    for (int sign = 0; sign < 2; sign++) {
        for (uint32_t i = 0; i < n3; i++) x[i] = s->mesh.positions[i] + (sign ? -eps : eps) * p[i];
        sb_reference_forces(s->model, x, NULL, sign ? minus : plus, &e, &err);
    }
    for (uint32_t i = 0; i < n3; i++)
        out[i] = sb_model_is_fixed(s->model, i / 3) ? 0.0 : -(plus[i] - minus[i]) / (2 * eps);
}

/* K is positive semidefinite at rest, so the dominant eigenvalue of
 * M^-1/2 K M^-1/2 is the largest ω². */
double study_omega_max(const study_sheet* s) {
    uint32_t n3 = 3 * s->mesh.vertex_count;
    double *p = malloc(n3 * sizeof *p), *q = malloc(n3 * sizeof *q), *work = malloc(3 * n3 * sizeof *work);
    unsigned seed = 7;
    for (uint32_t i = 0; i < n3; i++)
        p[i] = sb_model_is_fixed(s->model, i / 3) ? 0.0 : (double)rand_r(&seed) / RAND_MAX - 0.5;
    double lambda = 0.0, scale = 1.0 / sqrt(STUDY_MASS);
    for (int it = 0; it < 2000; it++) {
        double norm = 0.0;
        for (uint32_t i = 0; i < n3; i++) norm += p[i] * p[i];
        for (uint32_t i = 0; i < n3; i++) p[i] /= sqrt(norm);
        for (uint32_t i = 0; i < n3; i++) q[i] = p[i] * scale;
        stiffness_product(s, q, q, work);
        double rayleigh = 0.0;
        for (uint32_t i = 0; i < n3; i++) {
            q[i] *= scale;
            rayleigh += p[i] * q[i];
        }
        bool converged = fabs(rayleigh - lambda) <= 1e-10 * rayleigh;
        lambda = rayleigh;
        memcpy(p, q, n3 * sizeof *p);
        if (converged) break;
    }
    free(p);
    free(q);
    free(work);
    return sqrt(lambda);
}

sb_solver_def study_solver_def(sb_integrator integrator) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.gravity[2] = 0.0;
    def.kernels = SB_KERNELS_REFERENCE;
    def.runtime.threads = 1;
    return def;
}

sb_solver* study_solver(const study_sheet* s, const sb_solver_def* def) {
    sb_error err;
    sb_solver* solver = sb_solver_create(s->model, def, &err);
    if (!solver) study_fail(err.message);
    return solver;
}

/* Every free vertex displaced a little, deterministically (study_trial). */
static void perturb(const study_sheet* s, sb_solver* solver, bool in_plane) {
    uint32_t n = s->mesh.vertex_count;
    double* x = malloc(3 * n * sizeof *x);
    memcpy(x, s->mesh.positions, 3 * n * sizeof *x);
    for (uint32_t i = 0; i < 3 * n; i++)
        if (in_plane || i % 3 == 2) x[i] += 1e-3 * sin(12.9898 * (in_plane ? i : i / 3));
    sb_solver_set_state(solver, x, NULL);
    free(x);
}

bool study_survives(const study_sheet* s, const sb_solver_def* def, double dt, const study_trial* trial) {
    sb_solver_def unloaded = *def;
    unloaded.external_force = NULL;
    sb_solver* solver = study_solver(s, &unloaded);
    perturb(s, solver, trial->in_plane);
    sb_energies e = sb_solver_energies(solver);
    double e0 = sb_energies_total(&e);
    bool ok = true;
    long steps = trial->duration > 0 ? lround(fmax(1.0, ceil(trial->duration / dt))) : STUDY_STABLE_STEPS;
    for (long step = 0; step < steps && ok; step++) {
        ok = sb_solver_advance(solver, dt) == SB_OK;
        if (ok) {
            e = sb_solver_energies(solver);
            ok = sb_energies_total(&e) <= 10.0 * e0;
        }
    }
    sb_solver_destroy(solver);
    return ok;
}

double study_largest_stable_step(const study_sheet* s, const sb_solver_def* def, double lo, double hi,
                                 const study_trial* trial) {
    if (study_survives(s, def, hi, trial)) return hi;
    bool found = false; /* lo itself is tried last: at a tiny step it is the costliest run */
    for (int it = 0; it < 14; it++) {
        double mid = sqrt(lo * hi);
        bool ok = study_survives(s, def, mid, trial);
        found |= ok;
        if (ok)
            lo = mid;
        else
            hi = mid;
    }
    return found || study_survives(s, def, lo, trial) ? lo : 0.0;
}

static void load_force(void* user, uint32_t vertex, double time, const double position[3], const double velocity[3],
                       double force[3]) {
    (void)time, (void)position, (void)velocity;
    const study_load* load = user;
    for (uint32_t i = 0; i < load->count; i++)
        if (load->vertices[i] == vertex)
            for (int c = 0; c < 3; c++) force[c] += load->force[c];
}

sb_solver* study_loaded_solver(const study_sheet* s, const sb_solver_def* def, const study_load* load) {
    sb_solver_def loaded = *def;
    loaded.external_force = load_force;
    loaded.external_user = (void*)load;
    return study_solver(s, &loaded);
}

double study_load_run(const study_sheet* s, const sb_solver_def* def, const study_load* load, double dt,
                      double duration, double* out) {
    sb_solver* solver = study_loaded_solver(s, def, load);
    long steps = lround(duration / dt);
    clock_t start = clock();
    bool ok = true;
    for (long i = 0; i < steps && ok; i++) ok = sb_solver_advance(solver, dt) == SB_OK;
    double seconds = (double)(clock() - start) / CLOCKS_PER_SEC;
    sb_solver_get_positions(solver, out);
    sb_solver_destroy(solver);
    return ok ? seconds : -1.0;
}

double study_dividing_step(double duration, double dt) { return duration / ceil(duration / dt * (1 - 1e-12)); }

double study_max_distance(const double* a, const double* b, uint32_t vertex_count) {
    double largest = 0.0;
    for (uint32_t i = 0; i < vertex_count; i++) {
        double dx = a[3 * i] - b[3 * i], dy = a[3 * i + 1] - b[3 * i + 1], dz = a[3 * i + 2] - b[3 * i + 2];
        largest = fmax(largest, sqrt(dx * dx + dy * dy + dz * dz));
    }
    return largest;
}

FILE* study_open(const char* dir, const char* name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE* f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "sb_study: cannot write %s\n", path);
        exit(1);
    }
    return f;
}
