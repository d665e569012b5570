/* The entries (see entries.h). Each writes the bytes to a file with the
 * parser's extension in a temporary folder of its own (made on first use,
 * removed at exit) and calls what `softbond` calls for such a file:
 *
 *   scene_yaml     sb_scene_load, then sb_scene_validate (a scene file)
 *   scene_set      sb_scene_set of the bytes up to the first NUL as
 *                  key=value, then sb_scene_validate (a --set)
 *   obj, off       sb_mesh_load_ex, merged and separate
 *   irit, pov      sb_mesh_load_ex, merged and separate
 *   tetgen         the bytes up to "@@\n" as .node, the rest as .ele:
 *                  sb_tet_mesh_load, sb_tet_mesh_check, sb_tet_mesh_surface
 *   gmsh           the same for a .msh file
 *   positions_csv  sb_positions_read for a mesh of 4 vertices
 *   haptics_csv    sb_haptic_device_open of a scripted trajectory, then
 *                  five reads
 *   assimp_ply     sb_mesh_load_ex of a .ply file: the PLY check, then
 *                  assimp in its isolated child
 *   checkpoint     sb_checkpoint_read (`softbond run --resume`) of the bytes
 *                  into a new solver of a small rig (a breakable 4 x 4
 *                  sheet, a floor, a dynamic ball, a hard and a soft
 *                  handle: every section of the solver's state), then
 *                  again with the checksums of the solver's state and of
 *                  the file made to match, so that mutations reach the
 *                  sections behind them; its seed is the rig's checkpoint
 *                  (sb_checkpoint_write, scene hash CHECKPOINT_SCENE_HASH)
 *                  after 20 steps of 0.1 ms with the hard handle driven
 *                  5 cm away (sb_handle_set_pose): 7 bonds broken */
#define _POSIX_C_SOURCE 200809L
#include "tests/fuzz/entries.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/sections.h"
#include "cli/checkpoint.h"
#include "cli/positions_csv.h"
#include "scenes/scene.h"
#include "softbond/softbond.h"

static char folder[256];

static void remove_folder(void) {
    char command[300];
    snprintf(command, sizeof command, "rm -rf '%s'", folder);
    if (system(command) != 0) fprintf(stderr, "sb_fuzz: cannot remove %s\n", folder);
}

/* folder/input<extension>, holding data; NULL when it cannot be written. */
static const char* write_input(const char* extension, const uint8_t* data, size_t size) {
    static char path[300];
    if (!folder[0]) {
        const char* base = getenv("TMPDIR");
        snprintf(folder, sizeof folder, "%s/sb_fuzz_XXXXXX", base && *base ? base : "/tmp");
        if (!mkdtemp(folder)) return NULL;
        atexit(remove_folder);
    }
    snprintf(path, sizeof path, "%s/input%s", folder, extension);
    FILE* f = fopen(path, "wb");
    if (!f) return NULL;
    bool written = fwrite(data, 1, size, f) == size;
    return fclose(f) == 0 && written ? path : NULL;
}

static int scene_yaml(const uint8_t* data, size_t size) {
    const char* path = write_input(".yaml", data, size);
    sb_scene scene;
    sb_error err;
    if (!path || sb_scene_init(&scene, &err) != SB_OK) return 0;
    if (sb_scene_load(&scene, path, &err) == SB_OK) sb_scene_validate(&scene, &err);
    sb_scene_free(&scene);
    return 0;
}

static int scene_set(const uint8_t* data, size_t size) {
    char* text = strndup((const char*)data, size);
    sb_scene scene;
    sb_error err;
    if (text && sb_scene_init(&scene, &err) == SB_OK) {
        if (sb_scene_set(&scene, text, &err) == SB_OK) sb_scene_validate(&scene, &err);
        sb_scene_free(&scene);
    }
    free(text);
    return 0;
}

static void load_surface(const char* path, bool separate) {
    sb_mesh_load_def def = sb_default_mesh_load_def();
    def.separate_objects = separate;
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    sb_error err;
    if (path && sb_mesh_load_ex(path, &def, &objects, &count, NULL, &err) == SB_OK)
        sb_mesh_objects_free(objects, count);
}

