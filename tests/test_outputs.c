/* The run's outputs tell the same story as log.csv (issue 31): the bonds
 * frames of the tearing and cutting scenes sum, frame by frame, to the log's
 * bond + spring energies (broken and severed bonds left out), and a run
 * whose duration is off the frame_interval grid writes its end state; keys
 * that would have no effect are refused; a mistyped value, option or
 * command gets the nearest name; vectors take one form everywhere;
 * output.vtu: binary and zlib frames read back by meshio (Debian's
 * python3-meshio) to the ASCII frame's points, triangles, bonds and
 * arrays. */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <sys/stat.h>

#include "scenes/colliders.h"
#include "scenes/scene.h"
#include "tests/test_files.h"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_outputs");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

/* ---- log.csv ---------------------------------------------------------------- */

typedef struct csv {
    char* text;
    char* names[128];
    int columns;
    double* rows; /* rows x columns */
    int count;
} csv;

static csv csv_read(const char* path) {
    csv c = {.text = tu_read_file(path)};
    if (!c.text) fail_msg("%s: missing", path);
    char* line_end = strchr(c.text, '\n');
    assert_non_null(line_end);
    *line_end = '\0';
    for (char* save = NULL, *name = strtok_r(c.text, ",", &save); name && c.columns < 128;
         name = strtok_r(NULL, ",", &save))
        c.names[c.columns++] = name;
    size_t capacity = 16;
    c.rows = malloc(capacity * (size_t)c.columns * sizeof(double));
    for (char* p = line_end + 1; *p;) {
        if ((size_t)c.count == capacity) c.rows = realloc(c.rows, (capacity *= 2) * (size_t)c.columns * sizeof(double));
        for (int k = 0; k < c.columns; k++) {
            c.rows[(size_t)c.count * (size_t)c.columns + (size_t)k] = strtod(p, &p);
            if (*p == ',') p++;
        }
        while (*p && *p != '\n') p++;
        if (*p == '\n') p++;
        c.count++;
    }
    return c;
}

static double csv_at(const csv* c, int row, const char* name) {
    for (int k = 0; k < c->columns; k++)
        if (strcmp(c->names[k], name) == 0) return c->rows[(size_t)row * (size_t)c->columns + (size_t)k];
    fail_msg("log.csv: no column '%s'", name);
    return 0.0;
}

static void csv_free(csv* c) {
    free(c->text);
    free(c->rows);
}

/* ---- the bonds frames ---------------------------------------------------------- */

/* The sum of the DataArray `name`'s numbers in the file at path, and their count. */
static double array_sum(const char* path, const char* name, int* count) {
    char* text = tu_read_file(path);
    if (!text) fail_msg("%s: missing", path);
    char key[64];
    snprintf(key, sizeof key, "Name=\"%s\"", name);
    const char* p = strstr(text, key);
    if (!p) fail_msg("%s: no array %s", path, name);
    p = strchr(p, '>') + 1;
    const char* end = strstr(p, "</DataArray>");
    double sum = 0.0;
    *count = 0;
    for (char* next; p < end; p = next) {
        double v = strtod(p, &next);
        if (next == p) break;
        sum += v;
        ++*count;
    }
    free(text);
    return sum;
}

/* Runs SCENE into DIR and compares each frame's bond energies with log.csv's
 * bond + spring terms; the last frame must have broken bonds. */
