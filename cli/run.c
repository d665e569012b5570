/* `softbond run SCENE.yaml`: advances the scene's model with a fixed dt
 * until its duration or a stop condition (stop.c: the kinetic energy below
 * stop.kinetic_energy, the watchdog stop.max_time; a last frame at the stop,
 * and a line saying which ended the run), writing frame k at step round(k frame_interval / dt)
 * for k = 0 .. floor(duration / frame_interval), and one more at the end
 * when the duration is not on that grid (always the end state): a file each in every
 * format of output.formats (unless output.frames is false; frame_export.c),
 * frames.pvd listing the .vtu frames, and a row of log.csv (with the
 * contacts and each collider's force, colliders.h, then each soft handle's,
 * handles.h).
 * Nothing is created before the scene is valid and its model compiled. */
#define _POSIX_C_SOURCE 200809L
#include "cli/checkpoint.h"
#include "common/atomic_file.h"
#include "common/clock.h"
#include "cli/cli.h"
#include "cli/energy_log.h"
#include "common/error.h"
#include "cli/frame_export.h"
#include "cli/output_dir.h"
#include "cli/progress.h"
#include "cli/run_record.h"
#include "scenes/simulation.h"
#include "cli/stop.h"
#include "cli/study_case.h"
#include "cli/torn_surface.h"
#include "cli/vtk.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

enum { INDEX_EVERY_FRAME = 1024 };

void sb_cli_run_usage(FILE* stream) {
    fprintf(stream, "usage: softbond run SCENE.yaml [--set key=value]... [--output DIR] [--threads N]\n"
                    "                    [--budget-ms X [--max-error M]] [--no-realtime] [--checkpoint-every T]\n"
                    "                    [--end-positions FILE.csv]\n"
                    "       softbond run SCENE.yaml [--set key=value]... --resume DIR [--threads N]\n"
                    "Runs a scene and writes its frames (output.formats: .vtu, listed in frames.pvd,\n"
                    "and ply, obj, gltf, glb, irit, pov) and log.csv\n"
                    "(per frame: the energy of each term, the solver's steps, sub-steps and\n"
                    "iterations, the vertex contacts and each collider's and soft handle's force\n"
                    "<name>_fx,_fy,_fz)\n"
                    "to DIR, by default out/<scene name>.\n"
                    "--set overrides any scene key (softbond keys; docs/scenes.md), e.g.\n"
                    "  --set 'colliders=[{type: plane, restitution: 0.5}]' --set contact.thickness=0.002\n"
                    "colliders: a list of {type: plane | sphere | capsule | box | mesh, name,\n"
                    "plane: point, normal; sphere: center, radius; capsule: a, b, radius; box:\n"
                    "center, half_extents, rotate; mesh: file, scale, rotate, translate;\n"
                    "friction, static_friction, restitution, thickness, footprint (not a\n"
                    "plane), path: [{time, translate, rotate}...], interpolation: linear |\n"
                    "smooth; a sphere or box: mass, velocity, angular_velocity}.\n"
                    "--threads (or SOFTBOND_THREADS) sets the solver's threads.\n"
                    "--budget-ms X times the fast step on the scene's surface mesh simplified to\n"
                    "1/2, 1/4, ... of its vertices and runs the largest that takes <= X ms a step\n"
                    "(the smallest if none does); it prints what it measured and picked.\n"
                    "--max-error M (m) also runs each level for the scene's first 0.5 s beside\n"
                    "the full mesh and keeps only the levels whose vertices end within M (RMS)\n"
                    "of the full model's: the largest of those within X, else the smallest of\n"
                    "them (the budget missed, and said).\n"
                    "--no-realtime: with haptics.tool set, the simulation runs as fast as it can\n"
                    "instead of paced to the wall clock (haptics.realtime: false).\n"
                    "--checkpoint-every T writes DIR/checkpoint.sbck (the whole state, atomically)\n"
                    "after the first frame at or past each T seconds of simulated time; --resume DIR\n"
                    "goes on from it, appending to DIR's frames and log.csv exactly as the run would\n"
                    "have: give the same scene and --set options (another scene is refused); a\n"
                    "longer duration (--set duration=T) goes on past a finished run's end, from its\n"
                    "last checkpoint, as one run of that length would have.\n"
                    "--end-positions FILE.csv writes the end state's vertex positions (a header x,y,z,\n"
                    "then a row per vertex, as eval --positions reads them) after a run that ends well.\n");
}

