/* A scene made ready to advance: its mesh, model, colliders, handles, blades, point
 * load, haptic device and solver, as `softbond run`, `view` and `film` make
 * them from the same arguments, and as the scene library
 * (include/softbond/scene.h) makes all but the solver and the device.
 * The arguments are text as the program received it, so that every
 * message names the option (--threads, --budget-ms) the way it was given. */
#ifndef SB_SCENE_SIMULATION_H
#define SB_SCENE_SIMULATION_H

#include "scenes/blades.h"
#include "scenes/colliders.h"
#include "scenes/handles.h"
#include "scenes/haptics.h"
#include "scenes/point_load.h"

/* What a simulation is made from: the program's arguments, or a library
 * caller's path and overrides (the rest NULL). */
typedef struct sb_simulation_args {
    const char* input;       /* the scene file; NULL = the defaults */
    const char* const* sets; /* "key=value" overrides, in order */
    int set_count;
    const char* threads;   /* --threads N, or NULL */
    const char* budget_ms; /* --budget-ms X (a level of detail), or NULL */
    const char* max_error; /* --max-error M (with budget_ms), or NULL */
} sb_simulation_args;

typedef struct sb_simulation {
    sb_scene scene;
    sb_mesh mesh;
    sb_model* model;
    sb_solver* solver;
    sb_point_load load;           /* the solver's external force reads it */
    sb_scene_colliders colliders; /* the solver reads them: destroyed after it */
    sb_scene_handles handles;     /* the same */
    sb_scene_blades blades;       /* copied by the solver */
    sb_handle** attached;         /* the scene's handles, then the caller's extra one */
    sb_scene_haptics haptics;     /* the device and the servo driving a tool (haptics.h) */
    sb_solver_def def;            /* the solver's settings, as prepared */
} sb_simulation;

/* The scene of args (file and --set), its colliders, its model
 * (args->budget_ms picks a level of detail, printing what it measured on
 * stdout), its handles and point load; then sb_simulation_start makes the
 * solver (args->threads) and opens the haptic device. `extra` (may be
 * NULL) is attached after the scene's handles and must outlive the solver.
 * On failure sb_simulation_free still frees what was made. */
sb_status sb_simulation_prepare(sb_simulation* sim, const sb_simulation_args* args, sb_error* err);
sb_status sb_simulation_start(sb_simulation* sim, sb_handle* extra, sb_error* err);
void sb_simulation_free(sb_simulation* sim);

/* The solver's thread count: `requested` (--threads, may be NULL), else
 * the scene's threads when not 0, else SOFTBOND_THREADS, else 0 (the
 * runtime's default). */
sb_status sb_simulation_threads(const char* requested, const sb_scene* scene, int* out, sb_error* err);

/* The scene's gravity, or +z when it has none: the direction shown up. */
void sb_simulation_up(const sb_simulation* sim, double up[3]);

#endif
