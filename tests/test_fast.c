/* The fast kernels against the double scalar reference, the coloring they
 * rely on, and determinism for any thread count. */
#include "test_util.h"

#include <stdio.h>

#include "kernels/forces/fast_model.h"

/* Float carries ~7 digits; after a few dozen operations per element the
 * error stays below 1e-5 of the largest force. Double: 1e-12. */
#define FAST_TOLERANCE (sizeof(sb_real) == sizeof(float) ? 1e-5 : 1e-12)

typedef enum { SHAPE_SHEET, SHAPE_JITTERED, SHAPE_SLIVERS, SHAPE_FLATTENED, SHAPE_SPHERE } shape;

static void make_mesh(shape kind, sb_mesh* mesh) {
    sb_error err;
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = 24;
    sheet.ny = 20;
    if (kind == SHAPE_JITTERED) sheet.jitter = 0.15;
    if (kind == SHAPE_SLIVERS) {
        sheet.nx = 40;
        sheet.ny = 3;
        sheet.height = 0.002; /* triangles 13 times longer than high */
    }
    sb_status status = kind == SHAPE_SPHERE ? sb_mesh_generate_icosphere(2, 0.5, mesh, &err)
                                            : sb_mesh_generate_sheet(&sheet, mesh, &err);
    assert_int_equal(status, SB_OK);
}

/* The bonds of a model: uniform and undamped, uniform and damped (both
 * fused into the triangles that own their edges), or mixed: every edge's
 * bond with constants and a rest length of its own (some damped, some not,
 * fused with per-slot constants), and bonds no triangle owns (i, i + 2),
 * which the bond kernel computes. */
typedef enum { BONDS_UNDAMPED, BONDS_DAMPED, BONDS_MIXED } bonds;

static bool is_edge(const sb_mesh* mesh, uint32_t i, uint32_t j) {
    for (uint32_t t = 0; t < mesh->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            uint32_t a = mesh->triangles[3 * t + c], b = mesh->triangles[3 * t + (c + 1) % 3];
            if ((a == i && b == j) || (a == j && b == i)) return true;
        }
    return false;
}

static void add_mixed_bonds(sb_builder* builder, const sb_mesh* mesh) {
    tu_rng rng = {7};
    for (uint32_t t = 0; t < mesh->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            uint32_t i = mesh->triangles[3 * t + c], j = mesh->triangles[3 * t + (c + 1) % 3];
            if (i > j) continue; /* each interior edge once */
            double rest = t % 2 ? -1.0 : tu_dist(mesh->positions + 3 * i, mesh->positions + 3 * j) * 1.03;
            double damping = c == 1 ? 0.0 : tu_uniform(&rng, 0.02, 0.08);
            assert_true(tu_bond(builder, i, j, rest, tu_uniform(&rng, 30, 70), tu_uniform(&rng, 10, 30), damping) >= 0);
        }
    for (uint32_t i = 0; i + 2 < mesh->vertex_count; i += 5)
        if (!is_edge(mesh, i, i + 2))
            assert_true(tu_bond(builder, i, i + 2, -1.0, tu_uniform(&rng, 30, 70), 5.0, tu_uniform(&rng, 0, 0.05)) >=
                        0);
}

static sb_model* make_model(const sb_mesh* mesh, bonds kind) {
    sb_material_def material = sb_default_material_def();
    bool mixed = kind == BONDS_MIXED;
    material.bond_k = mixed ? 0.0 : 50.0;
    material.angle_k = 0.3;
    material.stretch_bend_k = 2.0;
    material.spring_k = mixed ? 0.0 : 20.0;
    material.spring_damping = kind == BONDS_DAMPED ? 0.05 : 0.0;
    material.bend_k = 0.01;
    sb_builder* builder = sb_builder_create();
    sb_error err;
    assert_int_equal(sb_builder_add_mesh(builder, mesh, &material, &err), SB_OK);
    if (mixed) add_mixed_bonds(builder, mesh);
    sb_model* model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    if (!model) fail_msg("%s", err.message);
    return model;
}

/* Perturbed positions and random velocities, rounded to sb_real so both
 * implementations see the same input. Flattened squashes y to 1e-3 of the
 * rest, making nearly straight and nearly closed corner angles. */
static void perturb(const sb_mesh* mesh, shape kind, uint64_t seed, double* x, double* v) {
    tu_rng rng = {seed};
    double size = kind == SHAPE_SLIVERS ? 0.0005 : 0.01;
    for (uint32_t i = 0; i < 3 * mesh->vertex_count; i++) {
        double p = mesh->positions[i] + tu_uniform(&rng, -size, size);
        if (kind == SHAPE_FLATTENED && i % 3 == 1) p = mesh->positions[i] * 1e-3;
        x[i] = (sb_real)p;
        v[i] = (sb_real)tu_uniform(&rng, -0.5, 0.5);
    }
}

static sb_solver* make_fast_solver(const sb_model* model, int threads) {
    sb_solver_def def = sb_default_solver_def();
    def.kernels = SB_KERNELS_FAST;
    def.runtime.threads = threads;
    def.gravity[2] = 0.0;
    sb_error err;
    sb_solver* solver = sb_solver_create(model, &def, &err);
    if (!solver) fail_msg("%s", err.message);
    return solver;
}

/* The fast forces and term energies at (x, v) (v may be NULL) against the
 * double reference's: the largest force error within FAST_TOLERANCE of the
 * largest force, each term's energy within FAST_TOLERANCE of the largest
 * term. Prints the force error after `what`; returns the fast bending
 * energy over the reference's less one, for the tests of that small term. */
static double assert_fast_matches_reference(const sb_model* model, const double* x, const double* v, const char* what) {
    uint32_t n = sb_model_vertex_count(model);
    double *f = malloc(3 * n * sizeof *f), *fast_f = malloc(3 * n * sizeof *fast_f);
    sb_energies reference;
    sb_error err;
    assert_int_equal(sb_reference_forces(model, x, v, f, &reference, &err), SB_OK);
    sb_solver* solver = make_fast_solver(model, 2);
    assert_int_equal(sb_solver_set_state(solver, x, v), SB_OK);
    sb_solver_get_forces(solver, fast_f);
    double largest = tu_max_abs(f, 3 * n), worst = 0.0;
    for (size_t k = 0; k < 3 * (size_t)n; k++) worst = fmax(worst, fabs(fast_f[k] - f[k]));
    print_message("%s: largest force error %.3g of the largest force\n", what, worst / largest);
    assert_true(largest > 0.0);
    TU_ASSERT_LE(worst, FAST_TOLERANCE * largest);
    sb_energies fast = sb_solver_energies(solver);
    double scale = 0.0;
    for (int t = 0; t < SB_TERM_COUNT; t++) scale = fmax(scale, fabs(reference.term[t]));
    for (int t = 0; t < SB_TERM_COUNT; t++) TU_ASSERT_NEAR(fast.term[t], reference.term[t], FAST_TOLERANCE * scale);
    sb_solver_destroy(solver);
    free(f);
    free(fast_f);
    return fast.term[SB_TERM_BEND] / reference.term[SB_TERM_BEND] - 1.0;
}

