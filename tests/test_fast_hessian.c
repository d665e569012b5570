/* The fast kernels' second derivatives (kernels/forces/fast_hessian.h) against the
 * reference's exact ones (kernels/forces/hessian.h): the product K p + w D p
 * against sb_stiffness_product and the damping blocks, the diagonal blocks
 * against the element matrices, the product's symmetry, each on 1, 2 and 3
 * threads with bitwise equal results; and implicit Euler on the fast
 * kernels (kernels/integrators/implicit_fast.c) against the reference's over large
 * steps, bitwise the same on 1, 2 and 3 threads, its forces and energies
 * when asked as a fresh evaluation's, its first guess (the last step's Δv)
 * saving CG iterations. */
#include "test_util.h"

#include "kernels/forces/fast_hessian.h"
#include "kernels/forces/fast_hessian_bonds.h"
#include "kernels/forces/fast_hessian_corners.h"
#include "kernels/forces/fast_hessian_hinges.h"
#include "kernels/forces/fast_tets.h"
#include "kernels/forces/fast_membranes.h"
#include "kernels/forces/hessian.h"
#include "kernels/forces/hessian_edges.h"
#include "kernels/state/solver_data.h"
#include "kernels/state/vertex_state.h"
#include "kernels/state/solver_forces.h"
#include "kernels/state/solver_fast.h"

/* The fast kernels' relative error against the double reference: rounding
 * of sb_real. In float the derivative parts come out of the same
 * cancellations as the forces (a bond's 1 − r0/r, a corner's c − c0, at
 * strains of a few percent), each rounding of 6e-8 amplified by up to the
 * inverse strain; measured 1.5e-7 (product) and 2.3e-7 (blocks) of the
 * largest entry, bounded at 1e-5. */
#if SB_DOUBLE
#define PRODUCT_TOLERANCE 1e-12
#else
#define PRODUCT_TOLERANCE 1e-5
#endif

#define DAMPING_WEIGHT 50.0 /* 1 / dt at dt = 20 ms */

/* A jittered 8 × 7 sheet folded so the hinges are not flat, every term on,
 * plus damped bonds between vertices two apart along x (no triangle owns
 * them: they run in the bond pass; the sheet's own edges are fused into
 * the triangles'). Vertex 0 fixed. */
static sb_model* make_model(void) {
    sb_error err;
    sb_mesh mesh;
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = 8;
    sheet.ny = 7;
    sheet.jitter = 0.2;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    for (uint32_t i = 0; i < mesh.vertex_count; i++) {
        double* p = mesh.positions + 3 * i;
        p[2] = 0.3 * sin(3.0 * p[0]) + 0.1 * p[1] * p[1];
    }
    sb_material_def material = sb_default_material_def();
    material.bond_k = 50.0;
    material.spring_k = 20.0;
    material.spring_damping = 0.05;
    material.angle_k = 0.3;
    material.stretch_bend_k = 2.0;
    material.bend_k = 0.01;
    sb_builder* b = sb_builder_create();
    assert_int_equal(sb_builder_add_mesh(b, &mesh, &material, &err), SB_OK);
    for (uint32_t i = 0; i + 2 < mesh.vertex_count; i += 3) tu_bond(b, i, i + 2, -1.0, 30.0, 10.0, 0.03);
    sb_builder_vertex(b, 0)->fixed = true;
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    sb_mesh_free(&mesh);
    return m;
}

/* n3 doubles moved by up to `amplitude`, rounded to sb_real (what the fast
 * kernels see), and their packed copy. */
static void random_vector(tu_rng* rng, const double* base, double amplitude, double* out, sb_real* packed, size_t n) {
    for (size_t i = 0; i < n; i++)
        for (int a = 0; a < 4; a++) {
            sb_real value =
                a < 3 ? (sb_real)((base ? base[3 * i + a] : 0.0) + tu_uniform(rng, -amplitude, amplitude)) : 0;
            packed[4 * i + a] = value;
            if (a < 3) out[3 * i + a] = value;
        }
}

static sb_real* packed_vector(size_t n) {
    sb_real* v = aligned_alloc(64, ((4 * n * sizeof(sb_real)) / 64 + 1) * 64);
    assert_non_null(v);
    memset(v, 0, 4 * n * sizeof(sb_real));
    return v;
}