static void assert_bonds_agree(const char* scene, const char* dir) {
    char path[256];
    snprintf(path, sizeof path, "%s/scenes/%s", SB_SOURCE_DIR, scene);
    /* cut_through off: the blade scene's blade severs the bonds it crosses (through the triangles none break) */
    tu_result r = tu_run((const char*[]){"run", path, "--set", "cut_through=false", "--output", dir, NULL});
    if (r.code != 0) fail_msg("%s: exit %d: %s", scene, r.code, r.err);
    tu_result_free(&r);
    snprintf(path, sizeof path, "%s/log.csv", dir);
    csv log = csv_read(tu_tmp_path(path));
    assert_true(log.count > 2);
    int total_bonds = -1;
    for (int f = 0; f < log.count; f++) {
        snprintf(path, sizeof path, "%s/frame_%06d_bonds.vtu", dir, f);
        int cells;
        double cells_energy = array_sum(tu_tmp_path(path), "energy", &cells);
        double logged = csv_at(&log, f, "bond") + csv_at(&log, f, "spring");
        if (fabs(cells_energy - logged) > 1e-4 * fabs(logged) + 1e-9)
            fail_msg("%s frame %d: the bonds frame's energies sum to %.9g J, log.csv's bond + spring %.9g J", scene,
                     f, cells_energy, logged);
        if (f == 0) total_bonds = cells;
        assert_int_equal(cells + (int)csv_at(&log, f, "broken"), total_bonds);
    }
    assert_true(csv_at(&log, log.count - 1, "broken") > 0.0);
    csv_free(&log);
}

static void test_bonds_frames_agree_with_log_tearing(void** state) {
    (void)state;
    assert_bonds_agree("tearing_sheet.yaml", "tearing");
}

static void test_bonds_frames_agree_with_log_cutting(void** state) {
    (void)state;
    assert_bonds_agree("blade_cut.yaml", "cutting");
}

/* ---- the end state ------------------------------------------------------------- */

static const char tiny_scene[] = "mesh: {generator: sheet, nx: 4, ny: 4, width: 0.1, height: 0.1}\n"
                                 "pin: top_edge\n"
                                 "dt: 0.001\n"
                                 "duration: 0.1\n"
                                 "frame_interval: 0.02\n";

static void test_end_state_written(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    tu_result r = tu_run((const char*[]){"run", "tiny.yaml", "--set", "duration=0.01", "--set", "frame_interval=1",
                                         "--output", "end", NULL});
    if (r.code != 0) fail_msg("exit %d: %s", r.code, r.err);
    TU_ASSERT_CONTAINS(r.out, "frame 1 is the end state at t = 0.01");
    tu_result_free(&r);
    csv log = csv_read(tu_tmp_path("end/log.csv"));
    assert_int_equal(log.count, 2);
    TU_ASSERT_NEAR(csv_at(&log, 1, "time"), 0.01, 1e-12);
    assert_int_equal((int)csv_at(&log, 1, "steps"), 10);
    csv_free(&log);
    struct stat info;
    assert_int_equal(stat(tu_tmp_path("end/frame_000001.vtu"), &info), 0);
    char* pvd = tu_read_file(tu_tmp_path("end/frames.pvd"));
    TU_ASSERT_CONTAINS(pvd, "timestep=\"0.01");
    free(pvd);

    /* on the grid: no extra frame, nothing said */
    r = tu_run((const char*[]){"run", "tiny.yaml", "--output", "grid", NULL});
    assert_int_equal(r.code, 0);
    assert_null(strstr(r.out, "end state"));
    tu_result_free(&r);
    log = csv_read(tu_tmp_path("grid/log.csv"));
    assert_int_equal(log.count, 6);
    csv_free(&log);
}


/* ---- keys without effect, suggestions, vectors ------------------------------------ */

static void assert_fails(const char* const* args, int code, const char* message) {
    tu_result r = tu_run(args);
    if (r.code != code || !strstr(r.err, message))
        fail_msg("expected exit %d and '%s', got %d: %s", code, message, r.code, r.err);
    tu_result_free(&r);
}

