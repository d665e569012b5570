/* The `softbond` program, run as a child process in a temporary directory:
 * `eval` energies and forces against values computed here by hand from the
 * definitions (DESIGN.md), absent terms, the --forces CSV, bad input (exit
 * 2, one line on stderr, no output left behind), and `run` writing
 * frames.pvd, the .vtu frames and log.csv with one row per frame, its
 * contact columns, and every malformed `colliders` entry's message. */
#define _POSIX_C_SOURCE 200809L

#include <dirent.h>
#include <stdio.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/test_files.h"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_cli");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

static bool exists(const char* path) {
    struct stat info;
    return stat(path, &info) == 0;
}

static int count_lines(const char* text) {
    int n = 0;
    for (; *text; text++) n += *text == '\n';
    return n;
}

static int count_occurrences(const char* text, const char* word) {
    int n = 0;
    for (const char* p = strstr(text, word); p; p = strstr(p + 1, word)) n++;
    return n;
}

/* Exit 2, nothing on stdout, and exactly `message` on stderr. */
static void assert_input_error(const tu_result* r, const char* message) {
    assert_int_equal(r->code, 2);
    assert_string_equal(r->out, "");
    char expected[600];
    snprintf(expected, sizeof expected, "softbond: %s\n", message);
    assert_string_equal(r->err, expected);
}

/* ---- hand computations from the definitions ---------------------------------- */

typedef struct vec {
    double x, y, z;
} vec;

static vec sub(vec a, vec b) { return (vec){a.x - b.x, a.y - b.y, a.z - b.z}; }

