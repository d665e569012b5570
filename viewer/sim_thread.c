/* The viewer's simulation thread (viewer/sim_thread.h).
 *
 * Design. The thread runs batches of steps: a batch ends when the
 * simulated time has caught up with the wall clock (times the pace) or
 * after BATCH_WALL seconds, and only its last step publishes a snapshot
 * (sb_solver_advance_published: on the fused path the copy is part of the
 * step's last pass). Between batches it tries the shared record's lock
 * once: controls in, report out; when the render thread holds the lock the
 * batch goes on without them. So the renderer costs the solver a snapshot
 * per batch and nothing else, whatever its frame rate. With a script, no
 * step starts at or after the time of its next event (controls.hold)
 * until the renderer has handled the event: the simulation waits there,
 * published, so each event meets the same state on every run. */
#define _POSIX_C_SOURCE 200809L
#include "viewer/sim_thread.h"
#include "common/clock.h"
#include "common/error.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const double BATCH_WALL = 1.0 / 120.0; /* s: the longest batch, so snapshots come at least this often */
static const double RATE_WINDOW = 0.5;        /* s: steps per second and the real-time factor over this */

static void nap(double seconds) {
    struct timespec t = {.tv_sec = 0, .tv_nsec = (long)(seconds * 1e9)};
    while (nanosleep(&t, &t) == -1 && errno == EINTR) {
    }
}

sb_handle* sb_sim_grab_handle(double stiffness, double damping, sb_error* err) {
    static const uint32_t first = 0;
    sb_handle_def def = sb_default_handle_def();
    def.name = "mouse";
    def.vertices = &first;
    def.vertex_count = 1;
    def.stiffness = stiffness;
    def.damping = damping;
    sb_handle* h = sb_handle_create(&def, err);
    if (h) sb_handle_release(h); /* nothing held until a pick */
    return h;
}

/* The thread's own view of what it has applied. */
typedef struct sim_state {
    sb_sim_controls applied;
    double* scratch; /* 3n: positions, for stop */
    double translate[3], grabbed_at[3];
    double wall_origin, sim_origin; /* the pace: sim_origin at wall_origin */
    double window_wall, window_sim; /* the rate window's start */
    uint64_t window_steps;
    bool failed;
    uint64_t single_steps;   /* taken so far */
    uint64_t published_step; /* the step count of the last snapshot published */
    sb_view_topology topology; /* read here when the solver tears; handed over at an exchange */
    uint32_t broken, vertices; /* what the last read saw */
    bool tears, handed;        /* handed: the last read is in t->topology */
} sim_state;

static void apply_gravity(sb_sim_thread* t, const sb_sim_controls* c) {
    const double* g = sb_scene_vec3(&t->sim->scene, SB_KEY_GRAVITY);
    double sign = c->gravity_off ? 0.0 : c->gravity_reversed ? -1.0 : 1.0, now_g[3];
    for (int k = 0; k < 3; k++) now_g[k] = sign * g[k];
    sb_solver_set_gravity(t->sim->solver, now_g);
}

static void stop_bodies(sb_sim_thread* t, sim_state* s) {
    sb_solver_get_positions(t->sim->solver, s->scratch);
    sb_solver_set_state(t->sim->solver, s->scratch, NULL);
}

static void apply_pick(sb_sim_thread* t, sim_state* s, const sb_sim_controls* c) {
    if (c->picks != s->applied.picks && c->pick >= 0) {
        sb_handle_grab_vertex(t->grab, (uint32_t)c->pick);
        sb_handle_target(t->grab, 0, s->grabbed_at);
    } else if (c->pick < 0 && sb_handle_held(t->grab)) {
        sb_handle_release(t->grab);
    }
}

/* Applies what changed since the last exchange; true when the state
 * changed without a step (to be published). */
static bool apply(sb_sim_thread* t, sim_state* s, const sb_sim_controls* c) {
    bool changed = false;
    if (c->gravity_off != s->applied.gravity_off || c->gravity_reversed != s->applied.gravity_reversed)
        apply_gravity(t, c);
    if (c->resets != s->applied.resets) {
        sb_solver_set_state(t->sim->solver, NULL, NULL);
        changed = true;
    }
    if (c->stopped && !s->applied.stopped) {
        stop_bodies(t, s);
        changed = true;
    }
    apply_pick(t, s, c);
    s->applied = *c;
    return changed;
}