static void test_keys_without_effect_refused(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    assert_fails((const char*[]){"run", "tiny.yaml", "--set", "mesh.file=" SB_SOURCE_DIR "/scenes/bowl.obj", "--output",
                                 "never", NULL},
                 2, "--set mesh.file=" SB_SOURCE_DIR "/scenes/bowl.obj: 'mesh.file' has no effect: 'mesh.generator' is sheet");
    tu_write_file("mouse.yaml", "mesh: {generator: sheet, nx: 4, ny: 4, width: 0.1, height: 0.1}\n"
                                "dt: 0.001\nduration: 0.01\n"
                                "colliders: [{type: sphere, name: probe, center: [0, 0, 0.1], radius: 0.01}]\n"
                                "haptics:\n  device: mouse\n  tool: probe\n");
    assert_fails((const char*[]){"run", "mouse.yaml", "--output", "never", NULL}, 2,
                 "mouse.yaml:6: 'haptics.device: mouse' is moved by the mouse in softbond view only");
    assert_fails((const char*[]){"film", "mouse.yaml", "--movie", "never.mp4", NULL}, 2,
                 "'haptics.device: mouse' is moved by the mouse in softbond view only");
    struct stat info;
    assert_int_not_equal(stat(tu_tmp_path("never"), &info), 0);
}

static void test_suggestions(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    assert_fails((const char*[]){"run", "tiny.yaml", "--set", "integrator=xbpd", NULL}, 2,
                 "got 'xbpd' (did you mean 'xpbd'?)");
    assert_fails((const char*[]){"run", "tiny.yaml", "--set", "pin=top_corner", NULL}, 2,
                 "got 'top_corner' (did you mean 'top_corners'?)");
    assert_fails((const char*[]){"run", "tiny.yaml", "--set", "output.formats=vtu,pyl", NULL}, 2,
                 "(did you mean 'ply'?)");
    assert_fails((const char*[]){"run", "tiny.yaml", "--set", "colliders=[{type: spere}]", NULL}, 2,
                 "got 'spere' (did you mean 'sphere'?)");
    assert_fails((const char*[]){"run", "tiny.yaml", "--thread", "2", NULL}, 2,
                 "unknown option '--thread' (did you mean '--threads'?)");
    assert_fails((const char*[]){"runn", "tiny.yaml", NULL}, 2, "unknown command 'runn' (did you mean 'run'?)");
    assert_fails((const char*[]){"run", "tiny.yaml", "--set", "integrator=zzzzzz", NULL}, 2, "got 'zzzzzz'");
    tu_result r = tu_run((const char*[]){"run", "tiny.yaml", "--set", "integrator=zzzzzz", NULL});
    assert_null(strstr(r.err, "did you mean"));
    tu_result_free(&r);
}

/* One form for every vector: [x, y, z] or x,y,z, in the file, --set and the lists alike. */
static void test_vector_forms(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    /* in a list's block map too (a flow map {...} splits at commas: YAML's own rule) */
    tu_write_file("ball.yaml", "colliders:\n  - type: sphere\n    center: 0, 0, -0.2\n    radius: 0.1\n");
    tu_write_file("ball_brackets.yaml", "colliders:\n  - type: sphere\n    center: [0, 0, -0.2]\n    radius: 0.1\n");
    static const char* const a[] = {"gravity=[0, 0, -3]", "gravity=0,0,-3", "gravity=0, 0, -3", NULL};
    char* first = NULL;
    for (int i = 0; a[i]; i++) {
        char dir[16], scene[700];
        snprintf(dir, sizeof dir, "vec%d", i);
        char* ball = tu_read_file(tu_tmp_path(i == 0 ? "ball_brackets.yaml" : "ball.yaml"));
        snprintf(scene, sizeof scene, "%s%s", tiny_scene, ball);
        free(ball);
        tu_write_file("vec.yaml", scene);
        tu_result r = tu_run((const char*[]){"run", "vec.yaml", "--set", a[i], "--output", dir, NULL});
        if (r.code != 0) fail_msg("%s: exit %d: %s", a[i], r.code, r.err);
        tu_result_free(&r);
        char path[64];
        snprintf(path, sizeof path, "%s/log.csv", dir);
        char* log = tu_read_file(tu_tmp_path(path));
        assert_non_null(log);
        if (!first)
            first = log;
        else {
            assert_string_equal(log, first);
            free(log);
        }
    }
    free(first);
    assert_fails((const char*[]){"run", "tiny.yaml", "--set", "gravity=0,0", NULL}, 2,
                 "'gravity' expects 3 numbers: [x, y, z] or x,y,z, got '0,0'");
    assert_fails((const char*[]){"run", "tiny.yaml", "--set", "colliders=[{type: sphere, center: [0, 0], radius: 1}]",
                                 NULL},
                 2, "'colliders[0].center' expects 3 numbers: [x, y, z] or x,y,z");
}