static double dot(vec a, vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

static double len(vec a) { return sqrt(dot(a, a)); }

static vec cross(vec a, vec b) { return (vec){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

/* The triangle used by most tests: rest and moved positions. */
static const vec tri_rest[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
static const vec tri_moved[3] = {{0.1, -0.05, 0.0}, {1.3, 0.1, 0.2}, {-0.1, 0.9, -0.1}};

static const char* const tri_obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
static const char* const tri_pos = "x,y,z\n0.1,-0.05,0\n1.3,0.1,0.2\n-0.1,0.9,-0.1\n";

/* Σ over the 3 edges of ½ k (r − r0)². */
static double edge_energy(double k) {
    double e = 0.0;
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3;
        double dr = len(sub(tri_moved[j], tri_moved[i])) - len(sub(tri_rest[j], tri_rest[i]));
        e += 0.5 * k * dr * dr;
    }
    return e;
}

static double corner_cos(const vec* p, int i, int j, int k) {
    vec a = sub(p[j], p[i]), b = sub(p[k], p[i]);
    return dot(a, b) / (len(a) * len(b));
}

/* Σ over the 3 corners of ½ kθ (c − c0)² and of ksb (c − c0)[(A − A0) + (B − B0)]. */
static void corner_energies(double angle_k, double sb_k, double* angle, double* stretch_bend) {
    *angle = *stretch_bend = 0.0;
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        double dc = corner_cos(tri_moved, i, j, k) - corner_cos(tri_rest, i, j, k);
        double da = len(sub(tri_moved[j], tri_moved[i])) - len(sub(tri_rest[j], tri_rest[i]));
        double db = len(sub(tri_moved[k], tri_moved[i])) - len(sub(tri_rest[k], tri_rest[i]));
        *angle += 0.5 * angle_k * dc * dc;
        *stretch_bend += sb_k * dc * (da + db);
    }
}

/* The value of "name": in a one-line JSON object; fails when absent. */
static double json_number(const char* json, const char* name) {
    char key[64];
    snprintf(key, sizeof key, "\"%s\":", name);
    const char* at = strstr(json, key);
    if (!at) fail_msg("%s missing from %s", key, json);
    char* end;
    double value = strtod(at + strlen(key), &end);
    assert_true(end != at + strlen(key) && (*end == ',' || *end == '}'));
    return value;
}

static bool json_has(const char* json, const char* name) {
    char key[64];
    snprintf(key, sizeof key, "\"%s\":", name);
    return strstr(json, key) != NULL;
}

static void assert_one_json_line(const char* out) {
    assert_int_equal(out[0], '{');
    assert_int_equal(count_lines(out), 1);
    assert_string_equal(out + strlen(out) - 2, "}\n");
}

#define ASSERT_REL(a, b) TU_ASSERT_NEAR(a, b, 1e-12 * fmax(1.0, fabs(b)))

/* ---- eval ---------------------------------------------------------------------- */

static void test_eval_energies_match_hand_values(void** state) {
    (void)state;
    tu_write_file("tri.obj", tri_obj);
    tu_write_file("tri_pos.csv", tri_pos);
    tu_result r =
        tu_run((const char*[]){"eval", "tri.obj", "--set", "bond.k=100", "--set", "angle.k=2", "--set",
                               "stretch_bend.k=3", "--set", "spring.k=5", "--positions", "tri_pos.csv", NULL});
    assert_int_equal(r.code, 0);
    assert_string_equal(r.err, "");
    assert_one_json_line(r.out);
    double angle, stretch_bend;
    corner_energies(2.0, 3.0, &angle, &stretch_bend);
    ASSERT_REL(json_number(r.out, "bond"), edge_energy(100.0));
    ASSERT_REL(json_number(r.out, "spring"), edge_energy(5.0));
    ASSERT_REL(json_number(r.out, "angle"), angle);
    ASSERT_REL(json_number(r.out, "stretch_bend"), stretch_bend);
    ASSERT_REL(json_number(r.out, "total"), edge_energy(105.0) + angle + stretch_bend);
    assert_false(json_has(r.out, "bend")); /* bend.k is 0 by default */
    assert_true(stretch_bend != 0.0 && angle > 0.0);
    tu_result_free(&r);
}

static void test_eval_terms_with_zero_constant_are_absent(void** state) {
    (void)state;
    tu_write_file("tri.obj", tri_obj);
    tu_result r = tu_run((const char*[]){"eval", "tri.obj", "--set", "angle.k=0", NULL});
    assert_int_equal(r.code, 0);
    assert_one_json_line(r.out);
    assert_true(json_has(r.out, "bond"));
    assert_false(json_has(r.out, "angle"));
    assert_false(json_has(r.out, "stretch_bend"));
    assert_false(json_has(r.out, "spring"));
    assert_false(json_has(r.out, "bend"));
    /* at the file's own positions every term is at rest */
    assert_true(json_number(r.out, "bond") == 0.0);
    assert_true(json_number(r.out, "total") == 0.0);
    tu_result_free(&r);
}

static void test_eval_bend_of_a_folded_square(void** state) {
    (void)state;
    tu_write_file("square.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
    tu_write_file("fold.csv", "x,y,z\n0,0,0\n1,0,0\n0,1,0\n1,1,0.3\n");
    tu_result r = tu_run((const char*[]){"eval", "square.obj", "--set", "bond.k=0", "--set", "angle.k=0", "--set",
                                         "bend.k=2", "--positions", "fold.csv", NULL});
    assert_int_equal(r.code, 0);
    vec q[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.3}};
    vec n1 = cross(sub(q[1], q[0]), sub(q[2], q[0]));
    vec n2 = cross(sub(q[3], q[1]), sub(q[2], q[1]));
    double phi = acos(dot(n1, n2) / (len(n1) * len(n2))); /* flat at rest: φ0 = 0 */
    ASSERT_REL(json_number(r.out, "bend"), 0.5 * 2.0 * phi * phi);
    ASSERT_REL(json_number(r.out, "total"), 0.5 * 2.0 * phi * phi);
    assert_false(json_has(r.out, "bond"));
    assert_false(json_has(r.out, "angle"));
    tu_result_free(&r);
}

static void test_eval_fast_agrees_with_the_reference(void** state) {
    (void)state;
    tu_write_file("tri.obj", tri_obj);
    tu_write_file("tri_pos.csv", tri_pos);
    const char* sets[] = {"eval",        "tri.obj",     "--set",  "angle.k=2", "--set", "stretch_bend.k=3",
                          "--positions", "tri_pos.csv", "--fast", NULL};
    tu_result fast = tu_run(sets);
    sets[8] = NULL;
    tu_result reference = tu_run(sets);
    assert_int_equal(fast.code, 0);
    assert_int_equal(reference.code, 0);
    const char* terms[] = {"bond", "angle", "stretch_bend", "total"};
    for (int t = 0; t < 4; t++) {
        double expected = json_number(reference.out, terms[t]);
        /* the fast kernels run in sb_real (float by default) */
        TU_ASSERT_NEAR(json_number(fast.out, terms[t]), expected, 1e-5 * fabs(expected));
    }
    assert_false(json_has(fast.out, "spring"));
    tu_result_free(&fast);
    tu_result_free(&reference);
}

/* A field of the forces CSV: a number that %.17g prints back unchanged. */
static double csv_number(char** cursor) {
    char* end;
    double value = strtod(*cursor, &end);
    assert_true(end != *cursor);
    char printed[40];
    snprintf(printed, sizeof printed, "%.17g", value);
    assert_int_equal(strncmp(*cursor, printed, (size_t)(end - *cursor)), 0);
    assert_int_equal(strlen(printed), (size_t)(end - *cursor));
    *cursor = end + (*end == ',' || *end == '\n');
    return value;
}

static void test_eval_forces_csv(void** state) {
    (void)state;
    tu_write_file("tri.obj", tri_obj);
    tu_write_file("tri_pos.csv", tri_pos);
    const double k = 100.0;
    tu_result r = tu_run((const char*[]){"eval", "tri.obj", "--set", "angle.k=0", "--positions", "tri_pos.csv",
                                         "--forces", "forces.csv", NULL});
    assert_int_equal(r.code, 0);
    char* csv = tu_read_file(tu_tmp_path("forces.csv"));
    assert_non_null(csv);
    assert_false(exists(tu_tmp_path("forces.csv.tmp")));
    assert_int_equal(count_lines(csv), 4);
    assert_int_equal(strncmp(csv, "id,fx,fy,fz\n", 12), 0);
    char* cursor = csv + 12;
    double sum[3] = {0, 0, 0};
    for (int i = 0; i < 3; i++) {
        assert_int_equal(csv_number(&cursor), i);
        /* bond i-j pulls i toward j with k (r − r0) when stretched */
        vec f = {0, 0, 0};
        for (int j = 0; j < 3; j++) {
            if (j == i) continue;
            vec d = sub(tri_moved[j], tri_moved[i]);
            double s = k * (len(d) - len(sub(tri_rest[j], tri_rest[i]))) / len(d);
            f = (vec){f.x + s * d.x, f.y + s * d.y, f.z + s * d.z};
        }
        double fx = csv_number(&cursor), fy = csv_number(&cursor), fz = csv_number(&cursor);
        TU_ASSERT_NEAR(fx, f.x, 1e-10);
        TU_ASSERT_NEAR(fy, f.y, 1e-10);
        TU_ASSERT_NEAR(fz, f.z, 1e-10);
        sum[0] += fx, sum[1] += fy, sum[2] += fz;
    }
    assert_int_equal(*cursor, '\0');
    for (int c = 0; c < 3; c++) TU_ASSERT_NEAR(sum[c], 0.0, 1e-10);
    free(csv);
    tu_result_free(&r);
}

/* An eval that must fail with exit 2 and leave no forces file. */
static void assert_eval_fails(const char* const* args, const char* message) {
    remove(tu_tmp_path("bad_forces.csv"));
    tu_result r = tu_run(args);
    assert_input_error(&r, message);
    assert_false(exists(tu_tmp_path("bad_forces.csv")));
    assert_false(exists(tu_tmp_path("bad_forces.csv.tmp")));
    tu_result_free(&r);
}

static void test_eval_bad_positions(void** state) {
    (void)state;
    tu_write_file("tri.obj", tri_obj);
    tu_write_file("short.csv", "x,y,z\n0,0,0\n1,0,0\n");
    tu_write_file("long.csv", "x,y,z\n0,0,0\n1,0,0\n0,1,0\n2,2,2\n");
    tu_write_file("word.csv", "x,y,z\n0,0,0\n1,zero,0\n0,1,0\n");
    tu_write_file("inf.csv", "x,y,z\n0,0,0\n1,0,0\n0,inf,0\n");
    tu_write_file("header.csv", "a,b,c\n0,0,0\n1,0,0\n0,1,0\n");
    assert_eval_fails(
        (const char*[]){"eval", "tri.obj", "--positions", "short.csv", "--forces", "bad_forces.csv", NULL},
        "short.csv:4: 2 rows, but the mesh has 3 vertices");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--positions", "long.csv", "--forces", "bad_forces.csv", NULL},
                      "long.csv:5: more rows than the mesh's 3 vertices");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--positions", "word.csv", "--forces", "bad_forces.csv", NULL},
                      "word.csv:3: column 2: expected a number, got 'zero'");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--positions", "inf.csv", "--forces", "bad_forces.csv", NULL},
                      "inf.csv:4: column 2: expected a finite number, got 'inf'");
    assert_eval_fails(
        (const char*[]){"eval", "tri.obj", "--positions", "header.csv", "--forces", "bad_forces.csv", NULL},
        "header.csv:1: expected the header 'x,y,z', got 'a,b,c'");
}

static void test_eval_bad_input(void** state) {
    (void)state;
    tu_write_file("tri.obj", tri_obj);
    tu_write_file("broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--set", "bond.kk=1", "--forces", "bad_forces.csv", NULL},
                      "--set bond.kk=1: unknown key 'bond.kk' (did you mean 'bond.k'?)");
    assert_eval_fails((const char*[]){"eval", "missing.obj", "--forces", "bad_forces.csv", NULL},
                      "missing.obj: cannot open: No such file or directory");
    assert_eval_fails(
        (const char*[]){"eval", "tri.obj", "--positions", "missing.csv", "--forces", "bad_forces.csv", NULL},
        "missing.csv: cannot open: No such file or directory");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--frobnicate", NULL},
                      "unknown option '--frobnicate' (see softbond eval --help)");
    assert_eval_fails((const char*[]){"eval", NULL}, "missing MESH (see softbond eval --help)");
    /* the mesh reader's own message names the line */
    tu_result r = tu_run((const char*[]){"eval", "broken.obj", NULL});
    assert_int_equal(r.code, 2);
    assert_int_equal(count_lines(r.err), 1);
    assert_int_equal(strncmp(r.err, "softbond: broken.obj:3: ", 24), 0);
    tu_result_free(&r);
}