typedef struct run_job {
    sb_cli_args args;
    sb_simulation sim; /* the scene, its model, colliders, handles, haptics and solver */
    double* forces;    /* 3 per collider, then 3 per soft handle: a frame's forces */
    sb_output_dir out;
    sb_energy_log log;
    sb_step_work work;    /* the solver's work since the last frame */
    sb_stop stop;         /* the stop conditions, and which ended the run */
    double index_written; /* when frames.pvd was last rewritten (sb_wall_seconds()) */
    sb_frame_export_def export;
    double* buffers;         /* positions, velocities, forces: 3n each, n the solver's vertex capacity */
    sb_torn_surface surface; /* what the frames show of a solver that tears */
    /* checkpoints (checkpoint.h): every > 0 when they are written */
    sb_run_state resumed; /* --resume: where the checkpoint left the run */
    uint64_t scene_hash;
    sb_checkpoint_files files; /* the scene's files, in the checkpoint's "FILE" section */
    double checkpoint_every, next_checkpoint;
    bool end_frame; /* the last frame is the end state, off the frame_interval grid */
    int argc;       /* the command line, for run.yaml */
    char** argv;
} run_job;

static int run_finish(run_job* job, int code) {
    free(job->resumed.times);
    sb_checkpoint_files_free(&job->files);
    free(job->buffers);
    sb_torn_surface_free(&job->surface);
    sb_error ignored;
    sb_energy_log_close(&job->log, &ignored);
    sb_output_dir_free(&job->out);
    sb_simulation_free(&job->sim);
    free(job->forces);
    sb_cli_args_free(&job->args);
    return code;
}

/* The frame formats (checked by sb_scene_validate), shown with up against
 * gravity (+z without gravity). */
static void set_export(run_job* job) {
    char bad[64];
    sb_frame_formats_parse(sb_scene_string(&job->sim.scene, SB_KEY_OUTPUT_FORMATS), &job->export.formats, bad,
                           sizeof bad);
    sb_simulation_up(&job->sim, job->export.up);
    const char* vtu = sb_scene_string(&job->sim.scene, SB_KEY_OUTPUT_VTU);
    job->export.vtu = strcmp(vtu, "zlib") == 0     ? SB_VTK_ZLIB
                      : strcmp(vtu, "binary") == 0 ? SB_VTK_BINARY
                                                   : SB_VTK_ASCII;
}

static bool soft(const sb_scene_handle* handle) { return handle->def.stiffness > 0.0; }

/* A force column of log.csv (<name>_fx,_fy,_fz) for each collider, then
 * for each soft handle. */
static sb_status make_force_columns(run_job* job, sb_error* err) {
    uint32_t count = job->sim.colliders.count + job->sim.handles.count;
    job->forces = calloc(3 * (size_t)(count ? count : 1), sizeof *job->forces);
    bool ok = job->forces != NULL;
    for (uint32_t c = 0; c < job->sim.colliders.count && ok; c++)
        ok = sb_energy_log_add_collider(&job->log, job->sim.colliders.entries[c].name);
    for (uint32_t h = 0; h < job->sim.handles.count && ok; h++)
        if (soft(&job->sim.handles.entries[h]))
            ok = sb_energy_log_add_collider(&job->log, job->sim.handles.entries[h].name);
    return ok ? SB_OK : sb_error_set(err, SB_ERR_NOMEM, "out of memory");
}

/* The frames a run writes at most: floor(end / interval) + 1, and one at a stop. */
static uint64_t most_frames(const run_job* job) {
    double interval = sb_scene_number(&job->sim.scene, SB_KEY_FRAME_INTERVAL);
    sb_stop stop = sb_stop_from_scene(&job->sim.scene);
    return (uint64_t)floor(sb_stop_end(&stop) / interval + 1e-9) + 2;
}

