/** @file
 * softbond's YAML scenes for an embedding program (libsoftbond_scene).
 *
 * One call loads a scene file the way `softbond run` does (the defaults,
 * the file, then each "key=value" override, then the checks) and builds
 * what running it needs: the model, and a solver definition whose
 * colliders, handles, blades and point load are filled in. The caller
 * makes the solver from these and advances it by the scene's dt:
 *
 *     sb_scene_file* scene;
 *     if (sb_scene_file_load("hook_pull.yaml", NULL, 0, &scene, &err) != SB_OK) ... err.message ...
 *     sb_solver* solver = sb_solver_create(sb_scene_file_model(scene), sb_scene_file_solver_def(scene), &err);
 *     while (sb_solver_time(solver) < sb_scene_file_duration(scene)) sb_solver_advance(solver,
 * sb_scene_file_dt(scene)); sb_solver_destroy(solver); sb_scene_file_destroy(scene);
 *
 * The solver reads the colliders, handles and point load that the scene
 * owns, so the scene is destroyed after every solver made from it. The
 * scene's haptics.* settings are not acted on (no device is opened), nor
 * are the program's own (output.*, --budget-ms). Errors are one line in
 * err, naming the file and the line of the offending value
 * ("scene.yaml:12: ...") or the override ("--set dt=0: ..."). */
#ifndef SOFTBOND_SCENE_H
#define SOFTBOND_SCENE_H

#include <stddef.h>

#include "softbond/export.h"
#include "softbond/model.h"
#include "softbond/solver.h"
#include "softbond/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A loaded scene: its model, its solver definition and the run's
 * settings (sb_scene_file_load); opaque, freed by sb_scene_file_destroy. */
typedef struct sb_scene_file sb_scene_file;

/** Loads the scene at path with `count` overrides "key=value" (a dotted key
 * such as "bond.k" or "mesh.nx"; the value a YAML scalar, flow sequence or
 * flow map), later ones winning, and builds its model into *out. A
 * relative path in the scene (mesh.file) is relative to the scene file.
 * The solver's thread count is the scene's `threads`, else
 * SOFTBOND_THREADS, else the runtime's default. On failure *out is NULL
 * and the status says why: SB_ERR_IO (a file cannot be read), SB_ERR_PARSE
 * (malformed YAML, an unknown key, a value of the wrong type), SB_ERR_INVALID
 * (a value out of range, a bad combination, a mesh that does not build),
 * SB_ERR_NOMEM. */
SB_API sb_status sb_scene_file_load(const char* path, const char* const* overrides, size_t count, sb_scene_file** out,
                                    sb_error* err);
/** Frees the scene, its model and what its solver definition points at.
 * NULL is a no-op. */
SB_API void sb_scene_file_destroy(sb_scene_file* scene);

/** The compiled model (the mesh placed, pinned and fixed as the scene says). */
SB_API const sb_model* sb_scene_file_model(const sb_scene_file* scene);
/** The solver's settings: integrator, gravity, kernels, threads, and the
 * scene's colliders, handles, blades and point load (pointers into the
 * scene, valid until sb_scene_file_destroy). */
SB_API const sb_solver_def* sb_scene_file_solver_def(const sb_scene_file* scene);

/** The time step, s (`dt`). */
SB_API double sb_scene_file_dt(const sb_scene_file* scene);
/** The simulated time the scene runs for, s (`duration`). */
SB_API double sb_scene_file_duration(const sb_scene_file* scene);
/** The simulated time between frames, s (`frame_interval`). */
SB_API double sb_scene_file_frame_interval(const sb_scene_file* scene);
/** Any number or integer setting by its dotted key ("stop.kinetic_energy",
 * "mesh.nx"), in the scene's units (docs/scene_keys.md, `softbond keys`).
 * SB_ERR_INVALID for an unknown key or one that is not a number. */
SB_API sb_status sb_scene_file_number(const sb_scene_file* scene, const char* key, double* out, sb_error* err);
/** The scene's name: its file name without directory and extension. */
SB_API const char* sb_scene_file_name(const sb_scene_file* scene);

#ifdef __cplusplus
}
#endif

#endif