/* ---- run ------------------------------------------------------------------------ */

static const char* const tiny_scene = "# a tiny sheet, pinned at its top corners\n"
                                      "mesh: {generator: sheet, nx: 4, ny: 3, width: 0.3, height: 0.2}\n"
                                      "bond: {k: 50}\n"
                                      "spring: {k: 10, damping: 0.01}\n"
                                      "mass: 0.01\n"
                                      "pin: top_corners\n"
                                      "dt: 0.001\n"
                                      "duration: 0.1\n"
                                      "frame_interval: 0.02\n";

/* Splits a CSV row into fields, returning how many there were. */
static int csv_fields(const char* row, double* values, int max) {
    int n = 0;
    for (const char* p = row; n < max; n++) {
        char* end;
        values[n] = strtod(p, &end);
        assert_true(end != p);
        if (*end != ',') return n + 1;
        p = end + 1;
    }
    return n;
}

static void assert_frames(const char* dir, int frames) {
    char name[400];
    for (int i = 0; i <= frames; i++) {
        snprintf(name, sizeof name, "%s/frame_%06d.vtu", dir, i);
        assert_int_equal(exists(name), i < frames);
        snprintf(name, sizeof name, "%s/frame_%06d.vtu.tmp", dir, i);
        assert_false(exists(name));
    }
    snprintf(name, sizeof name, "%s/frame_000000.vtu", dir);
    char* vtu = tu_read_file(name);
    /* 4 x 3 vertices, 3 x 2 quads of two triangles */
    assert_non_null(strstr(vtu, "<VTKFile type=\"UnstructuredGrid\""));
    assert_non_null(strstr(vtu, "NumberOfPoints=\"12\" NumberOfCells=\"12\""));
    assert_non_null(strstr(vtu, "Name=\"velocity\""));
    assert_non_null(strstr(vtu, "Name=\"force\""));
    free(vtu);
    snprintf(name, sizeof name, "%s/frames.pvd", dir);
    char* pvd = tu_read_file(name);
    assert_non_null(pvd);
    assert_int_equal(count_occurrences(pvd, "<DataSet "), 2 * frames); /* surface and bonds */
    assert_non_null(strstr(pvd, "file=\"frame_000000.vtu\""));
    assert_non_null(strstr(pvd, "part=\"1\" file=\"frame_000000_bonds.vtu\""));
    free(pvd);
}

enum {
    LOG_COLUMNS = 18, /* without colliders */
    LOG_STEPS = 11,
    LOG_SUBSTEPS,
    LOG_REJECTED,
    LOG_NEWTON,
    LOG_CG,
    LOG_UNCONVERGED,
    LOG_CONTACTS,
    LOG_MAX_COLUMNS = 64
};
static const char* const log_header =
    "time,kinetic,bond,angle,stretch_bend,spring,bend,corotated,membrane,gravity,total,"
    "steps,substeps,rejected,newton,cg,unconverged,contacts";

/* The header's collider columns after log_header: three per name. */
static void assert_collider_columns(const char* rest, const char* names) {
    char expected[600] = "";
    for (const char* p = names; *p;) {
        size_t n = strcspn(p, ",");
        size_t used = strlen(expected);
        snprintf(expected + used, sizeof expected - used, ",%.*s_fx,%.*s_fy,%.*s_fz", (int)n, p, (int)n, p, (int)n, p);
        p += n + (p[n] == ',');
    }
    assert_string_equal(rest, expected);
}

/* Any collider columns: a multiple of three, each triple <name>_fx, _fy,
 * _fz; then, where the model can break, the last column, broken. */
static int count_collider_columns(const char* rest) {
    int count = 0;
    for (const char* p = rest; *p; count++) {
        assert_int_equal(*p, ',');
        if (strcmp(p, ",broken") == 0 && count % 3 == 0) return count + 1;
        size_t n = strcspn(p + 1, ",");
        const char* suffixes[] = {"_fx", "_fy", "_fz"};
        assert_true(n > 3);
        assert_int_equal(strncmp(p + 1 + n - 3, suffixes[count % 3], 3), 0);
        p += 1 + n;
    }
    assert_int_equal(count % 3, 0);
    return count;
}

/* Reads the rows of DIR/log.csv (at most `max`, `stride` doubles apart)
 * under the exact header: log_header, then the force columns of the
 * colliders `names` (joined by commas; "" for none, NULL for any). Every
 * row has exactly the header's number of fields, returned in *columns. */
static int parse_log(const char* dir, const char* names, double* rows, int stride, int max, int* columns) {
    char name[400];
    snprintf(name, sizeof name, "%s/log.csv", dir);
    char* log = tu_read_file(name);
    assert_non_null(log);
    assert_int_equal(strncmp(log, log_header, strlen(log_header)), 0);
    char* newline = strchr(log, '\n');
    assert_non_null(newline);
    *newline = '\0';
    const char* rest = log + strlen(log_header);
    if (names) assert_collider_columns(rest, names);
    *columns = LOG_COLUMNS + count_collider_columns(rest);
    assert_true(*columns <= stride);
    int n = 0;
    for (const char* row = newline + 1; *row && n < max; row = strchr(row, '\n') + 1) {
        double values[LOG_MAX_COLUMNS + 1];
        assert_int_equal(csv_fields(row, values, LOG_MAX_COLUMNS + 1), *columns);
        memcpy(rows + (size_t)n++ * stride, values, (size_t)*columns * sizeof *values);
    }
    free(log);
    return n;
}

/* A log without colliders: each row exactly LOG_COLUMNS fields. */
static int read_log(const char* dir, double rows[][LOG_COLUMNS], int max) {
    int columns;
    return parse_log(dir, "", &rows[0][0], LOG_COLUMNS, max, &columns);
}

static void assert_log(const char* dir, int frames, double duration) {
    static double rows[64][LOG_COLUMNS];
    assert_int_equal(read_log(dir, rows, 64), frames);
    for (int i = 0; i < frames; i++) {
        /* total = kinetic + the seven terms + gravity */
        double sum = 0.0;
        for (int c = 1; c < 10; c++) sum += rows[i][c];
        TU_ASSERT_NEAR(rows[i][10], sum, 1e-12 * fmax(1.0, fabs(sum)));
    }
    for (int i = 0; i < frames; i++) assert_true(rows[i][LOG_CONTACTS] == 0.0); /* no colliders */
    const double* last = rows[frames - 1];
    assert_true(rows[0][0] == 0.0);
    TU_ASSERT_NEAR(last[0], duration, 1e-9);
    assert_true(last[1] > 0.0); /* moving */
    assert_true(last[9] < 0.0); /* fallen: −Σ m g·x < 0 */
}

