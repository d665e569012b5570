/* The `softbond` program, run as a child process in a temporary directory:
 * `eval` energies and forces against values computed here by hand from the
 * definitions (DESIGN.md), absent terms, the --forces CSV, bad input (exit
 * 2, one line on stderr, no output left behind), and `run` writing
 * frames.pvd, the .vtu frames and log.csv with one row per frame. */
#define _POSIX_C_SOURCE 200809L

#include <stdio.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/test_util.h"

static char tmp_dir[256];

static int setup_dir(void** state) {
    (void)state;
    const char* base = getenv("TMPDIR");
    snprintf(tmp_dir, sizeof tmp_dir, "%s/sb_test_cli_XXXXXX", base && *base ? base : "/tmp");
    return mkdtemp(tmp_dir) ? 0 : -1;
}

/* Removes the files the tests made (at most two levels deep). */
static int teardown_dir(void** state) {
    (void)state;
    char command[400];
    snprintf(command, sizeof command, "rm -rf '%s'", tmp_dir);
    return system(command) == 0 ? 0 : -1;
}

/* tmp_dir/name in a rotating set of buffers, enough for one call's paths. */
static const char* tmp_path(const char* name) {
    static char buffers[8][400];
    static int next;
    char* path = buffers[next++ % 8];
    snprintf(path, sizeof buffers[0], "%s/%s", tmp_dir, name);
    return path;
}