/* DIR/checkpoint.sbck of --resume DIR. */
static const char* checkpoint_path(run_job* job) { return sb_output_dir_path(&job->out, "checkpoint.sbck"); }

/* Whether log.csv's first `bytes` bytes are its header and `frames` rows:
 * frames + 1 whole lines. */
static bool log_rows_match(const char* path, uint64_t bytes, uint64_t frames) {
    FILE* f = fopen(path, "rb");
    if (!f) return false;
    uint64_t lines = 0, at = 0;
    int c = 0, last = 0;
    for (; at < bytes && (c = getc(f)) != EOF; at++, last = c) lines += c == '\n';
    fclose(f);
    return at == bytes && last == '\n' && lines == frames + 1;
}

/* --resume DIR: the checkpoint read and the solver's state loaded, its
 * stop conditions the scene's, and log.csv holding the rows the
 * checkpoint says; nothing written yet. */
static sb_status resume(run_job* job, sb_error* err) {
    job->out.dir = strdup(job->args.resume);
    if (!job->out.dir) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    sb_status status = sb_checkpoint_read(checkpoint_path(job), job->scene_hash, job->sim.mesh.vertex_count,
                                          most_frames(job), &job->resumed, job->sim.solver, err);
    if (status != SB_OK) return status;
    struct stat info;
    const char* log = sb_output_dir_path(&job->out, "log.csv");
    if (stat(log, &info) != 0 || (uint64_t)info.st_size < job->resumed.log_bytes)
        return sb_error_set(err, SB_ERR_INVALID, "%s: missing or shorter than the checkpoint's %llu bytes", log,
                            (unsigned long long)job->resumed.log_bytes);
    if (!log_rows_match(log, job->resumed.log_bytes, job->resumed.frames))
        return sb_error_set(err, SB_ERR_INVALID,
                            "%s: its first %llu bytes are not a header and %llu rows (the checkpoint's)", log,
                            (unsigned long long)job->resumed.log_bytes, (unsigned long long)job->resumed.frames);
    /* the solver's clock: as many steps of dt as its time holds */
    double dt = sb_scene_number(&job->sim.scene, SB_KEY_DT), now = sb_solver_time(job->sim.solver);
    uint64_t steps = sb_solver_step_count(job->sim.solver);
    if (!(fabs(now - (double)steps * dt) <= 1e-6 * (now + dt)))
        return sb_error_set(err, SB_ERR_INVALID,
                            "%s: the run's state is out of range (the solver at t = %g s after %llu steps of %g s)",
                            checkpoint_path(job), now, (unsigned long long)steps, dt);
    sb_stop scene_stop = sb_stop_from_scene(&job->sim.scene);
    const sb_stop* saved = &job->resumed.stop;
    if (saved->kinetic_energy != scene_stop.kinetic_energy || saved->min_time != scene_stop.min_time ||
        saved->max_time != scene_stop.max_time)
        return sb_error_set(err, SB_ERR_INVALID,
                            "%s: its stop conditions (stop.kinetic_energy %g, min_time %g, max_time %g) are not the "
                            "scene's (%g, %g, %g)",
                            checkpoint_path(job), saved->kinetic_energy, saved->min_time, saved->max_time,
                            scene_stop.kinetic_energy, scene_stop.min_time, scene_stop.max_time);
    job->checkpoint_every = job->resumed.every;
    job->next_checkpoint = job->resumed.next;
    /* the scene's duration now: the run may go on to a longer one */
    job->resumed.stop.duration = sb_scene_number(&job->sim.scene, SB_KEY_DURATION);
    double t = sb_solver_time(job->sim.solver), end = sb_stop_end(&job->resumed.stop);
    if (t > end + 1e-9 * sb_scene_number(&job->sim.scene, SB_KEY_DT))
        return sb_scene_fail(&job->sim.scene, SB_KEY_DURATION, err,
                             "--resume %s: its checkpoint is at t = %.9g s, past the run's end %.9g s (a resumed run "
                             "may only be longer)",
                             job->args.resume, t, end);
    return SB_OK;
}