/* ---- run.yaml ----------------------------------------------------------------------- */

/* Every key of a scene read with --set values, written and read back, is the same value. */
static void test_scene_write_round_trip(void** state) {
    (void)state;
    const char* path = tu_write_file("full.yaml", "mesh: {generator: sheet, nx: 5, ny: 4, jitter: 0.1}\n"
                                                 "fixed: [0, 3]\n"
                                                 "material: gallbladder\n"
                                                 "output: {formats: [vtu, ply]}\n"
                                                 "colliders:\n"
                                                 "  - {type: plane, name: 'floor', point: [0, 0, -0.5]}\n"
                                                 "  - type: sphere\n"
                                                 "    center: 0.1, 0, -0.2\n"
                                                 "    radius: 0.05\n"
                                                 "    path: [{time: 0, translate: [0, 0, 0]}, {time: 1, translate: [0, 0, 0.1]}]\n"
                                                 "handles: [{name: grip, vertices: [19], path: [{time: 0.5, rotate: [0, 0, 10]}]}]\n");
    const char* sets[] = {"dt=0.00033", "gravity=0.1,0,-9", "tissue.density=900", "haptics.file=x y.csv"};
    sb_scene scene, back;
    sb_error err;
    if (sb_scene_read(&scene, path, sets, 4, &err) != SB_OK) fail_msg("%s", err.message);
    FILE* f = fopen(tu_tmp_path("written.yaml"), "w");
    assert_non_null(f);
    sb_scene_write(&scene, f);
    fclose(f);
    if (sb_scene_read(&back, tu_tmp_path("written.yaml"), NULL, 0, &err) != SB_OK) fail_msg("%s", err.message);
    for (int key = 0; key < SB_KEY_COUNT; key++) {
        const sb_scene_key_info* info = sb_scene_key_get((sb_scene_key)key);
        const sb_scene_value *a = &scene.values[key], *b = &back.values[key];
        switch (info->type) {
        case SB_SCENE_NUMBER: assert_memory_equal(&a->number, &b->number, sizeof(double)); break;
        case SB_SCENE_INTEGER: assert_int_equal(a->integer, b->integer); break;
        case SB_SCENE_BOOL: assert_int_equal(a->boolean, b->boolean); break;
        case SB_SCENE_VEC3:
        case SB_SCENE_VEC3_OR_NUMBER: assert_memory_equal(a->vec3, b->vec3, sizeof a->vec3); break;
        case SB_SCENE_INDICES:
            assert_int_equal(a->index_count, b->index_count);
            if (a->index_count) assert_memory_equal(a->indices, b->indices, a->index_count * sizeof *a->indices);
            break;
        case SB_SCENE_STRING:
        case SB_SCENE_NAMES: {
            char* pa = sb_scene_path(&scene, (sb_scene_key)key);
            char* pb = sb_scene_path(&back, (sb_scene_key)key);
            if (key == SB_KEY_HAPTICS_FILE) {
                TU_ASSERT_CONTAINS(pb, "/x y.csv"); /* made absolute */
                assert_int_equal(pb[0], '/');
            } else if (key != SB_KEY_MESH_FILE)
                assert_string_equal(a->string, b->string);
            else if (a->string[0] == '\0')
                assert_string_equal(b->string, ""); /* an empty path stays empty */
            else
                assert_string_equal(pa, pb);
            free(pa);
            free(pb);
            break;
        }
        case SB_SCENE_LIST: break; /* checked below by what they build */
        }
        /* a key whose being set matters is set only where the scene set it */
        assert_int_equal(b->where[0] != 0, key != SB_KEY_TISSUE_YOUNG_MODULUS);
    }
    sb_scene_colliders ca, cb;
    assert_int_equal(sb_scene_colliders_read(&scene, &ca, &err), SB_OK);
    assert_int_equal(sb_scene_colliders_read(&back, &cb, &err), SB_OK);
    assert_int_equal(ca.count, 2);
    assert_int_equal(cb.count, 2);
    assert_string_equal(ca.entries[0].name, cb.entries[0].name);
    assert_memory_equal(ca.entries[1].def.center, cb.entries[1].def.center, 3 * sizeof(double));
    sb_scene_colliders_free(&ca);
    sb_scene_colliders_free(&cb);
    sb_scene_free(&scene);
    sb_scene_free(&back);
}