static const sb_fast_kernel kernels[5] = {sb_fast_bonds_hessian, sb_fast_corners_hessian, sb_fast_hinges_hessian,
                                          sb_fast_tets_hessian, sb_fast_membranes_hessian};

typedef struct pass_job {
    const sb_solver* s;
    sb_hessian_frame frame;
} pass_job;

static void pass_worker(void* context, const sb_worker* w) {
    pass_job* job = context;
    sb_fast_element_passes(w, job->s, kernels, &job->frame.base);
}

/* The product (p given) or the diagonal pass (p NULL) on `threads` threads:
 * out = K p + w D p, or blocks = the diagonal blocks of K + w D. */
static void fast_pass(const sb_model* m, int threads, const sb_real* x4, const sb_real* p4, sb_real* out4,
                      sb_real* blocks) {
    sb_solver_def def = sb_default_solver_def();
    def.kernels = SB_KERNELS_FAST;
    def.runtime.threads = threads;
    sb_solver* s = tu_solver(m, &def);
    size_t n = sb_model_vertex_count(m);
    if (out4) memset(out4, 0, 4 * n * sizeof *out4);
    if (blocks) memset(blocks, 0, SB_BLOCK_STRIDE * n * sizeof *blocks);
    pass_job job = {s, {{x4, s->carry4, p4, out4}, 1, (sb_real)DAMPING_WEIGHT, blocks}}; /* zero carries */
    sb_team_run(s->team, sb_team_size(s->team), pass_worker, &job);
    sb_solver_destroy(s);
}

/* ref += w D p over the damped bonds (D_ii = D_jj = −D_ij). */
static void add_damping_product(const sb_model* m, const double* x, const double* p, double* ref) {
    double block[9];
    for (uint32_t b = 0; b < m->bond_count; b++) {
        if (!sb_bond_damping_block(m, b, x, block)) continue;
        uint32_t i = m->bond_i[b], j = m->bond_j[b];
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                double d = DAMPING_WEIGHT * block[3 * r + c] * (p[3 * j + c] - p[3 * i + c]);
                ref[3 * i + r] -= d;
                ref[3 * j + r] += d;
            }
    }
}

/* max |fast − ref| / max |ref| over n vectors of `stride` (fast packed by 4
 * or blocks by SB_BLOCK_STRIDE, ref by 3 or SB_BLOCK_STRIDE). */
static double relative_error(const sb_real* fast, int fast_stride, const double* ref, int stride, size_t n) {
    double worst = 0.0, scale = 0.0;
    for (size_t i = 0; i < n; i++)
        for (int a = 0; a < stride; a++) {
            worst = fmax(worst, fabs(fast[fast_stride * i + a] - ref[stride * i + a]));
            scale = fmax(scale, fabs(ref[stride * i + a]));
        }
    return worst / scale;
}

static bool equal_reals(const sb_real* a, const sb_real* b, size_t count) {
    return memcmp(a, b, count * sizeof *a) == 0;
}

/* K p + w D p against the reference on a strained, folded sheet, on 1, 2 and
 * 3 threads: within PRODUCT_TOLERANCE, bitwise the same for each count. */
static void check_product(sb_model* m, double amplitude) {
    size_t n = sb_model_vertex_count(m);
    tu_rng rng = {7};
    double *rest = tu_rest_positions(m), *x = malloc(3 * n * sizeof *x), *p = malloc(3 * n * sizeof *p);
    double* ref = malloc(3 * n * sizeof *ref);
    sb_real *x4 = packed_vector(n), *p4 = packed_vector(n),
            *out4[3] = {packed_vector(n), packed_vector(n), packed_vector(n)};
    random_vector(&rng, rest, amplitude, x, x4, n);
    random_vector(&rng, NULL, 1.0, p, p4, n);
    assert_true(sb_stiffness_product(m, x, p, ref));
    add_damping_product(m, x, p, ref);
    for (int t = 0; t < 3; t++) fast_pass(m, t + 1, x4, p4, out4[t], NULL);
    double error = relative_error(out4[0], 4, ref, 3, n);
    print_message("K p + w D p: relative error %.3g (bound %g)\n", error, PRODUCT_TOLERANCE);
    assert_true(error <= PRODUCT_TOLERANCE);
    assert_true(equal_reals(out4[0], out4[1], 4 * n) && equal_reals(out4[0], out4[2], 4 * n));
    free(rest), free(x), free(p), free(ref), free(x4), free(p4);
    for (int t = 0; t < 3; t++) free(out4[t]);
    sb_model_destroy(m);
}