static void compare_with_reference(shape kind, bonds variant) {
    static const char* names[] = {"undamped", "damped", "mixed"};
    sb_mesh mesh = {0};
    make_mesh(kind, &mesh);
    sb_model* model = make_model(&mesh, variant);
    uint32_t n = mesh.vertex_count;
    double *x = malloc(3 * n * sizeof *x), *v = malloc(3 * n * sizeof *v);
    for (uint64_t seed = 1; seed <= 3; seed++) {
        perturb(&mesh, kind, seed, x, v);
        char what[64];
        snprintf(what, sizeof what, "shape %d, %s bonds, seed %llu", (int)kind, names[variant],
                 (unsigned long long)seed);
        assert_fast_matches_reference(model, x, v, what);
    }
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
    free(x);
    free(v);
}

static void test_regular_sheet(void** state) {
    (void)state;
    for (int variant = BONDS_UNDAMPED; variant <= BONDS_MIXED; variant++)
        compare_with_reference(SHAPE_SHEET, (bonds)variant);
}
static void test_jittered_sheet(void** state) {
    (void)state;
    for (int variant = BONDS_UNDAMPED; variant <= BONDS_MIXED; variant++)
        compare_with_reference(SHAPE_JITTERED, (bonds)variant);
}
static void test_sliver_triangles(void** state) {
    (void)state;
    for (int variant = BONDS_UNDAMPED; variant <= BONDS_MIXED; variant++)
        compare_with_reference(SHAPE_SLIVERS, (bonds)variant);
}
static void test_nearly_straight_angles(void** state) {
    (void)state;
    for (int variant = BONDS_UNDAMPED; variant <= BONDS_MIXED; variant++)
        compare_with_reference(SHAPE_FLATTENED, (bonds)variant);
}
static void test_icosphere(void** state) {
    (void)state;
    for (int variant = BONDS_UNDAMPED; variant <= BONDS_MIXED; variant++)
        compare_with_reference(SHAPE_SPHERE, (bonds)variant);
}

/* The hinges carried by the triangle slots; fails unless each color lists
 * its triangles by how many they carry, most first. */
static uint32_t carried_hinges(const sb_fast_model* fast) {
    uint32_t carried = 0;
    for (uint32_t r = 0; r < fast->triangles.range_count; r++) {
        uint32_t before = 3;
        for (uint32_t s = fast->triangles.ranges[r].begin; s < fast->triangles.ranges[r].end; s++) {
            uint32_t count = 0;
            for (int j = 0; j < 3; j++) count += (fast->tri_hinge_edges[s] >> 2 * j & 3u) != 0;
            assert_true(count <= before);
            before = count;
            carried += count;
        }
    }
    return carried;
}

/* Lone hinges (4 vertices each, hinges only) folded near where the angle
 * is delicate: near flat (φ0 and φ within 0.05 rad of 0), through itself
 * (φ0 within 0.1 of ±π, φ up to 0.2 from it, so φ crosses ±π and wraps),
 * and nearly closed (flat at rest, folded to within 0.1–0.3 of ±π: φ − φ0
 * near ±π but not at it, where the reference's force flips sign). */
typedef enum { FOLD_NEAR_FLAT, FOLD_THROUGH_ITSELF, FOLD_NEARLY_CLOSED } fold;

/* The hinge's edge along x, o0 in the plane, o1 turned by `angle` about
 * the edge: its dihedral angle is ±angle. */
static void place_hinge(double* x, double at, double angle, tu_rng* rng, double jitter) {
    const double wing[4][3] = {{0, 0, 0}, {1, 0, 0}, {0.4, -0.7, 0}, {0.55, 0.8 * cos(angle), 0.8 * sin(angle)}};
    for (int a = 0; a < 4; a++)
        for (int c = 0; c < 3; c++) x[3 * a + c] = wing[a][c] + (c == 0 ? at : 0) + tu_uniform(rng, -jitter, jitter);
}

static double random_sign(tu_rng* rng) { return tu_uniform(rng, -1, 1) < 0 ? -1.0 : 1.0; }

/* Rest and current angle of one hinge of the given fold. */
static void fold_angles(fold kind, tu_rng* rng, double* rest, double* now) {
    if (kind == FOLD_NEAR_FLAT) {
        *rest = tu_uniform(rng, -0.05, 0.05);
        *now = *rest + tu_uniform(rng, -0.05, 0.05);
    } else if (kind == FOLD_THROUGH_ITSELF) {
        *rest = random_sign(rng) * (M_PI - tu_uniform(rng, 0, 0.1));
        *now = *rest + tu_uniform(rng, -0.2, 0.2);
    } else {
        *rest = tu_uniform(rng, -0.05, 0.05);
        *now = *rest + random_sign(rng) * (M_PI - tu_uniform(rng, 0.1, 0.3));
    }
}

/* The hinge's two wings as triangles (no corner constants), each in either
 * orientation and in either order, so that the hinges are fused into
 * whichever wing carries them in every one of the four relative orders. */
static void add_wings(sb_builder* builder, uint32_t first, tu_rng* rng) {
    uint32_t e0 = first, e1 = first + 1, wing[2][2] = {{first + 2, 0}, {first + 3, 0}};
    for (int w = 0; w < 2; w++) wing[w][1] = random_sign(rng) < 0;
    int order = random_sign(rng) < 0;
    for (int k = 0; k < 2; k++) {
        const uint32_t* tip = wing[k ^ order];
        sb_triangle_def t = {tip[1] ? e1 : e0, tip[1] ? e0 : e1, tip[0], 0.0, 0.0};
        assert_true(sb_builder_add_triangle(builder, &t) >= 0);
    }
}

/* Lone hinges computed by the hinge kernel, or (wings) with their wing
 * triangles, fused into the triangle kernel. */
static void compare_hinges(fold kind, bool wings) {
    enum { hinges = 3 * 16 + 5 }; /* whole blocks and a part block at any width */
    uint32_t n = 4 * hinges;
    double *rest = malloc(3 * n * sizeof *rest), *x = malloc(3 * n * sizeof *x);
    tu_rng rng = {40 + (uint64_t)kind};
    for (uint32_t h = 0; h < hinges; h++) {
        double rest_angle, angle;
        fold_angles(kind, &rng, &rest_angle, &angle);
        place_hinge(rest + 12 * h, 2.0 * h, rest_angle, &rng, 0.0);
        place_hinge(x + 12 * h, 2.0 * h, angle, &rng, 0.01);
    }
    for (uint32_t k = 0; k < 3 * n; k++) x[k] = (sb_real)x[k];
    sb_builder* builder = sb_builder_create();
    for (uint32_t i = 0; i < n; i++) {
        sb_vertex_def vertex = sb_default_vertex_def();
        memcpy(vertex.position, rest + 3 * i, sizeof vertex.position);
        assert_true(sb_builder_add_vertex(builder, &vertex) >= 0);
    }
    for (uint32_t h = 0; h < hinges; h++) {
        assert_true(sb_builder_add_hinge(builder, &(sb_hinge_def){4 * h, 4 * h + 1, 4 * h + 2, 4 * h + 3, 0.2}) >= 0);
        if (wings) add_wings(builder, 4 * h, &rng);
    }
    sb_error err;
    sb_model* model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    if (!model) fail_msg("%s", err.message);
    sb_fast_model* fast = sb_fast_model_create(model, &err);
    assert_non_null(fast);
    assert_int_equal(fast->fused_hinges, wings);
    sb_fast_model_destroy(fast);
    char what[32];
    snprintf(what, sizeof what, "fold %d%s", (int)kind, wings ? " (fused)" : "");
    TU_ASSERT_LE(fabs(assert_fast_matches_reference(model, x, NULL, what)), FAST_TOLERANCE);
    sb_model_destroy(model);
    free(rest);
    free(x);
}