/* `softbond run OUT/run.yaml` from another folder gives the same log and frames, bit for bit. */
static void assert_rerun_same(const char* scene, const char* const* sets, const char* dir) {
    const char* args[24] = {"run", scene};
    int n = 2;
    for (int i = 0; sets[i]; i++) args[n++] = "--set", args[n++] = sets[i];
    args[n++] = "--output", args[n++] = dir, args[n++] = "--threads", args[n++] = "2", args[n] = NULL;
    tu_result r = tu_run(args);
    if (r.code != 0) fail_msg("%s: exit %d: %s", scene, r.code, r.err);
    tu_result_free(&r);
    char path[600], again[300];
    snprintf(path, sizeof path, "%s/%s/run.yaml", tu_tmp_dir, dir);
    char* record = tu_read_file(path);
    assert_non_null(record);
    TU_ASSERT_CONTAINS(record, "# softbond " SB_VERSION_STRING ", commit ");
    TU_ASSERT_CONTAINS(record, sizeof(sb_real) == sizeof(double) ? "# precision: double; SIMD: " : "# precision: float; SIMD: ");
    TU_ASSERT_CONTAINS(record, "; threads: 2\n");
    TU_ASSERT_CONTAINS(record, "# command: softbond run ");
    TU_ASSERT_CONTAINS(record, " --threads 2\n");
    TU_ASSERT_CONTAINS(record, "\nmass: ");      /* a default */
    TU_ASSERT_CONTAINS(record, "\noutput:\n  frames: ");
    free(record);
    snprintf(again, sizeof again, "%s_again", dir);
    assert_int_equal(mkdir(tu_tmp_path("elsewhere"), 0777) == 0 || errno == EEXIST, 1);
    char rerun_out[600];
    snprintf(rerun_out, sizeof rerun_out, "%s/%s", tu_tmp_dir, again);
    r = tu_run((const char*[]){"run", path, "--output", rerun_out, "--threads", "1", NULL});
    if (r.code != 0) fail_msg("%s again: exit %d: %s", path, r.code, r.err);
    tu_result_free(&r);
    static const char* const files[] = {"log.csv", "frame_000000.vtu", "frame_000001.vtu", "frame_000002_bonds.vtu"};
    for (size_t i = 0; i < 4; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        char* a = tu_read_file(tu_tmp_path(path));
        snprintf(path, sizeof path, "%s/%s", again, files[i]);
        char* b = tu_read_file(tu_tmp_path(path));
        if (!a || !b) fail_msg("%s: missing", files[i]);
        if (strcmp(a, b) != 0) fail_msg("%s/%s differs after softbond run run.yaml", dir, files[i]);
        free(a);
        free(b);
    }
}

