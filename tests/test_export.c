/* Export: sb_mesh_export round trips through sb_mesh_load (PLY, OBJ, glTF,
 * GLB, IRIT, POV-Ray: counts, positions within float rounding, total
 * area) and the OBJ's vertex normals; the bonds .vtu's strain and energy against values computed here
 * from positions and rest lengths; IRIT and POV-Ray files checked for
 * structure (counts, unit planes) and the POV-Ray object's axes for each
 * up direction; a POV-Ray frame rendered by povray and found not blank; the output.formats key (lists, --set text,
 * unknown names with file:line); and `softbond run` writing every format with no staging left behind, a failed write
 * reported with exit 1, an unknown format with exit 2. */
#define _POSIX_C_SOURCE 200809L

#include <ctype.h>
#include <dirent.h>
#include <stdio.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli/frame_export.h"
#include "scenes/scene.h"
#include "cli/vtk.h"
#include "tests/test_files.h"

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_export");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

static bool exists(const char* path) {
    struct stat st;
    return stat(path, &st) == 0;
}

/* A jittered 5 x 4 sheet, bent out of its plane, in `mesh`. */
static void bent_sheet(sb_mesh* mesh) {
    sb_sheet_def def = sb_default_sheet_def();
    def.nx = 5;
    def.ny = 4;
    def.width = 2.0;
    def.jitter = 0.2;
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&def, mesh, &err), SB_OK);
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        mesh->positions[3 * v + 2] = 0.3 * sin(2.0 * mesh->positions[3 * v]) + 0.01 * v;
}

static double total_area(const sb_mesh* mesh) {
    double area = 0.0;
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        const double* p[3];
        for (int c = 0; c < 3; c++) p[c] = mesh->positions + 3 * mesh->triangles[3 * t + c];
        double u[3], v[3], n[3];
        for (int k = 0; k < 3; k++) {
            u[k] = p[1][k] - p[0][k];
            v[k] = p[2][k] - p[0][k];
        }
        tu_cross(u, v, n);
        area += 0.5 * tu_norm(n);
    }
    return area;
}

/* Every vertex of `a` is within tol of one of `b` (the readers may renumber). */
static void assert_same_points(const sb_mesh* a, const sb_mesh* b, double tol) {
    assert_int_equal(a->vertex_count, b->vertex_count);
    for (uint32_t i = 0; i < a->vertex_count; i++) {
        double best = INFINITY;
        for (uint32_t j = 0; j < b->vertex_count; j++)
            best = fmin(best, tu_dist(a->positions + 3 * i, b->positions + 3 * j));
        TU_ASSERT_LE(best, tol);
    }
}

