/* A scene: every setting of a run, read from a YAML file and `--set`.
 *
 * The keys live in one table, SB_SCENE_KEYS: dotted name, type, default (as
 * YAML text, parsed by the same code as the file) and a short meaning. The
 * loader flattens nested maps into dotted keys (`bond: {k: 1}` is
 * `bond.k: 1`) and rejects unknown keys, wrong types, duplicate keys and
 * malformed YAML with one line naming the file and the line. Each value
 * remembers where it came from, so later checks name that place too. */
#ifndef SB_SCENE_H
#define SB_SCENE_H

#include "softbond/softbond.h"
#include "scenes/scene_node.h"

#include <stdio.h>

typedef enum sb_scene_type {
    SB_SCENE_NUMBER,  /* a finite or non-finite double; validation decides */
    SB_SCENE_INTEGER, /* a whole number */
    SB_SCENE_STRING,
    SB_SCENE_BOOL,           /* true or false */
    SB_SCENE_VEC3,           /* a sequence of three numbers */
    SB_SCENE_VEC3_OR_NUMBER, /* three numbers, or one number for all three */
    SB_SCENE_INDICES,        /* a sequence of non-negative integers */
    SB_SCENE_NAMES,          /* a sequence of names, or one "a,b" text; kept as the string "a,b" */
    SB_SCENE_LIST            /* a sequence of maps, kept as read (scene_node.h) for its own module to check */
} sb_scene_type;

/* X(id, name, type, default, unit, meaning): the unit is SI, "1" for a ratio,
 * "" for a count, a name or a switch. `softbond keys` prints this table and
 * docs/scene_keys.md is its output (tests/CMakeLists.txt: scene_keys_doc). */
