/* `softbond tetra IN OUT`: fills a closed surface with tetrahedra by
 * running TetGen, Debian's `tetgen` program (the TetGen library is not
 * linked: the program is called).
 *
 *   1. IN is read with sb_mesh_load (any surface format; objects merged)
 *      and must be closed: every edge on exactly two triangles
 *      (sb_mesh_count_edges). A boundary or non-manifold edge is an input
 *      error, before TetGen runs.
 *   2. The surface is written as surface.off in a fresh temporary directory
 *      ($TMPDIR or /tmp, softbond_tetra_XXXXXX) and TetGen is run on it as
 *          tetgen -pq<quality>[a<max volume>]F surface.off
 *      -p: tetrahedralize the piecewise linear complex (the surface is
 *      kept; Steiner points may be added on it); -q: quality, radius-edge
 *      ratio bound (default 1.414); -a: largest tetrahedron volume, m³
 *      (only with --max-volume); -F: no .face/.edge files. Its output goes
 *      to tetgen.log there; the program is `tetgen` on PATH, or
 *      $SOFTBOND_TETGEN.
 *   3. surface.1.node/.ele are read back (sb_tet_mesh_load_tetgen), checked
 *      (sb_tet_mesh_check: no inverted or zero-volume tetrahedron) and
 *      written as the TetGen pair OUT.node and OUT.ele (OUT must end in
 *      .node or .ele; numbering from 0; every tetrahedron's corners in the
 *      order of a positive volume, sb_tet_volume > 0), each atomically. The temporary
 *      directory is removed.
 * --max-volume V with V smaller than the surface's enclosed volume divided
 * by SB_TETRA_MAX_TETS is refused before TetGen runs: it would need more
 * tetrahedra than that (TetGen would run for hours or exhaust memory).
 * Exit codes: 2 for bad arguments or input (unreadable or open surface),
 * 1 when TetGen is missing or fails (its last message is shown) or OUT
 * cannot be written. */
#define _POSIX_C_SOURCE 200809L
#include "common/atomic_file.h"
#include "cli/cli.h"
#include "common/error.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

#define SB_TETRA_MAX_TETS 1e7

void sb_cli_tetra_usage(FILE* stream) {
    fprintf(stream, "usage: softbond tetra IN OUT [--quality Q] [--max-volume V]\n"
                    "Fills the closed surface IN (any mesh format) with tetrahedra by running TetGen\n"
                    "(`tetgen -pq<Q>a<V>`; Debian: apt-get install tetgen) and writes OUT.node and\n"
                    "OUT.ele (OUT ends in .node or .ele). --quality: radius-edge ratio bound, > 1\n"
                    "(default 1.414; nearer 1 gives rounder tetrahedra and more of them);\n"
                    "--max-volume: largest tetrahedron volume, m^3 (default: no bound).\n");
}

typedef struct tetra_job {
    const char* in;
    const char* out;
    double quality, max_volume;
    bool help;
    char switches[128]; /* tetgen's switches, "-pq1.414F" */
    char dir[512];      /* the temporary directory, "" when none */
    char out_base[512]; /* OUT without its extension */
    sb_mesh surface;
    sb_tet_mesh volume;
} tetra_job;

/* ---- arguments ------------------------------------------------------------ */

static sb_status number_option(const char* name, const char* text, double* out, sb_error* err) {
    char* end = NULL;
    errno = 0;
    *out = text ? strtod(text, &end) : NAN;
    if (!text || end == text || *end != '\0' || errno != 0 || !isfinite(*out))
        return sb_error_set(err, SB_ERR_INVALID, "%s: expected a number, got '%s' (see softbond tetra --help)", name,
                            text ? text : "");
    return SB_OK;
}

/* --name=value or --name value: the value, or NULL when the argument is another option. */
static const char* option_value(int argc, char** argv, int* i, const char* name) {
    size_t n = strlen(name);
    if (strncmp(argv[*i], name, n) != 0) return NULL;
    if (argv[*i][n] == '=') return argv[*i] + n + 1;
    if (argv[*i][n] == '\0') return *i + 1 < argc ? argv[++*i] : "";
    return NULL;
}