static void write_file(const char* name, const char* text) {
    FILE* f = fopen(tmp_path(name), "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* The whole file, or NULL when it does not exist. Caller frees. */
static char* read_file(const char* path) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char* text = malloc((size_t)size + 1);
    assert_non_null(text);
    assert_int_equal(fread(text, 1, (size_t)size, f), (size_t)size);
    text[size] = '\0';
    fclose(f);
    return text;
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

/* What a run of the program left: exit code, stdout, stderr. */
typedef struct result {
    int code;
    char* out;
    char* err;
} result;

static void result_free(result* r) {
    free(r->out);
    free(r->err);
}

/* Runs softbond with args (NULL-terminated) in tmp_dir, with the variable
 * env_name (unless NULL) set to env_value in its environment. */
static result run_env(const char* env_name, const char* env_value, const char* const* args) {
    const char* argv[32] = {SB_PROGRAM};
    int argc = 1;
    for (; args[argc - 1]; argc++) argv[argc] = args[argc - 1];
    argv[argc] = NULL;
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        bool ok = chdir(tmp_dir) == 0 && freopen("stdout.txt", "w", stdout) &&
                  freopen("stderr.txt", "w", stderr);
        if (ok && env_name) ok = setenv(env_name, env_value, 1) == 0;
        if (ok) execv(SB_PROGRAM, (char* const*)argv);
        _exit(127);
    }
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    result r = {WEXITSTATUS(status), read_file(tmp_path("stdout.txt")),
                read_file(tmp_path("stderr.txt"))};
    assert_int_not_equal(r.code, 127);
    assert_non_null(r.out);
    assert_non_null(r.err);
    return r;
}

static result run(const char* const* args) {
    return run_env(NULL, NULL, args);
}

/* Exit 2, nothing on stdout, and exactly `message` on stderr. */
static void assert_input_error(const result* r, const char* message) {
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

static vec sub(vec a, vec b) {
    return (vec){a.x - b.x, a.y - b.y, a.z - b.z};
}

static double dot(vec a, vec b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

static double len(vec a) {
    return sqrt(dot(a, a));
}

static vec cross(vec a, vec b) {
    return (vec){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

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
    write_file("tri.obj", tri_obj);
    write_file("tri_pos.csv", tri_pos);
    result r = run((const char*[]){"eval", "tri.obj", "--set", "bond.k=100", "--set", "angle.k=2",
                                   "--set", "stretch_bend.k=3", "--set", "spring.k=5",
                                   "--positions", "tri_pos.csv", NULL});
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
    result_free(&r);
}

static void test_eval_terms_with_zero_constant_are_absent(void** state) {
    (void)state;
    write_file("tri.obj", tri_obj);
    result r = run((const char*[]){"eval", "tri.obj", "--set", "angle.k=0", NULL});
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
    result_free(&r);
}

static void test_eval_bend_of_a_folded_square(void** state) {
    (void)state;
    write_file("square.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n");
    write_file("fold.csv", "x,y,z\n0,0,0\n1,0,0\n0,1,0\n1,1,0.3\n");
    result r = run((const char*[]){"eval", "square.obj", "--set", "bond.k=0", "--set", "angle.k=0",
                                   "--set", "bend.k=2", "--positions", "fold.csv", NULL});
    assert_int_equal(r.code, 0);
    vec q[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0.3}};
    vec n1 = cross(sub(q[1], q[0]), sub(q[2], q[0]));
    vec n2 = cross(sub(q[3], q[1]), sub(q[2], q[1]));
    double phi = acos(dot(n1, n2) / (len(n1) * len(n2))); /* flat at rest: φ0 = 0 */
    ASSERT_REL(json_number(r.out, "bend"), 0.5 * 2.0 * phi * phi);
    ASSERT_REL(json_number(r.out, "total"), 0.5 * 2.0 * phi * phi);
    assert_false(json_has(r.out, "bond"));
    assert_false(json_has(r.out, "angle"));
    result_free(&r);
}

static void test_eval_fast_agrees_with_the_reference(void** state) {
    (void)state;
    write_file("tri.obj", tri_obj);
    write_file("tri_pos.csv", tri_pos);
    const char* sets[] = {"eval", "tri.obj", "--set", "angle.k=2", "--set", "stretch_bend.k=3",
                          "--positions", "tri_pos.csv", "--fast", NULL};
    result fast = run(sets);
    sets[8] = NULL;
    result reference = run(sets);
    assert_int_equal(fast.code, 0);
    assert_int_equal(reference.code, 0);
    const char* terms[] = {"bond", "angle", "stretch_bend", "total"};
    for (int t = 0; t < 4; t++) {
        double expected = json_number(reference.out, terms[t]);
        /* the fast kernels run in sb_real (float by default) */
        TU_ASSERT_NEAR(json_number(fast.out, terms[t]), expected, 1e-5 * fabs(expected));
    }
    assert_false(json_has(fast.out, "spring"));
    result_free(&fast);
    result_free(&reference);
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
    write_file("tri.obj", tri_obj);
    write_file("tri_pos.csv", tri_pos);
    const double k = 100.0;
    result r = run((const char*[]){"eval", "tri.obj", "--set", "angle.k=0", "--positions",
                                   "tri_pos.csv", "--forces", "forces.csv", NULL});
    assert_int_equal(r.code, 0);
    char* csv = read_file(tmp_path("forces.csv"));
    assert_non_null(csv);
    assert_false(exists(tmp_path("forces.csv.tmp")));
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
    result_free(&r);
}

/* An eval that must fail with exit 2 and leave no forces file. */
static void assert_eval_fails(const char* const* args, const char* message) {
    remove(tmp_path("bad_forces.csv"));
    result r = run(args);
    assert_input_error(&r, message);
    assert_false(exists(tmp_path("bad_forces.csv")));
    assert_false(exists(tmp_path("bad_forces.csv.tmp")));
    result_free(&r);
}

static void test_eval_bad_positions(void** state) {
    (void)state;
    write_file("tri.obj", tri_obj);
    write_file("short.csv", "x,y,z\n0,0,0\n1,0,0\n");
    write_file("long.csv", "x,y,z\n0,0,0\n1,0,0\n0,1,0\n2,2,2\n");
    write_file("word.csv", "x,y,z\n0,0,0\n1,zero,0\n0,1,0\n");
    write_file("inf.csv", "x,y,z\n0,0,0\n1,0,0\n0,inf,0\n");
    write_file("header.csv", "a,b,c\n0,0,0\n1,0,0\n0,1,0\n");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--positions", "short.csv", "--forces",
                                      "bad_forces.csv", NULL},
                      "short.csv:4: 2 rows, but the mesh has 3 vertices");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--positions", "long.csv", "--forces",
                                      "bad_forces.csv", NULL},
                      "long.csv:5: more rows than the mesh's 3 vertices");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--positions", "word.csv", "--forces",
                                      "bad_forces.csv", NULL},
                      "word.csv:3: expected three numbers x,y,z, got '1,zero,0'");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--positions", "inf.csv", "--forces",
                                      "bad_forces.csv", NULL},
                      "inf.csv:4: non-finite number in '0,inf,0'");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--positions", "header.csv", "--forces",
                                      "bad_forces.csv", NULL},
                      "header.csv:1: expected the header 'x,y,z', got 'a,b,c'");
}