static void test_hinges_near_flat(void** state) {
    (void)state;
    compare_hinges(FOLD_NEAR_FLAT, false);
    compare_hinges(FOLD_NEAR_FLAT, true);
}
static void test_hinges_through_themselves(void** state) {
    (void)state;
    compare_hinges(FOLD_THROUGH_ITSELF, false);
    compare_hinges(FOLD_THROUGH_ITSELF, true);
}
static void test_hinges_nearly_closed(void** state) {
    (void)state;
    compare_hinges(FOLD_NEARLY_CLOSED, false);
    compare_hinges(FOLD_NEARLY_CLOSED, true);
}

/* Lone triangles, each carrying the hinges on a random non-empty set of
 * its edges (their other wings are no triangles of the model, so no other
 * triangle can take them), each hinge with its edge either way round and
 * the triangle's tip as o0 or o1: every hinge slot on every edge. */
static void test_triangles_carrying_three_hinges(void** state) {
    (void)state;
    enum { triangles = 3 * 16 + 5 };
    uint32_t n = 6 * triangles;
    double* x = malloc(3 * n * sizeof *x);
    tu_rng rng = {77};
    sb_builder* builder = sb_builder_create();
    for (uint32_t t = 0; t < triangles; t++) {
        const double corner[3][2] = {{0, 0}, {1, 0}, {0.45, 0.85}};
        for (int c = 0; c < 6; c++) {
            sb_vertex_def vertex = sb_default_vertex_def();
            if (c < 3) {
                vertex.position[0] = 3.0 * t + corner[c][0];
                vertex.position[1] = corner[c][1];
            } else { /* the tip beyond edge c − 3, folded by up to a radian */
                const double *a = corner[c - 3], *b = corner[(c - 2) % 3], *o = corner[(c - 1) % 3];
                double mid[2] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])}, fold = tu_uniform(&rng, -1, 1);
                double out[2] = {mid[0] - o[0], mid[1] - o[1]};
                vertex.position[0] = 3.0 * t + mid[0] + cos(fold) * out[0];
                vertex.position[1] = mid[1] + cos(fold) * out[1];
                vertex.position[2] = sin(fold) * 0.9;
            }
            assert_true(sb_builder_add_vertex(builder, &vertex) >= 0);
        }
        uint32_t v = 6 * t;
        assert_true(sb_builder_add_triangle(builder, &(sb_triangle_def){v, v + 1, v + 2, 1e-9, 0.0}) >= 0);
        int edges = 1 + (int)(t % 7); /* every non-empty subset of the three */
        for (int c = 0; c < 3; c++) {
            if (!(edges >> c & 1)) continue;
            uint32_t a = v + (uint32_t)c, b = v + (uint32_t)(c + 1) % 3, tip = v + (uint32_t)(c + 2) % 3,
                     far = v + 3 + c;
            bool swap_edge = random_sign(&rng) < 0, swap_wings = random_sign(&rng) < 0;
            sb_hinge_def h = {swap_edge ? b : a, swap_edge ? a : b, swap_wings ? far : tip, swap_wings ? tip : far,
                              0.2};
            assert_true(sb_builder_add_hinge(builder, &h) >= 0);
        }
    }
    sb_error err;
    sb_model* model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    if (!model) fail_msg("%s", err.message);
    sb_fast_model* fast = sb_fast_model_create(model, &err);
    assert_true(fast->fused_hinges);
    assert_int_equal(carried_hinges(fast), sb_model_hinge_count(model));
    sb_fast_model_destroy(fast);
    for (uint32_t i = 0; i < n; i++) {
        sb_model_rest_position(model, i, x + 3 * i);
        for (int c = 0; c < 3; c++) x[3 * i + c] = (sb_real)(x[3 * i + c] + tu_uniform(&rng, -0.05, 0.05));
    }
    TU_ASSERT_LE(fabs(assert_fast_matches_reference(model, x, NULL, "triangles carrying 1 to 3 hinges")),
                 FAST_TOLERANCE);
    sb_model_destroy(model);
    free(x);
}

/* The bending term alone on every mesh shape (hinges fused into the
 * triangles): forces and energy against
 * the reference. Its forces are far smaller than the stretching terms', in
 * whose error the tests above would hide them. */
static void test_fused_hinges_on_meshes(void** state) {
    (void)state;
    for (int kind = SHAPE_SHEET; kind <= SHAPE_SPHERE; kind++) {
        sb_mesh mesh = {0};
        make_mesh((shape)kind, &mesh);
        sb_material_def material = sb_default_material_def();
        material.bond_k = material.stretch_bend_k = material.spring_k = 0.0;
        material.angle_k = 1e-9; /* a model has triangles only with some corner term */
        material.bend_k = 0.01;
        sb_builder* builder = sb_builder_create();
        sb_error err;
        assert_int_equal(sb_builder_add_mesh(builder, &mesh, &material, &err), SB_OK);
        sb_model* model = sb_builder_compile(builder, &err);
        sb_builder_destroy(builder);
        assert_non_null(model);
        sb_fast_model* fast = sb_fast_model_create(model, &err);
        assert_true(fast->fused_hinges);
        sb_fast_model_destroy(fast);
        uint32_t n = mesh.vertex_count;
        double *x = malloc(3 * n * sizeof *x), *v = malloc(3 * n * sizeof *v);
        perturb(&mesh, (shape)kind, 11, x, v);
        char what[32];
        snprintf(what, sizeof what, "shape %d, bending alone", kind);
        TU_ASSERT_LE(fabs(assert_fast_matches_reference(model, x, v, what)), FAST_TOLERANCE);
        sb_model_destroy(model);
        sb_mesh_free(&mesh);
        free(x);
        free(v);
    }
}

/* Whether vertex a of slot s repeats an earlier one of the same slot (a
 * fused hinge slot that carries none names one of its triangle's). */
static bool repeated(uint32_t* const* ids, int a, uint32_t s) {
    for (int b = 0; b < a; b++)
        if (ids[b][s] == ids[a][s]) return true;
    return false;
}

/* Marks the vertices of range r's real slots with `mark`; fails on a vertex
 * already marked with it. */
static void mark_range(const sb_color_range* range, int arity, uint32_t* const* ids, uint32_t* owner, uint32_t mark,
                       const char* what) {
    for (uint32_t s = range->begin; s < range->end; s++)
        for (int a = 0; a < arity; a++) {
            if (repeated(ids, a, s)) continue;
            if (owner[ids[a][s]] == mark) fail_msg("%s %u: vertex %u taken twice (slot %u)", what, mark, ids[a][s], s);
            owner[ids[a][s]] = mark;
        }
}

/* Every element of the group (model elements numbered below
 * element_count) appears exactly once; within an element color no two
 * elements share a vertex (SIMD lanes); within a block color no two blocks
 * share a vertex (threads). */
