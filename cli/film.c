/* `softbond film SCENE`: the Spring Systems film maker, finished. The scene
 * (any scene, or a .pov file of mesh2 objects itself, with gravity and the
 * contact between its bodies) is simulated; each frame is written as a
 * POV-Ray scene of the whole simulation, bodies and colliders at their
 * poses (viewer/film_scene.h); once the run is over, its bounds give the
 * camera of every frame (the setting they include); Debian's povray
 * renders them two at a time, one per core; Debian's ffmpeg assembles the
 * pictures into an H.264 MP4. One progress bar runs over the phases. */
#define _POSIX_C_SOURCE 200809L
#include "cli/cli.h"
#include "common/atomic_file.h"
#include "common/error.h"
#include "cli/output_dir.h"
#include "scenes/simulation.h"
#include "viewer/camera.h"
#include "viewer/film_scene.h"
#include "common/clock.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

enum { RENDERERS = 2, BAR = 40 };

void sb_cli_film_usage(FILE* stream) {
    fprintf(stream, "usage: softbond film SCENE.yaml|SCENE.pov [--set key=value]... [--movie OUT.mp4] [--size WxH]\n"
                    "                     [--fps F] [--eye x,y,z] [--target x,y,z] [--output DIR] [--threads N]\n"
                    "Simulates the scene for its duration (a .pov file of mesh2 objects is a scene itself:\n"
                    "the Spring Systems film maker's), writes a POV-Ray scene per frame (F frames per\n"
                    "simulated second, default 30) of the bodies and the colliders at their poses to DIR\n"
                    "(default out/<scene name>/film), renders them with povray (WxH pixels, default\n"
                    "640x480; two at a time) over a checker floor and assembles an H.264 MP4 with ffmpeg\n"
                    "(default DIR/<scene name>.mp4). The camera: --eye and --target (m, the scene's\n"
                    "coordinates), by default framing the bounds of the whole run. A progress bar with\n"
                    "an ETA on a terminal. Needs Debian's povray and ffmpeg.\n");
}

typedef struct film_job {
    sb_cli_args args;
    sb_simulation sim;
    sb_output_dir out;
    int width, height;
    double fps;
    uint32_t frames;
    double eye[3], target[3]; /* the camera of every frame */
    bool eye_given, target_given;
    double lo[3], hi[3]; /* the bounds of the whole run */
    sb_film_scene drawing;
    char* movie;
    double done, total; /* the progress bar's work: steps, then frames (x RENDER_WEIGHT), then the encoding */
    double started, drawn; /* wall clock: the start, the bar's last drawing */
} film_job;

/* ---- progress ------------------------------------------------------------ */

/* Drawn on a terminal only, at most 5 times a second, and always at the
 * end (100 %, the time it took); the ETA is the time so far stretched over
 * the work left. */
static void progress(film_job* job, double add, const char* phase) {
    job->done += add;
    if (!isatty(STDERR_FILENO)) return;
    double now = sb_wall_seconds(), fraction = fmin(1.0, job->done / job->total);
    bool end = strcmp(phase, "done") == 0;
    if (!end && now - job->drawn < 0.2) return;
    job->drawn = now;
    if (end) fraction = 1.0;
    int filled = (int)(BAR * fraction);
    char bar[BAR + 1], eta[32];
    for (int i = 0; i < BAR; i++) bar[i] = i < filled ? '#' : '.';
    bar[BAR] = '\0';
    double elapsed = now - job->started, left = fraction > 0.01 ? elapsed * (1.0 - fraction) / fraction : -1.0;
    if (end)
        snprintf(eta, sizeof eta, "in %d:%02d", (int)elapsed / 60, (int)elapsed % 60);
    else if (left >= 0)
        snprintf(eta, sizeof eta, "ETA %d:%02d", (int)left / 60, (int)left % 60);
    else
        snprintf(eta, sizeof eta, "ETA -:--");
    fprintf(stderr, "\rsoftbond: film [%s] %3.0f%%  %-10s %-10s", bar, 100.0 * fraction, phase, eta);
    fflush(stderr);
}

/* ---- the programs it runs ------------------------------------------------- */

static bool on_path(const char* program) {
    const char* path = getenv("PATH");
    char dir[4096];
    for (const char* p = path ? path : ""; *p;) {
        size_t n = strcspn(p, ":");
        snprintf(dir, sizeof dir, "%.*s/%s", (int)n, p, program);
        if (access(dir, X_OK) == 0) return true;
        p += n + (p[n] == ':');
    }
    return false;
}

static sb_status need(const char* program, const char* package, sb_error* err) {
    return on_path(program)
               ? SB_OK
               : sb_error_set(err, SB_ERR_INVALID, "film: %s is not on PATH (install Debian's %s: apt-get install %s)",
                              program, package, package);
}

