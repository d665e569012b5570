/* sb_solver_advance and sb_solver_publish never allocate: this program
 * replaces malloc and its kin (glibc's allocator stays underneath, through
 * its __libc_* entry points) and counts the calls made while a step or a
 * publication runs, on every thread, for every integrator, both kernel
 * choices, adaptive stepping, an external force and handles (a hard one
 * released and grabbed again between steps, a soft one on a path). Not run under the
 * sanitizers, which bring their own malloc. */
#include "test_util.h"

#include <stdatomic.h>

extern void* __libc_malloc(size_t size);
extern void* __libc_calloc(size_t count, size_t size);
extern void* __libc_realloc(void* p, size_t size);
extern void* __libc_memalign(size_t alignment, size_t size);
extern void __libc_free(void* p);

static atomic_int counting;
static atomic_long allocations;

static void count(void) {
    if (atomic_load_explicit(&counting, memory_order_relaxed)) atomic_fetch_add(&allocations, 1);
}

void* malloc(size_t size) {
    count();
    return __libc_malloc(size);
}
void* calloc(size_t count_, size_t size) {
    count();
    return __libc_calloc(count_, size);
}
void* realloc(void* p, size_t size) {
    count();
    return __libc_realloc(p, size);
}
void* aligned_alloc(size_t alignment, size_t size) {
    count();
    return __libc_memalign(alignment, size);
}
int posix_memalign(void** out, size_t alignment, size_t size) {
    count();
    *out = __libc_memalign(alignment, size);
    return *out ? 0 : 12; /* ENOMEM */
}
void free(void* p) { __libc_free(p); }

static void push(void* user, uint32_t vertex, double time, const double x[3], const double v[3], double f[3]) {
    (void)user, (void)time, (void)x, (void)v;
    if (vertex == 5) f[2] += 0.01;
}

/* break_strain 0: no bond can break. */
static sb_model* make_model(sb_mesh* mesh, double break_strain) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = 40;
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, mesh, &err), SB_OK);
    /* a metre up, so that gravity's energy sets the scale of adaptive stepping's test */
    for (uint32_t i = 0; i < mesh->vertex_count; i++) mesh->positions[3 * i + 2] += 1.0;
    sb_material_def material = sb_default_material_def();
    material.bond_k = 50.0;
    material.angle_k = 0.3;
    material.stretch_bend_k = 2.0;
    material.spring_k = 10.0;
    material.spring_damping = 0.01;
    material.bend_k = 0.01;
    material.break_strain = break_strain;
    sb_builder* builder = sb_builder_create();
    assert_int_equal(sb_builder_add_mesh(builder, mesh, &material, &err), SB_OK);
    sb_builder_vertex(builder, 0)->fixed = true;
    sb_model* model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    assert_non_null(model);
    return model;
}

/* Allocations made by 5 advances with a publication and 5 advances that
 * publish, of one configuration; with contact, the sheet lies within the
 * contact thickness of a floor and self-contact is on. */
static long allocations_in_steps(const sb_model* model, sb_integrator integrator, sb_kernels kernels, bool adaptive,
                                 bool contact, uint32_t* broken) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.kernels = kernels;
    def.adaptive = adaptive;
    def.external_force = push;
    def.runtime.threads = 2;
    def.implicit_cg_iterations = 20;
    def.implicit_solver = SB_LINEAR_CG; /* the factored path: test_factored_steps_do_not_allocate */
    sb_error err;
    sb_collider_def floor_def = sb_default_collider_def();
    floor_def.point[2] = 1.0 - 0.001; /* the sheet rests on it, the thickness away */
    sb_collider* floor = sb_collider_create(&floor_def, &err);
    assert_non_null(floor);
    const sb_keyframe path[2] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {1.0, {0, 0, 0.1}, {0, 0, 0}}};
    uint32_t held[2] = {10, 11}, pulled = 20;
    sb_handle_def hard = sb_default_handle_def(), soft = sb_default_handle_def();
    hard.vertices = held;
    hard.vertex_count = 2;
    soft.vertices = &pulled;
    soft.vertex_count = 1;
    soft.stiffness = 1.0;
    soft.damping = 0.01;
    soft.path = path;
    soft.path_count = 2;
    sb_handle* handles[2] = {sb_handle_create(&hard, &err), sb_handle_create(&soft, &err)};
    assert_non_null(handles[0]);
    assert_non_null(handles[1]);
    def.handles = handles;
    def.handle_count = 2;
    if (contact) {
        def.colliders = &floor;
        def.collider_count = 1;
        def.contact_thickness = 0.001;
        def.self_collision = true;
    }
    sb_solver* solver = tu_solver(model, &def);
    sb_state_buffer* buffer = sb_state_buffer_create(sb_solver_vertex_capacity(solver), 1, &err);
    assert_non_null(buffer);
    uint32_t contacts = 0;
    atomic_store(&allocations, 0);
    atomic_store(&counting, 1);
    for (int s = 0; s < 5; s++) {
        sb_status status = sb_solver_advance(solver, 1e-4);
        if (status != SB_OK) fail_msg("%s", sb_solver_error(solver));
        assert_int_equal(sb_solver_publish(solver, buffer), SB_OK);
        status = sb_solver_advance_published(solver, 1e-4, buffer);
        if (status != SB_OK) fail_msg("%s", sb_solver_error(solver));
        contacts += sb_solver_last_step(solver).contacts;
        if (s == 2) sb_handle_release(handles[0]);
        if (s == 3) assert_int_equal(sb_handle_grab(handles[0]), SB_OK);
    }
    atomic_store(&counting, 0);
    *broken = sb_solver_broken_count(solver);
    sb_state_buffer_destroy(buffer);
    sb_solver_destroy(solver);
    sb_collider_destroy(floor);
    sb_handle_destroy(handles[0]);
    sb_handle_destroy(handles[1]);
    if (contact && contacts == 0)
        fail_msg("%s: the contact configuration made no contact", sb_integrator_name(integrator));
    return atomic_load(&allocations);
}

