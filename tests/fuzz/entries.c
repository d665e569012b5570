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
 *   assimp_ply     sb_mesh_load_ex of a .ply file: the PLY check, then
 *                  assimp in its isolated child */
#define _POSIX_C_SOURCE 200809L
#include "tests/fuzz/entries.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scenes/positions_csv.h"
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
    {"assimp_ply", assimp_ply},
};
const size_t sb_fuzz_entry_count = sizeof sb_fuzz_entries / sizeof sb_fuzz_entries[0];

const sb_fuzz_entry* sb_fuzz_entry_find(const char* name) {
    for (size_t i = 0; i < sb_fuzz_entry_count; i++)
        if (strcmp(sb_fuzz_entries[i].name, name) == 0) return &sb_fuzz_entries[i];
    return NULL;
}