static void check_group(const sb_element_group* g, uint32_t element_count, uint32_t vertex_count, int arity,
                        uint32_t* const* ids) {
    uint8_t* seen = calloc(element_count + 1, 1);
    uint32_t* lane_owner = malloc(vertex_count * sizeof *lane_owner);
    uint32_t* block_owner = malloc(vertex_count * sizeof *block_owner);
    for (uint32_t v = 0; v < vertex_count; v++) lane_owner[v] = block_owner[v] = UINT32_MAX;
    for (uint32_t k = 0; k < g->block_colors && k != SB_OVERFLOW_COLOR; k++) {
        for (uint32_t b = g->color_first_block[k]; b < g->color_first_block[k + 1]; b++) {
            const sb_block* block = &g->blocks[b];
            for (uint32_t r = block->first_range; r < block->first_range + block->range_count; r++) {
                const sb_color_range* range = &g->ranges[r];
                for (uint32_t s = range->begin; s < range->end; s++) {
                    assert_int_equal(seen[g->source[s]], 0);
                    seen[g->source[s]] = 1;
                    for (int a = 0; a < arity; a++) {
                        uint32_t owner = block_owner[ids[a][s]];
                        if (owner != UINT32_MAX && owner != b && owner >= g->color_first_block[k])
                            fail_msg("block color %u: blocks %u and %u share vertex %u", k, owner, b, ids[a][s]);
                        block_owner[ids[a][s]] = b;
                    }
                }
                if (!range->serial) mark_range(range, arity, ids, lane_owner, r, "element color range");
            }
        }
    }
    uint32_t count = 0;
    for (uint32_t e = 0; e < element_count; e++) count += seen[e];
    assert_int_equal(count, g->count);
    free(seen);
    free(lane_owner);
    free(block_owner);
}

/* The triangle edges that own a bond. */
static uint32_t owned_edges(const sb_fast_model* fast) {
    uint32_t owned = 0;
    for (uint32_t r = 0; r < fast->triangles.range_count; r++)
        for (uint32_t s = fast->triangles.ranges[r].begin; s < fast->triangles.ranges[r].end; s++)
            for (int c = 0; c < 3; c++) owned += fast->tri_owned[s] >> c & 1u;
    return owned;
}

static void test_coloring(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_icosphere(4, 1.0, &mesh, &err), SB_OK); /* 5120 triangles: 20 blocks */
    assert_int_equal(sb_mesh_reorder(&mesh, NULL, &err), SB_OK);
    sb_model* model = make_model(&mesh, BONDS_MIXED); /* bonds (i, i + 2) in the bond group */
    sb_fast_model* fast = sb_fast_model_create(model, &err);
    assert_non_null(fast);
    assert_true(fast->bonds.count > 0);
    check_group(&fast->bonds, sb_model_bond_count(model), mesh.vertex_count, 2,
                (uint32_t* const[]){fast->bond_i, fast->bond_j});
    assert_int_equal(fast->triangles.count, sb_model_triangle_count(model));
    assert_int_equal(fast->hinges.count, sb_model_hinge_count(model));
    check_group(&fast->triangles, sb_model_triangle_count(model), mesh.vertex_count, 3, fast->tri_v);
    check_group(&fast->hinges, sb_model_hinge_count(model), mesh.vertex_count, 4, fast->hinge_v);
    /* the hinges fused into the triangles: their other vertices are colored
     * with the triangle's, and a triangle carrying more comes first in its color */
    assert_true(fast->fused_hinges);
    check_group(&fast->triangles, sb_model_triangle_count(model), mesh.vertex_count, 6,
                (uint32_t* const[]){fast->tri_v[0], fast->tri_v[1], fast->tri_v[2], fast->tri_hinge_other[0],
                                    fast->tri_hinge_other[1], fast->tri_hinge_other[2]});
    assert_int_equal(carried_hinges(fast), sb_model_hinge_count(model));
    print_message("blocks (block colors): %u (%u) bond, %u (%u) triangle, %u (%u) hinge\n", fast->bonds.block_count,
                  fast->bonds.block_colors, fast->triangles.block_count, fast->triangles.block_colors,
                  fast->hinges.block_count, fast->hinges.block_colors);
    assert_true(fast->triangles.block_count >= 16);
    assert_true(fast->triangles.block_colors <= 8); /* compact blocks of a surface have few neighbours */
    /* per-slot constants and rest lengths of their own for the fused bonds */
    assert_true(fast->fused_damping && fast->tri_edge_bond_k[0].values && fast->tri_edge_r0[0]);
    assert_int_equal(owned_edges(fast) + fast->bonds.count, sb_model_bond_count(model));
    sb_fast_model_destroy(fast);
    sb_model_destroy(model);
    /* uniform bonds, damped or not: every bond is owned by exactly one
     * triangle edge, its constants one value, its rest length the edge's */
    for (int kind = BONDS_UNDAMPED; kind <= BONDS_DAMPED; kind++) {
        model = make_model(&mesh, (bonds)kind);
        fast = sb_fast_model_create(model, &err);
        assert_non_null(fast);
        assert_true(fast->fused_bonds);
        assert_int_equal(fast->fused_damping, kind == BONDS_DAMPED);
        assert_int_equal(fast->bonds.count, 0);
        assert_int_equal(owned_edges(fast), sb_model_bond_count(model));
        for (int c = 0; c < 3; c++) assert_true(!fast->tri_edge_r0[c] && !fast->tri_edge_bond_k[c].values);
        sb_fast_model_destroy(fast);
        sb_model_destroy(model);
    }
    sb_mesh_free(&mesh);
}

/* A sheet large enough for blocks above 2 048 elements, the cap before the
 * blocks were sized by the cache (kernels/forces/fast_model.c): a 300 × 300
 * jittered sheet, every term (damped springs fused, hinges carried), 178 802
 * triangles in 64 blocks of 2 800. The layout is valid (check_group), the
 * forces follow the reference's, and 100 Verlet steps give the same state
 * on 1, 2 and 3 threads. */
