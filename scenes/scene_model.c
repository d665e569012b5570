/* Builds the library's mesh, model and solver settings from a scene. */
#include "scenes/scene_model.h"
#include "common/error.h"
#include "scenes/net.h"
#include "scenes/pin.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Whether the generated sheet's cells are cut all the same way: asked for,
 * or by default for a sheet stated by its material (factory membrane),
 * whose plate bending needs such a mesh (mesh/plate_stencils.c). */
static bool parallel_diagonals(const sb_scene* scene) {
    const char* diagonals = sb_scene_string(scene, SB_KEY_MESH_DIAGONALS);
    if (strcmp(diagonals, "auto") != 0) return strcmp(diagonals, "parallel") == 0;
    return strcmp(sb_scene_string(scene, SB_KEY_FACTORY), "membrane") == 0;
}

static sb_status make_sheet(const sb_scene* scene, sb_mesh* out, sb_error* err) {
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = (uint32_t)sb_scene_integer(scene, SB_KEY_MESH_NX);
    def.ny = (uint32_t)sb_scene_integer(scene, SB_KEY_MESH_NY);
    def.width = sb_scene_number(scene, SB_KEY_MESH_WIDTH);
    def.height = sb_scene_number(scene, SB_KEY_MESH_HEIGHT);
    def.jitter = sb_scene_number(scene, SB_KEY_MESH_JITTER);
    def.seed = (uint64_t)sb_scene_integer(scene, SB_KEY_MESH_SEED);
    def.parallel_diagonals = parallel_diagonals(scene);
    return sb_mesh_generate_sheet(&def, out, err);
}

/* The quadratic tissue's surface: its edges' middles are the model's
 * vertices too (sb_tet_mesh_quadratic_surface). */
static sb_status load_quadratic_surface(const sb_scene* scene, char* path, sb_mesh* out, sb_error* err) {
    sb_tet_mesh volume;
    sb_status status = sb_tet_mesh_load(path, &volume, err);
    free(path);
    if (status == SB_OK) status = sb_tet_mesh_quadratic_surface(&volume, out, err);
    sb_tet_mesh_free(&volume);
    return status == SB_OK ? SB_OK : sb_error_prefix(err, status, sb_scene_where(scene, SB_KEY_MESH_FILE));
}

static sb_status load_file(const sb_scene* scene, sb_mesh* out, sb_error* err) {
    char* path = sb_scene_path(scene, SB_KEY_MESH_FILE);
    if (!path) return sb_scene_fail(scene, SB_KEY_MESH_FILE, err, "out of memory");
    if (sb_scene_volumetric(scene) && sb_scene_tissue(scene).model == SB_TISSUE_COROTATED_QUADRATIC)
        return load_quadratic_surface(scene, path, out, err);
    sb_mesh_load_def def = sb_default_mesh_load_def();
    def.separate_objects = sb_scene_bool(scene, SB_KEY_MESH_SEPARATE_OBJECTS);
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    sb_status status = sb_mesh_load_ex(path, &def, &objects, &count, NULL, err);
    free(path);
    if (status != SB_OK) return sb_error_prefix(err, status, sb_scene_where(scene, SB_KEY_MESH_FILE));
    if (count == 1) {
        *out = objects[0];
        free(objects);
        return SB_OK;
    }
    status = sb_mesh_concatenate(objects, count, out, err);
    sb_mesh_objects_free(objects, count);
    return status;
}

bool sb_scene_lod(const sb_scene* scene) {
    return sb_scene_integer(scene, SB_KEY_MESH_TARGET_VERTICES) > 0 ||
           sb_scene_number(scene, SB_KEY_MESH_TARGET_ERROR) > 0.0;
}

/* mesh.target_vertices / mesh.target_error (target_vertices when not 0
 * wins over the scene's): the fixed vertices are locked and keep their
 * indices, so `fixed` still names them. */