static void test_product(void** state) {
    (void)state;
    check_product(make_model(), 0.01);
}

/* The diagonal blocks of K + w D (their upper triangles) against the
 * element matrices' and the damping blocks. */
static void check_diagonal_blocks(sb_model* m, double amplitude) {
    size_t n = sb_model_vertex_count(m);
    tu_rng rng = {11};
    double *rest = tu_rest_positions(m), *x = malloc(3 * n * sizeof *x), *ref = calloc(9 * n, sizeof *ref);
    double* ref_upper = calloc(SB_BLOCK_STRIDE * n, sizeof *ref_upper);
    sb_real *x4 = packed_vector(n), *blocks[3];
    random_vector(&rng, rest, amplitude, x, x4, n);
    double k[SB_ELEMENT_MATRIX], damping[9];
    for (uint64_t id = 0; id < sb_element_count(m); id++) {
        sb_element e = sb_element_at(m, id);
        int size = 3 * e.count;
        assert_true(sb_element_stiffness(m, &e, x, k));
        for (int a = 0; a < e.count; a++)
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++) ref[9 * e.vertex[a] + 3 * r + c] += k[(3 * a + r) * size + 3 * a + c];
    }
    for (uint32_t b = 0; b < m->bond_count; b++)
        if (sb_bond_damping_block(m, b, x, damping))
            for (int q = 0; q < 9; q++) {
                ref[9 * m->bond_i[b] + q] += DAMPING_WEIGHT * damping[q];
                ref[9 * m->bond_j[b] + q] += DAMPING_WEIGHT * damping[q];
            }
    static const int upper[SB_BLOCK_SIZE] = {0, 1, 2, 4, 5, 8};
    for (size_t i = 0; i < n; i++)
        for (int e = 0; e < SB_BLOCK_SIZE; e++)
            ref_upper[SB_BLOCK_STRIDE * i + sb_block_offset[e]] = ref[9 * i + upper[e]];
    for (int t = 0; t < 3; t++) {
        blocks[t] = packed_vector(2 * n);
        fast_pass(m, t + 1, x4, NULL, NULL, blocks[t]);
    }
    double error = relative_error(blocks[0], SB_BLOCK_STRIDE, ref_upper, SB_BLOCK_STRIDE, n);
    print_message("diagonal blocks: relative error %.3g (bound %g)\n", error, PRODUCT_TOLERANCE);
    assert_true(error <= PRODUCT_TOLERANCE);
    assert_true(equal_reals(blocks[0], blocks[1], SB_BLOCK_STRIDE * n) &&
                equal_reals(blocks[0], blocks[2], SB_BLOCK_STRIDE * n));
    free(rest), free(x), free(ref), free(ref_upper), free(x4);
    for (int t = 0; t < 3; t++) free(blocks[t]);
    sb_model_destroy(m);
}

static void test_diagonal_blocks(void** state) {
    (void)state;
    check_diagonal_blocks(make_model(), 0.01);
}

/* The co-rotated tetrahedra's pass (kernels/forces/fast_tets.c): R K0 Rᵀ p
 * and its diagonal blocks against the reference's element matrices, on a
 * clamped 4 × 3 × 3 block of 1 cm cubes (216 tetrahedra, E = 3.5 kPa,
 * ν = 0.45) strained by up to 1 mm a coordinate; bitwise on 1, 2, 3 threads. */
static void test_tets(void** state) {
    (void)state;
    check_product(tu_tet_block(4, 3, 3, 0.01, 3500.0, 0.45, 0.15, 3, true), 0.001);
    check_diagonal_blocks(tu_tet_block(4, 3, 3, 0.01, 3500.0, 0.45, 0.15, 3, true), 0.001);
}

/* A jittered 8 × 6 sheet of 0.1 × 0.08 m of a tissue membrane (factory
 * membrane: E 30 kPa, ν 0.45, 1 mm), membranes and hinges. */
