/* The scene loader: defaults, flattening of nested maps into dotted keys,
 * --set overrides, relative mesh paths, validation, pins, the exact
 * one-line message of every error kind (file and line, or --set), and the
 * collider definitions a `colliders` list builds (its malformed entries are
 * run through the program in test_cli.c). Scene files are written by the
 * tests into a fresh temporary directory. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <unistd.h>

#include "tests/test_util.h"
#include "scenes/colliders.h"
#include "scenes/scene.h"
#include "scenes/scene_model.h"

static char tmp_dir[256];
static char tmp_files[64][320];
static int tmp_count;

static int setup_dir(void** state) {
    (void)state;
    const char* base = getenv("TMPDIR");
    snprintf(tmp_dir, sizeof tmp_dir, "%s/sb_test_scene_XXXXXX", base && *base ? base : "/tmp");
    return mkdtemp(tmp_dir) ? 0 : -1;
}

static int teardown_dir(void** state) {
    (void)state;
    for (int i = 0; i < tmp_count; i++) remove(tmp_files[i]);
    return rmdir(tmp_dir);
}

/* Writes text to tmp_dir/name; returns the path (valid until teardown). */
static const char* write_file(const char* name, const char* text) {
    assert_true(tmp_count < 64);
    char* path = tmp_files[tmp_count++];
    snprintf(path, sizeof tmp_files[0], "%s/%s", tmp_dir, name);
    FILE* f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    return path;
}

/* Loads text as a scene file over the defaults; returns the status. */
static sb_status load_text(sb_scene* scene, const char* name, const char* text, sb_error* err) {
    assert_int_equal(sb_scene_init(scene, err), SB_OK);
    return sb_scene_load(scene, write_file(name, text), err);
}

/* The expected message for a file error: "<tmp_dir>/<name>:<rest>". */
static void assert_file_error(const sb_error* err, const char* name, const char* rest) {
    char expected[600];
    snprintf(expected, sizeof expected, "%s/%s:%s", tmp_dir, name, rest);
    assert_string_equal(err->message, expected);
}

/* A scene file that fails to load, with its exact message. */
static void assert_load_fails(const char* name, const char* text, const char* rest) {
    sb_scene scene;
    sb_error err;
    sb_status status = load_text(&scene, name, text, &err);
    if (status == SB_OK) status = sb_scene_validate(&scene, &err);
    assert_int_not_equal(status, SB_OK);
    assert_file_error(&err, name, rest);
    sb_scene_free(&scene);
}

/* ---- defaults, flattening, --set ------------------------------------------ */

static void test_defaults_are_valid_and_from_nowhere(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    assert_string_equal(sb_scene_string(&scene, SB_KEY_MESH_GENERATOR), "sheet");
    assert_string_equal(sb_scene_string(&scene, SB_KEY_MESH_FILE), "");
    assert_int_equal(sb_scene_integer(&scene, SB_KEY_MESH_NX), 10);
    TU_ASSERT_NEAR(sb_scene_number(&scene, SB_KEY_DT), 1e-4, 0.0);
    TU_ASSERT_NEAR(sb_scene_vec3(&scene, SB_KEY_GRAVITY)[2], -9.81, 0.0);
    assert_true(sb_scene_bool(&scene, SB_KEY_OUTPUT_FRAMES));
    uint32_t count = 99;
    sb_scene_indices(&scene, SB_KEY_FIXED, &count);
    assert_int_equal(count, 0);
    for (int k = 0; k < SB_KEY_COUNT; k++) assert_null(sb_scene_where(&scene, (sb_scene_key)k));
    sb_scene_free(&scene);
}

static void test_key_table_names_are_unique(void** state) {
    (void)state;
    for (int k = 0; k < SB_KEY_COUNT; k++) {
        sb_scene_key found;
        assert_true(sb_scene_key_find(sb_scene_key_get((sb_scene_key)k)->name, &found));
        assert_int_equal(found, k);
    }
    sb_scene_key found;
    assert_false(sb_scene_key_find("bond", &found));
}