/* --checkpoint-every T and --resume DIR (checkpoint.h); not with a haptic
 * device, whose motion no run repeats. */
static sb_status prepare_checkpoints(run_job* job, sb_error* err) {
    const char* every = job->args.checkpoint_every;
    if (!every && !job->args.resume) return SB_OK;
    if (job->sim.haptics.enabled)
        return sb_error_set(err, SB_ERR_INVALID,
                            "--checkpoint-every, --resume: not with haptics.tool (a device's "
                            "motion is not repeated by a resumed run)");
    if (job->args.resume && job->args.output)
        return sb_error_set(err, SB_ERR_INVALID, "--resume DIR writes into DIR: leave out --output");
    sb_status status = sb_checkpoint_scene_hash(&job->sim.scene, &job->args, &job->scene_hash, &job->files, err);
    if (status == SB_OK && job->args.resume) status = resume(job, err);
    if (status != SB_OK || !every) return status;
    char* end;
    job->checkpoint_every = strtod(every, &end);
    if (end == every || *end != '\0' || !(job->checkpoint_every > 0.0) || !isfinite(job->checkpoint_every))
        return sb_error_set(err, SB_ERR_INVALID, "--checkpoint-every: expected seconds > 0, got '%s'", every);
    if (!job->args.resume) job->next_checkpoint = job->checkpoint_every;
    return SB_OK;
}

/* The scene, its model and a solver for it: all the input, checked. */
static sb_status prepare(run_job* job, sb_error* err) {
    if (job->args.output && job->args.output[0] == '\0')
        return sb_error_set(err, SB_ERR_INVALID, "--output: expected a folder, got ''");
    sb_simulation_args sim_args = sb_cli_simulation_args(&job->args);
    sb_status status = sb_simulation_prepare(&job->sim, &sim_args, err);
    if (status == SB_OK) status = sb_cli_no_mouse(&job->sim.scene, "run", err);
    if (status == SB_OK) status = sb_simulation_start(&job->sim, NULL, err);
    if (status == SB_OK) status = make_force_columns(job, err);
    if (status != SB_OK) return status;
    set_export(job);
    if (job->args.no_realtime) job->sim.haptics.paced = false;
    size_t n = 3 * (size_t)sb_solver_vertex_capacity(job->sim.solver);
    job->buffers = malloc(3 * (n ? n : 1) * sizeof(double));
    if (!job->buffers) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    status = sb_torn_surface_init(&job->surface, job->sim.solver, err);
    return status == SB_OK ? prepare_checkpoints(job, err) : status;
}

static bool writes_vtu(const run_job* job) {
    return sb_scene_bool(&job->sim.scene, SB_KEY_OUTPUT_FRAMES) && (job->export.formats & SB_FRAME_VTU);
}

/* frames.pvd: after each frame while short, then once a second; always at the end. */
static sb_status write_index(run_job* job, bool last, sb_error* err) {
    if (!writes_vtu(job)) return SB_OK;
    if (!last && job->log.count > INDEX_EVERY_FRAME && sb_wall_seconds() - job->index_written < 1.0) return SB_OK;
    job->index_written = sb_wall_seconds();
    return sb_vtk_write_collection(sb_output_dir_path(&job->out, "frames.pvd"), job->log.times, job->log.count, err);
}

static sb_status write_frame(run_job* job, sb_error* err) {
    size_t n = 3 * (size_t)sb_solver_vertex_capacity(job->sim.solver);
    const sb_mesh* surface = sb_torn_surface_update(&job->surface, job->sim.solver, &job->sim.mesh, job->buffers);
    if (!surface) return sb_error_set(err, SB_ERR_NOMEM, "out of memory for the cut surface's triangles");
    sb_vtk_frame frame = {surface,         job->sim.model, job->buffers, job->buffers + n, job->buffers + 2 * n,
                          job->sim.solver, job->export.vtu};
    sb_solver_get_positions(job->sim.solver, job->buffers);
    sb_solver_get_velocities(job->sim.solver, job->buffers + n);
    sb_solver_get_forces(job->sim.solver, job->buffers + 2 * n);
    return sb_frame_export(&job->export, &job->out, job->log.count, &frame, err);
}