static void test_large_blocks(void** state) {
    (void)state;
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = 300;
    sheet.jitter = 0.15;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    sb_model* model = make_model(&mesh, BONDS_DAMPED);
    sb_fast_model* fast = sb_fast_model_create(model, &err);
    assert_non_null(fast);
    assert_true(fast->fused_hinges);
    check_group(&fast->triangles, sb_model_triangle_count(model), mesh.vertex_count, 6,
                (uint32_t* const[]){fast->tri_v[0], fast->tri_v[1], fast->tri_v[2], fast->tri_hinge_other[0],
                                    fast->tri_hinge_other[1], fast->tri_hinge_other[2]});
    uint32_t largest = 0;
    for (uint32_t b = 0; b < fast->triangles.block_count; b++) {
        const sb_block* block = &fast->triangles.blocks[b];
        uint32_t elements = 0;
        for (uint32_t r = block->first_range; r < block->first_range + block->range_count; r++)
            elements += fast->triangles.ranges[r].end - fast->triangles.ranges[r].begin;
        largest = elements > largest ? elements : largest;
    }
    print_message("%u triangles: %u blocks (%u block colors), the largest of %u\n", fast->triangles.count,
                  fast->triangles.block_count, fast->triangles.block_colors, largest);
    assert_true(largest > 2048);
    sb_fast_model_destroy(fast);
    uint32_t n = mesh.vertex_count;
    double *x = malloc(3 * n * sizeof *x), *v = malloc(3 * n * sizeof *v);
    tu_rng rng = {3}; /* moved by a tenth of the 3.3 mm spacing at most */
    for (uint32_t i = 0; i < 3 * n; i++) {
        x[i] = (sb_real)(mesh.positions[i] + tu_uniform(&rng, -3e-4, 3e-4));
        v[i] = (sb_real)tu_uniform(&rng, -0.05, 0.05);
    }
    assert_fast_matches_reference(model, x, v, "300 x 300 sheet");
    uint64_t hashes[3];
    for (int threads = 1; threads <= 3; threads++) {
        sb_solver* solver = make_fast_solver(model, threads);
        assert_int_equal(sb_solver_set_state(solver, x, v), SB_OK);
        for (int s = 0; s < 100; s++) assert_int_equal(sb_solver_advance(solver, 2e-5), SB_OK);
        hashes[threads - 1] = tu_state_hash(solver);
        sb_solver_destroy(solver);
    }
    print_message("hash %016llx (1 thread) %016llx (2) %016llx (3)\n", (unsigned long long)hashes[0],
                  (unsigned long long)hashes[1], (unsigned long long)hashes[2]);
    assert_true(hashes[0] == hashes[1] && hashes[1] == hashes[2]);
    free(x);
    free(v);
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* Steps for a run of `explicit_steps` of an explicit integrator: a tenth
 * of them for the iterative ones (implicit Euler's Newton-CG, pbd's and
 * xpbd's projections, vbd's sweeps), whose step makes tens of passes over
 * the elements on the team (and costs 30 to 700 times an explicit step):
 * still more parallel passes than the explicit run makes. */
static int steps_for(sb_integrator integrator, int explicit_steps) {
    bool iterative = integrator == SB_INTEGRATOR_IMPLICIT_EULER || integrator == SB_INTEGRATOR_PBD ||
                     integrator == SB_INTEGRATOR_XPBD || integrator == SB_INTEGRATOR_VBD;
    return iterative ? explicit_steps / 10 : explicit_steps;
}

static uint64_t run_steps(const sb_model* model, int threads, sb_integrator integrator) {
    sb_solver_def def = sb_default_solver_def();
    def.kernels = SB_KERNELS_FAST;
    def.runtime.threads = threads;
    def.integrator = integrator;
    sb_error err;
    sb_solver* solver = sb_solver_create(model, &def, &err);
    assert_non_null(solver);
    for (int s = 0; s < steps_for(integrator, 1000); s++) assert_int_equal(sb_solver_advance(solver, 2e-4), SB_OK);
    uint64_t h = tu_state_hash(solver);
    sb_solver_destroy(solver);
    return h;
}

/* The state after 1000 steps is bitwise the same for 1, 2 (twice) and 3 threads. */
static void assert_same_for_threads(const sb_model* model, sb_integrator integrator) {
    uint64_t one = run_steps(model, 1, integrator);
    uint64_t two = run_steps(model, 2, integrator);
    uint64_t again = run_steps(model, 2, integrator);
    uint64_t three = run_steps(model, 3, integrator);
    print_message("%s: hash %016llx (1 thread) %016llx (2) %016llx (2 again) %016llx (3)\n",
                  sb_integrator_name(integrator), (unsigned long long)one, (unsigned long long)two,
                  (unsigned long long)again, (unsigned long long)three);
    assert_true(one == two);
    assert_true(two == again);
    assert_true(one == three);
}

/* The mesh with this material, its vertex 0 fixed (and its last when both_ends). */
static sb_model* pinned_model(const sb_mesh* mesh, const sb_material_def* material, bool both_ends) {
    sb_builder* builder = sb_builder_create();
    sb_error err;
    assert_int_equal(sb_builder_add_mesh(builder, mesh, material, &err), SB_OK);
    sb_builder_vertex(builder, 0)->fixed = true;
    if (both_ends) sb_builder_vertex(builder, mesh->vertex_count - 1)->fixed = true;
    sb_model* model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    assert_non_null(model);
    return model;
}

/* Every term on: stretch-bend, a damped spring and a hinge beside the
 * default bond and angle. */
static sb_material_def every_term_material(void) {
    sb_material_def material = sb_default_material_def();
    material.stretch_bend_k = 1.0;
    material.spring_k = 10.0;
    material.spring_damping = 0.02;
    material.bend_k = 0.001;
    return material;
}

static void test_determinism(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    make_mesh(SHAPE_JITTERED, &mesh);
    sb_material_def material = every_term_material();
    sb_model* model = pinned_model(&mesh, &material, true);
    for (int integrator = 0; integrator < SB_INTEGRATOR_COUNT; integrator++)
        assert_same_for_threads(model, (sb_integrator)integrator);
    sb_model_destroy(model);
    model = make_model(&mesh, BONDS_MIXED); /* per-slot fused constants, and the bond kernel */
    assert_same_for_threads(model, SB_INTEGRATOR_VERLET);
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

static void test_collapse_reported(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    make_mesh(SHAPE_SHEET, &mesh);
    sb_model* model = make_model(&mesh, BONDS_DAMPED);
    sb_solver* solver = make_fast_solver(model, 2);
    double* x = malloc(3 * mesh.vertex_count * sizeof *x);
    memcpy(x, mesh.positions, 3 * mesh.vertex_count * sizeof *x);
    memcpy(x + 3 * 30, x + 3 * 31, 3 * sizeof *x); /* vertex 30 onto its neighbour 31 */
    assert_int_equal(sb_solver_set_state(solver, x, NULL), SB_ERR_DEGENERATE);
    TU_ASSERT_CONTAINS(sb_solver_error(solver), "collapsed");
    free(x);
    sb_solver_destroy(solver);
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* A constant push on vertex 5, through the external force callback. */
static void push(void* user, uint32_t vertex, double time, const double position[3], const double velocity[3],
                 double force[3]) {
    (void)user, (void)time, (void)position, (void)velocity;
    if (vertex == 5) force[2] += 0.02;
}

/* pushed: drag and the push callback; without, nothing reads the Verlet
 * step's half-step velocities before its kick (kernels/state/solver_fast.c). */
static sb_energies run_trajectory(const sb_model* model, sb_kernels kernels, sb_integrator integrator, bool pushed,
                                  double* out) {
    sb_solver_def def = sb_default_solver_def();
    def.kernels = kernels;
    def.integrator = integrator;
    def.runtime.threads = 2;
    def.drag = pushed ? 0.3 : 0.0;
    def.external_force = pushed ? push : NULL;
    sb_error err;
    sb_solver* solver = sb_solver_create(model, &def, &err);
    assert_non_null(solver);
    for (int s = 0; s < steps_for(integrator, 300); s++) assert_int_equal(sb_solver_advance(solver, 2e-4), SB_OK);
    sb_solver_get_positions(solver, out);
    sb_energies energies = sb_solver_energies(solver);
    sb_solver_destroy(solver);
    return energies;
}

/* The fused fast step (drift, forces, external forces, kick) follows the
 * reference integrators: same trajectory, within what float rounding of
 * the state accumulates over 300 steps (30 of an iterative integrator;
 * double: 1e-9), and never tighter than ε times the largest coordinate
 * (one to two units in its last place): both runs keep their positions in
 * sb_real, so they may differ by a rounding of each (pbd's 30 steps move
 * the sheet 0.18 mm, 1e-4 of which is 1.8e-8 m, under the 6e-8 m of a
 * float's last place at 1 m). */
static void test_fast_step_follows_reference(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    make_mesh(SHAPE_JITTERED, &mesh);
    uint32_t n = mesh.vertex_count;
    for (int damped = 0; damped < 2; damped++) {
        sb_material_def material = sb_default_material_def();
        material.stretch_bend_k = 1.0;
        material.spring_k = damped ? 10.0 : 0.0;
        material.spring_damping = damped ? 0.02 : 0.0;
        material.bend_k = damped ? 0.001 : 0.0;
        sb_model* model = pinned_model(&mesh, &material, false);
        double *reference = malloc(3 * n * sizeof *reference), *fast = malloc(3 * n * sizeof *fast);
        for (int integrator = 0; integrator < SB_INTEGRATOR_COUNT; integrator++) {
            run_trajectory(model, SB_KERNELS_REFERENCE, (sb_integrator)integrator, true, reference);
            run_trajectory(model, SB_KERNELS_FAST, (sb_integrator)integrator, true, fast);
            double moved = 0.0, worst = 0.0, extent = 0.0;
            for (uint32_t k = 0; k < 3 * n; k++) {
                moved = fmax(moved, fabs(reference[k] - mesh.positions[k]));
                worst = fmax(worst, fabs(fast[k] - reference[k]));
                extent = fmax(extent, fabs(reference[k]));
            }
            print_message("%s%s: fast vs reference after %d steps: %.3g m (largest displacement %.3g m)\n",
                          sb_integrator_name((sb_integrator)integrator), damped ? ", damped" : "",
                          steps_for((sb_integrator)integrator, 300), worst, moved);
            assert_true(moved > 1e-4); /* the sheet did move */
            TU_ASSERT_LE(worst, fmax((sizeof(sb_real) == sizeof(float) ? 1e-4 : 1e-9) * moved, TU_REAL_EPS * extent));
            for (int c = 0; c < 3; c++) assert_true(fast[c] == mesh.positions[c]); /* the pin held */
        }
        free(reference);
        free(fast);
        sb_model_destroy(model);
    }
    sb_mesh_free(&mesh);
}

/* The Verlet step's energies where the fast step sums them in other passes
 * (kernels/state/solver_fast.c): the gravitational one and the position check
 * in the drift pass, the kinetic one in the kick from half-step velocities
 * that, without damping, drag or a callback, it recomputes from the
 * displacements. Both follow the reference's within 1e-5 (double 1e-9)
 * after 300 steps, undamped and damped and pushed (velocities stored):
 * float rounding of the trajectory is under 1e-6, one step's fall (a sum
 * at the wrong step's positions) about 7e-3. */
static void test_fast_step_energies_follow_reference(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    make_mesh(SHAPE_JITTERED, &mesh);
    const double tolerance = sizeof(sb_real) == sizeof(float) ? 1e-5 : 1e-9;
    for (int damped = 0; damped < 2; damped++) {
        sb_material_def material = sb_default_material_def();
        material.spring_k = damped ? 10.0 : 0.0;
        material.spring_damping = damped ? 0.02 : 0.0;
        sb_model* model = pinned_model(&mesh, &material, false);
        double* x = malloc(3 * mesh.vertex_count * sizeof *x);
        sb_energies reference = run_trajectory(model, SB_KERNELS_REFERENCE, SB_INTEGRATOR_VERLET, damped, x);
        sb_energies fast = run_trajectory(model, SB_KERNELS_FAST, SB_INTEGRATOR_VERLET, damped, x);
        print_message("%s: kinetic %.9g / %.9g J, gravity %.9g / %.9g J (reference / fast)\n",
                      damped ? "damped, pushed" : "undamped", reference.kinetic, fast.kinetic, reference.gravity,
                      fast.gravity);
        assert_true(reference.kinetic > 0.0 && reference.gravity < 0.0); /* it fell */
        TU_ASSERT_LE(fabs(fast.kinetic - reference.kinetic), tolerance * reference.kinetic);
        TU_ASSERT_LE(fabs(fast.gravity - reference.gravity), tolerance * fabs(reference.gravity));
        free(x);
        sb_model_destroy(model);
    }
    sb_mesh_free(&mesh);
}

/* How a fused Verlet run is set up for the energy and check tests. */
typedef enum { RUN_STORMER, RUN_PUSHED, RUN_VELOCITY_VERLET, RUN_SELF_CONTACT, RUN_CONTACT, RUN_KINDS } run_kind;
static const char* const run_names[RUN_KINDS] = {"verlet", "verlet, damped and pushed", "velocity_verlet",
                                                 "verlet, self-contact", "verlet, on a plane"};

static sb_solver* make_run(const sb_model* model, run_kind kind, int threads, sb_collider** plane) {
    sb_solver_def def = sb_default_solver_def();
    def.kernels = SB_KERNELS_FAST;
    def.integrator = kind == RUN_VELOCITY_VERLET ? SB_INTEGRATOR_VELOCITY_VERLET : SB_INTEGRATOR_VERLET;
    def.runtime.threads = threads;
    def.drag = kind == RUN_PUSHED ? 0.3 : 0.0;
    def.external_force = kind == RUN_PUSHED ? push : NULL;
    def.self_collision = kind == RUN_SELF_CONTACT; /* vertices move after the drift: the sums in the kick */
    def.contact_thickness = kind == RUN_SELF_CONTACT ? 1e-3 : 0.0;
    if (kind == RUN_CONTACT) { /* the plane moves vertices after their drift: the check after the contact */
        sb_collider_def c = sb_default_collider_def();
        c.shape = SB_COLLIDER_PLANE;
        c.name = "floor";
        c.normal[2] = 1.0;
        c.point[2] = -0.005; /* reached after about 32 ms */
        sb_error err;
        *plane = sb_collider_create(&c, &err);
        if (!*plane) fail_msg("%s", err.message);
        def.colliders = plane;
        def.collider_count = 1;
    }
    sb_error err;
    sb_solver* solver = sb_solver_create(model, &def, &err);
    if (!solver) fail_msg("%s", err.message);
    return solver;
}

/* The energies at steps 7, 100 and 300 of a run, read after every step
 * (the fused step then sums its kinetic and gravitational energies in its
 * drift and kick, as it always did) or only at those steps (the steps
 * leave them to sb_solver_settle, which sums them from the packed state);
 * the state's hash at the end. */
typedef struct read_run {
    sb_energies at[3];
    uint64_t hash;
    uint64_t contacts, self_contacts;
} read_run;

static read_run run_reading(const sb_model* model, run_kind kind, int threads, bool every_step) {
    sb_collider* plane = NULL;
    sb_solver* solver = make_run(model, kind, threads, &plane);
    read_run r = {0};
    const int marks[3] = {7, 100, 300};
    for (int step = 1, k = 0; step <= 300; step++) {
        assert_int_equal(sb_solver_advance(solver, 2e-4), SB_OK);
        sb_step_stats stats = sb_solver_last_step(solver);
        r.contacts += stats.contacts;
        r.self_contacts += stats.self_contacts;
        bool mark = step == marks[k];
        if (every_step || mark) {
            sb_energies e = sb_solver_energies(solver);
            if (mark) r.at[k++] = e;
        }
    }
    r.hash = tu_state_hash(solver);
    sb_solver_destroy(solver);
    sb_collider_destroy(plane);
    return r;
}

static bool same_energies(const sb_energies* a, const sb_energies* b) {
    bool same = a->kinetic == b->kinetic && a->gravity == b->gravity;
    for (int t = 0; t < SB_TERM_COUNT; t++) same &= a->term[t] == b->term[t];
    return same;
}

/* The fused step sums its kinetic and gravitational energies only where
 * they are read (kernels/state/solver_fast.c, sb_step_sums); read after a step
 * that left them, sb_solver_settle sums them from the packed state with
 * the kick's arithmetic. Either way the energies are bitwise the same, for
 * 1, 2 and 3 threads, and reading them changes nothing of the trajectory:
 * in the Störmer form whose kick recomputes the half-step velocities, with
 * them stored (damped and pushed), in the velocity form, with self-contact
 * (the sums in the kick) and with a plane (the check after the contact). */
static void test_energies_the_same_when_read_lazily(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    make_mesh(SHAPE_JITTERED, &mesh);
    sb_material_def material = every_term_material();
    sb_model* model = pinned_model(&mesh, &material, false);
    for (int kind = 0; kind < RUN_KINDS; kind++) {
        read_run summed = run_reading(model, (run_kind)kind, 1, true);
        print_message("%s: kinetic %.9g J, gravity %.9g J at step 300 (%llu contacts, %llu self-contacts)\n",
                      run_names[kind], summed.at[2].kinetic, summed.at[2].gravity, (unsigned long long)summed.contacts,
                      (unsigned long long)summed.self_contacts);
        assert_true(summed.at[2].kinetic > 0.0 && summed.at[2].gravity < 0.0); /* it fell */
        if (kind == RUN_CONTACT) assert_true(summed.contacts > 0);
        for (int threads = 1; threads <= 3; threads++)
            for (int every = 0; every < 2; every++) {
                read_run r = run_reading(model, (run_kind)kind, threads, every);
                for (int k = 0; k < 3; k++)
                    if (!same_energies(&r.at[k], &summed.at[k]))
                        fail_msg("%s, %d threads, read %s: the energies at mark %d differ (kinetic %.17g / %.17g, "
                                 "gravity %.17g / %.17g)",
                                 run_names[kind], threads, every ? "every step" : "at the marks", k, r.at[k].kinetic,
                                 summed.at[k].kinetic, r.at[k].gravity, summed.at[k].gravity);
                assert_true(r.hash == summed.hash);
            }
    }
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* test_state_checked_on_every_step's vertex, and the step its trouble
 * starts on. */
#define LONER 700
#define TROUBLE_STEP 20

/* A NaN force on the loner from the trouble step on (the callback's clock
 * is the step's end time). */
static void poison(void* user, uint32_t vertex, double time, const double position[3], const double velocity[3],
                   double force[3]) {
    (void)position, (void)velocity;
    double dt = *(const double*)user;
    if (vertex == LONER && time > (TROUBLE_STEP - 0.5) * dt) force[0] = NAN;
}

/* The fused step checks the state on every step, whether or not anything
 * reads its energies: the check that runs in the drift's loop when nothing
 * does, and the kick's. 1 000 vertices on a 40 x 25 grid of 1 cm (the
 * runaway box 10^6 of its diagonal, 4.6e5 m from its centre), bonds along
 * the rows, and the loner, vertex 700 (in the third of four chunks: the
 * third worker's with 3 threads), bonded to nothing and sent along x fast
 * enough to leave the box half way through step 20: it is reported on that
 * step, not later (2.6 % of the box past its edge; at step 19 2.6 % inside,
 * the box measured from the centre or from the origin alike). With a NaN
 * force on it from step 20 on, the step's velocity is not finite and is
 * reported on step 20 too. Both Verlet forms, 1, 2 and 3 threads, the
 * energies read after every step (the sums and the check in the drift's
 * second, in-cache loop) or never (the check alone in its loop). */
static void test_state_checked_on_every_step(void** state) {
    (void)state;
    sb_builder* b = sb_builder_create();
    const int nx = 40, ny = 25;
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) tu_vertex(b, 0.01 * i, 0.01 * j, 0.0, 1e-3, false);
    for (int j = 0; j < ny; j++)
        for (int i = 0; i + 1 < nx; i++) {
            uint32_t a = (uint32_t)(j * nx + i);
            if (a != LONER && a + 1 != LONER) tu_bond(b, a, a + 1, 0.01, 10.0, 0.0, 0.0);
        }
    sb_model* model = tu_compile(b);
    sb_builder_destroy(b);
    const double dt = 1e-4, diagonal = 0.01 * hypot(nx - 1, ny - 1), box = 1e6 * diagonal;
    double* v = calloc(3 * (size_t)nx * ny, sizeof *v);
    for (int integrator = 0; integrator < 2; integrator++)
        for (int threads = 1; threads <= 3; threads++)
            for (int every = 0; every < 2; every++)
                for (int poisoned = 0; poisoned < 2; poisoned++) {
                    sb_solver_def def = sb_default_solver_def();
                    def.kernels = SB_KERNELS_FAST;
                    def.integrator = integrator ? SB_INTEGRATOR_VELOCITY_VERLET : SB_INTEGRATOR_VERLET;
                    def.runtime.threads = threads;
                    def.gravity[2] = 0.0;
                    def.external_force = poisoned ? poison : NULL;
                    def.external_user = (void*)&dt;
                    sb_error err;
                    sb_solver* solver = sb_solver_create(model, &def, &err);
                    if (!solver) fail_msg("%s", err.message);
                    v[3 * LONER] = poisoned ? 0.0 : box / ((TROUBLE_STEP - 0.5) * dt);
                    assert_int_equal(sb_solver_set_state(solver, NULL, v), SB_OK);
                    sb_status status = SB_OK;
                    int step = 0;
                    while (status == SB_OK && step < 2 * TROUBLE_STEP) {
                        status = sb_solver_advance(solver, dt);
                        step++;
                        if (every && status == SB_OK) sb_solver_energies(solver);
                    }
                    const char* message = sb_solver_error(solver);
                    if (status != SB_ERR_UNSTABLE || step != TROUBLE_STEP || !strstr(message, "vertex 700") ||
                        !strstr(message, poisoned ? "not finite" : "ran away"))
                        fail_msg("%s, %d threads, energies read %s, %s: %s on step %d (%s), expected on step %d",
                                 sb_integrator_name(def.integrator), threads, every ? "every step" : "never",
                                 poisoned ? "a NaN force" : "a runaway", sb_status_name(status), step, message,
                                 TROUBLE_STEP);
                    sb_solver_destroy(solver);
                }
    free(v);
    sb_model_destroy(model);
}

/* ---- co-rotated tetrahedra --------------------------------------------------
 * A clamped 10 × 5 × 5 block of 1 cm cubes, 1 500 tetrahedra (six blocks
 * of the blocked coloring), E = 3.5 kPa, ν = 0.45. */

static sb_model* tet_model(bool clamped) { return tu_tet_block(10, 5, 5, 0.01, 3500.0, 0.45, 0.15, 7, clamped); }

/* The same block of quadratic tetrahedra (a vertex at each edge's middle). */
static sb_model* quadratic_tet_model(bool clamped) {
    return tu_quadratic_tet_block(10, 5, 5, 0.01, 3500.0, 0.45, 0.15, 7, clamped);
}

/* The fast pass's forces and energy against the reference's at rest
 * (nothing), strained, and strained and turned by 1 rad (the element's
 * rotation at work): within FAST_TOLERANCE, the positions being rounded
 * to sb_real before the double element and the forces after it. Free
 * (a solver's forces on fixed vertices are not the reference's). */
static void check_tets_match_reference(sb_model* (*make)(bool)) {
    sb_model* model = make(false);
    uint32_t n = sb_model_vertex_count(model);
    double* rest = tu_rest_positions(model);
    double* x = malloc(3 * n * sizeof *x);
    tu_rng rng = {11};
    for (int turned = 0; turned < 2; turned++) {
        double c = cos(turned ? 1.0 : 0.0), sn = sin(turned ? 1.0 : 0.0);
        for (uint32_t i = 0; i < n; i++) {
            double p[3];
            for (int a = 0; a < 3; a++) p[a] = rest[3 * i + a] + 0.002 * tu_uniform(&rng, -1, 1);
            x[3 * i] = c * p[0] - sn * p[1];
            x[3 * i + 1] = sn * p[0] + c * p[1];
            x[3 * i + 2] = p[2];
        }
        assert_fast_matches_reference(model, x, NULL,
                                      turned ? "tetrahedra, strained and turned" : "tetrahedra, strained");
    }
    sb_solver* solver = make_fast_solver(model, 2);
    /* At rest, gravity off: the strain is sb_real's rounding of the rest
     * positions, ε (x / h) at most, bounded by 100 ε: the energy by
     * E V (100 ε)², V = 2.5e-4 m³, each force by E h² 100 ε. */
    const double E = 3500.0, h = 0.01, strain = 100 * TU_REAL_EPS;
    sb_energies e = sb_solver_energies(solver);
    print_message("tetrahedra at rest: energy %.3g J\n", e.term[SB_TERM_COROTATED]);
    TU_ASSERT_LE(fabs(e.term[SB_TERM_COROTATED]), E * 2.5e-4 * strain * strain);
    double* f = malloc(3 * n * sizeof *f);
    sb_solver_get_forces(solver, f);
    TU_ASSERT_LE(tu_max_abs(f, 3 * n), E * h * h * strain);
    sb_solver_destroy(solver);
    free(f);
    free(x);
    free(rest);
    sb_model_destroy(model);
}

static void test_tets_match_reference(void** state) {
    (void)state;
    check_tets_match_reference(tet_model);
}

static void test_quadratic_tets_match_reference(void** state) {
    (void)state;
    check_tets_match_reference(quadratic_tet_model);
}

/* The blocked coloring of the tetrahedra: no two of a color share a vertex
 * (all ten of a quadratic one's), and several blocks, so that the thread
 * test below splits them. */
static void check_tets_colored(sb_model* (*make)(bool)) {
    sb_model* model = make(true);
    sb_error err;
    sb_fast_model* fast = sb_fast_model_create(model, &err);
    assert_non_null(fast);
    check_group(&fast->tets, 1500, sb_model_vertex_count(model), SB_TET_NODES, fast->tet_v);
    assert_true(fast->tets.block_count > 2);
    assert_true(fast->has_tets);
    sb_fast_model_destroy(fast);
    sb_model_destroy(model);
}

static void test_tets_colored(void** state) {
    (void)state;
    check_tets_colored(tet_model);
}

static void test_quadratic_tets_colored(void** state) {
    (void)state;
    check_tets_colored(quadratic_tet_model);
}

/* The fused Verlet step, position Verlet and symplectic Euler on the fast
 * kernels (explicit Euler takes the same force passes, but grows the
 * block's fastest modes at this step): bitwise the
 * same on 1, 2 and 3 threads, and following the reference kernels'
 * trajectory (300 steps of 0.2 ms under gravity) within float rounding. */
static void check_tets_step(sb_model* (*make)(bool)) {
    sb_model* model = make(true);
    uint32_t n = sb_model_vertex_count(model);
    static const sb_integrator explicit_ones[] = {SB_INTEGRATOR_VERLET, SB_INTEGRATOR_VELOCITY_VERLET,
                                                  SB_INTEGRATOR_SYMPLECTIC_EULER, SB_INTEGRATOR_POSITION_VERLET};
    double *reference = malloc(3 * n * sizeof *reference), *fast = malloc(3 * n * sizeof *fast);
    double* rest = tu_rest_positions(model);
    for (size_t k = 0; k < sizeof explicit_ones / sizeof *explicit_ones; k++) {
        sb_integrator it = explicit_ones[k];
        assert_same_for_threads(model, it);
        run_trajectory(model, SB_KERNELS_REFERENCE, it, false, reference);
        run_trajectory(model, SB_KERNELS_FAST, it, false, fast);
        double moved = 0.0, worst = 0.0;
        for (uint32_t q = 0; q < 3 * n; q++) {
            moved = fmax(moved, fabs(reference[q] - rest[q]));
            worst = fmax(worst, fabs(fast[q] - reference[q]));
        }
        print_message("tetrahedra, %s: fast vs reference after 300 steps: %.3g m (largest displacement %.3g m)\n",
                      sb_integrator_name(it), worst, moved);
        assert_true(moved > 1e-5);
        TU_ASSERT_LE(worst, fmax((sizeof(sb_real) == sizeof(float) ? 1e-4 : 1e-9) * moved, TU_REAL_EPS * 0.1));
    }
    free(rest);
    free(reference);
    free(fast);
    sb_model_destroy(model);
}

static void test_tets_step(void** state) {
    (void)state;
    check_tets_step(tet_model);
}

static void test_quadratic_tets_step(void** state) {
    (void)state;
    check_tets_step(quadratic_tet_model);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_regular_sheet),
        cmocka_unit_test(test_jittered_sheet),
        cmocka_unit_test(test_sliver_triangles),
        cmocka_unit_test(test_nearly_straight_angles),
        cmocka_unit_test(test_icosphere),
        cmocka_unit_test(test_hinges_near_flat),
        cmocka_unit_test(test_hinges_through_themselves),
        cmocka_unit_test(test_hinges_nearly_closed),
        cmocka_unit_test(test_triangles_carrying_three_hinges),
        cmocka_unit_test(test_fused_hinges_on_meshes),
        cmocka_unit_test(test_coloring),
        cmocka_unit_test(test_large_blocks),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_collapse_reported),
        cmocka_unit_test(test_fast_step_follows_reference),
        cmocka_unit_test(test_fast_step_energies_follow_reference),
        cmocka_unit_test(test_energies_the_same_when_read_lazily),
        cmocka_unit_test(test_state_checked_on_every_step),
        cmocka_unit_test(test_tets_match_reference),
        cmocka_unit_test(test_quadratic_tets_match_reference),
        cmocka_unit_test(test_tets_colored),
        cmocka_unit_test(test_tets_step),
        cmocka_unit_test(test_quadratic_tets_colored),
        cmocka_unit_test(test_quadratic_tets_step),
    };
    return TU_RUN_TESTS(tests);
}