#define SB_SCENE_KEYS(X)                                                                                               \
    X(MESH_GENERATOR, "mesh.generator", STRING, "sheet", "", "sheet, icosphere or file")                               \
    X(MESH_FILE, "mesh.file", STRING, "''", "",                                                                        \
      "mesh file for generator file (OBJ, OFF, IRIT .itd, POV-Ray .pov, TetGen .node/.ele, Gmsh "                      \
      ".msh or any assimp format), relative to the scene file")                                                        \
    X(MESH_NX, "mesh.nx", INTEGER, "10", "", "sheet: vertices along x (>= 2)")                                         \
    X(MESH_NY, "mesh.ny", INTEGER, "10", "", "sheet: vertices along y (>= 2)")                                         \
    X(MESH_WIDTH, "mesh.width", NUMBER, "1", "m", "sheet: size along x, m")                                            \
    X(MESH_HEIGHT, "mesh.height", NUMBER, "1", "m", "sheet: size along y, m")                                          \
    X(MESH_JITTER, "mesh.jitter", NUMBER, "0", "1",                                                                    \
      "sheet: interior vertices moved by up to jitter x spacing, in [0, 0.5)")                                         \
    X(MESH_SEED, "mesh.seed", INTEGER, "1", "", "sheet: seed of the jitter")                                           \
    X(MESH_DIAGONALS, "mesh.diagonals", STRING, "auto", "",                                                            \
      "sheet: the cells cut along alternating diagonals (a checkerboard) or parallel ones (all the same way: a flat "  \
      "sheet of factory membrane then gets the plate bending, which honours sheet.poisson_ratio); auto: parallel "     \
      "for factory membrane, else alternating")                                                                        \
    X(MESH_SUBDIVISIONS, "mesh.subdivisions", INTEGER, "2", "", "icosphere: subdivisions of the icosahedron (0 to 8)") \
    X(MESH_RADIUS, "mesh.radius", NUMBER, "1", "m", "icosphere: radius, m")                                            \
    X(MESH_REORDER, "mesh.reorder", BOOL, "false", "",                                                                 \
      "renumber vertices along a Morton curve for speed (fixed indices then refer to the new "                         \
      "numbering)")                                                                                                    \
    X(MESH_SEPARATE_OBJECTS, "mesh.separate_objects", BOOL, "false", "",                                               \
      "file: keep the file's meshes as separate bodies (joined within each mesh only); false "                         \
      "merges them, joining identical positions across meshes")                                                        \
    X(MESH_SCALE, "mesh.scale", VEC3_OR_NUMBER, "1", "1",                                                              \
      "placement: scale factor, or [sx, sy, sz], about the origin, applied first")                                     \
    X(MESH_ROTATE, "mesh.rotate", VEC3, "[0, 0, 0]", "deg",                                                            \
      "placement: degrees about the x, then the y, then the z axis (fixed axes), after scale")                         \
    X(MESH_TRANSLATE, "mesh.translate", VEC3, "[0, 0, 0]", "m", "placement: shift, m, applied last")                   \
    X(MESH_TARGET_VERTICES, "mesh.target_vertices", INTEGER, "0", "",                                                  \
      "level of detail: simplify a surface to about this many vertices (meshoptimizer; boundary "                      \
      "and fixed vertices kept); 0 = off")                                                                             \
    X(MESH_TARGET_ERROR, "mesh.target_error", NUMBER, "0", "1",                                                        \
      "level of detail: simplify while the error stays below this fraction of the mesh's extent; "                     \
      "0 = off")                                                                                                       \
    X(BOND_K, "bond.k", NUMBER, "100", "N/m", "bond stretch stiffness, N/m (Eq. 3); 0 = off")                          \
    X(ANGLE_K, "angle.k", NUMBER, "0.1", "J", "angle bend constant, J (Eq. 4); 0 = off")                               \
    X(STRETCH_BEND_K, "stretch_bend.k", NUMBER, "0", "J/m", "stretch-bend constant, J/m (Eq. 5); 0 = off")             \
    X(SPRING_K, "spring.k", NUMBER, "0", "N/m", "damped spring stiffness, N/m (Eq. 2); 0 = off")                       \
    X(SPRING_DAMPING, "spring.damping", NUMBER, "0", "N s/m", "damped spring damping, N s/m")                          \
    X(BEND_K, "bend.k", NUMBER, "0", "J/rad^2", "dihedral bending across interior edges, J/rad^2; 0 = off")            \
    X(BOND_BREAK_STRAIN, "bond.break_strain", NUMBER, "0", "1",                                                        \
      "breakage: a bond breaks beyond its rest length times (1 + this), and the triangles and hinges on its edge "     \
      "go with it; 0 = never")                                                                                         \
    X(MASS, "mass", NUMBER, "0.01", "kg", "mass per vertex, kg (used when density is 0)")                              \
    X(DENSITY, "density", NUMBER, "0", "kg/m^2",                                                                       \
      "areal density, kg/m^2: a vertex gets a third of its triangles' mass; nonzero "                                  \
      "wins over mass")                                                                                                \
    X(FACTORY, "factory", STRING, "molecular", "",                                                                     \
      "surface model: molecular (bonds, angles, hinges), springs (stretch, bend and vicinity "                         \
      "springs), net (a sheet's rows and columns as bonds only) or membrane (a thin sheet of the sheet.* "             \
      "material: co-rotated triangles, plate bending when flat and suited, else discrete-shell hinges); a "            \
      "tetrahedral mesh.file always "                                                                                  \
      "builds the tissue model, a .pov one springs with each object's spring_system_* locals")                         \
    X(SHEET_YOUNG_MODULUS, "sheet.young_modulus", NUMBER, "30000", "Pa", "factory membrane: Young's modulus, Pa")      \
    X(SHEET_POISSON_RATIO, "sheet.poisson_ratio", NUMBER, "0.45", "1",                                                 \
      "factory membrane: Poisson's ratio, in (-1, 0.5)")                                                               \
    X(SHEET_THICKNESS, "sheet.thickness", NUMBER, "0.001", "m", "factory membrane: thickness, m")                      \
    X(SHEET_DENSITY, "sheet.density", NUMBER, "1060", "kg/m^3",                                                        \
      "factory membrane: density, kg/m^3 (a vertex gets a third of its triangles' density x thickness x area)")        \
    X(SHEET_STIFFNESS_DAMPING, "sheet.stiffness_damping", NUMBER, "0", "s",                                            \
      "factory membrane: the membranes' Rayleigh stiffness-proportional damping beta, s (an in-plane mode of "         \
      "frequency w: ratio beta w / 2; the bending is undamped)")                                                       \
    X(SPRINGS_STRETCH_K, "springs.stretch.k", NUMBER, "100", "N/m", "springs: per edge, N/m")                          \
    X(SPRINGS_STRETCH_DAMPING, "springs.stretch.damping", NUMBER, "0.1", "N s/m", "springs: per edge, N s/m")          \
    X(SPRINGS_BEND_K, "springs.bend.k", NUMBER, "10", "N/m", "springs: across adjacent triangles, N/m")                \
    X(SPRINGS_BEND_DAMPING, "springs.bend.damping", NUMBER, "0.01", "N s/m",                                           \
      "springs: across adjacent triangles, N s/m")                                                                     \
    X(SPRINGS_VICINITY_DISTANCE, "springs.vicinity.distance", NUMBER, "0", "m",                                        \
      "springs: join vertices nearer than this, m; 0 = off")                                                           \
    X(SPRINGS_VICINITY_K, "springs.vicinity.k", NUMBER, "100", "N/m", "springs: vicinity, N/m")                        \
    X(SPRINGS_VICINITY_DAMPING, "springs.vicinity.damping", NUMBER, "0.1", "N s/m", "springs: vicinity, N s/m")        \
    X(SPRINGS_BREAK_STRAIN, "springs.break_strain", NUMBER, "0", "1",                                                  \
      "springs: every spring breaks beyond its rest length times (1 + this); 0 = never")                               \
    X(MATERIAL, "material", STRING, "liver", "",                                                                       \
      "tetrahedral meshes: liver (E 3.5 kPa) or gallbladder (E 1.5 kPa), 1060 kg/m^3")                                 \
    X(TISSUE_YOUNG_MODULUS, "tissue.young_modulus", NUMBER, "3500", "Pa",                                              \
      "tetrahedral meshes: Young's modulus, Pa; when set, wins over the material's")                                   \
    X(TISSUE_DENSITY, "tissue.density", NUMBER, "1060", "kg/m^3",                                                      \
      "tetrahedral meshes: density, kg/m^3; when set, wins over the material's")                                       \
    X(TISSUE_DAMPING, "tissue.damping", NUMBER, "1", "1",                                                              \
      "tetrahedral meshes: factor on the papers' damping rule sqrt(k (mi + mj)) / l0 (springs only)")                  \
    X(TISSUE_STIFFNESS_DAMPING, "tissue.stiffness_damping", NUMBER, "0", "s",                                          \
      "tetrahedral meshes: Rayleigh's stiffness-proportional damping beta, s (a mode of frequency w: ratio beta w / "  \
      "2)")                                                                                                            \
    X(TISSUE_MODEL, "tissue.model", STRING, "auto", "",                                                                \
      "tetrahedral meshes: springs (Lloyd's edge springs, the papers'), corotated (linear finite elements, E and nu; " \
      "stiff in bending), corotated_quadratic (10-node finite elements, a vertex added at each edge's middle) or "     \
      "auto (corotated_quadratic when tissue.young_modulus is set, else springs)")                                     \
    X(TISSUE_POISSON_RATIO, "tissue.poisson_ratio", NUMBER, "0.45", "1",                                               \
      "tetrahedral meshes, the finite elements: Poisson's ratio, in (-1, 0.5)")                                        \
    X(FIXED, "fixed", INDICES, "[]", "", "indices of vertices held at their rest position")                            \
    X(PIN, "pin", STRING, "none", "",                                                                                  \
      "vertices pinned by place: none, top_corners, bottom_corners, left_corners, "                                    \
      "right_corners, <side>_edge or <side>_clamp (the side and its neighbours), side top, "                           \
      "bottom, left or right")                                                                                         \
    X(GRAVITY, "gravity", VEC3, "[0, 0, -9.81]", "m/s^2", "gravity, m/s^2")                                            \
    X(DRAG, "drag", NUMBER, "0", "1/s", "viscous drag, 1/s: each free vertex feels -drag m v")                         \
    X(LOAD_FORCE, "load.force", VEC3, "[0, 0, 0]", "N",                                                                \
      "a constant force, N, on the free vertex nearest load.at, from t = 0; [0, 0, 0] = none")                         \
    X(LOAD_AT, "load.at", VEC3, "[0, 0, 0]", "m",                                                                      \
      "where load.force acts: the vertex nearest this point of the placed rest shape, m")                              \
    X(COLLIDERS, "colliders", LIST, "[]", "",                                                                          \
      "what the bodies touch: a list of maps {type: plane, sphere, capsule, box or mesh; name; the shape's keys; "     \
      "friction, static_friction, restitution, thickness, footprint; path, interpolation} (scenes/colliders.c)")       \
    X(HANDLES, "handles", LIST, "[]", "",                                                                              \
      "vertices driven to a moving pose: a list of maps {name; vertices: [indices] or at: [x, y, z] with radius; "     \
      "stiffness, damping (soft when stiffness > 0); path, interpolation; release_at} (scenes/handles.c)")             \
    X(BLADES, "blades", LIST, "[]", "",                                                                                \
      "edges that cut the bonds they cross as they move: a list of maps {a, b: the ends, m; path, interpolation} "     \
      "(scenes/blades.c)")                                                                                             \
    X(CUT_THROUGH, "cut_through", BOOL, "false", "",                                                                   \
      "true: the blades split the triangles (or tetrahedra) they pass through along their path (needs an "             \
      "explicit integrator or implicit_euler, no break limits, no contact); false: they cut the bonds they cross")     \
    X(TEARING_MAX_SPLITS, "tearing.max_splits", INTEGER, "0", "",                                                      \
      "vertex copies tearing may make over the run (spare vertices reserved); 0 = default, -1 = no splitting")         \
    X(TEARING_MAX_SPLITS_PER_STEP, "tearing.max_splits_per_step", INTEGER, "0", "",                                    \
      "vertex copies a step may make, the rest wait; 0 = default 256")                                                 \
    X(TEARING_SHATTER, "tearing.shatter", BOOL, "false", "",                                                           \
      "true: every bond past its limit breaks at once; false: bonds break as cracks that run from their tips")         \
    X(CONTACT_THICKNESS, "contact.thickness", NUMBER, "0", "m",                                                        \
      "m, >= 0: added to every collider's own thickness; the distance self-contact keeps between surfaces; "           \
      "refused above the body's extent (its bounding box's diagonal), as is a collider's own thickness")               \
    X(SELF_COLLISION, "self_collision", BOOL, "false", "",                                                             \
      "the bodies' triangles against each other: folds of one body, bodies of a multi-object mesh (needs "             \
      "contact.thickness > 0)")                                                                                        \
    X(HAPTICS_DEVICE, "haptics.device", STRING, "none", "",                                                            \
      "the haptic device: none, scripted (haptics.file), udp (haptics.port) or mouse (softbond view: the "             \
      "pointer drives the tool); docs/haptics.md")                                                                     \
    X(HAPTICS_FILE, "haptics.file", STRING, "''", "",                                                                  \
      "scripted: the CSV trajectory (time,x,y,z[,qw,qx,qy,qz][,button]), relative to the scene")                       \
    X(HAPTICS_PORT, "haptics.port", INTEGER, "47000", "", "udp: the port on 127.0.0.1 poses arrive at")                \
    X(HAPTICS_RATE, "haptics.rate", NUMBER, "1000", "Hz", "the servo thread's rate, Hz")                               \
    X(HAPTICS_TOOL, "haptics.tool", STRING, "''", "",                                                                  \
      "the collider the device drives (not a plane, not dynamic); '' = no haptics")                                    \
    X(HAPTICS_COUPLING_STIFFNESS, "haptics.coupling.stiffness", NUMBER, "700", "N/m",                                  \
      "the virtual coupling's stiffness, N/m (at most the device's 700)")                                              \
    X(HAPTICS_COUPLING_DAMPING, "haptics.coupling.damping", NUMBER, "0.7", "N s/m",                                    \
      "the virtual coupling's damping, N s/m (> stiffness / rate / 2)")                                                \
    X(HAPTICS_MAX_FORCE, "haptics.max_force", NUMBER, "3.3", "N",                                                      \
      "the force sent to the device is clamped to this, N (at most the device's 3.3)")                                 \
    X(HAPTICS_WORKSPACE, "haptics.workspace", NUMBER, "0.5", "m",                                                      \
      "the device's reach about its origin, m: a pose outside is a device fault (the force ramps down)")               \
    X(HAPTICS_HAND_SPEED, "haptics.hand_speed", NUMBER, "10", "m/s",                                                   \
      "the fastest a hand moves the device, m/s: a faster jump is a device fault")                                     \
    X(HAPTICS_REALTIME, "haptics.realtime", BOOL, "true", "",                                                          \
      "pace the simulation to the wall clock while the servo runs; false = as fast as it can")                         \
    X(INTEGRATOR, "integrator", STRING, "verlet", "",                                                                  \
      "verlet, velocity_verlet, position_verlet, symplectic_euler, explicit_euler, "                                   \
      "implicit_euler, pbd, xpbd or vbd")                                                                              \
    X(ADAPTIVE, "adaptive", BOOL, "false", "",                                                                         \
      "energy-stable adaptive sub-steps: a sub-step that gains energy is retried at half the size")                    \
    X(MIN_DT, "min_dt", NUMBER, "1e-9", "s", "adaptive: the smallest sub-step, s")                                     \
    X(IMPLICIT_TOLERANCE, "implicit.tolerance", NUMBER, "1e-8", "1",                                                   \
      "implicit_euler: Newton stops at this fraction of the first residual")                                           \
    X(IMPLICIT_NEWTON_ITERATIONS, "implicit.newton_iterations", INTEGER, "20", "",                                     \
      "implicit_euler: Newton iterations per step, at most")                                                           \
    X(IMPLICIT_CG_ITERATIONS, "implicit.cg_iterations", INTEGER, "200", "",                                            \
      "implicit_euler: conjugate-gradient iterations per Newton iteration, at most")                                   \
    X(IMPLICIT_SOLVER, "implicit.solver", STRING, "auto", "",                                                          \
      "implicit_euler's linear solves: cholesky (a sparse factorization), cg, or auto (cholesky up to 20000 "          \
      "vertices where the stiffness outweighs the mass a hundredfold)")                                                \
    X(IMPLICIT_DEFINITE, "implicit.definite", BOOL, "false", "",                                                       \
      "implicit_euler: each element's stiffness replaced by a positive semi-definite stand-in")                        \
    X(PBD_ITERATIONS, "pbd.iterations", INTEGER, "10", "", "pbd, xpbd: constraint projection sweeps per step")         \
    X(VBD_ITERATIONS, "vbd.iterations", INTEGER, "10", "", "vbd: Gauss-Seidel sweeps over the vertex colors per step") \
    X(VBD_CHEBYSHEV_RHO, "vbd.chebyshev_rho", NUMBER, "0", "1",                                                        \
      "vbd: Chebyshev acceleration across the sweeps, the spectral radius estimate in [0, 1); 0 = off")                \
    X(VBD_RELAXATION, "vbd.relaxation", NUMBER, "1", "1",                                                              \
      "vbd: over-relaxation of each vertex's Newton step, in (0, 2); 1 = plain steps")                                 \
    X(DT, "dt", NUMBER, "0.0001", "s", "time step, s")                                                                 \
    X(DURATION, "duration", NUMBER, "1", "s", "simulated time, s")                                                     \
    X(STOP_KINETIC_ENERGY, "stop.kinetic_energy", NUMBER, "0", "J",                                                    \
      "J: stop when the total kinetic energy falls below it (not before stop.min_time); 0 = never")                    \
    X(STOP_MIN_TIME, "stop.min_time", NUMBER, "0", "s", "s: no kinetic-energy stop before this time")                  \
    X(STOP_MAX_TIME, "stop.max_time", NUMBER, "0", "s",                                                                \
      "s: the watchdog, the run ends here at the latest; 0 = the duration")                                            \
    X(FRAME_INTERVAL, "frame_interval", NUMBER, "0.04", "s", "simulated time between frames, s (>= dt)")               \
    X(THREADS, "threads", INTEGER, "0", "", "solver threads; 0 = SOFTBOND_THREADS or the runtime's default")           \
    X(WAIT, "wait", STRING, "passive", "",                                                                             \
      "how solver threads wait at barriers: spin (a dedicated machine), yield, passive (cores shared)")                \
    X(PIN_THREADS, "pin_threads", BOOL, "false", "", "bind solver thread i to core i (hwloc)")                         \
    X(ADAPTIVE_THREADS, "adaptive_threads", BOOL, "true", "",                                                          \
      "let a step run on one thread while that measures faster than all threads (a busy machine); false: always "      \
      "all threads")                                                                                                   \
    X(KERNELS, "kernels", STRING, "fast", "",                                                                          \
      "fast (SIMD, the solver's threads; tested against the reference) or reference (double scalar, for checking)")    \
    X(OUTPUT_FRAMES, "output.frames", BOOL, "true", "", "write frames (output.formats); false writes log.csv only")    \
    X(OUTPUT_FORMATS, "output.formats", NAMES, "[vtu]", "",                                                            \
      "frame formats, a list or joined by commas: vtu (with frames.pvd), ply, obj, gltf, glb, "                        \
      "irit, pov")                                                                                                     \
    X(OUTPUT_VTU, "output.vtu", STRING, "ascii", "",                                                                   \
      "how .vtu frames hold their arrays: ascii (text), binary (appended raw bytes) or zlib (appended, "               \
      "zlib-compressed: smaller, slower to write)")