static void test_steps_do_not_allocate(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_model* model = make_model(&mesh, 0.0);
    uint32_t broken;
    for (int i = 0; i < SB_INTEGRATOR_COUNT; i++)
        for (int k = 0; k < 2; k++)
            for (int adaptive = 0; adaptive < 2; adaptive++)
                for (int contact = 0; contact < 2; contact++) {
                    sb_kernels kernels = k ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
                    long n = allocations_in_steps(model, (sb_integrator)i, kernels, adaptive, contact, &broken);
                    if (n != 0)
                        fail_msg("%s, %s kernels%s%s: %ld allocations in 5 steps", sb_integrator_name((sb_integrator)i),
                                 k ? "fast" : "reference", adaptive ? ", adaptive" : "", contact ? ", contact" : "", n);
                }
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* Bonds breaking (kernels/interaction/breakage.c) inside the counted steps: a strain
 * limit of 1e-9 is passed at once by the bonds of the held vertices as the
 * sheet around them falls (a strain of about 1e-8 in 1 ms). */
static void test_breaking_steps_do_not_allocate(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_model* model = make_model(&mesh, 1e-9);
    for (int i = 0; i < SB_INTEGRATOR_COUNT; i++)
        for (int k = 0; k < 2; k++)
            for (int adaptive = 0; adaptive < 2; adaptive++) {
                uint32_t broken;
                sb_kernels kernels = k ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
                long n = allocations_in_steps(model, (sb_integrator)i, kernels, adaptive, false, &broken);
                if (n != 0 || broken == 0)
                    fail_msg("%s, %s kernels%s, breakable: %ld allocations in 5 steps, %u bonds broken",
                             sb_integrator_name((sb_integrator)i), k ? "fast" : "reference",
                             adaptive ? ", adaptive" : "", n, broken);
            }
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* implicit_euler with its systems factored (kernels/linear/sparse_cholesky.c,
 * whose numeric factorization and solves reuse what the analysis
 * allocated), on both kernels and 1 and 2 threads: steps of 10 ms, long
 * enough that Newton factors. */
static void test_factored_steps_do_not_allocate(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_model* model = make_model(&mesh, 0.0);
    for (int k = 0; k < 2; k++)
        for (int threads = 1; threads <= 2; threads++) {
            sb_solver_def def = sb_default_solver_def();
            def.integrator = SB_INTEGRATOR_IMPLICIT_EULER;
            def.kernels = k ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
            def.implicit_solver = SB_LINEAR_CHOLESKY;
            def.runtime.threads = threads;
            sb_solver* solver = tu_solver(model, &def);
            uint32_t factorizations = 0;
            atomic_store(&allocations, 0);
            atomic_store(&counting, 1);
            for (int s = 0; s < 3; s++) {
                sb_status status = sb_solver_advance(solver, 0.01);
                if (status != SB_OK) fail_msg("%s", sb_solver_error(solver));
                factorizations += sb_solver_last_step(solver).factorizations;
            }
            atomic_store(&counting, 0);
            long n = atomic_load(&allocations);
            if (n != 0 || factorizations == 0)
                fail_msg("implicit_euler factored, %s kernels, %d thread(s): %ld allocations in 3 steps, %u "
                         "factorizations",
                         k ? "fast" : "reference", threads, n, factorizations);
            sb_solver_destroy(solver);
        }
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* The counter works: a solver's creation allocates. */
static void test_the_counter_counts(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_model* model = make_model(&mesh, 0.0);
    sb_solver_def def = sb_default_solver_def();
    atomic_store(&allocations, 0);
    atomic_store(&counting, 1);
    sb_solver* solver = tu_solver(model, &def);
    atomic_store(&counting, 0);
    assert_true(atomic_load(&allocations) > 0);
    sb_solver_destroy(solver);
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_counter_counts),
        cmocka_unit_test(test_steps_do_not_allocate),
        cmocka_unit_test(test_breaking_steps_do_not_allocate),
        cmocka_unit_test(test_factored_steps_do_not_allocate),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