sb_status sb_scene_simplify(const sb_scene* scene, sb_mesh* mesh, uint32_t target_vertices, uint32_t* origin,
                            sb_simplify_report* report, sb_error* err) {
    if (sb_scene_volumetric(scene))
        return sb_scene_fail(scene, SB_KEY_MESH_TARGET_VERTICES, err,
                             "level of detail applies to surface meshes, not tetrahedral files");
    sb_simplify_def def = sb_default_simplify_def();
    def.target_vertices =
        target_vertices ? target_vertices : (uint32_t)sb_scene_integer(scene, SB_KEY_MESH_TARGET_VERTICES);
    def.target_error = sb_scene_number(scene, SB_KEY_MESH_TARGET_ERROR);
    def.locked = sb_scene_indices(scene, SB_KEY_FIXED, &def.locked_count);
    for (uint32_t i = 0; i < def.locked_count; i++)
        if (def.locked[i] >= mesh->vertex_count)
            return sb_scene_fail(scene, SB_KEY_FIXED, err, "'fixed': vertex %u out of range (the mesh has %u vertices)",
                                 def.locked[i], mesh->vertex_count);
    def.keep_locked_indices = true;
    return sb_mesh_simplify(mesh, &def, origin, report, err);
}

sb_mesh_transform_def sb_scene_placement(const sb_scene* scene) {
    sb_mesh_transform_def t = sb_default_mesh_transform_def();
    memcpy(t.scale, sb_scene_vec3(scene, SB_KEY_MESH_SCALE), sizeof t.scale);
    memcpy(t.rotate, sb_scene_vec3(scene, SB_KEY_MESH_ROTATE), sizeof t.rotate);
    memcpy(t.translate, sb_scene_vec3(scene, SB_KEY_MESH_TRANSLATE), sizeof t.translate);
    return t;
}

static sb_status make_mesh(const sb_scene* scene, sb_mesh* out, sb_error* err) {
    const char* generator = sb_scene_string(scene, SB_KEY_MESH_GENERATOR);
    if (strcmp(generator, "file") == 0) return load_file(scene, out, err);
    sb_status status = strcmp(generator, "sheet") == 0
                           ? make_sheet(scene, out, err)
                           : sb_mesh_generate_icosphere((uint32_t)sb_scene_integer(scene, SB_KEY_MESH_SUBDIVISIONS),
                                                        sb_scene_number(scene, SB_KEY_MESH_RADIUS), out, err);
    if (status == SB_OK) return SB_OK;
    const char* where = sb_scene_where(scene, SB_KEY_MESH_GENERATOR);
    return sb_error_prefix(err, status, where ? where : generator);
}

sb_status sb_scene_make_mesh(const sb_scene* scene, sb_mesh* out, sb_error* err) {
    sb_status status = make_mesh(scene, out, err);
    if (status == SB_OK && sb_scene_lod(scene)) status = sb_scene_simplify(scene, out, 0, NULL, NULL, err);
    sb_mesh_transform_def placement = sb_scene_placement(scene);
    if (status == SB_OK) status = sb_mesh_transform(out, &placement, err);
    if (status == SB_OK && sb_scene_bool(scene, SB_KEY_MESH_REORDER)) status = sb_mesh_reorder(out, NULL, err);
    if (status != SB_OK) sb_mesh_free(out);
    return status;
}

sb_material_def sb_scene_material(const sb_scene* scene) {
    sb_material_def m = sb_default_material_def();
    m.bond_k = sb_scene_number(scene, SB_KEY_BOND_K);
    m.angle_k = sb_scene_number(scene, SB_KEY_ANGLE_K);
    m.stretch_bend_k = sb_scene_number(scene, SB_KEY_STRETCH_BEND_K);
    m.spring_k = sb_scene_number(scene, SB_KEY_SPRING_K);
    m.spring_damping = sb_scene_number(scene, SB_KEY_SPRING_DAMPING);
    m.bend_k = sb_scene_number(scene, SB_KEY_BEND_K);
    m.break_strain = sb_scene_number(scene, SB_KEY_BOND_BREAK_STRAIN);
    m.mass = sb_scene_number(scene, SB_KEY_MASS);
    m.density = sb_scene_number(scene, SB_KEY_DENSITY);
    return m;
}