static void test_run_writes_frames_and_log(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    tu_result r = tu_run((const char*[]){"run", "tiny.yaml", NULL});
    assert_int_equal(r.code, 0);
    assert_string_equal(r.err, ""); /* no progress bar off a terminal */
    assert_int_equal(count_lines(r.out), 1);
    assert_non_null(strstr(r.out, "out/tiny"));
    int frames = (int)floor(0.1 / 0.02 + 1e-9) + 1;
    assert_frames(tu_tmp_path("out/tiny"), frames);
    assert_log(tu_tmp_path("out/tiny"), frames, 0.1);
    tu_result_free(&r);
}

/* The solver's work since the previous frame: 20 steps of 1 ms per 20 ms
 * frame (none before frame 0); implicit Euler's Newton and CG iterations
 * (with CG: at least one of each per step, CG at least once per Newton
 * iteration);
 * adaptive sub-steps at least one per step, and many where dt = 20 ms is
 * far past Verlet's limit: with bonds of 5000 N/m on 0.01 kg vertices,
 * omega_max > 2 sqrt(k/m) = 1400 rad/s, 2/omega_max < 1.4 ms, so
 * 5 steps take well over 25 sub-steps. */
static void test_run_logs_solver_work(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    const char* const cases[][4] = {{"integrator=verlet", "dt=0.001", "bond.k=50", "implicit.solver=auto"},
                                    {"integrator=implicit_euler", "dt=0.001", "bond.k=50", "implicit.solver=cg"},
                                    {"adaptive=true", "dt=0.02", "bond.k=5000", "implicit.solver=auto"}};
    for (int c = 0; c < 3; c++) {
        tu_result r =
            tu_run((const char*[]){"run", "tiny.yaml", "--set", cases[c][0], "--set", cases[c][1], "--set", cases[c][2],
                                   "--set", cases[c][3], "--set", "output.frames=false", "--output", "work", NULL});
        if (r.code != 0) fail_msg("%s: %s", cases[c][0], r.err);
        tu_result_free(&r);
        double rows[8][LOG_COLUMNS];
        assert_int_equal(read_log(tu_tmp_path("work"), rows, 8), 6);
        for (int col = LOG_STEPS; col < LOG_COLUMNS; col++) assert_true(rows[0][col] == 0.0);
        double substeps = 0;
        for (int i = 1; i < 6; i++) {
            const double* w = rows[i];
            assert_true(w[LOG_STEPS] == (c == 2 ? 1.0 : 20.0));
            assert_true(w[LOG_UNCONVERGED] == 0.0);
            substeps += w[LOG_SUBSTEPS];
            if (c == 1) {
                assert_true(w[LOG_NEWTON] >= w[LOG_STEPS]);
                assert_true(w[LOG_CG] >= w[LOG_NEWTON]);
            } else {
                assert_true(w[LOG_NEWTON] == 0.0 && w[LOG_CG] == 0.0);
            }
            if (c == 2)
                assert_true(w[LOG_SUBSTEPS] >= w[LOG_STEPS]);
            else
                assert_true(w[LOG_SUBSTEPS] == w[LOG_STEPS] && w[LOG_REJECTED] == 0.0);
        }
        print_message("%s: %g sub-steps in 5 frames\n", cases[c][0], substeps);
        if (c == 2) TU_ASSERT_LE(25.0, substeps);
    }
}

/* Reads a point array of a .vtu frame, 3 values per point: the one named
 * `name`, or the positions for "Points". */
static int vtu_array(const char* path, const char* name, double* out, int max) {
    char* vtu = tu_read_file(path);
    assert_non_null(vtu);
    char tag[64];
    bool points = strcmp(name, "Points") == 0;
    snprintf(tag, sizeof tag, points ? "<Points>" : "Name=\"%s\"", name);
    const char* p = strstr(vtu, tag);
    assert_non_null(p);
    if (points) p = strstr(p, "<DataArray");
    p = strchr(p, '>') + 1;
    int n = 0;
    for (char* end; n < max; p = end, n++) {
        out[n] = strtod(p, &end);
        if (end == p) break;
    }
    free(vtu);
    return n;
}

/* load.force acts on the free vertex nearest load.at, and on no other: at
 * rest, without gravity, the elastic forces vanish and frame 0's total
 * force is the load alone; the vertex then moves along it. */
static void test_run_point_load(void** state) {
    (void)state;
    tu_write_file("load.yaml", "mesh: {generator: sheet, nx: 4, ny: 3, width: 0.3, height: 0.2}\n"
                               "bond: {k: 50}\nmass: 0.01\npin: left_edge\ngravity: [0, 0, 0]\n"
                               "load:\n  force: [0, 0.1, 0.25]\n  at: [0.29, 0.19, 0.05]\n"
                               "dt: 0.001\nduration: 0.02\nframe_interval: 0.01\n");
    tu_result r = tu_run((const char*[]){"run", "load.yaml", "--output", "load", NULL});
    if (r.code != 0) fail_msg("%s", r.err);
    /* 0.01, 0.01 and 0.05 m from the corner: √27 × 0.01 */
    assert_non_null(strstr(r.out, "softbond: load [0, 0.1, 0.25] N on vertex 11 at [0.3, 0.2, 0] m "
                                  "(0.0519615 m from load.at)\n"));
    tu_result_free(&r);
    enum { N = 12, CORNER = 11 }; /* the sheet's vertices row by row: [0.3, 0.2, 0] is the last */
    double force[3 * N + 1], start[3 * N + 1], end[3 * N + 1];
    assert_int_equal(vtu_array(tu_tmp_path("load/frame_000000.vtu"), "force", force, 3 * N + 1), 3 * N);
    for (int v = 0; v < N; v++) {
        double expected[3] = {0, v == CORNER ? 0.1 : 0, v == CORNER ? 0.25 : 0};
        for (int k = 0; k < 3; k++) TU_ASSERT_NEAR(force[3 * v + k], expected[k], 1e-5);
    }
    vtu_array(tu_tmp_path("load/frame_000000.vtu"), "Points", start, 3 * N + 1);
    vtu_array(tu_tmp_path("load/frame_000002.vtu"), "Points", end, 3 * N + 1);
    /* a free particle would move ½ (F/m) t² = 5 mm along z in 20 ms */
    TU_ASSERT_LE(1e-3, end[3 * CORNER + 2] - start[3 * CORNER + 2]);
    TU_ASSERT_LE(end[3 * CORNER + 2] - start[3 * CORNER + 2], 5e-3 * 1.001);
    TU_ASSERT_LE(0.0, end[3 * CORNER + 1] - start[3 * CORNER + 1]);

    /* a load on a held vertex is refused, naming the key's place */
    r = tu_run((const char*[]){"run", "load.yaml", "--set", "load.at=[0, 0.1, 0]", NULL});
    assert_input_error(&r, "--set load.at=[0, 0.1, 0]: 'load.at' [0, 0.1, 0]: the nearest vertex, 4 at "
                           "[0, 0.1, 0], is fixed, so the load would do nothing");
    tu_result_free(&r);
    r = tu_run((const char*[]){"run", "load.yaml", "--set", "load.force=[0, nan, 0]", NULL});
    assert_input_error(&r, "--set load.force=[0, nan, 0]: 'load.force' must be finite");
    tu_result_free(&r);
}

