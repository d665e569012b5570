/* hello: a 10 x 10 sheet held at one corner falls for 0.1 s under gravity.
 * Build: cc hello.c $(pkg-config --cflags --libs softbond) -o hello */
#include <softbond/softbond.h>

#include <stdio.h>
#include <stdlib.h>

int main(void) {
    sb_error err;
    sb_mesh mesh = {0};
    sb_builder* builder = NULL;
    sb_model* model = NULL;
    sb_solver* solver = NULL;
    int code = EXIT_FAILURE;

    sb_sheet_def sheet = sb_default_sheet_def(); /* 10 x 10 vertices, 1 m x 1 m */
    if (sb_mesh_generate_sheet(&sheet, &mesh, &err) != SB_OK) goto fail;

    builder = sb_builder_create(); /* construction mode */
    if (!builder) goto out;
    sb_material_def material = sb_default_material_def(); /* bond, angle, mass */
    if (sb_builder_add_mesh(builder, &mesh, &material, &err) != SB_OK) goto fail;
    sb_builder_vertex(builder, 0)->fixed = true; /* hold the corner at the origin */
    model = sb_builder_compile(builder, &err);   /* validated, immutable */
    if (!model) goto fail;

    sb_solver_def def = sb_default_solver_def(); /* Verlet, gravity -z, fast kernels */
    def.runtime.threads = 1;
    solver = sb_solver_create(model, &def, &err);
    if (!solver) goto fail;
    for (int i = 0; i < 1000; i++) {
        if (sb_solver_advance(solver, 1e-4) != SB_OK) {
            fprintf(stderr, "hello: %s\n", sb_solver_error(solver));
            goto out;
        }
    }

    uint32_t n = sb_solver_vertex_count(solver);
    double* x = malloc(3 * (size_t)n * sizeof *x);
    if (!x) goto out;
    sb_solver_get_positions(solver, x);
    double far_z = x[3 * (n - 1) + 2]; /* the corner opposite the held one */
    free(x);
    sb_energies e = sb_solver_energies(solver);
    printf("hello: t = %.3f s, the free corner at z = %.4f m, total energy %.6f J\n", sb_solver_time(solver), far_z,
           sb_energies_total(&e));
    code = far_z < 0.0 ? EXIT_SUCCESS : EXIT_FAILURE; /* it fell */
    goto out;
fail:
    fprintf(stderr, "hello: %s\n", err.message);
out:
    sb_solver_destroy(solver);
    sb_model_destroy(model);
    sb_builder_destroy(builder);
    sb_mesh_free(&mesh);
    return code;
}