static sb_status fix_vertices(const sb_scene* scene, const sb_mesh* mesh, sb_builder* builder, sb_error* err) {
    uint32_t count;
    const uint32_t* fixed = sb_scene_indices(scene, SB_KEY_FIXED, &count);
    for (uint32_t i = 0; i < count; i++) {
        if (fixed[i] >= mesh->vertex_count)
            return sb_scene_fail(scene, SB_KEY_FIXED, err, "'fixed': vertex %u out of range (the mesh has %u vertices)",
                                 fixed[i], mesh->vertex_count);
        sb_builder_vertex(builder, fixed[i])->fixed = true;
    }
    sb_pin_apply(sb_scene_string(scene, SB_KEY_PIN), mesh, builder);
    return SB_OK;
}

sb_spring_mesh_def sb_scene_springs(const sb_scene* scene) {
    sb_spring_mesh_def d = sb_default_spring_mesh_def();
    d.stretch_k = sb_scene_number(scene, SB_KEY_SPRINGS_STRETCH_K);
    d.stretch_damping = sb_scene_number(scene, SB_KEY_SPRINGS_STRETCH_DAMPING);
    d.bend_k = sb_scene_number(scene, SB_KEY_SPRINGS_BEND_K);
    d.bend_damping = sb_scene_number(scene, SB_KEY_SPRINGS_BEND_DAMPING);
    d.vicinity = sb_scene_number(scene, SB_KEY_SPRINGS_VICINITY_DISTANCE);
    d.vicinity_k = sb_scene_number(scene, SB_KEY_SPRINGS_VICINITY_K);
    d.vicinity_damping = sb_scene_number(scene, SB_KEY_SPRINGS_VICINITY_DAMPING);
    d.break_strain = sb_scene_number(scene, SB_KEY_SPRINGS_BREAK_STRAIN);
    d.mass = sb_scene_number(scene, SB_KEY_MASS);
    d.density = sb_scene_number(scene, SB_KEY_DENSITY);
    return d;
}

sb_sheet_material_def sb_scene_sheet(const sb_scene* scene) {
    sb_sheet_material_def d = sb_default_sheet_material_def();
    d.young_modulus = sb_scene_number(scene, SB_KEY_SHEET_YOUNG_MODULUS);
    d.poisson_ratio = sb_scene_number(scene, SB_KEY_SHEET_POISSON_RATIO);
    d.thickness = sb_scene_number(scene, SB_KEY_SHEET_THICKNESS);
    d.density = sb_scene_number(scene, SB_KEY_SHEET_DENSITY);
    d.stiffness_damping = sb_scene_number(scene, SB_KEY_SHEET_STIFFNESS_DAMPING);
    return d;
}

sb_tissue_def sb_scene_tissue(const sb_scene* scene) {
    sb_tissue_def t = sb_default_tissue_def();
    sb_tissue_from_name(sb_scene_string(scene, SB_KEY_MATERIAL), &t);
    if (scene->values[SB_KEY_TISSUE_YOUNG_MODULUS].where[0])
        t.young_modulus = sb_scene_number(scene, SB_KEY_TISSUE_YOUNG_MODULUS);
    if (scene->values[SB_KEY_TISSUE_DENSITY].where[0]) t.density = sb_scene_number(scene, SB_KEY_TISSUE_DENSITY);
    t.damping = sb_scene_number(scene, SB_KEY_TISSUE_DAMPING);
    t.stiffness_damping = sb_scene_number(scene, SB_KEY_TISSUE_STIFFNESS_DAMPING);
    const char* model = sb_scene_string(scene, SB_KEY_TISSUE_MODEL);
    bool physical = scene->values[SB_KEY_TISSUE_YOUNG_MODULUS].where[0]; /* auto: E stated, E honoured */
    t.model = strcmp(model, "corotated") == 0 ? SB_TISSUE_COROTATED
              : strcmp(model, "corotated_quadratic") == 0 || (strcmp(model, "auto") == 0 && physical)
                  ? SB_TISSUE_COROTATED_QUADRATIC
                  : SB_TISSUE_SPRINGS;
    t.poisson_ratio = sb_scene_number(scene, SB_KEY_TISSUE_POISSON_RATIO);
    return t;
}