static void test_eval_bad_input(void** state) {
    (void)state;
    write_file("tri.obj", tri_obj);
    write_file("broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--set", "bond.kk=1", "--forces",
                                      "bad_forces.csv", NULL},
                      "--set bond.kk=1: unknown key 'bond.kk'");
    assert_eval_fails((const char*[]){"eval", "missing.obj", "--forces", "bad_forces.csv", NULL},
                      "missing.obj: cannot open: No such file or directory");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--positions", "missing.csv", "--forces",
                                      "bad_forces.csv", NULL},
                      "missing.csv: cannot open: No such file or directory");
    assert_eval_fails((const char*[]){"eval", "tri.obj", "--frobnicate", NULL},
                      "unknown option '--frobnicate' (see softbond eval --help)");
    assert_eval_fails((const char*[]){"eval", NULL}, "missing MESH (see softbond eval --help)");
    /* the mesh reader's own message names the line */
    result r = run((const char*[]){"eval", "broken.obj", NULL});
    assert_int_equal(r.code, 2);
    assert_int_equal(count_lines(r.err), 1);
    assert_int_equal(strncmp(r.err, "softbond: broken.obj:3: ", 24), 0);
    result_free(&r);
}

/* ---- run ------------------------------------------------------------------------ */

static const char* const tiny_scene =
    "# a tiny sheet, pinned at its top corners\n"
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
    char* vtu = read_file(name);
    /* 4 x 3 vertices, 3 x 2 quads of two triangles */
    assert_non_null(strstr(vtu, "<VTKFile type=\"UnstructuredGrid\""));
    assert_non_null(strstr(vtu, "NumberOfPoints=\"12\" NumberOfCells=\"12\""));
    assert_non_null(strstr(vtu, "Name=\"velocity\""));
    assert_non_null(strstr(vtu, "Name=\"force\""));
    free(vtu);
    snprintf(name, sizeof name, "%s/frames.pvd", dir);
    char* pvd = read_file(name);
    assert_non_null(pvd);
    assert_int_equal(count_occurrences(pvd, "<DataSet "), frames);
    assert_non_null(strstr(pvd, "file=\"frame_000000.vtu\""));
    free(pvd);
}

static void assert_log(const char* dir, int frames, double duration) {
    char name[400];
    snprintf(name, sizeof name, "%s/log.csv", dir);
    char* log = read_file(name);
    assert_non_null(log);
    const char* header = "time,kinetic,bond,angle,stretch_bend,spring,bend,gravity,total\n";
    assert_int_equal(strncmp(log, header, strlen(header)), 0);
    assert_int_equal(count_lines(log), frames + 1);
    const char* row = log + strlen(header);
    double values[10], first_time = -1.0;
    for (int i = 0; i < frames; i++) {
        assert_int_equal(csv_fields(row, values, 10), 9);
        if (i == 0) first_time = values[0];
        /* total = kinetic + the five terms + gravity */
        double sum = 0.0;
        for (int c = 1; c < 8; c++) sum += values[c];
        TU_ASSERT_NEAR(values[8], sum, 1e-12 * fmax(1.0, fabs(sum)));
        row = strchr(row, '\n') + 1;
    }
    assert_true(first_time == 0.0);
    TU_ASSERT_NEAR(values[0], duration, 1e-9);
    assert_true(values[1] > 0.0); /* moving */
    assert_true(values[7] < 0.0); /* fallen: −Σ m g·x < 0 */
    free(log);
}

static void test_run_writes_frames_and_log(void** state) {
    (void)state;
    write_file("tiny.yaml", tiny_scene);
    result r = run((const char*[]){"run", "tiny.yaml", NULL});
    assert_int_equal(r.code, 0);
    assert_string_equal(r.err, ""); /* no progress bar off a terminal */
    assert_int_equal(count_lines(r.out), 1);
    assert_non_null(strstr(r.out, "out/tiny"));
    int frames = (int)floor(0.1 / 0.02 + 1e-9) + 1;
    assert_frames(tmp_path("out/tiny"), frames);
    assert_log(tmp_path("out/tiny"), frames, 0.1);
    result_free(&r);
}