static void test_nested_maps_flatten_to_dotted_keys(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    const char* text = "mesh:\n"
                       "  generator: icosphere\n"
                       "  subdivisions: 1\n"
                       "bond: {k: 250.5}\n"
                       "spring.k: 7\n"
                       "spring:\n"
                       "  damping: 0.25\n"
                       "gravity: [1, -2, 3.5]\n"
                       "fixed: [4, 0, 2]\n"
                       "output: {frames: false}\n";
    assert_int_equal(load_text(&scene, "nested.yaml", text, &err), SB_OK);
    assert_string_equal(sb_scene_string(&scene, SB_KEY_MESH_GENERATOR), "icosphere");
    assert_int_equal(sb_scene_integer(&scene, SB_KEY_MESH_SUBDIVISIONS), 1);
    TU_ASSERT_NEAR(sb_scene_number(&scene, SB_KEY_BOND_K), 250.5, 0.0);
    TU_ASSERT_NEAR(sb_scene_number(&scene, SB_KEY_SPRING_K), 7.0, 0.0);
    TU_ASSERT_NEAR(sb_scene_number(&scene, SB_KEY_SPRING_DAMPING), 0.25, 0.0);
    const double* g = sb_scene_vec3(&scene, SB_KEY_GRAVITY);
    assert_true(g[0] == 1.0 && g[1] == -2.0 && g[2] == 3.5);
    uint32_t count;
    const uint32_t* fixed = sb_scene_indices(&scene, SB_KEY_FIXED, &count);
    assert_int_equal(count, 3);
    assert_true(fixed[0] == 4 && fixed[1] == 0 && fixed[2] == 2);
    assert_false(sb_scene_bool(&scene, SB_KEY_OUTPUT_FRAMES));
    /* untouched keys keep their defaults */
    TU_ASSERT_NEAR(sb_scene_number(&scene, SB_KEY_MESH_RADIUS), 1.0, 0.0);
    assert_string_equal(scene.name, "nested");
    char where[400];
    snprintf(where, sizeof where, "%s/nested.yaml:4", tmp_dir);
    assert_string_equal(sb_scene_where(&scene, SB_KEY_BOND_K), where);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    sb_scene_free(&scene);
}

static void test_set_overrides_file_and_earlier_sets(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    assert_int_equal(load_text(&scene, "set.yaml", "bond:\n  k: 5\ndt: 0.001\n", &err), SB_OK);
    assert_int_equal(sb_scene_set(&scene, "bond.k=12", &err), SB_OK);
    TU_ASSERT_NEAR(sb_scene_number(&scene, SB_KEY_BOND_K), 12.0, 0.0);
    assert_string_equal(sb_scene_where(&scene, SB_KEY_BOND_K), "--set bond.k=12");
    assert_int_equal(sb_scene_set(&scene, "bond={k: 13, }", &err), SB_OK);
    TU_ASSERT_NEAR(sb_scene_number(&scene, SB_KEY_BOND_K), 13.0, 0.0);
    assert_int_equal(sb_scene_set(&scene, "gravity=[0,0,-1]", &err), SB_OK);
    TU_ASSERT_NEAR(sb_scene_vec3(&scene, SB_KEY_GRAVITY)[2], -1.0, 0.0);
    assert_int_equal(sb_scene_set(&scene, "pin=left_edge", &err), SB_OK);
    assert_string_equal(sb_scene_string(&scene, SB_KEY_PIN), "left_edge");
    assert_int_equal(sb_scene_set(&scene, "fixed=[1,2]", &err), SB_OK);
    assert_int_equal(sb_scene_set(&scene, "fixed=[3]", &err), SB_OK);
    uint32_t count;
    assert_int_equal(sb_scene_indices(&scene, SB_KEY_FIXED, &count)[0], 3);
    assert_int_equal(count, 1);
    TU_ASSERT_NEAR(sb_scene_number(&scene, SB_KEY_DT), 0.001, 0.0);
    sb_scene_free(&scene);
}