static int surface_both_ways(const char* extension, const uint8_t* data, size_t size) {
    const char* path = write_input(extension, data, size);
    load_surface(path, false);
    load_surface(path, true);
    return 0;
}

static int obj(const uint8_t* data, size_t size) { return surface_both_ways(".obj", data, size); }
static int off(const uint8_t* data, size_t size) { return surface_both_ways(".off", data, size); }
static int irit(const uint8_t* data, size_t size) { return surface_both_ways(".itd", data, size); }
static int pov(const uint8_t* data, size_t size) { return surface_both_ways(".pov", data, size); }

/* The scripted haptic device's trajectory (common/csv.h's tokenizer, as
 * positions_csv), opened and read at a few times. */
static int haptics_csv(const uint8_t* data, size_t size) {
    const char* path = write_input(".csv", data, size);
    if (!path) return 0;
    sb_haptic_device_def def = sb_default_haptic_device_def();
    def.kind = "scripted";
    def.file = path;
    sb_error err;
    sb_haptic_device* device = sb_haptic_device_open(&def, &err);
    if (device) {
        sb_haptic_pose pose;
        for (int k = -1; k < 4; k++) sb_haptic_device_read(device, 0.5 * k, &pose);
        sb_haptic_device_close(device);
    }
    return 0;
}

static int assimp_ply(const uint8_t* data, size_t size) {
    load_surface(write_input(".ply", data, size), false);
    return 0;
}

static void load_volume(const char* path) {
    sb_tet_mesh volume;
    sb_mesh surface;
    sb_error err;
    if (!path || sb_tet_mesh_load(path, &volume, &err) != SB_OK) return;
    if (sb_tet_mesh_check(&volume, &err) == SB_OK && sb_tet_mesh_surface(&volume, &surface, &err) == SB_OK)
        sb_mesh_free(&surface);
    sb_tet_mesh_free(&volume);
}

static int tetgen(const uint8_t* data, size_t size) {
    const uint8_t* split = NULL;
    for (size_t i = 0; i + 3 <= size && !split; i++)
        if (memcmp(data + i, "@@\n", 3) == 0) split = data + i;
    size_t node_size = split ? (size_t)(split - data) : size;
    const uint8_t* ele = split ? split + 3 : data + size;
    if (!write_input(".ele", ele, (size_t)(data + size - ele))) return 0;
    load_volume(write_input(".node", data, node_size));
    return 0;
}

static int gmsh(const uint8_t* data, size_t size) {
    load_volume(write_input(".msh", data, size));
    return 0;
}

static int positions_csv(const uint8_t* data, size_t size) {
    const char* path = write_input(".csv", data, size);
    double positions[12];
    sb_error err;
    if (path) sb_positions_read(path, 4, positions, &err);
    return 0;
}

/* ---- checkpoint ---------------------------------------------------------- */

enum { CHECKPOINT_SIDE = 4, CHECKPOINT_FRAMES = 100 };
#define CHECKPOINT_SCENE_HASH 0x5eedull

/* A solver with every kind of state, and what it owns. */
typedef struct checkpoint_rig {
    sb_model* model;
    sb_collider* colliders[2];
    sb_handle* handles[2];
    uint32_t rows[2][CHECKPOINT_SIDE];
    sb_solver* solver;
} checkpoint_rig;

static void checkpoint_rig_free(checkpoint_rig* r) {
    sb_solver_destroy(r->solver);
    for (int k = 0; k < 2; k++) {
        sb_collider_destroy(r->colliders[k]);
        sb_handle_destroy(r->handles[k]);
    }
    sb_model_destroy(r->model);
}

static sb_model* checkpoint_sheet(void) {
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = def.ny = CHECKPOINT_SIDE;
    sb_mesh mesh = {0};
    sb_error err;
    if (sb_mesh_generate_sheet(&def, &mesh, &err) != SB_OK) return NULL;
    sb_material_def material = sb_default_material_def();
    material.break_strain = 0.05;
    sb_builder* builder = sb_builder_create();
    sb_model* model =
        sb_builder_add_mesh(builder, &mesh, &material, &err) == SB_OK ? sb_builder_compile(builder, &err) : NULL;
    sb_builder_destroy(builder);
    sb_mesh_free(&mesh);
    return model;
}