static void round_trip(const char* format) {
    sb_mesh mesh = {0}, back = {0};
    sb_error err;
    bent_sheet(&mesh);
    char name[32];
    snprintf(name, sizeof name, "trip%s", sb_mesh_export_extension(format));
    const char* path = tu_tmp_path(name);
    if (sb_mesh_export(path, format, &mesh, NULL, &err) != SB_OK) fail_msg("%s", err.message);
    if (sb_mesh_load(path, &back, &err) != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(back.triangle_count, mesh.triangle_count);
    assert_same_points(&mesh, &back, 4e-7); /* float positions of size ~2 m */
    TU_ASSERT_NEAR(total_area(&back), total_area(&mesh), 1e-5);
    sb_mesh_free(&mesh);
    sb_mesh_free(&back);
}

static void test_round_trips(void** state) {
    (void)state;
    round_trip("ply");
    round_trip("obj");
    round_trip("gltf");
    round_trip("glb");
    round_trip("irit");
    round_trip("pov");
    assert_true(exists(tu_tmp_path("trip.mtl")));
    assert_true(exists(tu_tmp_path("trip.bin")));
}

/* The OBJ's normals (assimp writes the ones it is given; it renumbers the
 * vertices) against the area-weighted normals of the file's own geometry. */
typedef struct obj_file {
    double v[64][3], vn[64][3];
    unsigned f[64][3], fn[64][3];
    int vertices, normals, faces;
} obj_file;

static void parse_obj(char* text, obj_file* o) {
    memset(o, 0, sizeof *o);
    for (char* line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        double* v = o->v[o->vertices % 64];
        double* n = o->vn[o->normals % 64];
        unsigned* f = o->f[o->faces % 64];
        unsigned* fn = o->fn[o->faces % 64];
        if (sscanf(line, "v %lf %lf %lf", &v[0], &v[1], &v[2]) == 3) o->vertices++;
        if (sscanf(line, "vn %lf %lf %lf", &n[0], &n[1], &n[2]) == 3) o->normals++;
        if (sscanf(line, "f %u//%u %u//%u %u//%u", &f[0], &fn[0], &f[1], &fn[1], &f[2], &fn[2]) == 6) o->faces++;
    }
    assert_true(o->vertices <= 64 && o->normals <= 64 && o->faces <= 64);
}

static void test_obj_normals(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_error err;
    bent_sheet(&mesh);
    const char* path = tu_tmp_path("normals.obj");
    if (sb_mesh_export(path, "obj", &mesh, NULL, &err) != SB_OK) fail_msg("%s", err.message);
    char* text = tu_read_file(path);
    obj_file o;
    parse_obj(text, &o);
    assert_int_equal(o.faces, mesh.triangle_count);
    double sum[64][3] = {{0.0}};
    for (int t = 0; t < o.faces; t++) {
        const double *a = o.v[o.f[t][0] - 1], *b = o.v[o.f[t][1] - 1], *c = o.v[o.f[t][2] - 1];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, n[3];
        tu_cross(u, w, n);
        for (int corner = 0; corner < 3; corner++)
            for (int k = 0; k < 3; k++) sum[o.f[t][corner] - 1][k] += n[k];
    }
    for (int t = 0; t < o.faces; t++)
        for (int corner = 0; corner < 3; corner++) {
            const double* e = sum[o.f[t][corner] - 1];
            const double* n = o.vn[o.fn[t][corner] - 1];
            for (int k = 0; k < 3; k++) TU_ASSERT_NEAR(n[k], e[k] / tu_norm(e), 1e-5);
        }
    free(text);
    sb_mesh_free(&mesh);
}

static void test_export_errors(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_error err;
    bent_sheet(&mesh);
    assert_int_equal(sb_mesh_export("/nonexistent/dir/x.ply", "ply", &mesh, NULL, &err), SB_ERR_IO);
    TU_ASSERT_CONTAINS(err.message, "/nonexistent/dir/x.ply: cannot write");
    assert_int_equal(sb_mesh_export(tu_tmp_path("x.stl"), "stl", &mesh, NULL, &err), SB_ERR_INVALID);
    TU_ASSERT_CONTAINS(err.message, "unknown export format 'stl'");
    assert_null(sb_mesh_export_extension("stl"));
    assert_string_equal(sb_mesh_export_extension("irit"), ".itd");
    sb_mesh_free(&mesh);
}

/* ---- the bonds .vtu ---------------------------------------------------------- */

/* The numbers of the DataArray named `name` (after `after`, when given). */
static size_t read_array(const char* text, const char* name, double* out, size_t max) {
    char key[64];
    snprintf(key, sizeof key, "Name=\"%s\"", name);
    const char* p = strstr(text, key);
    assert_non_null(p);
    p = strchr(p, '>') + 1;
    const char* end = strstr(p, "</DataArray>");
    size_t n = 0;
    for (char* next; p < end && n < max; p = next) {
        out[n] = strtod(p, &next);
        if (next == p) break;
        n++;
    }
    return n;
}

/* A unit square of two triangles; bonds on its sides and one diagonal with
 * rest lengths and constants chosen here, drawn at stretched positions. */
static void test_bond_cells(void** state) {
    (void)state;
    static const double rest[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    static const double now[4][3] = {{0, 0, 0}, {1.2, 0, 0}, {1.3, 0.9, 0.2}, {-0.1, 1.1, 0}};
    static const uint32_t pairs[5][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {0, 2}};
    static const double k[5] = {100, 0, 50, 20, 10}, spring_k[5] = {0, 30, 5, 0, 0};
    sb_builder* b = sb_builder_create();
    for (int v = 0; v < 4; v++) tu_vertex(b, rest[v][0], rest[v][1], rest[v][2], 0.01, false);
    for (int e = 0; e < 5; e++) tu_bond(b, pairs[e][0], pairs[e][1], -1.0, k[e], spring_k[e], 0.0);
    sb_model* model = tu_compile(b);
    uint32_t triangles[6] = {0, 1, 2, 0, 2, 3};
    sb_mesh mesh = {4, (double*)rest, 2, triangles};
    double zero[12] = {0};
    sb_vtk_frame frame = {&mesh, model, &now[0][0], zero, zero, NULL, SB_VTK_ASCII};
    sb_error err;
    const char* path = tu_tmp_path("bonds.vtu");
    if (sb_vtk_write_bonds(path, &frame, &err) != SB_OK) fail_msg("%s", err.message);
    char* text = tu_read_file(path);
    TU_ASSERT_CONTAINS(text, "NumberOfPoints=\"4\" NumberOfCells=\"5\"");
    double nodes[10], strain[5], energy[5], types[5];
    assert_int_equal(read_array(text, "connectivity", nodes, 10), 10);
    assert_int_equal(read_array(text, "strain", strain, 5), 5);
    assert_int_equal(read_array(text, "energy", energy, 5), 5);
    assert_int_equal(read_array(text, "types", types, 5), 5);
    for (int c = 0; c < 5; c++) {
        uint32_t i = (uint32_t)nodes[2 * c], j = (uint32_t)nodes[2 * c + 1];
        int e = 0; /* the bond these cell nodes are */
        while (e < 5 && !((pairs[e][0] == i && pairs[e][1] == j) || (pairs[e][0] == j && pairs[e][1] == i))) e++;
        assert_true(e < 5);
        double l = tu_dist(now[i], now[j]), l0 = tu_dist(rest[i], rest[j]);
        TU_ASSERT_NEAR(strain[c], (l - l0) / l0, 1e-8);
        TU_ASSERT_NEAR(energy[c], 0.5 * (k[e] + spring_k[e]) * (l - l0) * (l - l0), 1e-8);
        assert_int_equal((int)types[c], 3); /* VTK_LINE */
    }
    free(text);
    sb_model_destroy(model);
    sb_builder_destroy(b);
}

/* ---- IRIT and POV-Ray ------------------------------------------------------- */

static size_t count_of(const char* text, const char* needle) {
    size_t n = 0;
    for (const char* p = text; (p = strstr(p, needle)); p += strlen(needle)) n++;
    return n;
}

static void test_irit_structure(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_error err;
    bent_sheet(&mesh);
    const char* path = tu_tmp_path("sheet.itd");
    if (sb_mesh_export(path, "irit", &mesh, NULL, &err) != SB_OK) fail_msg("%s", err.message);
    char* text = tu_read_file(path);
    assert_int_equal(strncmp(text, "[OBJECT ", 8), 0);
    assert_int_equal(count_of(text, "[POLYGON [PLANE "), mesh.triangle_count);
    assert_int_equal(count_of(text, "] 3\n"), mesh.triangle_count);
    assert_int_equal(count_of(text, "["), 1 + 2 * mesh.triangle_count + 3 * mesh.triangle_count);
    assert_int_equal(count_of(text, "["), count_of(text, "]"));
    const char* p = text;
    for (uint32_t t = 0; t < mesh.triangle_count; t++) {
        double plane[4], corner[3][3];
        p = strstr(p, "[PLANE ") + 7;
        assert_int_equal(sscanf(p, "%lf %lf %lf %lf] 3 [%lf %lf %lf] [%lf %lf %lf] [%lf %lf %lf]", &plane[0], &plane[1],
                                &plane[2], &plane[3], &corner[0][0], &corner[0][1], &corner[0][2], &corner[1][0],
                                &corner[1][1], &corner[1][2], &corner[2][0], &corner[2][1], &corner[2][2]),
                         13);
        TU_ASSERT_NEAR(tu_norm(plane), 1.0, 1e-8);
        for (int c = 0; c < 3; c++) {
            TU_ASSERT_NEAR(tu_dot(plane, corner[c]) + plane[3], 0.0, 1e-8);
            TU_ASSERT_LE(tu_dist(corner[c], mesh.positions + 3 * mesh.triangles[3 * t + c]), 1e-8);
        }
    }
    free(text);
    sb_mesh_free(&mesh);
}

static void test_pov_structure(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_error err;
    bent_sheet(&mesh);
    const char* path = tu_tmp_path("sheet.pov");
    if (sb_mesh_export(path, "pov", &mesh, NULL, &err) != SB_OK) fail_msg("%s", err.message);
    char* text = tu_read_file(path);
    unsigned vertices, faces;
    const char* p = strstr(text, "vertex_vectors {");
    assert_non_null(p);
    assert_int_equal(sscanf(p, "vertex_vectors { %u", &vertices), 1);
    assert_int_equal(vertices, mesh.vertex_count);
    p = strstr(text, "face_indices {");
    assert_non_null(p);
    assert_int_equal(sscanf(p, "face_indices { %u", &faces), 1);
    assert_int_equal(faces, mesh.triangle_count);
    /* one <...> per vertex and face, and eight more: the up in the first
     * comment, background, camera location and look_at, light position and
     * colour, matrix, pigment */
    assert_int_equal(count_of(text, "<"), mesh.vertex_count + mesh.triangle_count + 8);
    TU_ASSERT_CONTAINS(text, "mesh2 {");
    TU_ASSERT_CONTAINS(text, "camera {");
    TU_ASSERT_CONTAINS(text, "light_source {");
    TU_ASSERT_CONTAINS(text, "matrix <1, 0, 0,  0, 0, 1,  0, 1, 0,  0, 0, 0>"); /* z up: y, z swapped */
    free(text);
    sb_mesh_free(&mesh);
}

/* The object's matrix for other up directions: the nearest axis goes to +y. */
static void test_pov_up(void** state) {
    (void)state;
    static const struct {
        double up[3];
        const char* matrix;
    } cases[] = {
        {{0.1, 9.8, 0.0}, "matrix <1, 0, 0,  0, 1, 0,  0, 0, 1,  0, 0, 0>"},    /* y: as it is */
        {{0.0, 0.0, -1.0}, "matrix <1, 0, 0,  0, 0, -1,  0, -1, 0,  0, 0, 0>"}, /* -z */
        {{2.0, 1.0, 0.0}, "matrix <0, 1, 0,  1, 0, 0,  0, 0, 1,  0, 0, 0>"},    /* x */
    };
    sb_mesh mesh = {0};
    sb_error err;
    bent_sheet(&mesh);
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sb_mesh_export_def def = sb_default_mesh_export_def();
        memcpy(def.up, cases[i].up, sizeof def.up);
        const char* path = tu_tmp_path("up.pov");
        if (sb_mesh_export(path, "pov", &mesh, &def, &err) != SB_OK) fail_msg("%s", err.message);
        char* text = tu_read_file(path);
        TU_ASSERT_CONTAINS(text, cases[i].matrix);
        free(text);
    }
    sb_mesh_free(&mesh);
}

/* The next number of a PPM header, past blanks and # comments; the one
 * blank after it is consumed. */
static int ppm_number(FILE* f) {
    int c = fgetc(f);
    while (c == '#' || isspace(c))
        if (c == '#')
            while ((c = fgetc(f)) != '\n' && c != EOF) continue;
        else
            c = fgetc(f);
    int n = 0;
    for (; isdigit(c); c = fgetc(f)) n = 10 * n + (c - '0');
    return n;
}

/* A binary PPM (P6, maxval 255): pixels as RGB bytes; NULL when unreadable. */
static unsigned char* read_ppm(const char* path, int* width, int* height) {
    FILE* f = fopen(path, "rb");
    if (!f) return NULL;
    unsigned char* pixels = NULL;
    bool p6 = fgetc(f) == 'P' && fgetc(f) == '6';
    *width = ppm_number(f);
    *height = ppm_number(f);
    if (p6 && ppm_number(f) == 255) {
        size_t size = (size_t)*width * (size_t)*height * 3;
        pixels = malloc(size ? size : 1);
        if (pixels && fread(pixels, 1, size, f) != size) {
            free(pixels);
            pixels = NULL;
        }
    }
    fclose(f);
    return pixels;
}

/* An icosphere frame rendered at 64 x 48: a white background and enough
 * pixels of another colour. */
static void test_pov_render(void** state) {
    (void)state;
    if (system("command -v povray > /dev/null 2>&1") != 0) {
        print_message("povray is not installed (Debian package povray; make deps): skipped\n");
        skip();
    }
    sb_mesh mesh = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_icosphere(2, 0.5, &mesh, &err), SB_OK);
    if (sb_mesh_export(tu_tmp_path("ball.pov"), "pov", &mesh, NULL, &err) != SB_OK) fail_msg("%s", err.message);
    char command[600];
    snprintf(command, sizeof command,
             "cd '%s' && HOME='%s' povray +Iball.pov +Oball.ppm +FP +W64 +H48 -D -V > povray.txt 2>&1", tu_tmp_dir,
             tu_tmp_dir);
    if (system(command) != 0) fail_msg("povray failed:\n%s", tu_read_file(tu_tmp_path("povray.txt")));
    int width, height;
    unsigned char* pixels = read_ppm(tu_tmp_path("ball.ppm"), &width, &height);
    assert_non_null(pixels);
    assert_int_equal(width, 64);
    assert_int_equal(height, 48);
    assert_true(pixels[0] == 255 && pixels[1] == 255 && pixels[2] == 255); /* background */
    int other = 0;
    for (int i = 0; i < width * height; i++) other += memcmp(pixels + 3 * i, pixels, 3) != 0;
    TU_ASSERT_LE(0.1 * width * height, other); /* the ball covers about a quarter */
    TU_ASSERT_LE(other, 0.9 * width * height);
    free(pixels);
    sb_mesh_free(&mesh);
}