static sb_model* membrane_model(void) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = 8, sheet.ny = 6, sheet.width = 0.1, sheet.height = 0.08, sheet.jitter = 0.2;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    sb_builder* b = sb_builder_create();
    sb_sheet_material_def material = sb_default_sheet_material_def();
    assert_int_equal(sb_builder_add_sheet(b, &mesh, &material, &err), SB_OK);
    sb_model* m = tu_compile(b);
    sb_builder_destroy(b);
    sb_mesh_free(&mesh);
    return m;
}

/* The membranes' pass (kernels/forces/fast_membranes.c) with the hinges':
 * K p and the diagonal blocks against the element matrices, strained by up
 * to 1 mm a coordinate; bitwise on 1, 2, 3 threads. */
static void test_membranes(void** state) {
    (void)state;
    check_product(membrane_model(), 0.001);
    check_diagonal_blocks(membrane_model(), 0.001);
}

/* A flat 8 × 6 sheet of 0.1 × 0.08 m, every quad cut along the same
 * diagonal and its inner vertices jittered in the plane: the factory gives
 * it the plate bending (kernels/forces/plate.c, run in the membranes'
 * slots) in place of the hinges. */
static sb_model* plate_model(void) {
    const uint32_t nx = 8, ny = 6;
    sb_mesh mesh = {nx * ny, malloc(3 * (size_t)nx * ny * sizeof(double)), 2 * (nx - 1) * (ny - 1),
                    malloc(6 * (size_t)(nx - 1) * (ny - 1) * sizeof(uint32_t))};
    tu_rng rng = {29};
    for (uint32_t j = 0; j < ny; j++)
        for (uint32_t i = 0; i < nx; i++) {
            double* p = mesh.positions + 3 * ((size_t)j * nx + i);
            bool inner = i > 0 && j > 0 && i + 1 < nx && j + 1 < ny;
            p[0] = 0.1 * i / (nx - 1) + (inner ? tu_uniform(&rng, -0.002, 0.002) : 0.0);
            p[1] = 0.08 * j / (ny - 1) + (inner ? tu_uniform(&rng, -0.002, 0.002) : 0.0);
            p[2] = 0.0;
        }
    uint32_t* t = mesh.triangles;
    for (uint32_t j = 0; j + 1 < ny; j++)
        for (uint32_t i = 0; i + 1 < nx; i++) {
            uint32_t a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
            const uint32_t two[6] = {a, b, c, a, c, d};
            memcpy(t, two, sizeof two);
            t += 6;
        }
    sb_builder* builder = sb_builder_create();
    sb_sheet_material_def material = sb_default_sheet_material_def();
    sb_error err;
    assert_int_equal(sb_builder_add_sheet(builder, &mesh, &material, &err), SB_OK);
    sb_model* m = tu_compile(builder);
    sb_builder_destroy(builder);
    sb_mesh_free(&mesh);
    assert_int_equal(sb_model_hinge_count(m), 0);
    return m;
}

/* The membranes' pass with the plates': K p and the diagonal blocks
 * against the element matrices, strained by up to 1 mm a coordinate;
 * bitwise on 1, 2, 3 threads. */
static void test_plates(void** state) {
    (void)state;
    check_product(plate_model(), 0.001);
    check_diagonal_blocks(plate_model(), 0.001);
}

/* The same for the quadratic tetrahedra (the same block, a vertex at each
 * edge's middle: 30 × 30 element matrices). */
static void test_quadratic_tets(void** state) {
    (void)state;
    check_product(tu_quadratic_tet_block(4, 3, 3, 0.01, 3500.0, 0.45, 0.15, 3, true), 0.001);
    check_diagonal_blocks(tu_quadratic_tet_block(4, 3, 3, 0.01, 3500.0, 0.45, 0.15, 3, true), 0.001);
}

static double packed_dot(const sb_real* a, const sb_real* b, size_t n) {
    double sum = 0.0;
    for (size_t k = 0; k < 4 * n; k++) sum += (double)a[k] * b[k];
    return sum;
}