static sb_handle* checkpoint_handle(checkpoint_rig* r, int k, double stiffness) {
    for (uint32_t i = 0; i < CHECKPOINT_SIDE; i++)
        r->rows[k][i] = (uint32_t)k * (CHECKPOINT_SIDE - 1) * CHECKPOINT_SIDE + i;
    sb_handle_def def = sb_default_handle_def();
    def.vertices = r->rows[k];
    def.vertex_count = CHECKPOINT_SIDE;
    def.stiffness = stiffness;
    sb_error err;
    return sb_handle_create(&def, &err);
}

/* The rig; false when it could not be made. */
static bool checkpoint_rig_create(checkpoint_rig* r) {
    *r = (checkpoint_rig){.model = checkpoint_sheet()};
    sb_collider_def floor = sb_default_collider_def(), ball = sb_default_collider_def();
    floor.shape = SB_COLLIDER_PLANE;
    floor.normal[2] = 1.0;
    floor.point[2] = -0.01;
    ball.shape = SB_COLLIDER_SPHERE;
    ball.radius = 0.1;
    ball.center[2] = 0.2;
    ball.mass = 1.0;
    sb_error err;
    r->colliders[0] = sb_collider_create(&floor, &err);
    r->colliders[1] = sb_collider_create(&ball, &err);
    r->handles[0] = checkpoint_handle(r, 0, 0.0);
    r->handles[1] = checkpoint_handle(r, 1, 10.0);
    if (!r->model || !r->colliders[0] || !r->colliders[1] || !r->handles[0] || !r->handles[1]) return false;
    sb_solver_def def = sb_default_solver_def();
    def.runtime.threads = 1;
    def.colliders = r->colliders;
    def.collider_count = 2;
    def.handles = r->handles;
    def.handle_count = 2;
    return (r->solver = sb_solver_create(r->model, &def, &err)) != NULL;
}

/* The last 8 bytes of a sections file made the checksum of the rest. */
static void reseal(uint8_t* data, size_t size) {
    if (size < 24) return;
    uint64_t sum = sb_hash(SB_HASH_START, data, size - 24);
    memcpy(data + size - 8, &sum, sizeof sum);
}

/* The solver state inside, then the whole file. */
static void reseal_checkpoint(uint8_t* data, size_t size) {
    sb_sections_reader r = {.data = data, .size = size};
    sb_cursor state;
    if (sb_sections_find(&r, "SOLV", &state)) reseal(data + (state.at - data), state.left);
    reseal(data, size);
}

static void read_checkpoint(const uint8_t* data, size_t size) {
    const char* path = write_input(".sbck", data, size);
    checkpoint_rig rig;
    sb_run_state run;
    sb_error err;
    if (checkpoint_rig_create(&rig) && path &&
        sb_checkpoint_read(path, CHECKPOINT_SCENE_HASH, CHECKPOINT_SIDE * CHECKPOINT_SIDE, CHECKPOINT_FRAMES, &run,
                           rig.solver, &err) == SB_OK)
        free(run.times);
    checkpoint_rig_free(&rig);
}

static int checkpoint(const uint8_t* data, size_t size) {
    read_checkpoint(data, size);
    uint8_t* copy = malloc(size ? size : 1);
    if (!copy) return 0;
    memcpy(copy, data, size);
    reseal_checkpoint(copy, size);
    read_checkpoint(copy, size);
    free(copy);
    return 0;
}

const sb_fuzz_entry sb_fuzz_entries[] = {
    {"scene_yaml", scene_yaml},
    {"scene_set", scene_set},
    {"obj", obj},
    {"off", off},
    {"irit", irit},
    {"pov", pov},
    {"tetgen", tetgen},
    {"gmsh", gmsh},
    {"positions_csv", positions_csv},
    {"haptics_csv", haptics_csv},
    {"assimp_ply", assimp_ply},
    {"checkpoint", checkpoint},
};
const size_t sb_fuzz_entry_count = sizeof sb_fuzz_entries / sizeof sb_fuzz_entries[0];

const sb_fuzz_entry* sb_fuzz_entry_find(const char* name) {
    for (size_t i = 0; i < sb_fuzz_entry_count; i++)
        if (strcmp(sb_fuzz_entries[i].name, name) == 0) return &sb_fuzz_entries[i];
    return NULL;
}
