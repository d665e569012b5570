/* A program outside the project that uses the installed library: builds a
 * two-vertex bond, stretches it and checks the reference energy. */
#include <math.h>
#include <stdio.h>
#include <softbond/softbond.h>

int main(void) {
    sb_builder* builder = sb_builder_create();
    sb_vertex_def v = sb_default_vertex_def();
    sb_builder_add_vertex(builder, &v);
    v.position[0] = 1.0;
    sb_builder_add_vertex(builder, &v);
    sb_bond_def bond = sb_default_bond_def();
    bond.i = 0;
    bond.j = 1;
    bond.k = 4.0;
    sb_builder_add_bond(builder, &bond);
    sb_error err;
    sb_model* model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    if (!model) {
        fprintf(stderr, "consumer: %s\n", err.message);
        return 1;
    }
    double positions[6] = {0, 0, 0, 1.5, 0, 0}, forces[6];
    sb_energies energies;
    sb_status status = sb_reference_forces(model, positions, NULL, forces, &energies, &err);
    sb_model_destroy(model);
    /* ½ k (r − r0)² = ½ · 4 · 0.25 = 0.5 */
    if (status != SB_OK || fabs(energies.term[SB_TERM_BOND] - 0.5) > 1e-12) {
        fprintf(stderr, "consumer: wrong energy %g\n", energies.term[SB_TERM_BOND]);
        return 1;
    }
    printf("consumer: ok\n");
    return 0;
}