/* pᵀ (K + w D) q = qᵀ (K + w D) p, to the kernels' rounding. */
static void test_symmetry(void** state) {
    (void)state;
    sb_model* m = make_model();
    size_t n = sb_model_vertex_count(m);
    tu_rng rng = {13};
    double *rest = tu_rest_positions(m), *scratch = malloc(3 * n * sizeof *scratch);
    sb_real *x4 = packed_vector(n), *p4 = packed_vector(n), *q4 = packed_vector(n);
    sb_real *kp = packed_vector(n), *kq = packed_vector(n);
    random_vector(&rng, rest, 0.01, scratch, x4, n);
    random_vector(&rng, NULL, 1.0, scratch, p4, n);
    random_vector(&rng, NULL, 1.0, scratch, q4, n);
    fast_pass(m, 2, x4, p4, kp, NULL);
    fast_pass(m, 2, x4, q4, kq, NULL);
    double pkq = packed_dot(p4, kq, n), qkp = packed_dot(q4, kp, n);
    double scale = sqrt(packed_dot(p4, p4, n) * packed_dot(kq, kq, n));
    print_message("p.Kq %.9g, q.Kp %.9g: asymmetry %.3g of |p||Kq|\n", pkq, qkp, fabs(pkq - qkp) / scale);
    assert_true(fabs(pkq - qkp) <= PRODUCT_TOLERANCE * scale);
    free(rest), free(scratch), free(x4), free(p4), free(q4), free(kp), free(kq);
    sb_model_destroy(m);
}

/* ---- implicit Euler on the fast kernels ---------------------------------- */

#define IMPLICIT_STEPS 3
#define IMPLICIT_DT 0.02
/* The fast step's velocities against the reference's, relative to the
 * largest: the Newton tolerance (1e-10) times the system's conditioning in
 * double (measured 1.1e-10), float's stopping floor in float (6e-5 and
 * 1.2e-4 measured, the floor ~4e-5 of the first residual). */
#if SB_DOUBLE
#define IMPLICIT_AGREEMENT 1e-8
#else
#define IMPLICIT_AGREEMENT 5e-4
#endif

/* An external force on vertex 7, along z. */
static void push(void* user, uint32_t vertex, double time, const double x[3], const double v[3], double f[3]) {
    (void)user, (void)time, (void)x, (void)v;
    if (vertex == 7) f[2] += 0.05;
}

/* A hard handle moving vertices 10 and 11 up and a soft one pulling vertex
 * 30 (both along a path), and the push above, on def. */
typedef struct loads {
    sb_handle* handles[2];
    uint32_t held[2], pulled;
    sb_keyframe path[2];
} loads;

static void add_loads(loads* l, sb_solver_def* def) {
    sb_error err;
    *l = (loads){.held = {10, 11}, .pulled = 30, .path = {{0.0, {0, 0, 0}, {0, 0, 0}}, {1.0, {0, 0, 0.5}, {0, 0, 0}}}};
    sb_handle_def hard = sb_default_handle_def(), soft = sb_default_handle_def();
    hard.vertices = l->held;
    hard.vertex_count = 2;
    hard.path = l->path;
    hard.path_count = 2;
    soft.vertices = &l->pulled;
    soft.vertex_count = 1;
    soft.stiffness = 5.0;
    soft.damping = 0.05;
    soft.path = l->path;
    soft.path_count = 2;
    l->handles[0] = sb_handle_create(&hard, &err);
    l->handles[1] = sb_handle_create(&soft, &err);
    assert_non_null(l->handles[0]);
    assert_non_null(l->handles[1]);
    def->handles = l->handles;
    def->handle_count = 2;
    def->external_force = push;
}

/* IMPLICIT_STEPS steps of implicit Euler (CG) from a strained, moving sheet
 * under gravity, with the loads above when `loaded`; positions and
 * velocities out (3n each), stats returned. */
