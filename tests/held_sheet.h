/* The simulated tissue of the haptics tests: a square sheet held along its
 * four sides and a sphere for the tool, in zero gravity with a little drag,
 * stepped on one thread; shared by tests/test_haptics_tissue.c and
 * tests/test_haptics_surface.c. */
#ifndef SB_TEST_HELD_SHEET_H
#define SB_TEST_HELD_SHEET_H

#include "test_util.h"

typedef struct held_sheet {
    sb_mesh mesh;
    sb_model* model;
    sb_collider* tool;
    sb_solver* solver;
} held_sheet;

/* side × side vertices over width metres; the tool a sphere of `radius` at
 * `centre` with `footprint` (m; 0: none), on `path` (NULL: driven or still). */
static inline void held_sheet_open(held_sheet* s, uint32_t side, double width, const double centre[3], double radius,
                                   double footprint, const sb_keyframe* path, uint32_t path_count) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = side;
    sheet.width = sheet.height = width;
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &s->mesh, &err), SB_OK);
    sb_material_def material = sb_default_material_def();
    material.bond_k = 200;
    material.angle_k = 0.0005;
    material.density = 0.5;
    sb_builder* builder = sb_builder_create();
    assert_int_equal(sb_builder_add_mesh(builder, &s->mesh, &material, &err), SB_OK);
    for (uint32_t row = 0; row < side; row++)
        for (uint32_t col = 0; col < side; col++)
            sb_builder_vertex(builder, row * side + col)->fixed =
                row == 0 || col == 0 || row == side - 1 || col == side - 1;
    s->model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    assert_non_null(s->model);
    sb_collider_def c = sb_default_collider_def();
    c.shape = SB_COLLIDER_SPHERE;
    memcpy(c.center, centre, sizeof c.center);
    c.radius = radius;
    c.footprint = footprint;
    c.path = path;
    c.path_count = path_count;
    s->tool = sb_collider_create(&c, &err);
    assert_non_null(s->tool);
    sb_solver_def def = sb_default_solver_def();
    def.gravity[0] = def.gravity[1] = def.gravity[2] = 0;
    def.drag = 20;
    def.colliders = &s->tool;
    def.collider_count = 1;
    def.contact_thickness = 0.0005;
    def.runtime.threads = 1;
    s->solver = sb_solver_create(s->model, &def, &err);
    assert_non_null(s->solver);
}

static inline void held_sheet_close(held_sheet* s) {
    sb_solver_destroy(s->solver);
    sb_collider_destroy(s->tool);
    sb_model_destroy(s->model);
    sb_mesh_free(&s->mesh);
}

#endif