static void test_mesh_file_is_relative_to_the_scene(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    write_file("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const char* text = "mesh: {generator: file, file: tri.obj}\n";
    assert_int_equal(load_text(&scene, "rel.yaml", text, &err), SB_OK);
    char* path = sb_scene_path(&scene, SB_KEY_MESH_FILE);
    char expected[400];
    snprintf(expected, sizeof expected, "%s/tri.obj", tmp_dir);
    assert_string_equal(path, expected);
    free(path);
    sb_mesh mesh = {0};
    assert_int_equal(sb_scene_make_mesh(&scene, &mesh, &err), SB_OK);
    assert_int_equal(mesh.vertex_count, 3);
    sb_mesh_free(&mesh);
    /* a --set path is relative to the current directory */
    assert_int_equal(sb_scene_set(&scene, "mesh.file=sub/x.obj", &err), SB_OK);
    path = sb_scene_path(&scene, SB_KEY_MESH_FILE);
    assert_string_equal(path, "sub/x.obj");
    free(path);
    sb_scene_free(&scene);
}

/* ---- errors: one line naming file and line ------------------------------------ */

static void test_unknown_keys(void** state) {
    (void)state;
    /* the nearest known key is suggested when it is one edit away (two for names of 5 or more) */
    assert_load_fails("unknown.yaml", "dt: 0.001\nbond:\n  kk: 1\n",
                      "3: unknown key 'bond.kk' (did you mean 'bond.k'?)");
    assert_load_fails("unknown2.yaml", "bnd.k: 1\n", "1: unknown key 'bnd.k' (did you mean 'bond.k'?)");
    assert_load_fails("unknown3.yaml", "mesh: {}\n", "1: unknown key 'mesh'");
    assert_load_fails("swapped.yaml", "mesh:\n  nx: 4\n  yn: 3\n",
                      "3: unknown key 'mesh.yn' (did you mean 'mesh.ny'?)");
    assert_load_fails("far.yaml", "stiffness: 1\n", "1: unknown key 'stiffness'");
    assert_load_fails("entry.yaml", "colliders:\n  - {type: sphere, raduis: 0.1}\n",
                      "2: unknown key 'colliders[0].raduis' (did you mean 'colliders[0].radius'?)");
}

static void test_wrong_types(void** state) {
    (void)state;
    assert_load_fails("type1.yaml", "\ndt: fast\n", "2: 'dt' expects a number, got 'fast'");
    assert_load_fails("type2.yaml", "mesh:\n  nx: 2.5\n", "2: 'mesh.nx' expects an integer, got '2.5'");
    assert_load_fails("type3.yaml", "output:\n  frames: maybe\n",
                      "2: 'output.frames' expects true or false, got 'maybe'");
    assert_load_fails("type4.yaml", "gravity: [0, 0]\n",
                      "1: 'gravity' expects 3 numbers: [x, y, z] or x,y,z, got a sequence of 2");
    assert_load_fails("type5.yaml", "gravity:\n  - 0\n  - x\n  - 1\n", "3: 'gravity' expects a number, got 'x'");
    assert_load_fails("type6.yaml", "fixed: [1, -2]\n",
                      "1: 'fixed' expects a vertex index (an integer >= 0), got '-2'");
    assert_load_fails("type7.yaml", "bond: {k: [1]}\n", "1: 'bond.k' expects a number, got a sequence of 1");
    assert_load_fails("type8.yaml", "dt: '0.1'\n", "1: 'dt' expects a number, got '0.1'");
    assert_load_fails("type9.yaml", "pin: {a: 1}\n", "1: 'pin' expects a string, got a map");
}

static void test_duplicate_keys(void** state) {
    (void)state;
    assert_load_fails("dup1.yaml", "dt: 0.1\ndt: 0.2\n", "2: duplicate key 'dt' (first set at line 1)");
    assert_load_fails("dup2.yaml", "bond: {k: 1}\nangle.k: 1\nbond.k: 2\n",
                      "3: duplicate key 'bond.k' (first set at line 1)");
}

static void test_malformed_yaml(void** state) {
    (void)state;
    assert_load_fails("bad1.yaml", "dt: 0.1\ngravity: [0, 0\n", "3: malformed YAML: did not find expected ',' or ']'");
    assert_load_fails("bad2.yaml", "- dt\n- 0.1\n", "1: a scene must be a map of keys");
    assert_load_fails("bad3.yaml", "dt: 0.1\n---\ndt: 0.2\n", "3: a scene file holds one YAML document");
    assert_load_fails("bad4.yaml", "dt: 0.1\n  bond: 3\n",
                      "2: malformed YAML: mapping values are not allowed in this context");
}

static void test_missing_file(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    assert_int_equal(sb_scene_load(&scene, "/nonexistent/scene.yaml", &err), SB_ERR_IO);
    assert_string_equal(err.message, "/nonexistent/scene.yaml: cannot open: No such file or directory");
    sb_scene_free(&scene);
}

static void assert_set_fails(const char* assignment, const char* message) {
    sb_scene scene;
    sb_error err;
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    sb_status status = sb_scene_set(&scene, assignment, &err);
    if (status == SB_OK) status = sb_scene_validate(&scene, &err);
    assert_int_not_equal(status, SB_OK);
    assert_string_equal(err.message, message);
    sb_scene_free(&scene);
}

static void test_set_errors_name_the_set(void** state) {
    (void)state;
    assert_set_fails("bond.kk=1", "--set bond.kk=1: unknown key 'bond.kk' (did you mean 'bond.k'?)");
    assert_set_fails("dt=abc", "--set dt=abc: 'dt' expects a number, got 'abc'");
    assert_set_fails("gravity=[0,0", "--set gravity=[0,0: malformed value: did not find expected ',' or ']'");
    assert_set_fails("dt", "--set dt: expected key=value");
    assert_set_fails("=1", "--set =1: expected key=value");
    assert_set_fails("dt=", "--set dt=: missing value after '='");
    assert_set_fails("dt=-1", "--set dt=-1: 'dt' must be > 0, got -1");
}

/* ---- validation ---------------------------------------------------------------- */

static void test_validation_names_where_the_value_was_set(void** state) {
    (void)state;
    assert_load_fails("v1.yaml", "dt: 0\n", "1: 'dt' must be > 0, got 0");
    assert_load_fails("v2.yaml", "duration: 1\nbond.k: -3\n", "2: 'bond.k' must be >= 0, got -3");
    assert_load_fails("v3.yaml", "angle: {k: inf}\n", "1: 'angle.k' must be finite, got inf");
    assert_load_fails("v4.yaml", "dt: 0.01\nframe_interval: 0.001\n",
                      "2: 'frame_interval' (0.001) must be >= 'dt' (0.01)");
    assert_load_fails("v5.yaml", "mass: 0\n", "1: 'mass' and 'density' are both 0: free vertices need a mass");
    assert_load_fails("v6.yaml", "mesh: {generator: cube}\n",
                      "1: 'mesh.generator' must be sheet, icosphere or file, got 'cube'");
    assert_load_fails("v7.yaml", "integrator: rk4\n",
                      "1: 'integrator' must be verlet, velocity_verlet, position_verlet, "
                      "symplectic_euler, explicit_euler, implicit_euler, pbd, xpbd or vbd, got 'rk4'");
    assert_load_fails("v7b.yaml", "adaptive: true\nmin_dt: 0\n", "2: 'min_dt' must be > 0, got 0");
    assert_load_fails("v8.yaml", "kernels: gpu\n", "1: 'kernels' must be reference or fast, got 'gpu'");
    assert_load_fails("v8b.yaml", "implicit:\n  solver: lu\n",
                      "2: 'implicit.solver' must be auto, cg or cholesky, got 'lu'");
    assert_load_fails("v9.yaml", "mesh:\n  generator: file\n",
                      "2: 'mesh.generator' is file but 'mesh.file' is not set");
    assert_load_fails("v10.yaml", "mesh: {nx: 1}\n", "1: 'mesh.nx' must be in [2, 65536], got 1");
    assert_load_fails("v11.yaml", "mesh: {jitter: 0.5}\n", "1: 'mesh.jitter' must be < 0.5");
    assert_load_fails("v12.yaml", "threads: -1\n", "1: 'threads' must be in [0, 1024], got -1");
    assert_load_fails("v13.yaml", "gravity: [0, nan, 0]\n", "1: 'gravity' must be finite");
    assert_load_fails("v14.yaml", "drag: -1\n", "1: 'drag' must be >= 0, got -1");
    assert_load_fails("v15.yaml", "duration: 1\nself_collision: true\n",
                      "2: 'self_collision' needs 'contact.thickness' > 0 (the distance kept between surfaces)");
}

static void test_pin_names(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    assert_int_equal(load_text(&scene, "pin.yaml", "pin: middle\n", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_ERR_INVALID);
    assert_non_null(strstr(err.message, ":1: 'pin' must be one of none, top_corners"));
    assert_non_null(strstr(err.message, "got 'middle'"));
    sb_scene_free(&scene);
}

/* ---- the model: pins and fixed vertices ---------------------------------------- */

/* Builds a 3 x 2 sheet (vertex = row * 3 + column, row along y) with the
 * given settings and returns which vertices are fixed, as a bit mask. */
static unsigned fixed_mask(const char* const* sets, int count) {
    sb_scene scene;
    sb_error err;
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    assert_int_equal(sb_scene_set(&scene, "mesh={nx: 3, ny: 2, width: 2, height: 1}", &err), SB_OK);
    for (int i = 0; i < count; i++) assert_int_equal(sb_scene_set(&scene, sets[i], &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    sb_mesh mesh = {0};
    assert_int_equal(sb_scene_make_mesh(&scene, &mesh, &err), SB_OK);
    sb_model* model = sb_scene_build_model(&scene, &mesh, "sheet", &err);
    assert_non_null(model);
    unsigned mask = 0;
    for (uint32_t v = 0; v < sb_model_vertex_count(model); v++)
        if (sb_model_is_fixed(model, v)) mask |= 1u << v;
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
    sb_scene_free(&scene);
    return mask;
}

static void test_pins_select_by_place(void** state) {
    (void)state;
    /* row 0 (y = 0): 0 1 2; row 1 (y = 1): 3 4 5 */
    assert_int_equal(fixed_mask((const char*[]){"pin=none"}, 1), 0);
    assert_int_equal(fixed_mask((const char*[]){"pin=top_corners"}, 1), (1u << 3) | (1u << 5));
    assert_int_equal(fixed_mask((const char*[]){"pin=bottom_corners"}, 1), (1u << 0) | (1u << 2));
    assert_int_equal(fixed_mask((const char*[]){"pin=left_edge"}, 1), (1u << 0) | (1u << 3));
    assert_int_equal(fixed_mask((const char*[]){"pin=right_edge"}, 1), (1u << 2) | (1u << 5));
    assert_int_equal(fixed_mask((const char*[]){"pin=top_edge"}, 1), 7u << 3);
    assert_int_equal(fixed_mask((const char*[]){"pin=left_corners"}, 1), (1u << 0) | (1u << 3));
    /* a side and its neighbours along the triangles, whichever way the
     * sheet's cells are split: the 3 x 2 sheet's middle column joins both */
    assert_int_equal(fixed_mask((const char*[]){"pin=left_clamp"}, 1), 0x1bu);  /* 0 1 3 4 */
    assert_int_equal(fixed_mask((const char*[]){"pin=right_clamp"}, 1), 0x36u); /* 1 2 4 5 */
    assert_int_equal(fixed_mask((const char*[]){"pin=bottom_clamp"}, 1), 0x3fu);
    assert_int_equal(fixed_mask((const char*[]){"fixed=[1, 4]", "pin=bottom_corners"}, 2),
                     (1u << 0) | (1u << 1) | (1u << 2) | (1u << 4));
}

static void test_fixed_index_out_of_range(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    assert_int_equal(load_text(&scene, "range.yaml", "mesh: {nx: 2, ny: 2}\nfixed: [0, 4]\n", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    sb_mesh mesh = {0};
    assert_int_equal(sb_scene_make_mesh(&scene, &mesh, &err), SB_OK);
    assert_null(sb_scene_build_model(&scene, &mesh, "sheet", &err));
    assert_file_error(&err, "range.yaml", "2: 'fixed': vertex 4 out of range (the mesh has 4 vertices)");
    sb_mesh_free(&mesh);
    sb_scene_free(&scene);
}

static void test_material_and_solver_follow_the_scene(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    const char* text = "bond.k: 3\nangle.k: 0\nstretch_bend.k: 4\nspring: {k: 5, damping: 6}\n"
                       "bend.k: 7\nmass: 8\ndensity: 9\nintegrator: velocity_verlet\n"
                       "kernels: reference\nthreads: 2\ngravity: [1, 2, 3]\ndrag: 0.5\n";
    assert_int_equal(load_text(&scene, "mat.yaml", text, &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    sb_material_def m = sb_scene_material(&scene);
    assert_true(m.bond_k == 3 && m.angle_k == 0 && m.stretch_bend_k == 4 && m.spring_k == 5);
    assert_true(m.spring_damping == 6 && m.bend_k == 7 && m.mass == 8 && m.density == 9);
    sb_solver_def def = sb_scene_solver_def(&scene);
    assert_int_equal(def.integrator, SB_INTEGRATOR_VELOCITY_VERLET);
    assert_int_equal(def.kernels, SB_KERNELS_REFERENCE); /* not the default: the key reaches the solver */
    assert_int_equal(def.runtime.threads, 2);
    assert_true(def.gravity[0] == 1 && def.gravity[1] == 2 && def.gravity[2] == 3);
    assert_true(def.drag == 0.5);
    sb_scene_free(&scene);
}

/* ---- colliders ------------------------------------------------------------------ */

static void assert_vec3(const double* v, double x, double y, double z) {
    assert_true(v[0] == x && v[1] == y && v[2] == z);
}

static void test_colliders_build_their_defs(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    const char* text = "contact: {thickness: 0.002}\n"                                                   /* 1 */
                       "colliders:\n"                                                                    /* 2 */
                       "  - type: plane\n"                                                               /* 3 */
                       "  - {type: sphere, name: ball, center: [0, 0, 1], radius: 0.5, friction: 0.3}\n" /* 4 */
                       "  - type: capsule\n"                                                             /* 5 */
                       "    a: [0, 0, 0]\n"
                       "    b: [1, 0, 0]\n"
                       "    radius: 0.1\n"
                       "    friction: 0.2\n"
                       "    static_friction: 0.7\n"
                       "    restitution: 0.5\n"
                       "    thickness: 0.01\n"
                       "  - type: box\n" /* 13 */
                       "    center: [1, 2, 3]\n"
                       "    half_extents: [0.5, 0.25, 0.1]\n"
                       "    rotate: [0, 0, 45]\n"
                       "    interpolation: smooth\n"
                       "    path:\n"
                       "      - {time: 0}\n"
                       "      - {time: 1.5, translate: [0, 0, 1], rotate: [0, 0, 90]}\n";
    assert_int_equal(load_text(&scene, "colliders.yaml", text, &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    sb_scene_colliders c;
    assert_int_equal(sb_scene_colliders_read(&scene, &c, &err), SB_OK);
    assert_int_equal(c.count, 4);
    TU_ASSERT_NEAR(c.thickness, 0.002, 0.0);
    /* a plane with every default: through the origin, normal +z, static */
    const sb_collider_def* d = &c.entries[0].def;
    assert_int_equal(d->shape, SB_COLLIDER_PLANE);
    assert_string_equal(d->name, "plane0");
    assert_vec3(d->point, 0, 0, 0);
    assert_vec3(d->normal, 0, 0, 1);
    assert_true(d->friction == 0 && d->static_friction == 0 && d->restitution == 0 && d->thickness == 0);
    assert_null(d->path);
    assert_int_equal(d->path_count, 0);
    /* static_friction defaults to friction */
    d = &c.entries[1].def;
    assert_int_equal(d->shape, SB_COLLIDER_SPHERE);
    assert_string_equal(d->name, "ball");
    assert_vec3(d->center, 0, 0, 1);
    assert_true(d->radius == 0.5 && d->friction == 0.3 && d->static_friction == 0.3);
    d = &c.entries[2].def;
    assert_int_equal(d->shape, SB_COLLIDER_CAPSULE);
    assert_string_equal(d->name, "capsule2");
    assert_vec3(d->a, 0, 0, 0);
    assert_vec3(d->b, 1, 0, 0);
    assert_true(d->radius == 0.1 && d->friction == 0.2 && d->static_friction == 0.7);
    assert_true(d->restitution == 0.5 && d->thickness == 0.01);
    d = &c.entries[3].def;
    assert_int_equal(d->shape, SB_COLLIDER_BOX);
    assert_string_equal(d->name, "box3");
    assert_vec3(d->center, 1, 2, 3);
    assert_vec3(d->half_extents, 0.5, 0.25, 0.1);
    assert_vec3(d->rotate, 0, 0, 45);
    assert_int_equal(d->interpolation, SB_INTERPOLATION_SMOOTH);
    assert_int_equal(d->path_count, 2);
    assert_true(d->path[0].time == 0.0);
    assert_vec3(d->path[0].translate, 0, 0, 0);
    assert_vec3(d->path[0].rotate, 0, 0, 0);
    assert_true(d->path[1].time == 1.5);
    assert_vec3(d->path[1].translate, 0, 0, 1);
    assert_vec3(d->path[1].rotate, 0, 0, 90);
    /* each entry knows where it was written */
    char where[400];
    snprintf(where, sizeof where, "%s/colliders.yaml:4", tmp_dir);
    assert_string_equal(c.entries[1].where, where);
    snprintf(where, sizeof where, "%s/colliders.yaml:13", tmp_dir);
    assert_string_equal(c.entries[3].where, where);
    /* the library's colliders, handed to the solver's def */
    assert_int_equal(sb_scene_colliders_create(&c, &err), SB_OK);
    sb_solver_def def = sb_scene_solver_def(&scene);
    sb_scene_colliders_attach(&c, &def);
    assert_int_equal(def.collider_count, 4);
    assert_true(def.colliders == (sb_collider* const*)c.colliders);
    TU_ASSERT_NEAR(def.contact_thickness, 0.002, 0.0);
    for (uint32_t i = 0; i < c.count; i++) assert_string_equal(sb_collider_name(c.colliders[i]), c.entries[i].name);
    sb_scene_colliders_free(&c);
    assert_int_equal(c.count, 0);
    sb_scene_free(&scene);
}

/* `{type: plane}` is what a library user who changes nothing gets. */
static void test_colliders_default_plane_is_the_library_default(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    assert_int_equal(sb_scene_set(&scene, "colliders=[{type: plane}]", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    sb_scene_colliders c;
    assert_int_equal(sb_scene_colliders_read(&scene, &c, &err), SB_OK);
    assert_int_equal(c.count, 1);
    assert_string_equal(c.entries[0].where, "--set colliders=[{type: plane}]");
    const sb_collider_def *d = &c.entries[0].def, library = sb_default_collider_def();
    assert_int_equal(d->shape, library.shape);
    for (int k = 0; k < 3; k++) assert_true(d->point[k] == library.point[k] && d->normal[k] == library.normal[k]);
    assert_true(d->friction == library.friction && d->static_friction == library.static_friction);
    assert_true(d->restitution == library.restitution && d->thickness == library.thickness);
    assert_int_equal(d->path_count, library.path_count);
    assert_int_equal(d->interpolation, library.interpolation);
    sb_scene_colliders_free(&c);
    sb_scene_free(&scene);
}

/* No colliders by default; a --set replaces the file's whole list. */
static void test_colliders_set_replaces_the_list(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    sb_scene_colliders c;
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    assert_int_equal(sb_scene_colliders_read(&scene, &c, &err), SB_OK);
    assert_int_equal(c.count, 0);
    sb_solver_def def = sb_scene_solver_def(&scene);
    sb_scene_colliders_attach(&c, &def);
    assert_int_equal(def.collider_count, 0);
    sb_scene_colliders_free(&c);
    sb_scene_free(&scene);

    /* the file's list is checked only when the scene is validated, after
     * the --sets: a bad entry replaced by a --set is no error */
    const char* text = "colliders:\n  - {type: plane, name: floor}\n  - {type: plane, radius: 1}\n";
    assert_int_equal(load_text(&scene, "replace.yaml", text, &err), SB_OK);
    assert_int_equal(sb_scene_set(&scene, "colliders=[{type: sphere, center: [0, 0, 0], radius: 1}]", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    assert_int_equal(sb_scene_colliders_read(&scene, &c, &err), SB_OK);
    assert_int_equal(c.count, 1);
    assert_string_equal(c.entries[0].name, "sphere0");
    sb_scene_colliders_free(&c);
    assert_int_equal(sb_scene_set(&scene, "colliders=[]", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    assert_int_equal(sb_scene_colliders_read(&scene, &c, &err), SB_OK);
    assert_int_equal(c.count, 0);
    sb_scene_colliders_free(&c);
    sb_scene_free(&scene);
}

/* mass and velocity make a sphere or box dynamic; read as written. */
static void test_colliders_dynamic_keys(void** state) {
    (void)state;
    sb_scene scene;
    sb_scene_colliders c;
    sb_error err;
    const char* text = "colliders:\n  - {type: sphere, center: [0, 0, 1], radius: 0.1, mass: 0.5, velocity: [0, 0, "
                       "-5]}\n  - {type: box, center: [0, 0, 0], half_extents: [1, 1, 1], mass: 0}\n";
    assert_int_equal(load_text(&scene, "dynamic.yaml", text, &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    assert_int_equal(sb_scene_colliders_read(&scene, &c, &err), SB_OK);
    assert_int_equal(c.count, 2);
    assert_true(c.entries[0].def.mass == 0.5 && c.entries[0].def.velocity[2] == -5.0);
    assert_true(c.entries[1].def.mass == 0.0);
    assert_int_equal(sb_scene_colliders_create(&c, &err), SB_OK);
    double p[3], v[3];
    sb_collider_state(c.colliders[0], p, v);
    assert_true(p[2] == 1.0 && v[2] == -5.0);
    sb_scene_colliders_free(&c);
    sb_scene_free(&scene);
}

/* Where the loader itself refuses a list: not a sequence (the entries are
 * checked by colliders.c when the scene is validated). */
static void test_colliders_must_be_a_list(void** state) {
    (void)state;
    assert_load_fails("list1.yaml", "dt: 0.001\ncolliders: {type: plane}\n",
                      "2: 'colliders' expects a sequence of maps, got a map");
    assert_load_fails("list2.yaml", "colliders:\n  - type: plane\n    radius: 2\n",
                      "3: 'colliders[0].radius' does not apply to a plane (its shape's keys: point, normal)");
    assert_set_fails("colliders=plane", "--set colliders=plane: 'colliders' expects a sequence of maps, got 'plane'");
    assert_set_fails("colliders=[{type: plane, density: 1}]",
                     "--set colliders=[{type: plane, density: 1}]: unknown key 'colliders[0].density'");
    /* mass and velocity: a dynamic sphere or box */
    assert_set_fails("colliders=[{type: plane, mass: 1}]",
                     "--set colliders=[{type: plane, mass: 1}]: unknown key 'colliders[0].mass'");
    assert_set_fails("colliders=[{type: capsule, a: [0, 0, 0], b: [1, 0, 0], radius: 1, velocity: [0, 0, 1]}]",
                     "--set colliders=[{type: capsule, a: [0, 0, 0], b: [1, 0, 0], radius: 1, velocity: [0, 0, 1]}]: "
                     "unknown key 'colliders[0].velocity'");
    assert_set_fails("colliders=[{type: sphere, center: [0, 0, 0], radius: 1, mass: -1}]",
                     "--set colliders=[{type: sphere, center: [0, 0, 0], radius: 1, mass: -1}]: 'colliders[0].mass' "
                     "must be >= 0, got -1");
    assert_set_fails("colliders=[{type: sphere, center: [0, 0, 0], radius: 1, velocity: [1, 0, 0]}]",
                     "--set colliders=[{type: sphere, center: [0, 0, 0], radius: 1, velocity: [1, 0, 0]}]: "
                     "unknown key 'colliders[0].velocity'");
    assert_set_fails("colliders=[{type: box, center: [0, 0, 0], half_extents: [1, 1, 1], mass: 2, path: []}]",
                     "--set colliders=[{type: box, center: [0, 0, 0], half_extents: [1, 1, 1], mass: 2, path: []}]: "
                     "'colliders[0].path': a dynamic collider (mass 2) cannot have a path");
    assert_set_fails("colliders=[{type: box, center: [0, 0, 0], half_extents: [1, 1, 1], mass: 2, velocity: [1, 0]}]",
                     "--set colliders=[{type: box, center: [0, 0, 0], half_extents: [1, 1, 1], mass: 2, velocity: [1, "
                     "0]}]: 'colliders[0].velocity' expects 3 numbers: [x, y, z] or x,y,z, got a sequence of 2");
    assert_set_fails("self_collision=true",
                     "--set self_collision=true: 'self_collision' needs 'contact.thickness' > 0 (the distance kept "
                     "between surfaces)");
    assert_set_fails("contact.thickness=-0.5",
                     "--set contact.thickness=-0.5: 'contact.thickness' must be >= 0, got -0.5");
    assert_set_fails("colliders=[{type: plane, path: [{time: 0}, {time: 0}]}]",
                     "--set colliders=[{type: plane, path: [{time: 0}, {time: 0}]}]: 'colliders[0].path[1].time' (0) "
                     "must be > the time before it (0)");
}

/* The key table states its defaults as YAML text; the library has its own
 * sb_default_*_def(). A scene that sets nothing must build what a library
 * user who changes nothing gets, so the two must agree key by key. */
static void test_defaults_match_the_library(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    sb_material_def m = sb_scene_material(&scene), lm = sb_default_material_def();
    assert_true(m.bond_k == lm.bond_k && m.angle_k == lm.angle_k && m.stretch_bend_k == lm.stretch_bend_k);
    assert_true(m.spring_k == lm.spring_k && m.spring_damping == lm.spring_damping && m.bend_k == lm.bend_k);
    assert_true(m.mass == lm.mass && m.density == lm.density);
    sb_spring_mesh_def sp = sb_scene_springs(&scene), lsp = sb_default_spring_mesh_def();
    assert_true(sp.stretch_k == lsp.stretch_k && sp.stretch_damping == lsp.stretch_damping);
    assert_true(sp.bend_k == lsp.bend_k && sp.bend_damping == lsp.bend_damping);
    assert_true(sp.vicinity == lsp.vicinity && sp.vicinity_k == lsp.vicinity_k);
    assert_true(sp.vicinity_damping == lsp.vicinity_damping);
    assert_true(sp.mass == lsp.mass && sp.density == lsp.density);
    sb_tissue_def lt = sb_default_tissue_def();
    assert_true(sb_scene_number(&scene, SB_KEY_TISSUE_YOUNG_MODULUS) == lt.young_modulus);
    assert_true(sb_scene_number(&scene, SB_KEY_TISSUE_DENSITY) == lt.density);
    assert_true(sb_scene_number(&scene, SB_KEY_TISSUE_DAMPING) == lt.damping);
    sb_solver_def d = sb_scene_solver_def(&scene), ld = sb_default_solver_def();
    assert_int_equal(d.integrator, ld.integrator);
    assert_int_equal(d.kernels, ld.kernels);
    assert_int_equal(ld.kernels, SB_KERNELS_FAST); /* the fast kernels by default; the reference is opted into */
    assert_int_equal(d.runtime.threads, ld.runtime.threads);
    assert_int_equal(d.runtime.wait, ld.runtime.wait);
    assert_int_equal(d.runtime.pin, ld.runtime.pin);
    for (int k = 0; k < 3; k++) assert_true(d.gravity[k] == ld.gravity[k]);
    assert_true(d.drag == ld.drag && d.adaptive == ld.adaptive && d.min_dt == ld.min_dt);
    assert_true(d.implicit_tolerance == ld.implicit_tolerance);
    assert_int_equal(d.implicit_newton_iterations, ld.implicit_newton_iterations);
    assert_int_equal(d.implicit_cg_iterations, ld.implicit_cg_iterations);
    assert_int_equal(d.pbd_iterations, ld.pbd_iterations);
    assert_true(sb_scene_number(&scene, SB_KEY_CONTACT_THICKNESS) == ld.contact_thickness);
    sb_scene_free(&scene);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_are_valid_and_from_nowhere),
        cmocka_unit_test(test_key_table_names_are_unique),
        cmocka_unit_test(test_nested_maps_flatten_to_dotted_keys),
        cmocka_unit_test(test_set_overrides_file_and_earlier_sets),
        cmocka_unit_test(test_mesh_file_is_relative_to_the_scene),
        cmocka_unit_test(test_unknown_keys),
        cmocka_unit_test(test_wrong_types),
        cmocka_unit_test(test_duplicate_keys),
        cmocka_unit_test(test_malformed_yaml),
        cmocka_unit_test(test_missing_file),
        cmocka_unit_test(test_set_errors_name_the_set),
        cmocka_unit_test(test_validation_names_where_the_value_was_set),
        cmocka_unit_test(test_pin_names),
        cmocka_unit_test(test_pins_select_by_place),
        cmocka_unit_test(test_fixed_index_out_of_range),
        cmocka_unit_test(test_material_and_solver_follow_the_scene),
        cmocka_unit_test(test_colliders_build_their_defs),
        cmocka_unit_test(test_colliders_default_plane_is_the_library_default),
        cmocka_unit_test(test_colliders_set_replaces_the_list),
        cmocka_unit_test(test_colliders_must_be_a_list),
        cmocka_unit_test(test_colliders_dynamic_keys),
        cmocka_unit_test(test_defaults_match_the_library),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