static void test_run_yaml_reproduces(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    assert_rerun_same("tiny.yaml", (const char*[]){"bond.k=250", "gravity=0,0.5,-9", "integrator=xpbd",
                                                   "colliders=[{type: sphere, center: [0, 0, -0.05], radius: 0.03}]",
                                                   NULL},
                      "tiny_run");
    assert_rerun_same(SB_SOURCE_DIR "/scenes/mesh_bowl.yaml", (const char*[]){"duration=0.1", NULL}, "bowl_run");
    assert_rerun_same(SB_SOURCE_DIR "/scenes/tearing_sheet.yaml", (const char*[]){"duration=0.3", NULL}, "tear_run");
}

/* ---- --resume to a longer duration -------------------------------------------------- */

static void run_in(const char* const* args) {
    tu_result r = tu_run(args);
    if (r.code != 0) fail_msg("softbond %s %s: exit %d: %s", args[0], args[1], r.code, r.err);
    tu_result_free(&r);
}

/* SCENE run for `shorter` s, then resumed to `longer` s, against one run of `longer` s. */
static void assert_extends(const char* scene, const char* shorter, const char* longer, const char* every) {
    char set_short[64], set_long[64], command[1200];
    snprintf(set_short, sizeof set_short, "duration=%s", shorter);
    snprintf(set_long, sizeof set_long, "duration=%s", longer);
    snprintf(command, sizeof command, "rm -rf '%s' '%s'", tu_tmp_path("ext_one"), tu_tmp_path("ext_two"));
    assert_int_equal(system(command), 0);
    run_in((const char*[]){"run", scene, "--set", set_long, "--checkpoint-every", every, "--output", "ext_one", NULL});
    run_in((const char*[]){"run", scene, "--set", set_short, "--checkpoint-every", every, "--output", "ext_two", NULL});
    tu_result r = tu_run((const char*[]){"run", scene, "--set", set_long, "--resume", "ext_two", NULL});
    if (r.code != 0) fail_msg("--resume to %s s: exit %d: %s", longer, r.code, r.err);
    TU_ASSERT_CONTAINS(r.out, "softbond: resuming ext_two at frame");
    tu_result_free(&r);
    snprintf(command, sizeof command, "diff -r -x run.yaml '%s' '%s' >&2", tu_tmp_path("ext_one"),
             tu_tmp_path("ext_two"));
    assert_int_equal(system(command), 0);
    char* record = tu_read_file(tu_tmp_path("ext_two/run.yaml"));
    char line[80];
    snprintf(line, sizeof line, "\nduration: %.17g\n", atof(longer));
    TU_ASSERT_CONTAINS(record, line);
    free(record);
}

static void test_resume_longer(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    assert_extends("tiny.yaml", "0.1", "0.2", "0.04");
    assert_extends(SB_SOURCE_DIR "/scenes/tearing_sheet.yaml", "0.5", "0.7", "0.1"); /* bonds break from 0.4 s */
    /* shorter than the checkpoint, or another key changed: refused, nothing touched */
    assert_fails((const char*[]){"run", SB_SOURCE_DIR "/scenes/tearing_sheet.yaml", "--set", "duration=0.69",
                                 "--resume", "ext_one", NULL},
                 2, "its checkpoint is at t = 0.7 s, past the run's end 0.69 s (a resumed run may only be longer)");
    tu_write_file("tiny2.yaml", tiny_scene);
    run_in((const char*[]){"run", "tiny.yaml", "--checkpoint-every", "0.04", "--output", "ext_three", NULL});
    assert_fails((const char*[]){"run", "tiny.yaml", "--set", "duration=0.3", "--set", "bond.k=1", "--resume",
                                 "ext_three", NULL},
                 2, "written for another scene (a key other than duration differs)");
    /* the same scene under another file name and with a comment is the same scene */
    tu_write_file("tiny2.yaml", "# a copy\n"
                                "mesh: {generator: sheet, nx: 4, ny: 4, width: 0.1, height: 0.1}\n"
                                "pin: top_edge\ndt: 0.001\nduration: 0.1\nframe_interval: 0.02\n");
    run_in((const char*[]){"run", "tiny2.yaml", "--set", "duration=0.3", "--resume", "ext_three", NULL});
}

