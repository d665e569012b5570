/* From a validated scene to the library's objects: the mesh, the model
 * (material, fixed vertices, pins) and the solver's settings. */
#ifndef SB_SCENE_MODEL_H
#define SB_SCENE_MODEL_H

#include "scenes/scene.h"

/* The mesh the scene asks for: a sheet, an icosphere or a file (its
 * objects merged, or kept apart as separate bodies with
 * mesh.separate_objects), simplified (mesh.target_vertices,
 * mesh.target_error), then placed (mesh.scale, mesh.rotate,
 * mesh.translate), then reordered if asked. Errors name the file (and
 * line), or where the generator's settings came from. */
sb_status sb_scene_make_mesh(const sb_scene* scene, sb_mesh* out, sb_error* err);
/* Whether mesh.target_vertices or mesh.target_error asks for a level of detail. */
bool sb_scene_lod(const sb_scene* scene);
/* Simplifies a surface mesh as the scene asks (target_vertices, when not 0,
 * overrides mesh.target_vertices): fixed vertices locked at their indices,
 * the boundary kept. origin (may be NULL) receives each new vertex's index
 * before (as sb_mesh_simplify's). An error for a tetrahedral file. */
sb_status sb_scene_simplify(const sb_scene* scene, sb_mesh* mesh, uint32_t target_vertices, uint32_t* origin,
                            sb_simplify_report* report, sb_error* err);
/* mesh.scale, mesh.rotate and mesh.translate as a transform. */
sb_mesh_transform_def sb_scene_placement(const sb_scene* scene);

sb_material_def sb_scene_material(const sb_scene* scene);
/* The springs.* keys with mass and density (factory: springs). */
sb_spring_mesh_def sb_scene_springs(const sb_scene* scene);
/* The sheet.* keys (factory: membrane). */
sb_sheet_material_def sb_scene_sheet(const sb_scene* scene);
/* material, then tissue.young_modulus and tissue.density where set, tissue.damping and
 * tissue.stiffness_damping. */
sb_tissue_def sb_scene_tissue(const sb_scene* scene);
/* A file generator with a tetrahedral mesh file (.node, .ele, .msh): the
 * model is the tissue model of its tetrahedra. */
bool sb_scene_volumetric(const sb_scene* scene);

/* A file generator with a POV-Ray mesh.file (.pov): a body per mesh2
 * object, built by the spring factory with the object's spring_system_*
 * locals over the springs.* keys, mass and density (whatever `factory`
 * says); a fixed object has every vertex fixed. */
bool sb_scene_pov(const sb_scene* scene);

/* Adds the mesh with the scene's material, fixes the `fixed` vertices and
 * the `pin` selection, and compiles. On failure returns NULL; err names the
 * bad index or element, prefixed with `source` (the mesh's file or the
 * scene) for errors of the mesh itself. */
sb_model* sb_scene_build_model(const sb_scene* scene, const sb_mesh* mesh, const char* source, sb_error* err);

/* Integrator, gravity, drag, kernels and threads (as the scene says; 0 =
 * the runtime's default). */
sb_solver_def sb_scene_solver_def(const sb_scene* scene);

#endif