typedef enum sb_scene_key {
#define SB_SCENE_KEY_ENUM(id, name, type, def, unit, meaning) SB_KEY_##id,
    SB_SCENE_KEYS(SB_SCENE_KEY_ENUM)
#undef SB_SCENE_KEY_ENUM
        SB_KEY_COUNT
} sb_scene_key;

typedef struct sb_scene_key_info {
    const char* name;
    sb_scene_type type;
    const char* default_value; /* YAML text */
    const char* unit;          /* SI; "1" a ratio; "" none */
    const char* meaning;
} sb_scene_key_info;

/* A key of the maps in a list (`colliders`, `handles`, `blades`): each
 * loader keeps one table of them, reads the names from it and hands it to
 * `softbond keys` (sb_scene_collider_keys, sb_scene_handle_keys,
 * sb_scene_blade_keys), which prints it as `colliders[].radius` ... */
#define SB_ENTRY_REQUIRED "required" /* the default_value of a key an entry must have */
typedef struct sb_entry_key {
    const char* name;
    sb_scene_type type;
    const char* default_value; /* YAML text, a description ("<type><index>"), or SB_ENTRY_REQUIRED */
    const char* unit;          /* SI; "1" a ratio; "" none */
    unsigned shapes;           /* colliders: bit (1u << sb_collider_shape) of each shape that takes it; else 0 */
    const char* meaning;
} sb_entry_key;