bool sb_scene_volumetric(const sb_scene* scene) {
    return strcmp(sb_scene_string(scene, SB_KEY_MESH_GENERATOR), "file") == 0 &&
           sb_tet_mesh_path(sb_scene_string(scene, SB_KEY_MESH_FILE));
}

/* The tetrahedra behind the surface of a .node/.ele/.msh file. */
static sb_status add_tissue(const sb_scene* scene, const sb_mesh* mesh, sb_builder* builder, sb_error* err) {
    char* path = sb_scene_path(scene, SB_KEY_MESH_FILE);
    if (!path) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    sb_tet_mesh volume;
    sb_status status = sb_tet_mesh_load(path, &volume, err);
    free(path);
    sb_mesh_transform_def placement = sb_scene_placement(scene);
    sb_mesh points = {.vertex_count = volume.vertex_count, .positions = volume.positions};
    if (status == SB_OK) status = sb_mesh_transform(&points, &placement, err);
    sb_tissue_def tissue = sb_scene_tissue(scene);
    uint32_t first = sb_builder_vertex_count(builder);
    if (status == SB_OK) status = sb_builder_add_tet_mesh(builder, &volume, &tissue, err);
    if (status == SB_OK && sb_builder_vertex_count(builder) - first != mesh->vertex_count)
        status = sb_error_set(err, SB_ERR_INVALID, "the file changed while it was read");
    sb_tet_mesh_free(&volume);
    return status;
}

bool sb_scene_pov(const sb_scene* scene) {
    return strcmp(sb_scene_string(scene, SB_KEY_MESH_GENERATOR), "file") == 0 &&
           sb_pov_path(sb_scene_string(scene, SB_KEY_MESH_FILE));
}

/* Self-contact keeps the model's triangles apart, and the Spring Systems
 * and sheet factories make none: with `self_collision` the mesh's
 * triangles (from vertex `base` on) are added too, without terms (angle
 * and stretch-bend constants 0, which the step skips), as the body's
 * surface. */
static sb_status add_surface(const sb_mesh* mesh, uint32_t base, sb_builder* builder, sb_error* err) {
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t* v = mesh->triangles + 3 * (size_t)t;
        sb_triangle_def def = sb_default_triangle_def();
        def.i = base + v[0], def.j = base + v[1], def.k = base + v[2];
        def.angle_k = 0.0, def.stretch_bend_k = 0.0;
        if (sb_builder_add_triangle(builder, &def) < 0) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    }
    return SB_OK;
}

static sb_status add_spring_body(const sb_mesh* mesh, const sb_spring_mesh_def* springs, bool surface,
                                 sb_builder* builder, sb_error* err) {
    uint32_t base = sb_builder_vertex_count(builder);
    sb_status status = sb_builder_add_spring_mesh(builder, mesh, springs, err);
    return status == SB_OK && surface ? add_surface(mesh, base, builder, err) : status;
}

/* One mesh2 object: its triangles over its part of the (placed) mesh,
 * which starts at vertex `first`; a fixed object has every vertex fixed. */