static sb_step_stats implicit_run(const sb_model* m, sb_kernels kernels, int threads, bool loaded, double* x, double* v,
                                  uint64_t* hash) {
    sb_solver_def def = sb_default_solver_def();
    loads l;
    if (loaded) add_loads(&l, &def);
    def.integrator = SB_INTEGRATOR_IMPLICIT_EULER;
    def.implicit_solver = SB_LINEAR_CG;
    def.implicit_tolerance = 1e-10;
    def.kernels = kernels;
    def.runtime.threads = threads;
    sb_solver* s = tu_solver(m, &def);
    size_t n = sb_model_vertex_count(m);
    tu_rng rng = {17};
    double *rest = tu_rest_positions(m), *v0 = malloc(3 * n * sizeof *v0);
    for (size_t k = 0; k < 3 * n; k++) {
        rest[k] += k > 2 ? tu_uniform(&rng, -0.005, 0.005) : 0.0;
        v0[k] = k > 2 ? tu_uniform(&rng, -0.1, 0.1) : 0.0;
    }
    assert_int_equal(sb_solver_set_state(s, rest, v0), SB_OK);
    sb_step_stats total = {0};
    total.converged = true;
    for (int step = 0; step < IMPLICIT_STEPS; step++) {
        tu_advance(s, IMPLICIT_DT, 1);
        sb_step_stats stats = sb_solver_last_step(s);
        total.newton_iterations += stats.newton_iterations;
        total.cg_iterations += stats.cg_iterations;
        total.cg_indefinite += stats.cg_indefinite;
        total.converged &= stats.converged;
    }
    sb_solver_get_positions(s, x);
    sb_solver_get_velocities(s, v);
    if (hash) *hash = tu_state_hash(s);
    free(rest), free(v0);
    sb_solver_destroy(s);
    if (loaded) sb_handle_destroy(l.handles[0]), sb_handle_destroy(l.handles[1]);
    return total;
}

/* The fast Newton reaches the reference's backward Euler steps: the same
 * positions to the Newton tolerance in double (1e-10 of the residual), to
 * float's stopping floor in float; bitwise the same on 1, 2 and 3 threads;
 * free, and with hard and soft handles and an external force. */
static void implicit_against_reference(bool loaded) {
    sb_model* m = make_model();
    size_t n3 = 3 * (size_t)sb_model_vertex_count(m);
    double *x = malloc(n3 * sizeof *x), *v = malloc(n3 * sizeof *v);
    double *ref_x = malloc(n3 * sizeof *x), *ref_v = malloc(n3 * sizeof *v);
    sb_step_stats ref = implicit_run(m, SB_KERNELS_REFERENCE, 1, loaded, ref_x, ref_v, NULL);
    uint64_t hash[3];
    sb_step_stats fast[3];
    for (int t = 0; t < 3; t++) fast[t] = implicit_run(m, SB_KERNELS_FAST, t + 1, loaded, x, v, hash + t);
    double dx = 0.0, dv = 0.0, vmax = tu_max_abs(ref_v, n3);
    for (size_t k = 0; k < n3; k++) {
        dx = fmax(dx, fabs(x[k] - ref_x[k]));
        dv = fmax(dv, fabs(v[k] - ref_v[k]));
    }
    print_message("%s: reference: %d Newton, %d CG (%u indefinite); fast: %d Newton, %d CG (%u indefinite)\n",
                  loaded ? "handles and a push" : "free", ref.newton_iterations, ref.cg_iterations, ref.cg_indefinite,
                  fast[0].newton_iterations, fast[0].cg_iterations, fast[0].cg_indefinite);
    print_message("fast against reference after %d steps of %g s: |dx| %.3g m, |dv| %.3g of |v| %.3g\n", IMPLICIT_STEPS,
                  IMPLICIT_DT, dx, dv / vmax, vmax);
    assert_true(ref.converged && fast[0].converged);
    assert_true(fast[0].newton_iterations >= IMPLICIT_STEPS && fast[0].cg_iterations > fast[0].newton_iterations);
    /* x moves by dt v each step: its difference stays within the steps'
     * velocity differences */
    assert_true(dv <= IMPLICIT_AGREEMENT * vmax);
    assert_true(dx <= IMPLICIT_STEPS * IMPLICIT_DT * IMPLICIT_AGREEMENT * vmax);
    assert_true(hash[0] == hash[1] && hash[0] == hash[2]);
    for (int t = 1; t < 3; t++) assert_int_equal(fast[t].cg_iterations, fast[0].cg_iterations);
    free(x), free(v), free(ref_x), free(ref_v);
    sb_model_destroy(m);
}

static void test_implicit_fast(void** state) {
    (void)state;
    implicit_against_reference(false);
}

static void test_implicit_fast_loaded(void** state) {
    (void)state;
    implicit_against_reference(true);
}

/* On a sheet large enough for 3 workers (one per 4 096 vertices,
 * sb_implicit_width) over many vertex chunks, whose vector operations'
 * sums (kernels/integrators/implicit_fast.c: SIMD lanes, 4 vertices a block) end in
 * partial blocks: 111 x 111 = 12 321 vertices, the last chunk 33 vertices
 * (132 reals: 8 blocks of 16 and 4 left; 8 blocks of 4 vertices and 1).
 * Hung from two corners, falling from rest at 10 ms steps: converged on
 * every step, bitwise the same on 1, 2 and 3 threads. */