const sb_scene_key_info* sb_scene_key_get(sb_scene_key key);
/* Returns false when no key has this dotted name. */
bool sb_scene_key_find(const char* name, sb_scene_key* out);

typedef struct sb_scene_value {
    double number;
    int64_t integer;
    bool boolean;
    double vec3[3];
    char* string;
    uint32_t* indices;
    uint32_t index_count;
    sb_scene_tree* tree; /* SB_SCENE_LIST: the value as read, with the line of every node */
    char where[320];     /* "scene.yaml:12", "--set k=v"; empty for the default */
    char* base_dir;      /* directory a relative path in this value is relative to */
} sb_scene_value;

typedef struct sb_scene {
    char* path; /* the scene file, NULL when none was loaded */
    char* name; /* its file name without directory and extension */
    sb_scene_value values[SB_KEY_COUNT];
} sb_scene;

/* Every key at its default. Fails only when out of memory. */
sb_status sb_scene_init(sb_scene* scene, sb_error* err);
void sb_scene_free(sb_scene* scene);

/* Reads a scene file over the current values. Errors: "PATH:LINE: ...". */
sb_status sb_scene_load(sb_scene* scene, const char* path, sb_error* err);
/* Applies one "key=value" (the value a YAML scalar, flow sequence or flow
 * map); a later --set wins over the file and over earlier --sets. */