/* ---- the output.formats key ------------------------------------------------ */

static void test_formats_key(void** state) {
    (void)state;
    sb_scene scene;
    sb_error err;
    sb_frame_formats formats;
    char bad[64];
    assert_int_equal(sb_scene_init(&scene, &err), SB_OK);
    assert_string_equal(sb_scene_string(&scene, SB_KEY_OUTPUT_FORMATS), "vtu");
    assert_int_equal(sb_scene_set(&scene, "output.formats=[ply, obj, pov]", &err), SB_OK);
    assert_string_equal(sb_scene_string(&scene, SB_KEY_OUTPUT_FORMATS), "ply,obj,pov");
    assert_int_equal(sb_scene_set(&scene, "output.formats=vtu,irit,vtu", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_OK);
    assert_true(sb_frame_formats_parse("vtu,irit,vtu", &formats, bad, sizeof bad));
    assert_true(sb_frame_formats_parse("vtu", &formats, bad, sizeof bad));
    assert_int_equal(formats, SB_FRAME_VTU);
    assert_false(sb_frame_formats_parse("vtu,,pov", &formats, bad, sizeof bad));
    assert_string_equal(bad, "");
    const char* path = tu_write_file("formats.yaml", "dt: 0.001\noutput:\n  formats: [vtu, stl]\n");
    assert_int_equal(sb_scene_load(&scene, path, &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_ERR_INVALID);
    TU_ASSERT_CONTAINS(err.message, "formats.yaml:3: 'output.formats': unknown format 'stl'");
    assert_int_equal(sb_scene_set(&scene, "output.formats=[]", &err), SB_OK);
    assert_int_equal(sb_scene_validate(&scene, &err), SB_ERR_INVALID);
    TU_ASSERT_CONTAINS(err.message, "--set output.formats=[]: 'output.formats': an empty format name (known: vtu,");
    assert_int_equal(sb_scene_set(&scene, "output.formats={a: 1}", &err), SB_ERR_PARSE);
    sb_scene_free(&scene);
}

/* ---- softbond run ------------------------------------------------------------- */

static const char* scene_text = "mesh: {nx: 4, ny: 3}\nduration: 0.04\nframe_interval: 0.02\n";

/* Two frames in every format, nothing staged left, the .pvd and the
 * companions (bonds, .mtl, .bin) in place. */
static void test_run_every_format(void** state) {
    (void)state;
    tu_write_file("all.yaml", scene_text);
    tu_result r = tu_run((const char*[]){"run", "all.yaml", "--output", "all", "--set",
                                         "output.formats=[vtu, ply, obj, gltf, glb, irit, pov]", NULL});
    if (r.code != 0) fail_msg("run failed: %s", r.err);
    tu_result_free(&r);
    static const char* const names[] = {".vtu",  "_bonds.vtu", ".ply", ".obj", ".mtl",
                                        ".gltf", ".bin",       ".glb", ".itd", ".pov"};
    char name[64];
    for (int frame = 0; frame < 3; frame++)
        for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
            snprintf(name, sizeof name, "all/frame_%06d%s", frame, names[i]);
            assert_true(exists(tu_tmp_path(name)));
        }
    assert_true(exists(tu_tmp_path("all/frames.pvd")));
    char* pov = tu_read_file(tu_tmp_path("all/frame_000000.pov")); /* gravity -z: z up */
    TU_ASSERT_CONTAINS(pov, "matrix <1, 0, 0,  0, 0, 1,  0, 1, 0,  0, 0, 0>");
    free(pov);
    DIR* dir = opendir(tu_tmp_path("all"));
    assert_non_null(dir);
    for (struct dirent* entry; (entry = readdir(dir));)
        if (strcmp(entry->d_name, ".") != 0 && strcmp(entry->d_name, "..") != 0)
            if (entry->d_name[0] == '.' || strstr(entry->d_name, ".tmp")) fail_msg("left behind: %s", entry->d_name);
    closedir(dir);
}

/* A film-maker style scene, gravity along -y: its POV-Ray frames as they are. */
static void test_run_pov_up(void** state) {
    (void)state;
    tu_write_file("up.yaml", scene_text);
    tu_result r = tu_run((const char*[]){"run", "up.yaml", "--output", "up", "--set", "output.formats=pov", "--set",
                                         "gravity=[0, -9.8, 0]", NULL});
    if (r.code != 0) fail_msg("run failed: %s", r.err);
    tu_result_free(&r);
    char* pov = tu_read_file(tu_tmp_path("up/frame_000001.pov"));
    TU_ASSERT_CONTAINS(pov, "matrix <1, 0, 0,  0, 1, 0,  0, 0, 1,  0, 0, 0>");
    free(pov);
    assert_false(exists(tu_tmp_path("up/frames.pvd"))); /* no vtu, no index */
}

static void test_run_failures(void** state) {
    (void)state;
    tu_write_file("fail.yaml", scene_text);
    tu_result r = tu_run((const char*[]){"run", "fail.yaml", "--set", "output.formats=vtu,stl", NULL});
    assert_int_equal(r.code, 2);
    assert_string_equal(r.err, "softbond: --set output.formats=vtu,stl: 'output.formats': unknown format "
                               "'stl' (known: vtu, ply, obj, gltf, glb, irit, pov)\n");
    tu_result_free(&r);
    /* a folder where the first frame's PLY should go: its rename fails */
    assert_int_equal(mkdir(tu_tmp_path("blocked"), 0777), 0);
    assert_int_equal(mkdir(tu_tmp_path("blocked/frame_000000.ply"), 0777), 0);
    assert_int_equal(mkdir(tu_tmp_path("blocked/frame_000000.ply/x"), 0777), 0);
    r = tu_run((const char*[]){"run", "fail.yaml", "--output", "blocked", "--set", "output.formats=ply", NULL});
    assert_int_equal(r.code, 1);
    TU_ASSERT_CONTAINS(r.err, "frame_000000.ply: cannot rename to blocked/frame_000000.ply");
    assert_false(exists(tu_tmp_path("blocked/.frame_000000.ply.tmp")));
    assert_false(exists(tu_tmp_path("blocked/frame_000001.ply")));
    tu_result_free(&r);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trips),      cmocka_unit_test(test_obj_normals),
        cmocka_unit_test(test_export_errors),    cmocka_unit_test(test_bond_cells),
        cmocka_unit_test(test_irit_structure),   cmocka_unit_test(test_pov_structure),
        cmocka_unit_test(test_pov_up),           cmocka_unit_test(test_pov_render),
        cmocka_unit_test(test_run_pov_up),       cmocka_unit_test(test_formats_key),
        cmocka_unit_test(test_run_every_format), cmocka_unit_test(test_run_failures),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