static void fill_report(sb_sim_thread* t, sb_sim_report* r) {
    sb_handle_force(t->grab, r->pick_force);
    const sb_scene_colliders* colliders = &t->sim->colliders;
    r->collider_count = colliders->count < SB_SIM_MAX_COLLIDERS ? colliders->count : SB_SIM_MAX_COLLIDERS;
    for (uint32_t c = 0; c < r->collider_count; c++) {
        sb_collider_orientation(colliders->colliders[c], r->poses[c], NULL);
        sb_collider_state(colliders->colliders[c], r->poses[c] + 9, NULL);
    }
}

static void measure(sb_sim_thread* t, sim_state* s, sb_sim_report* r) {
    double wall = sb_wall_seconds(), elapsed = wall - s->window_wall;
    uint64_t steps = sb_solver_step_count(t->sim->solver);
    if (elapsed < RATE_WINDOW) return;
    double simulated = sb_solver_time(t->sim->solver) - s->window_sim;
    r->steps_per_second = (double)(steps - s->window_steps) / elapsed;
    r->realtime_factor = simulated / elapsed;
    s->window_wall = wall;
    s->window_sim = sb_solver_time(t->sim->solver);
    s->window_steps = steps;
}

/* Controls in, report out, if the lock is free now (the first time: once
 * it is, so that controls set before the start apply to the first step);
 * false on quit. */
static bool exchange(sb_sim_thread* t, sim_state* s, bool first) {
    if ((first ? pthread_mutex_lock(&t->lock) : pthread_mutex_trylock(&t->lock)) != 0) return true;
    sb_sim_controls c = t->controls;
    measure(t, s, &t->report);
    fill_report(t, &t->report);
    if (s->failed) snprintf(t->report.failure, sizeof t->report.failure, "%s", sb_solver_error(t->sim->solver));
    if (!s->handed) sb_view_topology_copy(&t->topology, &s->topology);
    s->handed = true;
    pthread_mutex_unlock(&t->lock);
    bool was_running = !s->applied.paused && !s->applied.stopped;
    if (apply(t, s, &c)) sb_solver_publish(t->sim->solver, t->buffer);
    if (!was_running) { /* the clock starts again from here */
        s->wall_origin = sb_wall_seconds();
        s->sim_origin = sb_solver_time(t->sim->solver);
    }
    return !c.quit;
}

static void drive_mouse(sb_sim_thread* t, sim_state* s) {
    const sb_sim_controls* c = &s->applied;
    if (sb_handle_held(t->grab)) {
        for (int k = 0; k < 3; k++) s->translate[k] += c->target[k] - s->grabbed_at[k];
        memcpy(s->grabbed_at, c->target, sizeof s->grabbed_at);
        const double none[3] = {0, 0, 0};
        sb_handle_set_pose(t->grab, s->translate, none);
    }
    if (t->mouse && c->tool) {
        sb_haptic_pose pose = {.orientation = {1, 0, 0, 0}, .buttons = 1};
        for (int k = 0; k < 3; k++) pose.position[k] = c->target[k] - t->tool_rest[k];
        sb_haptic_device_move(t->mouse, &pose);
    }
}

static bool step(sb_sim_thread* t, sim_state* s, double dt, bool publish) {
    sb_simulation* sim = t->sim;
    drive_mouse(t, s);
    sb_scene_haptics_before_step(&sim->haptics, sim->solver);
    sb_status status =
        publish ? sb_solver_advance_published(sim->solver, dt, t->buffer) : sb_solver_advance(sim->solver, dt);
    if (publish) s->published_step = sb_solver_step_count(sim->solver);
    sb_error ignored;
    if (status == SB_OK) sb_scene_haptics_after_step(&sim->haptics, sim->solver, &ignored);
    return status == SB_OK;
}

/* A tearing solver's topology read again when bonds broke or vertices split. */
static void follow_tearing(sb_sim_thread* t, sim_state* s) {
    const sb_solver* solver = t->sim->solver;
    if (!s->tears || (sb_solver_broken_count(solver) == s->broken && sb_solver_vertex_count(solver) == s->vertices))
        return;
    s->broken = sb_solver_broken_count(solver);
    s->vertices = sb_solver_vertex_count(solver);
    sb_view_topology_read(&s->topology, solver, &t->sim->mesh);
    s->handed = false;
}

/* At the hold (a script's event not yet handled): the state there is
 * published, so that the renderer sees it and handles the event. */
static bool held(sb_sim_thread* t, sim_state* s) {
    if (sb_solver_time(t->sim->solver) < s->applied.hold) return false;
    if (s->published_step != sb_solver_step_count(t->sim->solver)) {
        sb_solver_publish(t->sim->solver, t->buffer);
        s->published_step = sb_solver_step_count(t->sim->solver);
    }
    nap(5e-4);
    return true;
}