static int record_frame(run_job* job, sb_error* err) {
    if (sb_scene_bool(&job->sim.scene, SB_KEY_OUTPUT_FRAMES) && write_frame(job, err) != SB_OK) return SB_EXIT_FAILURE;
    sb_energies energies = sb_solver_energies(job->sim.solver);
    /* the last advance's contacts and forces; none before the first */
    bool advanced = sb_solver_step_count(job->sim.solver) > 0;
    uint32_t contacts = advanced ? sb_solver_last_step(job->sim.solver).contacts : 0;
    for (uint32_t c = 0; c < job->sim.colliders.count; c++) {
        double* f = job->forces + 3 * (size_t)c;
        f[0] = f[1] = f[2] = 0.0;
        if (advanced) sb_solver_contact_force(job->sim.solver, c, f);
    }
    double* f = job->forces + 3 * (size_t)job->sim.colliders.count;
    for (uint32_t h = 0; h < job->sim.handles.count; h++) {
        if (!soft(&job->sim.handles.entries[h])) continue;
        sb_handle_force(job->sim.handles.handles[h], f); /* set at the last force evaluation: 0 at rest on frame 0 */
        f += 3;
    }
    sb_status status = sb_energy_log_add(&job->log, sb_solver_time(job->sim.solver), &energies, &job->work, contacts,
                                         job->forces, sb_solver_broken_count(job->sim.solver), err);
    if (status == SB_OK) status = write_index(job, false, err);
    job->work = (sb_step_work){0};
    return status == SB_OK ? SB_EXIT_OK : SB_EXIT_FAILURE;
}

/* After a frame: the checkpoint, when one is due. */
static int checkpoint(run_job* job, sb_error* err) {
    double t = sb_solver_time(job->sim.solver), every = job->checkpoint_every;
    if (!(every > 0.0) || t < job->next_checkpoint - 1e-9 * every) return SB_EXIT_OK;
    job->next_checkpoint = every * (floor(t / every + 1e-9) + 1.0);
    sb_run_state run = {.frames = job->log.count,
                        .log_bytes = sb_energy_log_bytes(&job->log),
                        .every = every,
                        .next = job->next_checkpoint,
                        .stop = job->stop,
                        .times = job->log.times,
                        .files = &job->files};
    sb_status status = sb_checkpoint_write(checkpoint_path(job), job->scene_hash, job->sim.mesh.vertex_count, &run,
                                           job->sim.solver, err);
    return status == SB_OK ? SB_EXIT_OK : SB_EXIT_FAILURE;
}

static int advance_to(run_job* job, uint64_t step, sb_progress* progress, sb_error* err) {
    double dt = sb_scene_number(&job->sim.scene, SB_KEY_DT);
    while (sb_solver_step_count(job->sim.solver) < step) {
        sb_scene_haptics_before_step(&job->sim.haptics, job->sim.solver);
        if (sb_solver_advance(job->sim.solver, dt) != SB_OK) {
            sb_error_set(err, SB_ERR_UNSTABLE, "%s", sb_solver_error(job->sim.solver));
            return SB_EXIT_SOLVER;
        }
        if (sb_scene_haptics_after_step(&job->sim.haptics, job->sim.solver, err) != SB_OK) return SB_EXIT_FAILURE;
        sb_step_stats stats = sb_solver_last_step(job->sim.solver);
        sb_step_work_add(&job->work, &stats);
        sb_progress_update(progress, sb_solver_step_count(job->sim.solver));
        double time = sb_solver_time(job->sim.solver);
        if (sb_stop_watches(&job->stop, time) &&
            sb_stop_after_step(&job->stop, time, sb_solver_energies(job->sim.solver).kinetic))
            break;
    }
    return SB_EXIT_OK;
}

