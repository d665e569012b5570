/* A breakable sheet pulled apart by two hard handles on its first and last
 * rows, and the pieces of a torn surface, shared by tests/test_breakage.c,
 * tests/test_tearing.c and tests/test_cutting.c. */
#ifndef SB_TEST_PULLED_SHEET_H
#define SB_TEST_PULLED_SHEET_H

#include "test_util.h"
#include "softbond/handle.h"

/* side × side vertices over 0.1 m, bonds breaking beyond r0 (1 + break_strain). */
static inline sb_model* ps_sheet_model(uint32_t side, double jitter, double break_strain) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = side;
    sheet.width = sheet.height = 0.1;
    sheet.jitter = jitter;
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, &mesh, &err), SB_OK);
    sb_material_def material = sb_default_material_def();
    material.bond_k = 200.0;
    material.angle_k = 1e-3;
    material.stretch_bend_k = 1e-2;
    material.bend_k = 1e-4;
    material.mass = 0.01;
    material.break_strain = break_strain;
    sb_model* m = tu_mesh_model(&mesh, &material);
    sb_mesh_free(&mesh);
    return m;
}

/* The first row moves −y and the last +y, 0.05 m each in 0.5 s. */
static const sb_keyframe ps_down[2] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {0.5, {0, -0.05, 0}, {0, 0, 0}}};
static const sb_keyframe ps_up[2] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {0.5, {0, 0.05, 0}, {0, 0, 0}}};

/* A hard handle on row `row` (its side vertices written to `vertices`). */
static inline sb_handle* ps_row_handle(uint32_t side, uint32_t row, const sb_keyframe* path, uint32_t* vertices) {
    for (uint32_t i = 0; i < side; i++) vertices[i] = row * side + i;
    sb_handle_def def = sb_default_handle_def();
    def.name = row ? "top" : "bottom";
    def.vertices = vertices;
    def.vertex_count = side;
    def.path = path;
    def.path_count = 2;
    sb_error err;
    sb_handle* h = sb_handle_create(&def, &err);
    if (!h) fail_msg("%s", err.message);
    return h;
}

/* The two handles: the first row pulled down, the last up (rows[2][side]). */
static inline void ps_handles(uint32_t side, sb_handle* handles[2], uint32_t* rows) {
    handles[0] = ps_row_handle(side, 0, ps_down, rows);
    handles[1] = ps_row_handle(side, side - 1, ps_up, rows + side);
}

static inline void ps_destroy(sb_solver* solver, sb_handle* handles[2], sb_model* model) {
    sb_solver_destroy(solver);
    sb_handle_destroy(handles[0]);
    sb_handle_destroy(handles[1]);
    sb_model_destroy(model);
}

static inline uint32_t ps_find(uint32_t* parent, uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

/* parent[] of the vertices joined by the live triangles. */
static inline uint32_t* ps_components(const sb_solver* s) {
    uint32_t n = sb_solver_vertex_count(s), triangles = sb_solver_triangle_count(s);
    uint32_t* parent = malloc(n * sizeof *parent);
    for (uint32_t i = 0; i < n; i++) parent[i] = i;
    for (uint32_t t = 0; t < triangles; t++) {
        if (!sb_solver_triangle_alive(s, t)) continue;
        uint32_t v[3];
        sb_solver_triangle(s, t, v);
        for (int c = 1; c < 3; c++) parent[ps_find(parent, v[c])] = ps_find(parent, v[0]);
    }
    return parent;
}

#endif