static void test_implicit_fast_chunks(void** state) {
    (void)state;
    sb_model* m = tu_every_term_sheet(111, true);
    uint64_t hash[3];
    int cg[3];
    for (int t = 0; t < 3; t++) {
        sb_solver_def def = sb_default_solver_def();
        def.integrator = SB_INTEGRATOR_IMPLICIT_EULER;
        def.implicit_solver = SB_LINEAR_CG;
        def.kernels = SB_KERNELS_FAST;
        def.runtime.threads = t + 1;
        sb_solver* s = tu_solver(m, &def);
        cg[t] = 0;
        for (int step = 0; step < 3; step++) {
            tu_advance(s, 0.01, 1);
            sb_step_stats stats = sb_solver_last_step(s);
            assert_true(stats.converged);
            assert_true(stats.newton_iterations >= 1 && stats.cg_iterations > stats.newton_iterations);
            cg[t] += stats.cg_iterations;
        }
        hash[t] = tu_state_hash(s);
        sb_solver_destroy(s);
    }
    print_message("111 x 111 sheet: %d CG iterations in 3 steps\n", cg[0]);
    assert_true(hash[0] == hash[1] && hash[0] == hash[2]);
    assert_true(cg[0] == cg[1] && cg[0] == cg[2]);
    sb_model_destroy(m);
}

/* A hanging sheet's run for the first-guess test: `steps` steps of dt
 * (every other step dt (1 + 1e-9) when `cold`: a step whose dt differs
 * from the last one's starts from Δv = 0, kernels/integrators/implicit_fast.c), the
 * stats summed, the steps Newton left at their guess counted, the
 * positions into x (3n), the state's hash returned. */
typedef struct guess_run {
    int newton, cg, guessed; /* guessed: steps that took no Newton iteration */
    bool converged;
    uint64_t hash;
} guess_run;

static guess_run run_hanging(const sb_model* m, int threads, double tolerance, bool cold, int steps, double dt,
                             double* x) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_IMPLICIT_EULER;
    def.implicit_solver = SB_LINEAR_CG;
    def.implicit_tolerance = tolerance;
    def.kernels = SB_KERNELS_FAST;
    def.runtime.threads = threads;
    sb_solver* s = tu_solver(m, &def);
    guess_run r = {.converged = true};
    for (int step = 0; step < steps; step++) {
        tu_advance(s, cold && step % 2 ? dt * (1.0 + 1e-9) : dt, 1);
        sb_step_stats stats = sb_solver_last_step(s);
        r.newton += stats.newton_iterations;
        r.cg += stats.cg_iterations;
        r.guessed += stats.newton_iterations == 0;
        r.converged &= stats.converged;
    }
    sb_solver_get_positions(s, x);
    r.hash = tu_state_hash(s);
    sb_solver_destroy(s);
    return r;
}

/* The first guess (the last step's Δv): a sheet hung from two corners,
 * falling from rest in steps of GUESS_DT at tolerance 1e-2 (ended by the
 * tolerance, not the rounding floor, in float too). Warm, the run takes
 * fewer CG iterations and no more Newton iterations than one that starts
 * every step from Δv = 0 (in double some steps take none: the guess is
 * within the tolerance); bitwise the same on 1, 2 and 3 threads; and its
 * state about as close to a tight-tolerance run's as the cold one's: within
 * three times its distance (a kept guess may end a step at the tolerance,
 * where CG aims at half of it). Measured: float 27 against 60 CG, 1.58e-5
 * against 1.98e-5 m; double 20 against 60 CG, 3 steps with no Newton
 * iteration, 3.38e-5 against 1.98e-5 m. */