/* The solver has moved on since the last frame: the end state is still to write. */
static bool past_last_frame(const run_job* job) {
    return job->log.count == 0 || sb_solver_time(job->sim.solver) > job->log.times[job->log.count - 1];
}

static int simulate(run_job* job, sb_error* err) {
    double dt = sb_scene_number(&job->sim.scene, SB_KEY_DT);
    double interval = sb_scene_number(&job->sim.scene, SB_KEY_FRAME_INTERVAL);
    job->stop = job->args.resume ? job->resumed.stop : sb_stop_from_scene(&job->sim.scene);
    double end = sb_stop_end(&job->stop);
    uint64_t frames = (uint64_t)floor(end / interval + 1e-9) + 1;
    uint64_t steps = (uint64_t)ceil(end / dt - 1e-9);
    sb_progress progress = sb_progress_start(steps, dt);
    int code = SB_EXIT_OK;
    bool stopped = job->stop.reason != SB_STOP_RUNNING; /* a stop condition fired: its frame is the last */
    for (uint64_t k = job->log.count; k < frames && code == SB_EXIT_OK && !stopped; k++) {
        code = advance_to(job, (uint64_t)llround((double)k * interval / dt), &progress, err);
        stopped = job->stop.reason != SB_STOP_RUNNING;
        if (code == SB_EXIT_OK) code = record_frame(job, err);
        if (code == SB_EXIT_OK) code = checkpoint(job, err);
    }
    if (code == SB_EXIT_OK && !stopped) {
        code = advance_to(job, steps, &progress, err);
        if (code == SB_EXIT_OK && past_last_frame(job)) {
            job->end_frame = job->stop.reason == SB_STOP_RUNNING; /* not a stop's frame: said at the end */
            code = record_frame(job, err);
        }
    }
    if (code == SB_EXIT_OK && job->stop.reason == SB_STOP_RUNNING)
        sb_stop_at_end(&job->stop, sb_solver_time(job->sim.solver), sb_solver_energies(job->sim.solver).kinetic);
    sb_progress_end(&progress);
    return code;
}

static void report(const run_job* job, uint32_t frames, double seconds) {
    const char* dir = job->out.dir;
    if (writes_vtu(job))
        printf("softbond: %u frame%s and log.csv in %s (open %s/frames.pvd in ParaView), "
               "%.1f s\n",
               frames, frames == 1 ? "" : "s", dir, dir, seconds);
    else if (sb_scene_bool(&job->sim.scene, SB_KEY_OUTPUT_FRAMES))
        printf("softbond: %u frame%s (%s) and log.csv in %s, %.1f s\n", frames, frames == 1 ? "" : "s",
               sb_scene_string(&job->sim.scene, SB_KEY_OUTPUT_FORMATS), dir, seconds);
    else
        printf("softbond: log.csv (%u rows) in %s, %.1f s\n", frames, dir, seconds);
}

/* The output folder and log.csv: made anew, or (--resume) as the
 * checkpoint left them, the log cut to its rows and the frames' times
 * taken over. */
static sb_status open_output(run_job* job, sb_error* err) {
    if (!job->args.resume) {
        sb_status status = sb_output_dir_create(&job->out, job->args.output, job->sim.scene.name, err);
        return status == SB_OK ? sb_energy_log_open(&job->log, sb_output_dir_path(&job->out, "log.csv"), err) : status;
    }
    sb_run_state* run = &job->resumed;
    double* times = run->times;
    run->times = NULL; /* the log's now */
    printf("softbond: resuming %s at frame %llu (t = %.9g s)\n", job->out.dir, (unsigned long long)run->frames,
           sb_solver_time(job->sim.solver));
    return sb_energy_log_resume(&job->log, sb_output_dir_path(&job->out, "log.csv"), run->log_bytes, times,
                                (uint32_t)run->frames, err);
}