/* ---- contact --------------------------------------------------------------------- */

/* A 6 x 6 sheet of 0.36 kg held 2 cm above the floor z = 0, a sphere far
 * away that nothing touches; drag brings it to rest on the floor. */
static const char* const floor_scene = "mesh: {nx: 6, ny: 6, width: 0.3, height: 0.3, translate: [0, 0, 0.02]}\n"
                                       "bond: {k: 50}\nmass: 0.01\ndrag: 10\n"
                                       "dt: 0.001\nduration: 1\nframe_interval: 0.1\n"
                                       "output: {frames: false}\n"
                                       "colliders:\n"
                                       "  - {type: plane, name: floor}\n"
                                       "  - {type: sphere, center: [5, 5, 5], radius: 0.1}\n";

/* log.csv has the vertices in contact and three force columns per collider
 * (the force the collider received over the frame's last step,
 * sb_solver_contact_force): a sheet at rest on the floor presses it down
 * with its weight, every vertex touching it, and the sphere gets nothing. */
static void test_run_logs_contact(void** state) {
    (void)state;
    tu_write_file("floor.yaml", floor_scene);
    tu_result r = tu_run((const char*[]){"run", "floor.yaml", "--output", "floor", NULL});
    if (r.code != 0) fail_msg("%s", r.err);
    tu_result_free(&r);
    static double rows[16][LOG_MAX_COLUMNS];
    int columns;
    assert_int_equal(parse_log(tu_tmp_path("floor"), "floor,sphere1", &rows[0][0], LOG_MAX_COLUMNS, 16, &columns), 11);
    assert_int_equal(columns, LOG_COLUMNS + 6);
    enum { FX = LOG_COLUMNS, FY, FZ, SX, SY, SZ };
    for (int c = LOG_CONTACTS; c < columns; c++) assert_true(rows[0][c] == 0.0); /* frame 0: no step yet */
    const double weight = 36 * 0.01 * 9.81;
    for (int i = 8; i < 11; i++) {
        const double* row = rows[i];
        print_message("t = %.1f s: %g contacts, floor force [%g, %g, %g] N\n", row[0], row[LOG_CONTACTS], row[FX],
                      row[FY], row[FZ]);
        assert_true(row[LOG_CONTACTS] == 36.0);
        /* the floor receives the sheet's weight, downwards */
        TU_ASSERT_NEAR(row[FZ], -weight, 1e-3 * weight);
        TU_ASSERT_NEAR(row[FX], 0.0, 1e-3 * weight);
        TU_ASSERT_NEAR(row[FY], 0.0, 1e-3 * weight);
        assert_true(row[SX] == 0.0 && row[SY] == 0.0 && row[SZ] == 0.0);
    }
    /* before it lands nothing touches */
    assert_true(rows[0][LOG_CONTACTS] == 0.0);
}

/* --set colliders=... is a key like any other: it replaces the file's list. */
static void test_run_set_colliders(void** state) {
    (void)state;
    tu_write_file("floor.yaml", floor_scene);
    tu_result r = tu_run((const char*[]){"run", "floor.yaml", "--set", "colliders=[{type: plane}]", "--set",
                                         "contact.thickness=0.001", "--set", "duration=0.3", "--output", "set", NULL});
    if (r.code != 0) fail_msg("%s", r.err);
    tu_result_free(&r);
    static double rows[8][LOG_MAX_COLUMNS];
    int columns;
    assert_int_equal(parse_log(tu_tmp_path("set"), "plane0", &rows[0][0], LOG_MAX_COLUMNS, 8, &columns), 4);
    TU_ASSERT_LE(rows[3][LOG_COLUMNS + 2], -0.5); /* landed: the plane is pressed down */
    assert_true(rows[3][LOG_CONTACTS] > 0.0);
    r = tu_run((const char*[]){"run", "floor.yaml", "--set", "colliders=[]", "--set", "duration=0.1", "--output",
                               "none", NULL});
    if (r.code != 0) fail_msg("%s", r.err);
    tu_result_free(&r);
    double plain[4][LOG_COLUMNS];
    assert_int_equal(read_log(tu_tmp_path("none"), plain, 4), 2);
}

/* A scene whose `colliders:` is on line 2 and whose entries (`entries`,
 * from line 3) are wrong: exit 2, nothing written, one line naming the
 * file, the line and the key. */
static void assert_colliders_fail(const char* entries, const char* rest) {
    char text[1000], message[500];
    snprintf(text, sizeof text, "mesh: {nx: 4, ny: 3}\ncolliders:%s%s", entries[0] == ' ' ? "\n" : " ", entries);
    tu_write_file("bad_colliders.yaml", text);
    snprintf(message, sizeof message, "bad_colliders.yaml:%s", rest);
    tu_result r = tu_run((const char*[]){"run", "bad_colliders.yaml", "--output", "never", NULL});
    assert_input_error(&r, message);
    assert_false(exists(tu_tmp_path("never")));
    tu_result_free(&r);
}