/* ---- output.vtu: binary and zlib against ascii, read by meshio --------------------- */

/* Reads each encoding's frame 3 (surface and bonds) with meshio and compares
 * it with the ASCII one: the cells exactly, the numbers to the ASCII's 9
 * significant digits. Prints what differs; exit 0 when all agree. */
static const char meshio_check[] =
    "import sys, meshio, numpy as np\n"
    "def close(a, b): return np.allclose(a, b, rtol=1e-8, atol=1e-12)\n"
    "bad = 0\n"
    "for part in ['frame_000003.vtu', 'frame_000003_bonds.vtu']:\n"
    "    a = meshio.read('vtu_ascii/' + part)\n"
    "    for e in ['binary', 'zlib']:\n"
    "        b = meshio.read('vtu_' + e + '/' + part)\n"
    "        if not close(a.points, b.points): bad += 1; print(e, part, 'points differ')\n"
    "        for c, d in zip(a.cells, b.cells):\n"
    "            if c.type != d.type or not np.array_equal(c.data, d.data): bad += 1; print(e, part, c.type, 'differ')\n"
    "        for k in a.point_data:\n"
    "            if not close(a.point_data[k], b.point_data[k]): bad += 1; print(e, part, k, 'differs')\n"
    "        for k in a.cell_data:\n"
    "            if not close(a.cell_data[k][0], b.cell_data[k][0]): bad += 1; print(e, part, k, 'differs')\n"
    "        if len(a.point_data) + len(a.cell_data) < 3: bad += 1; print(part, 'arrays missing')\n"
    "print('checked', len(a.points), 'points') \n"
    "sys.exit(bad)\n";

static void test_vtu_binary_and_zlib_read_back(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    const char* encodings[] = {"ascii", "binary", "zlib"};
    for (int e = 0; e < 3; e++) {
        char set[64], dir[64];
        snprintf(set, sizeof set, "output.vtu=%s", encodings[e]);
        snprintf(dir, sizeof dir, "vtu_%s", encodings[e]);
        run_in((const char*[]){"run", "tiny.yaml", "--set", set, "--output", dir, NULL});
    }
    char* text = tu_read_file(tu_tmp_path("vtu_binary/frame_000003.vtu"));
    TU_ASSERT_CONTAINS(text, "format=\"appended\" offset=\"");
    TU_ASSERT_CONTAINS(text, "<AppendedData encoding=\"raw\">");
    assert_null(strstr(text, "compressor="));
    free(text);
    text = tu_read_file(tu_tmp_path("vtu_zlib/frame_000003_bonds.vtu"));
    TU_ASSERT_CONTAINS(text, "compressor=\"vtkZLibDataCompressor\"");
    free(text);
    tu_write_file("meshio_check.py", meshio_check);
    char command[1200];
    snprintf(command, sizeof command, "cd '%s' && /usr/bin/python3 meshio_check.py >&2", tu_tmp_path(""));
    assert_int_equal(system(command), 0);
    assert_fails((const char*[]){"run", "tiny.yaml", "--set", "output.vtu=zlb", NULL}, 2, "did you mean 'zlib'");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bonds_frames_agree_with_log_tearing),
        cmocka_unit_test(test_bonds_frames_agree_with_log_cutting),
        cmocka_unit_test(test_end_state_written),
        cmocka_unit_test(test_keys_without_effect_refused),
        cmocka_unit_test(test_suggestions),
        cmocka_unit_test(test_vector_forms),
        cmocka_unit_test(test_scene_write_round_trip),
        cmocka_unit_test(test_run_yaml_reproduces),
        cmocka_unit_test(test_resume_longer),
        cmocka_unit_test(test_vtu_binary_and_zlib_read_back),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