static sb_status parse_arg(int argc, char** argv, int* i, tetra_job* job, sb_error* err) {
    const char* arg = argv[*i];
    const char* value;
    if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0)
        job->help = true;
    else if ((value = option_value(argc, argv, i, "--quality")))
        return number_option("--quality", value, &job->quality, err);
    else if ((value = option_value(argc, argv, i, "--max-volume")))
        return number_option("--max-volume", value, &job->max_volume, err);
    else if (arg[0] == '-' && arg[1] != '\0')
        return sb_error_set(err, SB_ERR_INVALID, "unknown option '%s' (see softbond tetra --help)", arg);
    else if (!job->in)
        job->in = arg;
    else if (!job->out)
        job->out = arg;
    else
        return sb_error_set(err, SB_ERR_INVALID, "unexpected argument '%s' (see softbond tetra --help)", arg);
    return SB_OK;
}

static sb_status parse_args(int argc, char** argv, tetra_job* job, sb_error* err) {
    for (int i = 1; i < argc; i++) {
        sb_status status = parse_arg(argc, argv, &i, job, err);
        if (status != SB_OK) return status;
    }
    if (job->help) return SB_OK;
    if (!job->in || !job->out)
        return sb_error_set(err, SB_ERR_INVALID, "missing %s (see softbond tetra --help)",
                            job->in ? "OUT" : "IN and OUT");
    if (!(job->quality > 1.0))
        return sb_error_set(err, SB_ERR_INVALID, "--quality %g: the radius-edge ratio bound must be > 1", job->quality);
    if (job->max_volume < 0.0)
        return sb_error_set(err, SB_ERR_INVALID, "--max-volume %g: must be > 0 (0: no bound)", job->max_volume);
    const char* dot = strrchr(job->out, '.');
    bool pair = dot && (strcmp(dot, ".node") == 0 || strcmp(dot, ".ele") == 0);
    if (!pair || (size_t)(dot - job->out) >= sizeof job->out_base)
        return sb_error_set(err, SB_ERR_INVALID, "%s: OUT must end in .node or .ele (a TetGen pair is written)",
                            job->out);
    memcpy(job->out_base, job->out, (size_t)(dot - job->out));
    return SB_OK;
}

/* ---- the input surface ---------------------------------------------------- */

static sb_status load_closed(tetra_job* job, sb_error* err) {
    sb_status status = sb_mesh_load(job->in, &job->surface, err);
    if (status != SB_OK) return status;
    sb_mesh_edge_counts edges;
    status = sb_mesh_count_edges(&job->surface, &edges, err);
    if (status == SB_OK && !edges.closed)
        return sb_error_set(err, SB_ERR_INVALID,
                            "%s: the surface is not closed (%u boundary and %u non-manifold edges of %u): "
                            "tetra needs a closed surface",
                            job->in, edges.boundary, edges.non_manifold, edges.edges);
    return status;
}

/* The volume the closed surface encloses: Σ a · (b × c) / 6 over its triangles. */
static double enclosed_volume(const sb_mesh* m) {
    double sum = 0.0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        const double* a = m->positions + 3 * (size_t)m->triangles[3 * t];
        const double* b = m->positions + 3 * (size_t)m->triangles[3 * t + 1];
        const double* c = m->positions + 3 * (size_t)m->triangles[3 * t + 2];
        sum += a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
               a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return fabs(sum) / 6.0;
}

/* At least volume / max_volume tetrahedra: refused past SB_TETRA_MAX_TETS. */
static sb_status check_max_volume(const tetra_job* job, sb_error* err) {
    if (job->max_volume == 0.0) return SB_OK;
    double volume = enclosed_volume(&job->surface);
    double needed = volume / job->max_volume;
    if (needed <= SB_TETRA_MAX_TETS) return SB_OK;
    return sb_error_set(err, SB_ERR_INVALID,
                        "--max-volume %g: the surface encloses %.6g m^3, which needs at least %.3g tetrahedra "
                        "of that size, more than the limit of %.0e (use --max-volume >= %.3g)",
                        job->max_volume, volume, needed, SB_TETRA_MAX_TETS, volume / SB_TETRA_MAX_TETS);
}

static const char* in_dir(const tetra_job* job, const char* name, char* buffer, size_t size) {
    snprintf(buffer, size, "%s/%s", job->dir, name);
    return buffer;
}