static sb_status add_pov_object(const sb_pov_object* object, const sb_mesh* mesh, uint32_t first,
                                const sb_spring_mesh_def* defaults, bool surface, sb_builder* builder, sb_error* err) {
    sb_mesh part = {.vertex_count = object->mesh.vertex_count,
                    .positions = mesh->positions + 3 * (size_t)first,
                    .triangle_count = object->mesh.triangle_count,
                    .triangles = object->mesh.triangles};
    sb_spring_mesh_def springs = sb_pov_object_springs(object, defaults);
    uint32_t base = sb_builder_vertex_count(builder);
    sb_status status = add_spring_body(&part, &springs, surface, builder, err);
    for (uint32_t v = 0; status == SB_OK && object->fixed && v < part.vertex_count; v++)
        sb_builder_vertex(builder, base + v)->fixed = true;
    if (status == SB_OK) return SB_OK;
    char where[128];
    snprintf(where, sizeof where, "mesh2 %s%s(line %zu)", object->name, object->name[0] ? " " : "", object->line);
    return sb_error_prefix(err, status, where);
}

/* The mesh2 objects of a .pov file, each with its own locals over the
 * scene's springs.* keys, mass and density. The mesh is the objects
 * concatenated and placed, so object i's vertices follow object i-1's. */
static sb_status add_pov(const sb_scene* scene, const sb_mesh* mesh, sb_builder* builder, sb_error* err) {
    if (sb_scene_lod(scene) || sb_scene_bool(scene, SB_KEY_MESH_REORDER))
        return sb_scene_fail(scene, SB_KEY_MESH_FILE, err,
                             "a .pov file's objects keep their vertices: mesh.target_vertices, "
                             "mesh.target_error and mesh.reorder do not apply");
    char* path = sb_scene_path(scene, SB_KEY_MESH_FILE);
    if (!path) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    sb_pov_object* objects = NULL;
    uint32_t count = 0, first = 0;
    sb_status status = sb_pov_load(path, &objects, &count, err);
    free(path);
    sb_spring_mesh_def defaults = sb_scene_springs(scene);
    bool surface = sb_scene_bool(scene, SB_KEY_SELF_COLLISION);
    for (uint32_t i = 0; i < count && status == SB_OK; i++) {
        if (objects[i].mesh.vertex_count > mesh->vertex_count - first)
            status = sb_error_set(err, SB_ERR_INVALID, "the file changed while it was read");
        else
            status = add_pov_object(&objects[i], mesh, first, &defaults, surface, builder, err);
        first += objects[i].mesh.vertex_count;
    }
    if (status == SB_OK && first != mesh->vertex_count)
        status = sb_error_set(err, SB_ERR_INVALID, "the file changed while it was read");
    sb_pov_objects_free(objects, count);
    return status;
}

static sb_status add_body(const sb_scene* scene, const sb_mesh* mesh, sb_builder* builder, sb_error* err) {
    if (sb_scene_volumetric(scene)) return add_tissue(scene, mesh, builder, err);
    if (sb_scene_pov(scene)) return add_pov(scene, mesh, builder, err);
    if (strcmp(sb_scene_string(scene, SB_KEY_FACTORY), "net") == 0) return sb_scene_add_net(scene, mesh, builder, err);
    if (strcmp(sb_scene_string(scene, SB_KEY_FACTORY), "membrane") == 0) {
        sb_sheet_material_def sheet = sb_scene_sheet(scene);
        uint32_t base = sb_builder_vertex_count(builder);
        sb_status status = sb_builder_add_sheet(builder, mesh, &sheet, err);
        return status == SB_OK && sb_scene_bool(scene, SB_KEY_SELF_COLLISION) ? add_surface(mesh, base, builder, err)
                                                                              : status;
    }
    if (strcmp(sb_scene_string(scene, SB_KEY_FACTORY), "springs") == 0) {
        sb_spring_mesh_def springs = sb_scene_springs(scene);
        return add_spring_body(mesh, &springs, sb_scene_bool(scene, SB_KEY_SELF_COLLISION), builder, err);
    }
    sb_material_def material = sb_scene_material(scene);
    return sb_builder_add_mesh(builder, mesh, &material, err);
}