#define GUESS_SIDE 111
#define GUESS_STEPS 12
#define GUESS_DT 0.002
#define GUESS_TOLERANCE 1e-2
static void test_implicit_fast_first_guess(void** state) {
    (void)state;
    sb_model* m = tu_every_term_sheet(GUESS_SIDE, true);
    size_t n3 = 3 * (size_t)sb_model_vertex_count(m);
    double* x[3] = {malloc(n3 * sizeof(double)), malloc(n3 * sizeof(double)), malloc(n3 * sizeof(double))};
    guess_run warm[3];
    for (int t = 0; t < 3; t++) warm[t] = run_hanging(m, t + 1, GUESS_TOLERANCE, false, GUESS_STEPS, GUESS_DT, x[0]);
    guess_run cold = run_hanging(m, 2, GUESS_TOLERANCE, true, GUESS_STEPS, GUESS_DT, x[1]);
    guess_run tight = run_hanging(m, 2, 1e-8, false, GUESS_STEPS, GUESS_DT, x[2]);
    double warm_error = 0.0, cold_error = 0.0;
    for (size_t k = 0; k < n3; k++) {
        warm_error = fmax(warm_error, fabs(x[0][k] - x[2][k]));
        cold_error = fmax(cold_error, fabs(x[1][k] - x[2][k]));
    }
    print_message("%d steps: warm %d Newton (%d steps none), %d CG; cold %d Newton (%d none), %d CG; tight %d Newton, "
                  "%d CG; from the tight run: warm %.3g m, cold %.3g m\n",
                  GUESS_STEPS, warm[0].newton, warm[0].guessed, warm[0].cg, cold.newton, cold.guessed, cold.cg,
                  tight.newton, tight.cg, warm_error, cold_error);
    assert_true(warm[0].converged && cold.converged && tight.converged);
    assert_int_equal(cold.guessed, 0);
    assert_true(warm[0].cg < cold.cg && warm[0].newton <= cold.newton);
    for (int t = 1; t < 3; t++) {
        assert_true(warm[t].hash == warm[0].hash);
        assert_int_equal(warm[t].cg, warm[0].cg);
        assert_int_equal(warm[t].newton, warm[0].newton);
    }
    assert_true(warm_error <= 3.0 * cold_error);
    for (int k = 0; k < 3; k++) free(x[k]);
    sb_model_destroy(m);
}

/* Free of loads, the fast step leaves the new state's forces and energies
 * for when they are asked for: what the getters return then is bitwise
 * what a solver set to the same state evaluates. */
static void test_implicit_fast_energies_when_asked(void** state) {
    (void)state;
    sb_model* m = make_model();
    size_t n3 = 3 * (size_t)sb_model_vertex_count(m);
    sb_solver_def def = sb_default_solver_def();
    def.integrator = SB_INTEGRATOR_IMPLICIT_EULER;
    def.implicit_solver = SB_LINEAR_CG;
    def.kernels = SB_KERNELS_FAST;
    sb_solver *s = tu_solver(m, &def), *fresh = tu_solver(m, &def);
    tu_advance(s, IMPLICIT_DT, 3);
    assert_true(s->forces_stale);
    double *x = malloc(n3 * sizeof *x), *v = malloc(n3 * sizeof *v),
           *f[2] = {malloc(n3 * sizeof *x), malloc(n3 * sizeof *x)};
    sb_solver_get_positions(s, x);
    sb_solver_get_velocities(s, v);
    assert_int_equal(sb_solver_set_state(fresh, x, v), SB_OK);
    sb_energies asked = sb_solver_energies(s), evaluated = sb_solver_energies(fresh);
    sb_solver_get_forces(s, f[0]);
    sb_solver_get_forces(fresh, f[1]);
    assert_memory_equal(&asked, &evaluated, sizeof asked);
    assert_memory_equal(f[0], f[1], n3 * sizeof *f[0]);
    assert_true(asked.term[SB_TERM_BOND] > 0.0);
    free(x), free(v), free(f[0]), free(f[1]);
    sb_solver_destroy(s);
    sb_solver_destroy(fresh);
    sb_model_destroy(m);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_product),
        cmocka_unit_test(test_diagonal_blocks),
        cmocka_unit_test(test_tets),
        cmocka_unit_test(test_membranes),
        cmocka_unit_test(test_plates),
        cmocka_unit_test(test_quadratic_tets),
        cmocka_unit_test(test_symmetry),
        cmocka_unit_test(test_implicit_fast),
        cmocka_unit_test(test_implicit_fast_loaded),
        cmocka_unit_test(test_implicit_fast_chunks),
        cmocka_unit_test(test_implicit_fast_energies_when_asked),
        cmocka_unit_test(test_implicit_fast_first_guess),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