/* Steps until the simulated time reaches the paced target or the hold, or
 * BATCH_WALL has passed; the last step publishes. */
static void batch(sb_sim_thread* t, sim_state* s) {
    double dt = sb_scene_number(&t->sim->scene, SB_KEY_DT), start = sb_wall_seconds();
    double goal = t->realtime > 0 ? s->sim_origin + (start - s->wall_origin) * t->realtime : INFINITY;
    if (held(t, s)) return;
    if (sb_solver_time(t->sim->solver) + dt > goal) {
        nap(fmin(1e-3, (sb_solver_time(t->sim->solver) + dt - goal) / t->realtime));
        return;
    }
    for (bool last = false; !last && !s->failed;) {
        double now = sb_solver_time(t->sim->solver);
        last = now + 2 * dt > goal || now + dt >= s->applied.hold || sb_wall_seconds() - start >= BATCH_WALL;
        s->failed = !step(t, s, dt, last);
        if (!last && sb_solver_time(t->sim->solver) >= s->applied.hold) break; /* rounding: held() publishes */
    }
    follow_tearing(t, s);
}

/* n: one step while paused or stopped (not past the hold). */
static void single_step(sb_sim_thread* t, sim_state* s) {
    if (held(t, s)) return;
    s->failed = !step(t, s, sb_scene_number(&t->sim->scene, SB_KEY_DT), true);
    s->single_steps++;
    follow_tearing(t, s);
}

static void* run(void* arg) {
    sb_sim_thread* t = arg;
    const sb_solver* solver = t->sim->solver;
    sim_state s = {.window_wall = sb_wall_seconds(), .window_sim = sb_solver_time(solver), .handed = true};
    s.scratch = malloc(3 * ((size_t)sb_solver_vertex_capacity(solver) + 1) * sizeof *s.scratch);
    s.tears = sb_solver_vertex_capacity(solver) > sb_model_vertex_count(sb_solver_model(solver));
    if (s.tears && sb_view_topology_create(&s.topology, solver, &t->sim->mesh, NULL) != SB_OK) s.tears = false;
    s.topology.version = t->topology.version; /* each read after it counts on from the start's */
    s.applied.pick = -1;
    s.applied.hold = INFINITY;
    s.wall_origin = sb_wall_seconds();
    for (bool first = true; exchange(t, &s, first); first = false) {
        if (!s.failed && s.scratch && s.single_steps != s.applied.single_steps)
            single_step(t, &s);
        else if (s.applied.paused || s.applied.stopped || s.failed || !s.scratch)
            nap(2e-3);
        else
            batch(t, &s);
    }
    free(s.scratch);
    sb_view_topology_free(&s.topology);
    return NULL;
}

sb_status sb_sim_thread_start(sb_sim_thread* t, sb_error* err) {
    if (sb_view_topology_create(&t->topology, t->sim->solver, &t->sim->mesh, err) != SB_OK) return SB_ERR_NOMEM;
    sb_view_topology_read(&t->topology, t->sim->solver, &t->sim->mesh);
    if (pthread_mutex_init(&t->lock, NULL) != 0) return sb_error_set(err, SB_ERR_NOMEM, "cannot make a mutex");
    sb_solver_publish(t->sim->solver, t->buffer);
    if (pthread_create(&t->thread, NULL, run, t) != 0) {
        pthread_mutex_destroy(&t->lock);
        return sb_error_set(err, SB_ERR_NOMEM, "cannot start the simulation thread");
    }
    t->started = true;
    return SB_OK;
}

void sb_sim_thread_stop(sb_sim_thread* t) {
    if (!t->started) return;
    pthread_mutex_lock(&t->lock);
    t->controls.quit = true;
    pthread_mutex_unlock(&t->lock);
    pthread_join(t->thread, NULL);
    pthread_mutex_destroy(&t->lock);
    sb_view_topology_free(&t->topology);
    t->started = false;
}

bool sb_sim_thread_exchange(sb_sim_thread* t, const sb_sim_controls* controls, sb_sim_report* report,
                            sb_view_topology* topology) {
    pthread_mutex_lock(&t->lock);
    bool quit = t->controls.quit;
    t->controls = *controls;
    t->controls.quit |= quit;
    *report = t->report;
    bool changed = topology->version != t->topology.version;
    if (changed) sb_view_topology_copy(topology, &t->topology);
    pthread_mutex_unlock(&t->lock);
    return changed;
}