static void test_run_bad_colliders(void** state) {
    (void)state;
    /* the list and its entries */
    assert_colliders_fail("plane\n", "2: 'colliders' expects a sequence of maps, got 'plane'");
    assert_colliders_fail("  - plane\n", "3: 'colliders[0]' expects a map, got 'plane'");
    assert_colliders_fail("  - {type: plane}\n  - radius: 1\n",
                          "4: 'colliders[1].type' is not set (plane, sphere, capsule, box or mesh)");
    assert_colliders_fail("  - type: cube\n",
                          "3: 'colliders[0].type' must be plane, sphere, capsule, box or mesh, got 'cube'");
    assert_colliders_fail("  - type: [plane]\n", "3: 'colliders[0].type' expects a string, got a sequence of 1");
    /* keys: unknown (dynamic colliders are not there yet), another shape's, missing, twice */
    assert_colliders_fail("  - type: plane\n    mass: 1\n", "4: unknown key 'colliders[0].mass'");
    assert_colliders_fail("  - type: sphere\n    center: [0, 0, 0]\n    radius: 1\n    velocity: [0, 0, 1]\n",
                          "6: unknown key 'colliders[0].velocity'");
    assert_colliders_fail("  - type: plane\nself_collision: true\n",
                          "4: 'self_collision' needs 'contact.thickness' > 0 (the distance kept between surfaces)");
    assert_colliders_fail("  - type: plane\n    radius: 1\n",
                          "4: 'colliders[0].radius' does not apply to a plane (its shape's keys: point, normal)");
    assert_colliders_fail("  - {type: sphere, center: [0, 0, 0], radius: 1, rotate: [0, 0, 1]}\n",
                          "3: 'colliders[0].rotate' does not apply to a sphere (its shape's keys: center, radius, "
                          "footprint)");
    assert_colliders_fail("  - type: box\n    center: [0, 0, 0]\n    half_extents: [1, 1, 1]\n    normal: [0, 0, 1]\n",
                          "6: 'colliders[0].normal' does not apply to a box (its shape's keys: center, "
                          "half_extents, rotate, footprint)");
    assert_colliders_fail("  - type: sphere\n    center: [0, 0, 0]\n",
                          "3: 'colliders[0].radius' is not set (a sphere needs center and radius)");
    assert_colliders_fail("  - {type: plane}\n  - type: capsule\n    a: [0, 0, 0]\n    radius: 0.1\n",
                          "4: 'colliders[1].b' is not set (a capsule needs a, b and radius)");
    assert_colliders_fail("  - type: box\n    center: [0, 0, 0]\n",
                          "3: 'colliders[0].half_extents' is not set (a box needs center and half_extents)");
    assert_colliders_fail("  - type: plane\n    friction: 0.1\n    friction: 0.2\n",
                          "5: duplicate key 'colliders[0].friction' (first set at line 4)");
    /* types and ranges */
    assert_colliders_fail("  - type: sphere\n    center: [0, 0]\n    radius: 1\n",
                          "4: 'colliders[0].center' expects 3 numbers: [x, y, z] or x,y,z, got a sequence of 2");
    assert_colliders_fail("  - type: sphere\n    center: [0, x, 0]\n    radius: 1\n",
                          "4: 'colliders[0].center' expects a number, got 'x'");
    assert_colliders_fail("  - type: sphere\n    center: [0, 0, 0]\n    radius: big\n",
                          "5: 'colliders[0].radius' expects a number, got 'big'");
    assert_colliders_fail("  - type: sphere\n    center: [0, 0, 0]\n    radius: -1\n",
                          "5: 'colliders[0].radius' must be > 0, got -1");
    assert_colliders_fail("  - type: capsule\n    a: [0, 0, 0]\n    b: [1, 0, 0]\n    radius: 0\n",
                          "6: 'colliders[0].radius' must be > 0, got 0");
    assert_colliders_fail("  - type: box\n    center: [0, 0, 0]\n    half_extents: [1, 0, 1]\n",
                          "5: 'colliders[0].half_extents' must be > 0, got [1, 0, 1]");
    assert_colliders_fail("  - {type: box, center: [0, 0, 0], half_extents: [1, 1, 1], rotate: [0, inf, 0]}\n",
                          "3: 'colliders[0].rotate' must be finite");
    assert_colliders_fail("  - type: plane\n    point: [0, nan, 0]\n", "4: 'colliders[0].point' must be finite");
    assert_colliders_fail("  - type: plane\n    normal: [0, 0, 0]\n", "4: 'colliders[0].normal' must not be [0, 0, 0]");
    assert_colliders_fail("  - type: plane\n    friction: -0.1\n", "4: 'colliders[0].friction' must be >= 0, got -0.1");
    assert_colliders_fail("  - type: plane\n    friction: 0.5\n    static_friction: 0.1\n",
                          "5: 'colliders[0].static_friction' (0.1) must be >= 'friction' (0.5)");
    assert_colliders_fail("  - type: plane\n    restitution: 1.5\n",
                          "4: 'colliders[0].restitution' must be in [0, 1], got 1.5");
    assert_colliders_fail("  - type: plane\n    thickness: -0.01\n",
                          "4: 'colliders[0].thickness' must be >= 0, got -0.01");
    assert_colliders_fail("  - type: plane\n    interpolation: cubic\n",
                          "4: 'colliders[0].interpolation' must be linear or smooth, got 'cubic'");
    /* the path */
    assert_colliders_fail(
        "  - type: plane\n    path: {time: 0}\n",
        "4: 'colliders[0].path' expects a sequence of keyframes {time, translate, rotate}, got a map");
    assert_colliders_fail("  - type: plane\n    path:\n      - 0\n",
                          "5: 'colliders[0].path[0]' expects a map {time, translate, rotate}, got '0'");
    assert_colliders_fail("  - type: plane\n    path:\n      - {time: 0}\n      - {translate: [0, 0, 1]}\n",
                          "6: 'colliders[0].path[1].time' is not set");
    assert_colliders_fail("  - type: plane\n    path:\n      - {time: 0, scale: 2}\n",
                          "5: unknown key 'colliders[0].path[0].scale'");
    assert_colliders_fail("  - type: plane\n    path:\n      - {time: 1}\n      - {time: 0.5}\n",
                          "6: 'colliders[0].path[1].time' (0.5) must be > the time before it (1)");
    assert_colliders_fail(
        "  - type: plane\n    path:\n      - time: 0\n        rotate: [0, 0]\n",
        "6: 'colliders[0].path[0].rotate' expects 3 numbers: [x, y, z] or x,y,z, got a sequence of 2");
    /* names: they head columns of log.csv */
    assert_colliders_fail("  - type: plane\n    name: my floor\n",
                          "4: 'colliders[0].name' must be 1 to 63 letters, digits, '_', '-' or '.', got 'my floor'");
    assert_colliders_fail("  - {type: plane, name: floor}\n  - {type: plane, name: floor}\n",
                          "4: 'colliders[1].name': 'floor' is already colliders[0]'s name");
    assert_colliders_fail("  - {type: plane, name: sphere1}\n  - {type: sphere, center: [0, 0, 0], radius: 1}\n",
                          "4: 'colliders[1]': its default name 'sphere1' is already colliders[0]'s name");
    /* contact.thickness */
    tu_write_file("bad_thickness.yaml", "contact:\n  thickness: -1\n");
    tu_result r = tu_run((const char*[]){"run", "bad_thickness.yaml", "--output", "never", NULL});
    assert_input_error(&r, "bad_thickness.yaml:2: 'contact.thickness' must be >= 0, got -1");
    tu_result_free(&r);
    /* --set is checked the same way and named as the place */
    tu_write_file("floor.yaml", floor_scene);
    r = tu_run((const char*[]){"run", "floor.yaml", "--set", "colliders=[{type: plane, radius: 1}]", "--output",
                               "never", NULL});
    assert_input_error(&r, "--set colliders=[{type: plane, radius: 1}]: 'colliders[0].radius' does not apply to a "
                           "plane (its shape's keys: point, normal)");
    tu_result_free(&r);
    r = tu_run((const char*[]){"run", "floor.yaml", "--set", "colliders={type: plane}", "--output", "never", NULL});
    assert_input_error(&r, "--set colliders={type: plane}: 'colliders' expects a sequence of maps, got a map");
    tu_result_free(&r);
    assert_false(exists(tu_tmp_path("never")));
}

/* How long a committed scene runs in the test: 10 ms, or long enough for
 * what the scene is about to have begun (a needle touching, a ball
 * reaching the net) where that takes longer. */