/* DIR/run.yaml: the scene as run and how (run_record.h); rewritten by --resume. */
static sb_status write_record(run_job* job, sb_error* err) {
    int threads = job->sim.def.runtime.threads;
    sb_run_record record = {&job->sim.scene, threads > 0 ? threads : sb_runtime_threads(0, NULL), job->argc, job->argv};
    return sb_run_record_write(sb_output_dir_path(&job->out, "run.yaml"), &record, err);
}

/* --end-positions FILE.csv: the end state's vertices, x,y,z (eval --positions' form), whole or not at all. */
static sb_status write_end_positions(run_job* job, sb_error* err) {
    if (!job->args.end_positions) return SB_OK;
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, job->args.end_positions, err);
    if (status != SB_OK) return status;
    sb_solver_get_positions(job->sim.solver, job->buffers);
    fputs("x,y,z\n", file.stream);
    for (uint32_t v = 0; v < sb_solver_vertex_count(job->sim.solver); v++)
        fprintf(file.stream, "%.17g,%.17g,%.17g\n", job->buffers[3 * v], job->buffers[3 * v + 1],
                job->buffers[3 * v + 2]);
    return sb_atomic_commit(&file, err);
}

/* Simulates, then writes the whole index and closes the log even after a
 * solver failure, so the frames up to the failure can be looked at. */
static int execute(run_job* job, sb_error* err) {
    double start = sb_wall_seconds();
    job->log.broken_column = sb_scene_number(&job->sim.scene, SB_KEY_BOND_BREAK_STRAIN) > 0.0 ||
                             sb_scene_number(&job->sim.scene, SB_KEY_SPRINGS_BREAK_STRAIN) > 0.0 ||
                             job->sim.blades.count > 0;
    if (open_output(job, err) != SB_OK || write_record(job, err) != SB_OK) return SB_EXIT_FAILURE;
    if (sb_scene_haptics_start(&job->sim.haptics, sb_output_dir_path(&job->out, "haptics.csv"), err) != SB_OK)
        return SB_EXIT_FAILURE;
    int code = simulate(job, err);
    if (sb_scene_haptics_finish(&job->sim.haptics, code == SB_EXIT_OK ? err : &(sb_error){0}) != SB_OK &&
        code == SB_EXIT_OK)
        code = SB_EXIT_FAILURE;
    sb_error index_err;
    sb_status index = write_index(job, true, &index_err);
    uint32_t frames = job->log.count;
    double last_time = frames ? job->log.times[frames - 1] : 0.0;
    if (index == SB_OK) index = sb_energy_log_close(&job->log, &index_err);
    if (code != SB_EXIT_OK) return code;
    if (index == SB_OK) index = write_end_positions(job, &index_err);
    if (index != SB_OK) {
        *err = index_err;
        return SB_EXIT_FAILURE;
    }
    sb_stop_print(&job->stop, stdout);
    if (job->end_frame)
        printf("softbond: frame %u is the end state at t = %.9g s (off the frame_interval grid)\n", frames - 1,
               last_time);
    report(job, frames, sb_wall_seconds() - start);
    return SB_EXIT_OK;
}

int sb_cli_run(int argc, char** argv) {
    static const char* const accepted[] = {"--output",    "--threads",       "--budget-ms",
                                           "--max-error", "--no-realtime",   "--checkpoint-every",
                                           "--resume",    "--end-positions", NULL};
    sb_study_end_with_parent();
    run_job job = {.argc = argc, .argv = argv};
    sb_error err;
    if (sb_cli_parse(argc, argv, accepted, &job.args, &err) != SB_OK)
        return run_finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    if (job.args.help) {
        sb_cli_run_usage(stdout);
        return run_finish(&job, SB_EXIT_OK);
    }
    if (prepare(&job, &err) != SB_OK) return run_finish(&job, sb_cli_fail(SB_EXIT_INPUT, &err));
    sb_point_load_print(&job.sim.load, &job.sim.scene, job.sim.model, stdout);
    int code = execute(&job, &err);
    if (code != SB_EXIT_OK) sb_cli_fail(code, &err);
    return run_finish(&job, code);
}