static sb_model* build(const sb_scene* scene, const sb_mesh* mesh, const char* source, sb_builder* builder,
                       sb_error* err) {
    sb_status status = add_body(scene, mesh, builder, err);
    if (status != SB_OK) {
        sb_error_prefix(err, status, source);
        return NULL;
    }
    if (fix_vertices(scene, mesh, builder, err) != SB_OK) return NULL;
    sb_model* model = sb_builder_compile(builder, err);
    if (!model) sb_error_prefix(err, SB_ERR_INVALID, source);
    return model;
}

sb_model* sb_scene_build_model(const sb_scene* scene, const sb_mesh* mesh, const char* source, sb_error* err) {
    sb_builder* builder = sb_builder_create();
    if (!builder) {
        sb_error_set(err, SB_ERR_NOMEM, "out of memory");
        return NULL;
    }
    sb_model* model = build(scene, mesh, source, builder, err);
    sb_builder_destroy(builder);
    return model;
}

sb_solver_def sb_scene_solver_def(const sb_scene* scene) {
    sb_solver_def def = sb_default_solver_def();
    sb_integrator_from_name(sb_scene_string(scene, SB_KEY_INTEGRATOR), &def.integrator);
    memcpy(def.gravity, sb_scene_vec3(scene, SB_KEY_GRAVITY), sizeof def.gravity);
    def.drag = sb_scene_number(scene, SB_KEY_DRAG);
    bool fast = strcmp(sb_scene_string(scene, SB_KEY_KERNELS), "fast") == 0;
    def.kernels = fast ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
    def.runtime.threads = (int)sb_scene_integer(scene, SB_KEY_THREADS);
    sb_wait_policy_from_name(sb_scene_string(scene, SB_KEY_WAIT), &def.runtime.wait);
    def.runtime.pin = sb_scene_bool(scene, SB_KEY_PIN_THREADS);
    def.runtime.fixed_width = !sb_scene_bool(scene, SB_KEY_ADAPTIVE_THREADS);
    def.adaptive = sb_scene_bool(scene, SB_KEY_ADAPTIVE);
    def.min_dt = sb_scene_number(scene, SB_KEY_MIN_DT);
    def.implicit_tolerance = sb_scene_number(scene, SB_KEY_IMPLICIT_TOLERANCE);
    def.implicit_newton_iterations = (int)sb_scene_integer(scene, SB_KEY_IMPLICIT_NEWTON_ITERATIONS);
    def.implicit_cg_iterations = (int)sb_scene_integer(scene, SB_KEY_IMPLICIT_CG_ITERATIONS);
    def.implicit_definite = sb_scene_bool(scene, SB_KEY_IMPLICIT_DEFINITE);
    sb_linear_solver_from_name(sb_scene_string(scene, SB_KEY_IMPLICIT_SOLVER), &def.implicit_solver);
    def.pbd_iterations = (int)sb_scene_integer(scene, SB_KEY_PBD_ITERATIONS);
    def.max_splits = (int32_t)sb_scene_integer(scene, SB_KEY_TEARING_MAX_SPLITS);
    def.max_splits_per_step = (int32_t)sb_scene_integer(scene, SB_KEY_TEARING_MAX_SPLITS_PER_STEP);
    def.shatter = sb_scene_bool(scene, SB_KEY_TEARING_SHATTER);
    def.cut_through = sb_scene_bool(scene, SB_KEY_CUT_THROUGH);
    def.vbd_iterations = (int)sb_scene_integer(scene, SB_KEY_VBD_ITERATIONS);
    def.vbd_chebyshev_rho = sb_scene_number(scene, SB_KEY_VBD_CHEBYSHEV_RHO);
    def.vbd_relaxation = sb_scene_number(scene, SB_KEY_VBD_RELAXATION);
    def.self_collision = sb_scene_bool(scene, SB_KEY_SELF_COLLISION);
    def.contact_thickness = sb_scene_number(scene, SB_KEY_CONTACT_THICKNESS);
    return def;
}