static const char* scene_test_duration(const char* name) {
    static const char* const longer[][2] = {{"falling_rock.yaml", "0.33"},      {"syringe.yaml", "0.7"},
                                            {"moon_hook.yaml", "0.3"},          {"film_bounce.yaml", "0.34"},
                                            {"film_map_on_table.yaml", "0.25"}, {"net.yaml", "0.6"}};
    for (size_t i = 0; i < sizeof longer / sizeof longer[0]; i++)
        if (strcmp(name, longer[i][0]) == 0) return longer[i][1];
    return "0.01";
}

/* SCENE shortened, on THREADS threads, into DIR: log.csv and one .vtu
 * frame, the last state. */
static void run_committed(const char* scene, const char* duration, const char* threads, const char* dir) {
    char path[600], length[40], interval[40];
    snprintf(path, sizeof path, SB_SOURCE_DIR "/scenes/%s", scene);
    snprintf(length, sizeof length, "duration=%s", duration);
    snprintf(interval, sizeof interval, "frame_interval=%s", duration);
    tu_result r = tu_run(
        (const char*[]){"run", path, "--set", length, "--set", interval, "--threads", threads, "--output", dir, NULL});
    if (r.code != 0) fail_msg("%s: %s", scene, r.err);
    tu_result_free(&r);
}

static char* read_output(const char* dir, const char* file) {
    char name[400];
    snprintf(name, sizeof name, "%s/%s", tu_tmp_path(dir), file);
    char* text = tu_read_file(name);
    if (!text) fail_msg("%s is missing", name);
    return text;
}

/* Every scene under scenes/ runs as committed, shortened, and gives the
 * same log (every energy to 17 digits at every frame) and the same last
 * frame on 1 and 2 threads. The haptics scene's servo thread runs on the
 * wall clock, so only that it runs is checked there. Under the sanitizers
 * each scene runs once, on 2 threads, for its memory errors: the two
 * runs' equality is the unsanitized builds' to check. */
static void test_committed_scenes_run(void** state) {
    (void)state;
    DIR* dir = opendir(SB_SOURCE_DIR "/scenes");
    assert_non_null(dir);
    int scenes = 0;
    for (struct dirent* e; (e = readdir(dir));) {
        size_t n = strlen(e->d_name);
        if (n < 6 || strcmp(e->d_name + n - 5, ".yaml") != 0) continue;
        const char* duration = scene_test_duration(e->d_name);
        const char* first = SB_TEST_SANITIZED ? "2" : "1";
        run_committed(e->d_name, duration, first, "committed1");
        double rows[2][LOG_MAX_COLUMNS];
        int columns;
        assert_true(parse_log(tu_tmp_path("committed1"), NULL, &rows[0][0], LOG_MAX_COLUMNS, 2, &columns) >= 1);
        scenes++;
        if (SB_TEST_SANITIZED || strncmp(e->d_name, "haptics", 7) == 0) continue;
        run_committed(e->d_name, duration, "2", "committed2");
        const char* files[] = {"log.csv", "frame_000001.vtu"};
        for (int f = 0; f < 2; f++) {
            char* one = read_output("committed1", files[f]);
            char* two = read_output("committed2", files[f]);
            if (strcmp(one, two) != 0) fail_msg("%s: %s differs between 1 and 2 threads", e->d_name, files[f]);
            free(one);
            free(two);
        }
        print_message("%s: the first %s s the same on 1 and 2 threads\n", e->d_name, duration);
    }
    closedir(dir);
    assert_true(scenes >= 7); /* default, sudhamani_sheet and the five contact scenes at least */
}

/* The Sudhamani scene's comment says it settles within its duration: the
 * kinetic energy at the end is below 1e-6 of its peak. */
static void test_sudhamani_scene_settles(void** state) {
    (void)state;
    tu_result r = tu_run((const char*[]){"run", SB_SOURCE_DIR "/scenes/sudhamani_sheet.yaml", "--set",
                                         "output.frames=false", "--output", "sudhamani", NULL});
    if (r.code != 0) fail_msg("%s", r.err);
    tu_result_free(&r);
    static double rows[200][LOG_COLUMNS];
    int n = read_log(tu_tmp_path("sudhamani"), rows, 200);
    assert_int_equal(n, 126);
    double peak = 0;
    for (int i = 0; i < n; i++) peak = fmax(peak, rows[i][1]);
    print_message("sudhamani scene: peak kinetic energy %.3g J, at the end %.3g J\n", peak, rows[n - 1][1]);
    assert_true(peak > 0);
    TU_ASSERT_LE(rows[n - 1][1], 1e-6 * peak);
}

static void test_run_set_and_output(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    tu_result r = tu_run((const char*[]){"run", "tiny.yaml", "--set", "duration=0.05", "--set", "output.frames=false",
                                         "--output", "custom/dir", "--threads", "1", NULL});
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "custom/dir"));
    assert_log(tu_tmp_path("custom/dir"), 4, 0.05); /* 0, 0.02, 0.04 and the end state */
    assert_false(exists(tu_tmp_path("custom/dir/frames.pvd")));
    assert_false(exists(tu_tmp_path("custom/dir/frame_000000.vtu")));
    tu_result_free(&r);
}

/* A run that must fail with exit 2 before creating its output folder. */
static void assert_run_fails(const char* env_name, const char* env_value, const char* const* args,
                             const char* message) {
    tu_result r = tu_run_env(env_name, env_value, args);
    assert_input_error(&r, message);
    assert_false(exists(tu_tmp_path("never")));
    tu_result_free(&r);
}

static void test_run_bad_input_creates_nothing(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    tu_write_file("typo.yaml", "mesh: {nx: 4, ny: 3}\nbond:\n  kk: 1\n");
    tu_write_file("range.yaml", "mesh: {nx: 4, ny: 3}\nfixed: [3, 12]\n");
    assert_run_fails(NULL, NULL, (const char*[]){"run", "typo.yaml", "--output", "never", NULL},
                     "typo.yaml:3: unknown key 'bond.kk' (did you mean 'bond.k'?)");
    assert_run_fails(NULL, NULL, (const char*[]){"run", "range.yaml", "--output", "never", NULL},
                     "range.yaml:2: 'fixed': vertex 12 out of range (the mesh has 12 vertices)");
    assert_run_fails(NULL, NULL, (const char*[]){"run", "nothere.yaml", "--output", "never", NULL},
                     "nothere.yaml: cannot open: No such file or directory");
    assert_run_fails(NULL, NULL, (const char*[]){"run", "tiny.yaml", "--set", "dt=0", "--output", "never", NULL},
                     "--set dt=0: 'dt' must be > 0, got 0");
    assert_run_fails("SOFTBOND_THREADS", "many", (const char*[]){"run", "tiny.yaml", "--output", "never", NULL},
                     "SOFTBOND_THREADS: expected an integer in [1, 1024], got 'many'");
    assert_run_fails(NULL, NULL, (const char*[]){"run", "tiny.yaml", "--threads", "-2", "--output", "never", NULL},
                     "--threads: expected an integer in [0, 1024], got '-2'");
}