sb_status sb_scene_set(sb_scene* scene, const char* assignment, sb_error* err);
/* Checks values and their combinations: dt > 0, constants finite and >= 0,
 * known names, ... Errors name where the offending value was set. */
sb_status sb_scene_validate(const sb_scene* scene, sb_error* err);

/* Defaults, then the file (when path is not NULL), then every set
 * ("key=value", in order), then the checks: a scene as a run uses it. On
 * failure the scene is freed. */
sb_status sb_scene_read(sb_scene* scene, const char* path, const char* const* sets, size_t set_count, sb_error* err);

double sb_scene_number(const sb_scene* scene, sb_scene_key key);
int64_t sb_scene_integer(const sb_scene* scene, sb_scene_key key);
bool sb_scene_bool(const sb_scene* scene, sb_scene_key key);
const char* sb_scene_string(const sb_scene* scene, sb_scene_key key);
const double* sb_scene_vec3(const sb_scene* scene, sb_scene_key key);
const uint32_t* sb_scene_indices(const sb_scene* scene, sb_scene_key key, uint32_t* count);
/* An SB_SCENE_LIST value: the sequence as read (root), and its source. */
const sb_scene_tree* sb_scene_tree_value(const sb_scene* scene, sb_scene_key key);

/* Where a key was set: "file:line", "--set k=v", or the scene file (NULL
 * without one) for a default. */
const char* sb_scene_where(const sb_scene* scene, sb_scene_key key);
/* Formats "WHERE: message" into err, WHERE being where key was set (the
 * message alone when there is no WHERE); returns SB_ERR_INVALID. */
sb_status sb_scene_fail(const sb_scene* scene, sb_scene_key key, sb_error* err, const char* format, ...)
    __attribute__((format(printf, 4, 5)));

/* Writes every key with its value now as YAML the loader reads back to the
 * same values (scene_write.c): nested maps, numbers to 17 digits, the
 * lists in block style, the paths made absolute. */
void sb_scene_write(const sb_scene* scene, FILE* stream);

/* A path value made usable: relative paths are joined to the directory of
 * the file that set it (the current directory for --set). Caller frees. */
char* sb_scene_path(const sb_scene* scene, sb_scene_key key);

#endif