static void test_run_set_and_output(void** state) {
    (void)state;
    write_file("tiny.yaml", tiny_scene);
    result r = run((const char*[]){"run", "tiny.yaml", "--set", "duration=0.05", "--set",
                                   "output.frames=false", "--output", "custom/dir", "--threads",
                                   "1", NULL});
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "custom/dir"));
    assert_log(tmp_path("custom/dir"), 3, 0.04);
    assert_false(exists(tmp_path("custom/dir/frames.pvd")));
    assert_false(exists(tmp_path("custom/dir/frame_000000.vtu")));
    result_free(&r);
}

/* A run that must fail with exit 2 before creating its output folder. */
static void assert_run_fails(const char* env_name, const char* env_value, const char* const* args,
                             const char* message) {
    result r = run_env(env_name, env_value, args);
    assert_input_error(&r, message);
    assert_false(exists(tmp_path("never")));
    result_free(&r);
}

static void test_run_bad_input_creates_nothing(void** state) {
    (void)state;
    write_file("tiny.yaml", tiny_scene);
    write_file("typo.yaml", "mesh: {nx: 4, ny: 3}\nbond:\n  kk: 1\n");
    write_file("range.yaml", "mesh: {nx: 4, ny: 3}\nfixed: [3, 12]\n");
    assert_run_fails(NULL, NULL, (const char*[]){"run", "typo.yaml", "--output", "never", NULL},
                     "typo.yaml:3: unknown key 'bond.kk'");
    assert_run_fails(NULL, NULL, (const char*[]){"run", "range.yaml", "--output", "never", NULL},
                     "range.yaml:2: 'fixed': vertex 12 out of range (the mesh has 12 vertices)");
    assert_run_fails(NULL, NULL, (const char*[]){"run", "nothere.yaml", "--output", "never", NULL},
                     "nothere.yaml: cannot open: No such file or directory");
    assert_run_fails(
        NULL, NULL, (const char*[]){"run", "tiny.yaml", "--set", "dt=0", "--output", "never", NULL},
        "--set dt=0: 'dt' must be > 0, got 0");
    assert_run_fails("SOFTBOND_THREADS", "many",
                     (const char*[]){"run", "tiny.yaml", "--output", "never", NULL},
                     "SOFTBOND_THREADS: expected an integer in [0, 4096], got 'many'");
    assert_run_fails(
        NULL, NULL,
        (const char*[]){"run", "tiny.yaml", "--threads", "-2", "--output", "never", NULL},
        "--threads: expected an integer in [0, 4096], got '-2'");
}

static void test_run_solver_failure_exits_3(void** state) {
    (void)state;
    write_file("tiny.yaml", tiny_scene);
    result r = run((const char*[]){"run", "tiny.yaml", "--set", "bond.k=1e6", "--set", "dt=0.01",
                                   "--set", "frame_interval=0.01", "--output", "unstable", NULL});
    assert_int_equal(r.code, 3);
    assert_int_equal(count_lines(r.err), 1);
    assert_int_equal(strncmp(r.err, "softbond: ", 10), 0);
    /* the frames up to the failure stay readable */
    assert_true(exists(tmp_path("unstable/log.csv")));
    result_free(&r);
}

static void test_help_and_version(void** state) {
    (void)state;
    result r = run((const char*[]){"--version", NULL});
    assert_int_equal(r.code, 0);
    assert_int_equal(strncmp(r.out, "softbond ", 9), 0);
    assert_non_null(strstr(r.out, SB_VERSION_STRING));
    result_free(&r);
    r = run((const char*[]){"run", "--help", NULL});
    assert_int_equal(r.code, 0);
    assert_int_equal(strncmp(r.out, "usage: softbond run SCENE.yaml", 30), 0);
    result_free(&r);
    r = run((const char*[]){"--help", NULL});
    assert_int_equal(r.code, 0);
    assert_non_null(strstr(r.out, "softbond eval MESH"));
    result_free(&r);
    r = run((const char*[]){"fly", NULL});
    assert_input_error(&r, "unknown command 'fly' (see softbond --help)");
    result_free(&r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
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
        cmocka_unit_test(test_help_and_version),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