static sb_status write_off(const tetra_job* job, sb_error* err) {
    char path[600];
    FILE* f = fopen(in_dir(job, "surface.off", path, sizeof path), "w");
    if (!f) return sb_error_set(err, SB_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    const sb_mesh* m = &job->surface;
    fprintf(f, "OFF\n%u %u 0\n", m->vertex_count, m->triangle_count);
    for (size_t i = 0; i < m->vertex_count; i++)
        fprintf(f, "%.17g %.17g %.17g\n", m->positions[3 * i], m->positions[3 * i + 1], m->positions[3 * i + 2]);
    for (size_t t = 0; t < m->triangle_count; t++)
        fprintf(f, "3 %u %u %u\n", m->triangles[3 * t], m->triangles[3 * t + 1], m->triangles[3 * t + 2]);
    return fclose(f) == 0 ? SB_OK : sb_error_set(err, SB_ERR_IO, "%s: cannot write", path);
}

/* ---- running tetgen ------------------------------------------------------- */

/* The last non-empty line of tetgen.log, into message. */
static void last_message(const tetra_job* job, char* message, size_t size) {
    char path[600];
    FILE* f = fopen(in_dir(job, "tetgen.log", path, sizeof path), "r");
    char line[512];
    snprintf(message, size, "no message");
    while (f && fgets(line, sizeof line, f)) {
        line[strcspn(line, "\r\n")] = '\0';
        if (line[strspn(line, " \t")] != '\0') snprintf(message, size, "%s", line + strspn(line, " \t"));
    }
    if (f) fclose(f);
}

static sb_status spawn_tetgen(const tetra_job* job, const char* program, char* const* argv, pid_t* pid, sb_error* err) {
    char log[600];
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, in_dir(job, "tetgen.log", log, sizeof log),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    int code = posix_spawnp(pid, program, &actions, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    if (code == ENOENT)
        return sb_error_set(err, SB_ERR_IO, "%s: program not found (Debian: apt-get install tetgen)", program);
    if (code != 0) return sb_error_set(err, SB_ERR_IO, "cannot run %s: %s", program, strerror(code));
    return SB_OK;
}

static sb_status run_tetgen(tetra_job* job, sb_error* err) {
    const char* env = getenv("SOFTBOND_TETGEN");
    const char* program = env && *env ? env : "tetgen";
    char* switches = job->switches;
    char input[600];
    int used = snprintf(switches, sizeof job->switches, "-pq%g", job->quality);
    if (job->max_volume > 0.0)
        used += snprintf(switches + used, sizeof job->switches - (size_t)used, "a%g", job->max_volume);
    snprintf(switches + used, sizeof job->switches - (size_t)used, "F");
    char* argv[] = {(char*)program, switches, (char*)in_dir(job, "surface.off", input, sizeof input), NULL};
    pid_t pid;
    sb_status status = spawn_tetgen(job, program, argv, &pid, err);
    if (status != SB_OK) return status;
    int wait_status;
    while (waitpid(pid, &wait_status, 0) < 0)
        if (errno != EINTR) return sb_error_set(err, SB_ERR_IO, "waiting for %s: %s", program, strerror(errno));
    if (WIFEXITED(wait_status) && WEXITSTATUS(wait_status) == 0) return SB_OK;
    char message[512];
    last_message(job, message, sizeof message);
    if (WIFEXITED(wait_status))
        return sb_error_set(err, SB_ERR_IO, "%s %s failed (exit %d): %s", program, switches, WEXITSTATUS(wait_status),
                            message);
    return sb_error_set(err, SB_ERR_IO,
                        "%s %s was killed by signal %d (%s); TetGen aborts so on a self-intersecting "
                        "surface: `tetgen -d` finds the intersections",
                        program, switches, WTERMSIG(wait_status), message);
}

/* Corners ordered so that (b - a) . ((c - a) x (d - a)) > 0: c and d
 * swapped where TetGen's order gives a negative volume. */
static void orient_positive(sb_tet_mesh* v) {
    for (size_t t = 0; t < v->tet_count; t++) {
        uint32_t* c = v->tets + 4 * t;
        if (sb_tet_volume(v->positions + 3 * (size_t)c[0], v->positions + 3 * (size_t)c[1],
                          v->positions + 3 * (size_t)c[2], v->positions + 3 * (size_t)c[3]) < 0.0) {
            uint32_t swap = c[2];
            c[2] = c[3];
            c[3] = swap;
        }
    }
}

static sb_status read_back(tetra_job* job, sb_error* err) {
    char node[600], ele[600];
    sb_status status = sb_tet_mesh_load_tetgen(in_dir(job, "surface.1.node", node, sizeof node),
                                               in_dir(job, "surface.1.ele", ele, sizeof ele), &job->volume, err);
    if (status == SB_OK) status = sb_tet_mesh_check(&job->volume, err);
    if (status == SB_OK) orient_positive(&job->volume);
    return status == SB_OK ? SB_OK : sb_error_prefix(err, status, "tetgen's output");
}

/* ---- the output pair ------------------------------------------------------ */

static sb_status write_pair_file(const tetra_job* job, const char* extension, sb_error* err) {
    char path[600];
    snprintf(path, sizeof path, "%s%s", job->out_base, extension);
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    const sb_tet_mesh* v = &job->volume;
    fprintf(file.stream, "# softbond tetra %s: tetgen %s\n", job->in, job->switches);
    if (strcmp(extension, ".node") == 0) {
        fprintf(file.stream, "%u 3 0 0\n", v->vertex_count);
        for (size_t i = 0; i < v->vertex_count; i++)
            fprintf(file.stream, "%zu %.17g %.17g %.17g\n", i, v->positions[3 * i], v->positions[3 * i + 1],
                    v->positions[3 * i + 2]);
    } else {
        fprintf(file.stream, "%u 4 0\n", v->tet_count);
        for (size_t t = 0; t < v->tet_count; t++)
            fprintf(file.stream, "%zu %u %u %u %u\n", t, v->tets[4 * t], v->tets[4 * t + 1], v->tets[4 * t + 2],
                    v->tets[4 * t + 3]);
    }
    return sb_atomic_commit(&file, err);
}

/* ---- the temporary directory ---------------------------------------------- */

static sb_status make_dir(tetra_job* job, sb_error* err) {
    const char* base = getenv("TMPDIR");
    snprintf(job->dir, sizeof job->dir, "%s/softbond_tetra_XXXXXX", base && *base ? base : "/tmp");
    if (mkdtemp(job->dir)) return SB_OK;
    sb_status status =
        sb_error_set(err, SB_ERR_IO, "%s: cannot make a temporary directory: %s", job->dir, strerror(errno));
    job->dir[0] = '\0';
    return status;
}

/* Removes what tetgen and tetra wrote there, then the directory. */
static void remove_dir(const tetra_job* job) {
    if (!job->dir[0]) return;
    DIR* d = opendir(job->dir);
    for (struct dirent* e; d && (e = readdir(d));) {
        char path[900];
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) {
            snprintf(path, sizeof path, "%s/%s", job->dir, e->d_name);
            unlink(path);
        }
    }
    if (d) closedir(d);
    rmdir(job->dir);
}

/* ---- the command ---------------------------------------------------------- */

static double tet_volume(const sb_tet_mesh* v) {
    double total = 0.0;
    for (size_t t = 0; t < v->tet_count; t++) {
        const uint32_t* c = v->tets + 4 * t;
        total += fabs(sb_tet_volume(v->positions + 3 * (size_t)c[0], v->positions + 3 * (size_t)c[1],
                                    v->positions + 3 * (size_t)c[2], v->positions + 3 * (size_t)c[3]));
    }
    return total;
}

static int tetra_finish(tetra_job* job, int code) {
    remove_dir(job);
    sb_mesh_free(&job->surface);
    sb_tet_mesh_free(&job->volume);
    return code;
}

static int tetrahedralize(tetra_job* job, sb_error* err) {
    if (load_closed(job, err) != SB_OK || check_max_volume(job, err) != SB_OK) return SB_EXIT_INPUT;
    if (make_dir(job, err) != SB_OK || write_off(job, err) != SB_OK || run_tetgen(job, err) != SB_OK ||
        read_back(job, err) != SB_OK || write_pair_file(job, ".node", err) != SB_OK ||
        write_pair_file(job, ".ele", err) != SB_OK)
        return SB_EXIT_FAILURE;
    printf("input: %s (%u vertices, %u triangles, closed)\n", job->in, job->surface.vertex_count,
           job->surface.triangle_count);
    printf("points: %u\ntetrahedra: %u\nvolume: %.9g m^3\n", job->volume.vertex_count, job->volume.tet_count,
           tet_volume(&job->volume));
    printf("wrote %s.node and %s.ele\n", job->out_base, job->out_base);
    return SB_EXIT_OK;
}

int sb_cli_tetra(int argc, char** argv) {
    tetra_job job = {.quality = 1.414};
    sb_error err;
    if (parse_args(argc, argv, &job, &err) != SB_OK) return tetra_finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    if (job.help) {
        sb_cli_tetra_usage(stdout);
        return tetra_finish(&job, SB_EXIT_OK);
    }
    int code = tetrahedralize(&job, &err);
    return tetra_finish(&job, code == SB_EXIT_OK ? code : sb_cli_fail(code, &err));
}