/* Starts argv quietly (stdout to the file `out` when it is not NULL, else
 * like stderr to /dev/null); its pid, or -1. */
static pid_t start(char* const* argv, FILE* out) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (out)
        posix_spawn_file_actions_adddup2(&actions, fileno(out), STDOUT_FILENO);
    else
        posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    pid_t pid;
    int failed = posix_spawnp(&pid, argv[0], &actions, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&actions);
    return failed ? -1 : pid;
}

static bool succeeded(pid_t pid) {
    int status;
    while (waitpid(pid, &status, 0) == -1)
        if (errno != EINTR) return false;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/* ---- the phases ------------------------------------------------------------- */

static const char* frame_path(film_job* job, uint32_t k, const char* extension) {
    char name[64];
    snprintf(name, sizeof name, "frame_%06u.%s", k, extension);
    return sb_output_dir_path(&job->out, name);
}

static sb_status write_frame(film_job* job, uint32_t k, double* positions, sb_error* err) {
    sb_solver_get_positions(job->sim.solver, positions);
    sb_film_scene_bounds(&job->drawing, positions, job->sim.mesh.vertex_count, job->lo, job->hi);
    return sb_film_scene_write_frame(&job->drawing, frame_path(job, k, "pov"), &job->sim.mesh, positions, err);
}

static sb_status simulate(film_job* job, sb_error* err) {
    double dt = sb_scene_number(&job->sim.scene, SB_KEY_DT);
    /* a tearing solver has more vertices than the mesh (its split copies): room for all it may write */
    double* positions = malloc(3 * ((size_t)sb_solver_vertex_capacity(job->sim.solver) + 1) * sizeof *positions);
    if (!positions) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    sb_status status = SB_OK;
    for (uint32_t k = 0; k < job->frames && status == SB_OK; k++) {
        uint64_t step = (uint64_t)llround(k / (job->fps * dt));
        while (status == SB_OK && sb_solver_step_count(job->sim.solver) < step) {
            if (sb_solver_advance(job->sim.solver, dt) != SB_OK)
                status = sb_error_set(err, SB_ERR_UNSTABLE, "%s", sb_solver_error(job->sim.solver));
            progress(job, 1.0, "simulating");
        }
        if (status == SB_OK) status = write_frame(job, k, positions, err);
    }
    free(positions);
    return status;
}

/* povray writes frame k's picture to its stdout (+O-), which is png's
 * NAME.tmp, renamed when the picture is whole: povray's exit status does
 * not say whether its writes succeeded (0 onto /dev/full), so the file is
 * read back for the PNG's last chunk, IEND. */
static pid_t start_povray(film_job* job, uint32_t k, sb_atomic_file* png, sb_error* err) {
    char in[4200], out[4200], w[32], h[32], library[4200];
    if (sb_atomic_open(png, frame_path(job, k, "png"), err) != SB_OK) return -2;
    snprintf(library, sizeof library, "+L%s", job->out.dir); /* where the frames' setting is */
    snprintf(in, sizeof in, "+I%s", frame_path(job, k, "pov"));
    snprintf(out, sizeof out, "+O-");
    snprintf(w, sizeof w, "+W%d", job->width);
    snprintf(h, sizeof h, "+H%d", job->height);
    char* argv[] = {"povray", in, library, out, w, h, "+FN", "-D", "+A0.3", "-V", NULL};
    return start(argv, png->stream);
}

static bool whole_png(const char* path) {
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    unsigned char tail[12];
    FILE* f = fopen(path, "rb");
    bool whole = f && fseek(f, -12, SEEK_END) == 0 && fread(tail, 1, 12, f) == 12 && memcmp(tail, iend, 12) == 0;
    if (f) fclose(f);
    return whole;
}

/* Two povrays at a time, frames in order; the first failure names its frame. */
static sb_status render(film_job* job, sb_error* err) {
    pid_t running[RENDERERS];
    sb_atomic_file png[RENDERERS];
    uint32_t frame_of[RENDERERS], next = 0;
    int count = 0;
    sb_status status = SB_OK;
    while (count > 0 || (next < job->frames && status == SB_OK)) {
        while (count < RENDERERS && next < job->frames && status == SB_OK) {
            frame_of[count] = next;
            running[count] = start_povray(job, next++, &png[count], err);
            if (running[count] == -1) {
                sb_atomic_abort(&png[count]);
                status = sb_error_set(err, SB_ERR_IO, "film: cannot start povray");
            } else if (running[count] == -2)
                status = SB_ERR_IO; /* the picture's file could not be opened: err says why */
            else
                count++;
        }
        if (count == 0) break;
        bool ok = succeeded(running[0]);
        if (!ok || (status == SB_OK && (fflush(png[0].stream) != 0 || !whole_png(sb_atomic_write_path(&png[0]))))) {
            sb_atomic_abort(&png[0]);
            if (status == SB_OK)
                status = ok ? sb_error_set(err, SB_ERR_IO, "%s: cannot write: povray's picture is cut short",
                                           frame_path(job, frame_of[0], "png"))
                            : sb_error_set(err, SB_ERR_IO, "film: povray failed on %s",
                                           frame_path(job, frame_of[0], "pov"));
        } else if (status != SB_OK)
            sb_atomic_abort(&png[0]);
        else
            status = sb_atomic_commit(&png[0], err);
        memmove(running, running + 1, (size_t)(count - 1) * sizeof *running);
        memmove(png, png + 1, (size_t)(count - 1) * sizeof *png);
        memmove(frame_of, frame_of + 1, (size_t)(count - 1) * sizeof *frame_of);
        count--;
        progress(job, 1.0, "rendering");
    }
    return status;
}

static sb_status encode(film_job* job, sb_error* err) {
    char rate[32], pattern[4200];
    snprintf(rate, sizeof rate, "%g", job->fps);
    snprintf(pattern, sizeof pattern, "%s/frame_%%06d.png", job->out.dir);
    /* the movie appears whole or not at all: ffmpeg writes NAME.tmp (hence -f mp4), renamed when it succeeded */
    sb_atomic_file movie;
    if (sb_atomic_open(&movie, job->movie, err) != SB_OK) return SB_ERR_IO;
    char* argv[] = {"ffmpeg",  "-y",         "-loglevel", "error", "-framerate", rate,      "-i", pattern,
                    "-c:v",    "libx264",    "-pix_fmt",  "yuv420p", "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                    "-f",      "mp4",        (char*)sb_atomic_write_path(&movie), NULL};
    progress(job, 0.0, "encoding");
    pid_t pid = start(argv, NULL);
    if (pid < 0 || !succeeded(pid)) {
        sb_atomic_abort(&movie);
        return sb_error_set(err, SB_ERR_IO, "film: ffmpeg could not make %s", job->movie);
    }
    if (sb_atomic_commit(&movie, err) != SB_OK) return SB_ERR_IO;
    progress(job, 1.0, "done");
    return SB_OK;
}

/* ---- the command -------------------------------------------------------------- */

static sb_status options(film_job* job, sb_error* err) {
    job->width = 640, job->height = 480, job->fps = 30.0;
    if (job->args.size && sb_cli_size(job->args.size, &job->width, &job->height, err) != SB_OK) return SB_ERR_INVALID;
    if (job->args.fps) {
        char* end;
        job->fps = strtod(job->args.fps, &end);
        if (end == job->args.fps || *end != '\0' || !(job->fps > 0.0 && job->fps <= 1000.0))
            return sb_error_set(err, SB_ERR_INVALID,
                                "--fps: expected a number of frames per second in (0, 1000], got '%s'", job->args.fps);
    }
    sb_status status = need("povray", "povray", err);
    return status == SB_OK ? need("ffmpeg", "ffmpeg", err) : status;
}

/* "x,y,z" (m) into out. */
static sb_status point(const char* option, const char* text, double out[3], sb_error* err) {
    char* end = (char*)text;
    for (int k = 0; k < 3; k++) {
        const char* from = end + (k > 0 && *end == ',');
        out[k] = strtod(from, &end);
        if (end == from || !isfinite(out[k])) break;
        if (k == 2 && *end == '\0') return SB_OK;
    }
    return sb_error_set(err, SB_ERR_INVALID, "%s: expected x,y,z in metres, got '%s'", option, text);
}

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1], out[1] = a[2] * b[0] - a[0] * b[2], out[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize(double v[3]) {
    double length = sqrt(dot(v, v));
    for (int k = 0; k < 3; k++) v[k] = length > 0 ? v[k] / length : 0.0;
}

/* --eye and --target, checked before the run; the camera is placed after it. */
static sb_status camera_options(film_job* job, sb_error* err) {
    job->eye_given = job->args.eye != NULL, job->target_given = job->args.target != NULL;
    sb_status status = job->args.eye ? point("--eye", job->args.eye, job->eye, err) : SB_OK;
    return status == SB_OK && job->args.target ? point("--target", job->args.target, job->target, err) : status;
}

/* The camera of every frame, where --eye and --target do not say: the
 * viewer's direction (from the front, a little above) on the centre of the
 * bounds of the whole run, bodies and colliders, as near as it can be with
 * all eight corners of that box in the picture; then the setting every
 * frame includes. */
static sb_status place_camera(film_job* job, sb_error* err) {
    double up[3], eye[3], target[3];
    sb_simulation_up(&job->sim, up);
    sb_camera camera = sb_camera_fit(job->lo, job->hi, up);
    double aspect = (double)job->width / job->height;
    for (int k = 0; k < 3; k++) camera.target[k] = 0.5 * (job->lo[k] + job->hi[k]);
    /* the nearest eye, along the viewer's direction, that has every corner of the box in view, 5 % in from the edges */
    double forward[3], right[3], above[3], t_v = 0.95 * tan(0.5 * camera.fov), t_h = t_v * aspect;
    camera.distance = 1.0;
    sb_camera_forward(&camera, forward);
    cross(forward, up, right);
    cross(right, forward, above);
    normalize(right), normalize(above);
    double distance = 1e-3;
    for (int corner = 0; corner < 8; corner++) {
        double d[3];
        for (int k = 0; k < 3; k++) d[k] = ((corner >> k) & 1 ? job->hi[k] : job->lo[k]) - camera.target[k];
        double depth = -dot(d, forward); /* toward the eye */
        distance = fmax(distance, depth + fmax(fabs(dot(d, right)) / t_h, fabs(dot(d, above)) / t_v));
    }
    camera.distance = distance;
    sb_camera_eye(&camera, eye);
    memcpy(target, camera.target, sizeof target);
    if (!job->eye_given) memcpy(job->eye, eye, sizeof eye);
    if (!job->target_given) memcpy(job->target, target, sizeof target);
    return sb_film_scene_write_setting(&job->drawing, sb_output_dir_path(&job->out, SB_FILM_SETTING), job->eye,
                                       job->target, camera.fov, aspect, job->lo, job->hi, err);
}

static sb_status prepare(film_job* job, sb_error* err) {
    sb_status status = options(job, err);
    sb_simulation_args sim_args = sb_cli_simulation_args(&job->args);
    if (status == SB_OK) status = sb_simulation_prepare(&job->sim, &sim_args, err);
    if (status == SB_OK) status = sb_cli_no_mouse(&job->sim.scene, "film", err);
    if (status == SB_OK) status = sb_simulation_start(&job->sim, NULL, err);
    if (status != SB_OK) return status;
    double duration = sb_scene_number(&job->sim.scene, SB_KEY_DURATION);
    job->frames = (uint32_t)fmin(floor(duration * job->fps + 1e-9) + 1, 1e6);
    if ((status = camera_options(job, err)) != SB_OK) return status;
    if ((status = sb_film_scene_create(&job->drawing, &job->sim, err)) != SB_OK) return status;
    for (int k = 0; k < 3; k++) job->lo[k] = INFINITY, job->hi[k] = -INFINITY;
    char dir[4096];
    snprintf(dir, sizeof dir, "out/%s/film", job->sim.scene.name);
    status = sb_output_dir_create(&job->out, job->args.output ? job->args.output : dir, job->sim.scene.name, err);
    if (status != SB_OK) return status;
    char movie[4200];
    snprintf(movie, sizeof movie, "%s/%s.mp4", job->out.dir, job->sim.scene.name);
    job->movie = strdup(job->args.movie ? job->args.movie : movie);
    double steps = ceil(duration / sb_scene_number(&job->sim.scene, SB_KEY_DT));
    job->total = steps + 20.0 * job->frames + 20.0; /* a frame renders in about the time of 20 steps */
    return job->movie ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory");
}

static int film_finish(film_job* job, int code) {
    free(job->movie);
    sb_film_scene_free(&job->drawing);
    sb_output_dir_free(&job->out);
    sb_simulation_free(&job->sim);
    sb_cli_args_free(&job->args);
    return code;
}

int sb_cli_film(int argc, char** argv) {
    static const char* const accepted[] = {"--movie", "--size",   "--fps",     "--output",
                                           "--eye",   "--target", "--threads", NULL};
    film_job job = {0};
    sb_error err;
    if (sb_cli_parse(argc, argv, accepted, &job.args, &err) != SB_OK)
        return film_finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    if (job.args.help) {
        sb_cli_film_usage(stdout);
        return film_finish(&job, SB_EXIT_OK);
    }
    if (prepare(&job, &err) != SB_OK) return film_finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    job.started = sb_wall_seconds();
    sb_status status = simulate(&job, &err);
    int code = status == SB_ERR_UNSTABLE ? SB_EXIT_SOLVER : SB_EXIT_FAILURE;
    if (status == SB_OK) status = place_camera(&job, &err);
    if (status == SB_OK) status = render(&job, &err);
    if (status == SB_OK) status = encode(&job, &err);
    if (isatty(STDERR_FILENO)) fprintf(stderr, "\n");
    if (status != SB_OK) return film_finish(&job, sb_cli_fail(code, &err));
    printf("softbond: %u frames (%dx%d, %g per second) in %s, movie %s\n", job.frames, job.width, job.height, job.fps,
           job.out.dir, job.movie);
    return film_finish(&job, SB_EXIT_OK);
}