static void test_run_solver_failure_exits_3(void** state) {
    (void)state;
    tu_write_file("tiny.yaml", tiny_scene);
    tu_result r = tu_run((const char*[]){"run", "tiny.yaml", "--set", "bond.k=1e6", "--set", "dt=0.01", "--set",
                                         "frame_interval=0.01", "--output", "unstable", NULL});
    assert_int_equal(r.code, 3);
    assert_int_equal(count_lines(r.err), 1);
    assert_int_equal(strncmp(r.err, "softbond: ", 10), 0);
    /* the frames up to the failure stay readable */
    assert_true(exists(tu_tmp_path("unstable/log.csv")));
    tu_result_free(&r);
}

static void test_help_and_version(void** state) {
    (void)state;
    tu_result r = tu_run((const char*[]){"--version", NULL});
    assert_int_equal(r.code, 0);
    assert_int_equal(strncmp(r.out, "softbond ", 9), 0);
    assert_non_null(strstr(r.out, SB_VERSION_STRING));
    tu_result_free(&r);
    r = tu_run((const char*[]){"run", "--help", NULL});
    assert_int_equal(r.code, 0);
    assert_int_equal(strncmp(r.out, "usage: softbond run SCENE.yaml", 30), 0);
    assert_non_null(strstr(r.out, "colliders: a list of {type: plane | sphere | capsule | box"));
    assert_non_null(strstr(r.out, "contact.thickness"));
    assert_non_null(strstr(r.out, "<name>_fx"));
    tu_result_free(&r);
    r = tu_run((const char*[]){"--help", NULL});
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "softbond eval MESH"));
    tu_result_free(&r);
    r = tu_run((const char*[]){"fly", NULL});
    assert_input_error(&r, "unknown command 'fly' (see softbond --help)");
    tu_result_free(&r);
}

/* A thickness larger than the body (contact.thickness:
 * 10, metres, in a scene of centimetres) is refused with the key's place;
 * it used to run at 1.3 s a step in silence. */
static void test_thickness_against_the_body_refused(void** state) {
    (void)state;
    tu_assert_scene_fails("mesh: {generator: sheet, nx: 4, ny: 3, width: 0.3, height: 0.2}\n"
                          "duration: 0.01\ncontact:\n  thickness: 10\n",
                          "bad.yaml:4: 'contact.thickness' 10 m is more than the body's whole extent (0.361 m, its "
                          "bounding box's diagonal): a slip of units? (lengths are in metres)");
    tu_assert_scene_fails("mesh: {generator: sheet, nx: 4, ny: 3, width: 0.3, height: 0.2}\n"
                          "duration: 0.01\ncolliders:\n  - {type: plane, name: floor, thickness: 5}\n",
                          "collider 'floor': thickness 5 m is more than the body's whole extent (0.361 m");
    tu_assert_scene_fails(
        "mesh: {generator: sheet, nx: 4, ny: 3, width: 0.3, height: 0.2}\n"
        "duration: 0.01\ncolliders:\n  - {type: sphere, name: ball, center: [0, 0, -51], radius: 50}\n",
        "collider 'ball': radius 50 m is more than 100 times the body's whole extent (0.361 m");
    tu_assert_scene_fails("mesh: {generator: sheet, nx: 4, ny: 3, width: 0.3, height: 0.2}\n"
                          "duration: 0.01\ncolliders:\n  - {type: box, name: table, center: [0, 0, -41], "
                          "half_extents: [40, 40, 40]}\n",
                          "collider 'table': half extent 40 m is more than 100 times the body's whole extent (0.361 m");
    tu_assert_scene_fails("mesh: {generator: sheet, nx: 4, ny: 3, width: 0.3, height: 0.2}\n"
                          "duration: 0.01\ncolliders:\n  - {type: capsule, name: rod, a: [-50, 0, -1], b: [50, 0, -1], "
                          "radius: 0.01}\n",
                          "collider 'rod': length 100 m is more than 100 times the body's whole extent (0.361 m");
}

/* Messages that name their place and their real cause. */
static void test_messages_name_place_and_cause(void** state) {
    (void)state;
    /* --output FILE: it said 'File exists' */
    tu_write_file("tiny.yaml", tiny_scene);
    tu_write_file("afile", "not a folder\n");
    tu_result r = tu_run((const char*[]){"run", "tiny.yaml", "--output", "afile", NULL});
    assert_int_equal(r.code, 1); /* an output that cannot be written */
    assert_string_equal(r.err, "softbond: afile: cannot create the output folder: it, or a folder above it, is a file "
                               "(not a folder)\n");
    tu_result_free(&r);
    /* a mesh at 1e20 m: it said 'an edge collapsed', naming no file (float overflow was the cause); a
     * double build overflows further out */
    const char* far = sizeof(sb_real) == 4 ? "1e20" : "1e200";
    char obj[200], expected[200];
    snprintf(obj, sizeof obj, "v 0 0 0\nv %s 0 0\nv 0 %s 0\nv %s %s 0\nf 1 2 3\nf 2 4 3\n", far, far, far, far);
    tu_write_file("far.obj", obj);
    snprintf(expected, sizeof expected, "bad.yaml:4: far.obj: vertex 1 at (%s, 0, 0) m, beyond ",
             sizeof(sb_real) == 4 ? "1e+20" : "1e+200");
    tu_assert_scene_fails("duration: 0.01\nmesh:\n  generator: file\n  file: far.obj\n", expected);
    /* a model's error: the scene's file and line too (it named only the mesh file) */
    tu_write_file("flat.obj", "v 0 0 0\nv 0 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
    tu_assert_scene_fails("duration: 0.01\nmesh:\n  generator: file\n  file: flat.obj\n",
                          "bad.yaml:4: flat.obj: bond 0 (0, 1): rest length 0 m must be positive");
    tu_assert_scene_fails("duration: 0.01\nmesh: {generator: sheet, nx: 2, ny: 2, width: 0.3, height: 1e-30}\n",
                          "bad.yaml:2: triangle 0 (0, 1, 3): zero area");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_thickness_against_the_body_refused),
        cmocka_unit_test(test_messages_name_place_and_cause),
        cmocka_unit_test(test_eval_energies_match_hand_values),
        cmocka_unit_test(test_eval_terms_with_zero_constant_are_absent),
        cmocka_unit_test(test_eval_bend_of_a_folded_square),
        cmocka_unit_test(test_eval_forces_csv),
        cmocka_unit_test(test_eval_fast_agrees_with_the_reference),
        cmocka_unit_test(test_eval_bad_positions),
        cmocka_unit_test(test_eval_bad_input),
        cmocka_unit_test(test_run_writes_frames_and_log),
        cmocka_unit_test(test_run_set_and_output),
        cmocka_unit_test(test_run_bad_input_creates_nothing),
        cmocka_unit_test(test_run_solver_failure_exits_3),
        cmocka_unit_test(test_run_logs_solver_work),
        cmocka_unit_test(test_run_point_load),
        cmocka_unit_test(test_run_logs_contact),
        cmocka_unit_test(test_run_set_colliders),
        cmocka_unit_test(test_run_bad_colliders),
        cmocka_unit_test(test_committed_scenes_run),
        cmocka_unit_test(test_sudhamani_scene_settles),
        cmocka_unit_test(test_help_and_version),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
