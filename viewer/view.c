/* The viewer (viewer/view.h).
 *
 * Design. Two threads. The simulation thread (viewer/sim_thread.c) owns
 * the solver and publishes snapshots; this thread, the render thread,
 * never calls the solver: it holds the latest snapshot of the state buffer
 * while it draws it, and meets the simulation thread once a frame in a
 * small record of controls (keys, the mouse's pick and target) and a
 * report (rates, collider poses, the mouse's force). A frame: events from
 * the window and the script (the script's times are simulated seconds of
 * the snapshot shown), the newest snapshot, the exchange, drawing, then a
 * sleep to the next frame time. */
#define _POSIX_C_SOURCE 200809L
#include "viewer/view.h"
#include "common/clock.h"
#include "common/error.h"
#include "viewer/collider_draw.h"
#include "viewer/input_script.h"
#include "viewer/mesh_draw.h"
#include "viewer/overlay.h"
#include "viewer/screenshot.h"
#include "viewer/sim_thread.h"
#include "viewer/window.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static const double PICK_PIXELS = 15.0; /* a press this close to a vertex's image picks it */
enum { WARM_UP_FRAMES = 3 };            /* frames drawn before the render share applies */

typedef enum drag_kind { DRAG_NONE, DRAG_ORBIT, DRAG_PAN, DRAG_PICK, DRAG_TOOL } drag_kind;

typedef struct view_app {
    const sb_view_options* options;
    sb_simulation sim;
    sb_handle* grab;
    sb_state_buffer* buffer;
    sb_sim_thread thread;
    int tool_index; /* the haptic tool's collider, -1 = none or not a mouse */
    sb_window* window;
    sb_shaders shaders;
    sb_mesh_draw mesh;
    sb_collider_draw colliders;
    sb_overlay overlay;
    sb_camera camera, home;
    sb_draw_flags flags;
    bool help, running;
    bool quiet; /* o: the statistics hidden */
    sb_sim_controls controls;
    sb_sim_report report;
    sb_view_topology topology; /* what is drawn: the solver's at the start, then the simulation thread's */
    sb_input_script script;
    const sb_snapshot* shown;
    uint64_t shown_sequence;
    drag_kind drag;
    double last_x, last_y;
    double plane_point[3]; /* the drag plane (facing the camera) of a pick or the tool */
    int width, height;
    double draw_seconds;
    uint64_t frames;
    bool save, reload;   /* p and l, done after the frame is drawn */
    unsigned saved;      /* the last screenshot's number */
    char notice[1100];   /* a line the overlay shows for a while: a screenshot saved, a reload refused */
    bool notice_alarm;   /* in red */
    double notice_until; /* wall clock */
} view_app;

static void nap_until(double when) {
    double wait = when - sb_wall_seconds();
    if (wait <= 0) return;
    struct timespec t = {.tv_sec = (time_t)wait, .tv_nsec = (long)((wait - floor(wait)) * 1e9)};
    while (nanosleep(&t, &t) == -1 && errno == EINTR) {
    }
}

sb_view_options sb_default_view_options(const sb_simulation_args* args) {
    return (sb_view_options){
        .args = args, .width = 960, .height = 720, .fps = 60.0, .realtime = 1.0, .render_share = 0.15};
}

/* ---- the simulation ------------------------------------------------------ */

/* The mouse's spring: stiff as the lightest free vertex allows at the
 * scene's dt (k dt² / m = 0.05), damped near critically (c = 2 √(k m)). */
static sb_status make_grab(view_app* a, sb_error* err) {
    const sb_model* m = a->sim.model;
    double lightest = INFINITY, dt = sb_scene_number(&a->sim.scene, SB_KEY_DT);
    for (uint32_t i = 0; i < sb_model_vertex_count(m); i++)
        if (!sb_model_is_fixed(m, i)) lightest = fmin(lightest, sb_model_mass(m, i));
    if (!isfinite(lightest)) lightest = 1.0;
    double k = 0.05 * lightest / (dt * dt);
    a->grab = sb_sim_grab_handle(k, 2.0 * sqrt(k * lightest), err);
    return a->grab ? SB_OK : SB_ERR_INVALID;
}

/* The scene's tool, when a "mouse" device drives it. */
static int mouse_tool(const sb_simulation* sim) {
    if (!sim->haptics.enabled || strcmp(sb_scene_string(&sim->scene, SB_KEY_HAPTICS_DEVICE), "mouse") != 0) return -1;
    const char* tool = sb_scene_string(&sim->scene, SB_KEY_HAPTICS_TOOL);
    for (uint32_t c = 0; c < sim->colliders.count; c++)
        if (strcmp(sim->colliders.entries[c].name, tool) == 0) return (int)c;
    return -1;
}

static sb_status start_simulation(view_app* a, sb_error* err) {
    sb_status status = sb_simulation_prepare(&a->sim, a->options->args, err);
    if (status == SB_OK) status = make_grab(a, err);
    if (status == SB_OK) status = sb_simulation_start(&a->sim, a->grab, err);
    if (status != SB_OK) return status;
    a->sim.haptics.paced = false; /* the simulation thread paces itself */
    a->tool_index = mouse_tool(&a->sim);
    uint32_t capacity = sb_solver_vertex_capacity(a->sim.solver);
    if (!(a->buffer = sb_state_buffer_create(capacity, 2, err))) return SB_ERR_NOMEM;
    if (sb_view_topology_create(&a->topology, a->sim.solver, &a->sim.mesh, err) != SB_OK) return SB_ERR_NOMEM;
    sb_view_topology_read(&a->topology, a->sim.solver, &a->sim.mesh);
    a->thread = (sb_sim_thread){.sim = &a->sim, .buffer = a->buffer, .grab = a->grab, .realtime = a->options->realtime};
    if (a->tool_index >= 0) {
        a->thread.mouse = a->sim.haptics.device;
        sb_collider_state(a->sim.colliders.colliders[a->tool_index], a->thread.tool_rest, NULL);
    }
    a->controls.pick = -1;
    a->controls.hold = INFINITY;
    return sb_solver_publish(a->sim.solver, a->buffer) == SB_OK
               ? SB_OK
               : sb_error_set(err, SB_ERR_INVALID, "view: cannot publish the first state");
}

/* ---- the picture ----------------------------------------------------------- */

static void rest_box(const sb_model* m, double lo[3], double hi[3]) {
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (uint32_t i = 0; i < sb_model_vertex_count(m); i++) {
        double p[3];
        sb_model_rest_position(m, i, p);
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], p[k]), hi[k] = fmax(hi[k], p[k]);
    }
}

/* The colliders but planes (the drawn square follows the bodies) grow the box. */
static void collider_box(const sb_scene_colliders* colliders, double lo[3], double hi[3]) {
    for (uint32_t c = 0; c < colliders->count; c++) {
        const sb_scene_collider* e = &colliders->entries[c];
        const sb_collider_def* d = &e->def;
        double r = 0.0;
        const double *p = NULL, *q = NULL;
        switch (d->shape) {
        case SB_COLLIDER_PLANE: continue;
        case SB_COLLIDER_SPHERE: p = q = d->center, r = d->radius; break;
        case SB_COLLIDER_CAPSULE: p = d->a, q = d->b, r = d->radius; break;
        case SB_COLLIDER_BOX:
            p = q = d->center;
            r = sqrt(d->half_extents[0] * d->half_extents[0] + d->half_extents[1] * d->half_extents[1] +
                     d->half_extents[2] * d->half_extents[2]);
            break;
        default:
            for (uint32_t i = 0; i < e->mesh.vertex_count; i++)
                for (int k = 0; k < 3; k++)
                    lo[k] = fmin(lo[k], e->mesh.positions[3 * i + k]),
                    hi[k] = fmax(hi[k], e->mesh.positions[3 * i + k]);
            continue;
        }
        for (int k = 0; k < 3; k++)
            lo[k] = fmin(lo[k], fmin(p[k], q[k]) - r), hi[k] = fmax(hi[k], fmax(p[k], q[k]) + r);
    }
}

/* What the scene's model and colliders need drawn (also after a reload);
 * the camera framing the bodies at rest and the colliders. */
static sb_status scene_drawing(view_app* a, sb_error* err) {
    double lo[3], hi[3], up[3], center[3], extent = 0.0;
    rest_box(a->sim.model, lo, hi);
    for (int k = 0; k < 3; k++) center[k] = 0.5 * (lo[k] + hi[k]), extent = fmax(extent, hi[k] - lo[k]);
    double bodies = extent;
    collider_box(&a->sim.colliders, lo, hi);
    sb_simulation_up(&a->sim, up);
    a->camera = a->home = sb_camera_fit(lo, hi, up);
    double size = 0.0;
    for (int k = 0; k < 3; k++) size = fmax(size, hi[k] - lo[k]);
    /* colliders beyond the bodies reach the box's edges: a step back keeps them clear of the overlay's lines */
    if (size > 1.01 * bodies) a->camera.distance = a->home.distance *= 1.25;
    sb_status status = sb_mesh_draw_create(&a->mesh, a->sim.model, sb_solver_vertex_capacity(a->sim.solver), err);
    if (status == SB_OK) sb_mesh_draw_topology(&a->mesh, &a->topology);
    if (status == SB_OK) status = sb_collider_draw_create(&a->colliders, &a->sim.colliders, extent, center, err);
    return status;
}

static sb_status start_drawing(view_app* a, sb_error* err) {
    const sb_view_options* o = a->options;
    if (!(a->window = sb_window_open(o->width, o->height, "softbond view", err))) return SB_ERR_INVALID;
    sb_window_size(a->window, &a->width, &a->height);
    /* a net (factory: net) is its bonds, strings with holes between: edges only (F4 shows the faces) */
    bool net = strcmp(sb_scene_string(&a->sim.scene, SB_KEY_FACTORY), "net") == 0;
    a->flags = (sb_draw_flags){.edges = true, .faces = !net};
    sb_status status = sb_shaders_build(&a->shaders, err);
    if (status == SB_OK) status = scene_drawing(a, err);
    if (status == SB_OK) status = sb_overlay_create(&a->overlay, err);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_PROGRAM_POINT_SIZE);
    return status;
}

/* Holds the newest snapshot (letting the one before go) and uploads it. */
static void take_snapshot(view_app* a) {
    const sb_snapshot* s = sb_state_buffer_acquire(a->buffer);
    if (!s) return;
    if (a->shown && s->sequence == a->shown_sequence) {
        sb_state_buffer_release(a->buffer, s);
        if (a->flags.strain) sb_mesh_draw_update(&a->mesh, a->shown->positions, a->shown->vertex_count, true);
        return;
    }
    if (a->shown) sb_state_buffer_release(a->buffer, a->shown);
    a->shown = s;
    a->shown_sequence = s->sequence;
    sb_mesh_draw_update(&a->mesh, s->positions, s->vertex_count, a->flags.strain);
}

/* ---- the mouse ------------------------------------------------------------- */

static double distance2(const double a[2], const double b[2]) {
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
}

/* The vertex of the shown snapshot whose image is nearest (x, y), within PICK_PIXELS; -1 if none. */
static int64_t pick_vertex(const view_app* a, double x, double y) {
    if (!a->shown) return -1;
    int64_t best = -1;
    double best2 = PICK_PIXELS * PICK_PIXELS, cursor[2] = {x, y};
    for (uint32_t i = 0; i < a->shown->vertex_count; i++) {
        double p[3] = {a->shown->positions[3 * i], a->shown->positions[3 * i + 1], a->shown->positions[3 * i + 2]};
        double pixel[2];
        if (!sb_camera_project(&a->camera, p, a->width, a->height, pixel)) continue;
        double d2 = distance2(pixel, cursor);
        if (d2 < best2) best2 = d2, best = i;
    }
    return best;
}

/* Where the cursor's ray meets the drag plane (through plane_point, facing the camera). */
static void cursor_point(const view_app* a, double x, double y, double out[3]) {
    double origin[3], direction[3], forward[3];
    sb_camera_ray(&a->camera, x, y, a->width, a->height, origin, direction);
    sb_camera_forward(&a->camera, forward);
    double along = 0.0, toward = 0.0;
    for (int k = 0; k < 3; k++) {
        along += (a->plane_point[k] - origin[k]) * forward[k];
        toward += direction[k] * forward[k];
    }
    double t = toward > 1e-9 ? along / toward : 0.0;
    for (int k = 0; k < 3; k++) out[k] = origin[k] + t * direction[k];
}

static void press(view_app* a, const sb_view_event* e) {
    a->last_x = e->x, a->last_y = e->y;
    if (e->button != SB_BUTTON_LEFT || e->shift) {
        a->drag = e->button == SB_BUTTON_RIGHT && !e->shift ? DRAG_ORBIT : DRAG_PAN;
        return;
    }
    if (a->tool_index >= 0 && !e->ctrl) {
        bool reported = a->report.collider_count > (uint32_t)a->tool_index; /* not before the first exchange */
        memcpy(a->plane_point, reported ? a->report.poses[a->tool_index] + 9 : a->thread.tool_rest,
               sizeof a->plane_point);
        a->drag = DRAG_TOOL;
        a->controls.tool = true;
        cursor_point(a, e->x, e->y, a->controls.target);
        return;
    }
    int64_t v = pick_vertex(a, e->x, e->y);
    if (v < 0) {
        a->drag = DRAG_ORBIT;
        return;
    }
    for (int k = 0; k < 3; k++) a->plane_point[k] = a->shown->positions[3 * v + k];
    a->drag = DRAG_PICK;
    a->controls.pick = v;
    a->controls.picks++;
    memcpy(a->controls.target, a->plane_point, sizeof a->plane_point);
}

static void move(view_app* a, const sb_view_event* e) {
    double dx = e->x - a->last_x, dy = e->y - a->last_y;
    a->last_x = e->x, a->last_y = e->y;
    switch (a->drag) {
    case DRAG_ORBIT: sb_camera_orbit(&a->camera, dx, dy); break;
    case DRAG_PAN: sb_camera_pan(&a->camera, dx, dy, a->height); break;
    case DRAG_PICK:
    case DRAG_TOOL: cursor_point(a, e->x, e->y, a->controls.target); break;
    case DRAG_NONE: break;
    }
}

static void release(view_app* a, const sb_view_event* e) {
    move(a, e);
    if (a->drag == DRAG_PICK) a->controls.pick = -1;
    a->drag = DRAG_NONE;
}

/* ---- keys -------------------------------------------------------------------- */

static void key(view_app* a, sb_view_key k) {
    sb_draw_flags* f = &a->flags;
    sb_sim_controls* c = &a->controls;
    switch (k) {
    case SB_VKEY_F1: f->vertices = !f->vertices; break;
    case SB_VKEY_F2: f->edges = !f->edges; break;
    case SB_VKEY_F3: f->strain = !f->strain; break;
    case SB_VKEY_F4: f->faces = !f->faces; break;
    case SB_VKEY_F5: f->texture = !f->texture; break;
    case SB_VKEY_R: c->gravity_reversed = !c->gravity_reversed; break;
    case SB_VKEY_S: c->stopped = !c->stopped; break;
    case SB_VKEY_G: c->gravity_off = !c->gravity_off; break;
    case SB_VKEY_SPACE: c->paused = !c->paused; break;
    case SB_VKEY_N:
        c->paused = true;
        c->single_steps++;
        break;
    case SB_VKEY_BACKSPACE: c->resets++; break;
    case SB_VKEY_P: a->save = true; break;
    case SB_VKEY_L: a->reload = true; break;
    case SB_VKEY_H: a->help = !a->help; break;
    case SB_VKEY_O: a->quiet = !a->quiet; break;
    case SB_VKEY_C: a->camera = a->home; break;
    case SB_VKEY_ESCAPE: a->running = false; break;
    default: break;
    }
    if (k == SB_VKEY_F3 && f->strain && a->shown)
        sb_mesh_draw_update(&a->mesh, a->shown->positions, a->shown->vertex_count, true);
}

static void handle(view_app* a, const sb_view_event* e) {
    switch (e->kind) {
    case SB_EVENT_KEY: key(a, e->key); break;
    case SB_EVENT_PRESS: press(a, e); break;
    case SB_EVENT_MOVE: move(a, e); break;
    case SB_EVENT_RELEASE: release(a, e); break;
    case SB_EVENT_SCROLL: sb_camera_zoom(&a->camera, e->y); break;
    case SB_EVENT_QUIT: a->running = false; break;
    }
}

static void events(view_app* a) {
    const sb_view_event* list;
    size_t count;
    sb_window_poll(a->window, &list, &count);
    for (size_t i = 0; i < count; i++) handle(a, &list[i]);
    sb_view_event e;
    double t = a->shown ? a->shown->time : 0.0;
    while (sb_input_script_next(&a->script, t, &e)) handle(a, &e);
    a->controls.hold = sb_input_script_next_time(&a->script); /* the simulation waits there for it */
}

/* ---- the overlay ----------------------------------------------------------------- */

static const float INK[4] = {0.08f, 0.08f, 0.1f, 1.0f}, ALARM[4] = {0.8f, 0.05f, 0.05f, 1.0f},
                   PAPER[4] = {1.0f, 1.0f, 1.0f, 0.85f}, STATUS_PAPER[4] = {0.98f, 0.97f, 0.9f, 0.8f};

static const char* mode(const view_app* a) {
    const sb_sim_controls* c = &a->controls;
    return c->paused             ? "paused"
           : c->stopped          ? "stopped"
           : c->gravity_off      ? "gravity off"
           : c->gravity_reversed ? "gravity reversed"
                                 : "";
}

/* The next line's place below a panel of the statistics: a line each at
 * fixed places (the tests' pictures know them), lower by what a wrapped one
 * took. */
static float below(float y, float panel_height) { return y + (panel_height > 26.0f ? panel_height : 22.0f); }

/* A statistics line on cream paper at (10, y): at the overlay's scale when
 * it fits the window, else at half of it, wrapped where even that does not
 * fit; returns where the next line goes. */
static float statistics_line(view_app* a, float y, const char* line) {
    const float wrap_at = (float)a->width - 32;
    float width, height;
    sb_overlay_measure(line, 2.0f, &width, &height);
    float scale = width <= wrap_at ? 2.0f : 1.0f;
    return below(y, sb_overlay_panel(&a->overlay, 10, y, wrap_at, scale, line, INK, STATUS_PAPER));
}

/* The statistics, on cream paper, and the solver's failure below them, all
 * fitted to the window. */
static void statistics(view_app* a) {
    char line[512];
    const sb_snapshot* s = a->shown;
    if (!s) return;
    const float wrap_at = (float)a->width - 32;
    snprintf(line, sizeof line, "t = %.3f s   %.2fx real time   %.0f steps/s   %u vertices%s%s", s->time,
             a->report.realtime_factor, a->report.steps_per_second, s->vertex_count, mode(a)[0] ? "   " : "", mode(a));
    float y = statistics_line(a, 10, line);
    double internal = sb_energies_internal(&s->energies);
    snprintf(line, sizeof line, "energy: kinetic %.4g J   internal %.4g J   gravity %.4g J   total %.4g J",
             s->energies.kinetic, internal, s->energies.gravity, s->energies.kinetic + internal + s->energies.gravity);
    y = statistics_line(a, y, line);
    if (a->controls.pick >= 0) {
        const double* f = a->report.pick_force;
        snprintf(line, sizeof line, "vertex %lld held: force %.4g N  [%.3g, %.3g, %.3g]", (long long)a->controls.pick,
                 sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]), f[0], f[1], f[2]);
        y = statistics_line(a, y, line);
    }
    if (a->report.failure[0]) y += sb_overlay_panel(&a->overlay, 10, y, wrap_at, 2.0f, a->report.failure, ALARM, PAPER);
    if (a->notice[0] && sb_wall_seconds() < a->notice_until)
        sb_overlay_panel(&a->overlay, 10, y, wrap_at, 2.0f, a->notice, a->notice_alarm ? ALARM : INK, PAPER);
    sb_overlay_panel(&a->overlay, 10, (float)a->height - 24, wrap_at, 2.0f, "h: keys", INK, STATUS_PAPER);
}

static void help(view_app* a) {
    char text[2048] = "keys\n";
    size_t used = strlen(text);
    for (int k = SB_VKEY_NONE + 1; k < SB_VKEY_COUNT; k++)
        used += (size_t)snprintf(text + used, sizeof text - used, "%-10s %s\n", sb_view_key_name((sb_view_key)k),
                                 sb_view_key_meaning((sb_view_key)k));
    snprintf(text + used, sizeof text - used,
             "\nmouse\nleft on a vertex: drag it (a spring)\nleft elsewhere, right: orbit\nshift+left, middle: pan\n"
             "wheel: zoom%s",
             a->tool_index >= 0 ? "\nleft: move the haptic tool (ctrl+left: a vertex)" : "");
    float w, h, scale = 2.0f;
    sb_overlay_measure(text, scale, &w, &h);
    /* a small window gets smaller letters: the whole card fits (down to half size) */
    float fit = fminf(((float)a->width - 32) / w, ((float)a->height - 32) / h);
    if (fit < 1.0f) {
        scale *= fmaxf(fit, 0.5f);
        sb_overlay_measure(text, scale, &w, &h);
    }
    float x = 0.5f * ((float)a->width - w), y = 0.5f * ((float)a->height - h);
    sb_overlay_rect(&a->overlay, x - 12, y - 12, w + 24, h + 24, PAPER);
    sb_overlay_text(&a->overlay, x, y, scale, text, INK);
}

/* The strain colours from −scale (blue) to +scale (red), at the right edge. */
static void color_scale(view_app* a) {
    const int steps = 64;
    float x = (float)a->width - 50, top = 120, height = 240;
    for (int i = 0; i < steps; i++) {
        float rgba[4];
        double strain = a->mesh.strain_scale * (1.0 - 2.0 * (i + 0.5) / steps);
        sb_strain_color(strain, a->mesh.strain_scale, rgba);
        sb_overlay_rect(&a->overlay, x, top + height * i / steps, 24, height / steps + 1, rgba);
    }
    char label[64];
    snprintf(label, sizeof label, "+%.2g%%", 100 * a->mesh.strain_scale);
    float w, h;
    sb_overlay_measure(label, 2.0f, &w, &h);
    sb_overlay_text(&a->overlay, x + 24 - w, top - 22, 2.0f, label, INK);
    snprintf(label, sizeof label, "-%.2g%%", 100 * a->mesh.strain_scale);
    sb_overlay_measure(label, 2.0f, &w, &h);
    sb_overlay_text(&a->overlay, x + 24 - w, top + height + 8, 2.0f, label, INK);
    sb_overlay_text(&a->overlay, x - 40, top + height + 30, 2.0f, "strain", INK);
}

/* ---- a frame -------------------------------------------------------------------------- */

static void draw(view_app* a) {
    sb_window_size(a->window, &a->width, &a->height);
    glViewport(0, 0, a->width, a->height);
    glClearColor(0.86f, 0.89f, 0.93f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    float matrix[16], light[3];
    double forward[3];
    sb_camera_matrix(&a->camera, (double)a->width / a->height, matrix);
    sb_camera_forward(&a->camera, forward);
    for (int k = 0; k < 3; k++) light[k] = (float)-forward[k];
    sb_collider_draw_render(&a->colliders, &a->shaders, matrix, light, (const double(*)[12])a->report.poses,
                            a->report.collider_count);
    if (a->shown) sb_mesh_draw_render(&a->mesh, &a->shaders, matrix, light, a->flags);
    sb_overlay_clear(&a->overlay);
    if (!a->quiet) statistics(a);
    if (a->flags.strain) color_scale(a);
    if (a->help) help(a);
    sb_overlay_draw(&a->overlay, &a->shaders, a->width, a->height);
}

static double cpu_seconds(clockid_t clock) {
    struct timespec t;
    return clock_gettime(clock, &t) == 0 ? (double)t.tv_sec + 1e-9 * (double)t.tv_nsec : 0.0;
}

/* The process's processor time but the simulation's threads' (the solver's
 * team works inside sb_solver_advance on the simulation thread and its
 * workers, whose clocks are not at hand: the team's time is counted only
 * when it has one thread): what drawing has used so far. */
static double drawing_cpu(const view_app* a) {
    clockid_t simulation;
    double sim = pthread_getcpuclockid(a->thread.thread, &simulation) == 0 ? cpu_seconds(simulation) : 0.0;
    return cpu_seconds(CLOCK_PROCESS_CPUTIME_ID) - sim;
}

static void notice(view_app* a, bool alarm, const char* format, const char* what) {
    snprintf(a->notice, sizeof a->notice, format, what);
    a->notice_alarm = alarm;
    a->notice_until = sb_wall_seconds() + 4.0;
}

/* p: the frame just drawn to SCENE_NNN.png in the current folder, the
 * first number not taken; a failure is said on stderr and in the window. */
static void save_screenshot(view_app* a) {
    char path[512];
    do snprintf(path, sizeof path, "%s_%03u.png", a->sim.scene.name ? a->sim.scene.name : "softbond", ++a->saved);
    while (access(path, F_OK) == 0 && a->saved < 100000);
    sb_error err;
    if (sb_screenshot_save(path, a->width, a->height, &err) == SB_OK)
        notice(a, false, "saved %s", path);
    else {
        fprintf(stderr, "softbond: %s\n", err.message);
        notice(a, true, "%s", err.message);
    }
}

/* Stops the simulation and frees what it made: the thread, the shown
 * snapshot, the topology, the haptic device, the scene, the grab handle and
 * the state buffer (a reload makes them again). */
static void release_simulation(view_app* a) {
    sb_sim_thread_stop(&a->thread);
    if (a->shown) sb_state_buffer_release(a->buffer, a->shown);
    a->shown = NULL;
    sb_view_topology_free(&a->topology);
    sb_error ignored;
    sb_scene_haptics_finish(&a->sim.haptics, &ignored);
    sb_simulation_free(&a->sim);
    sb_handle_destroy(a->grab);
    sb_state_buffer_destroy(a->buffer);
    a->sim = (sb_simulation){0};
    a->grab = NULL, a->buffer = NULL;
}

/* l: the scene file read again and started anew (the camera too). A scene
 * that does not read is refused in the window, the old one running on. */
static sb_status reload(view_app* a, sb_error* err) {
    const sb_simulation_args* args = a->options->args;
    sb_scene check = {0};
    sb_error why;
    sb_status readable = sb_scene_read(&check, args->input, args->sets, (size_t)args->set_count, &why);
    sb_scene_free(&check);
    if (readable != SB_OK) {
        notice(a, true, "reload refused: %s", why.message);
        return SB_OK;
    }
    release_simulation(a);
    sb_collider_draw_free(&a->colliders);
    sb_mesh_draw_free(&a->mesh);
    a->tool_index = -1, a->drag = DRAG_NONE;
    a->report = (sb_sim_report){0};
    bool paused = a->controls.paused;
    a->controls = (sb_sim_controls){0};
    sb_status status = start_simulation(a, err);
    if (status == SB_OK) status = scene_drawing(a, err);
    if (status == SB_OK) status = sb_scene_haptics_start(&a->sim.haptics, "/dev/null", err);
    if (status != SB_OK) return status;
    a->controls.paused = paused;
    a->controls.hold = sb_input_script_next_time(&a->script);
    a->thread.controls = a->controls;
    status = sb_sim_thread_start(&a->thread, err);
    if (status == SB_OK) notice(a, false, "reloaded %s", args->input);
    return status;
}

static sb_status frame_loop(view_app* a, sb_error* err) {
    const sb_view_options* o = a->options;
    double period = o->fps > 0 ? 1.0 / o->fps : 0.0, next = sb_wall_seconds(), begin = next;
    for (a->running = true; a->running;) {
        double start = sb_wall_seconds(), cpu_before = drawing_cpu(a);
        events(a);
        take_snapshot(a);
        if (sb_sim_thread_exchange(&a->thread, &a->controls, &a->report, &a->topology))
            sb_mesh_draw_topology(&a->mesh, &a->topology);
        draw(a);
        if (a->save) save_screenshot(a);
        a->save = false;
        a->frames++;
        bool last = !a->running || (o->frames && a->frames >= o->frames) ||
                    (o->seconds > 0 && sb_wall_seconds() - begin >= o->seconds);
        if (last && o->screenshot && sb_screenshot_save(o->screenshot, a->width, a->height, err) != SB_OK)
            return SB_ERR_IO;
        sb_window_swap(a->window);
        a->draw_seconds += sb_wall_seconds() - start;
        if (last) break;
        if (a->reload) {
            a->reload = false;
            if (reload(a, err) != SB_OK) return SB_ERR_INVALID;
        }
        /* the next frame one period on, and not before the renderer has
         * rested used (1/share − 1), used the processor time the frame took
         * on this thread and the renderer's own (llvmpipe's): its share */
        double share = o->render_share, used = drawing_cpu(a) - cpu_before;
        bool warm = a->frames > WARM_UP_FRAMES; /* the first frames compile shaders and fill buffers */
        double rest = warm && share > 0 && share < 1 ? used * (1.0 / share - 1.0) : 0.0;
        next = fmax(next + period, sb_wall_seconds() + rest);
        nap_until(next);
    }
    return SB_OK;
}

/* ---- the run ---------------------------------------------------------------------------- */

/* Script events at time 0 apply before the first step (the snapshot shown is the rest state). */
static void early_events(view_app* a) {
    take_snapshot(a);
    sb_view_event e;
    while (sb_input_script_next(&a->script, 0.0, &e)) handle(a, &e);
    a->controls.hold = sb_input_script_next_time(&a->script);
    a->thread.controls = a->controls;
}

static void fill_result(const view_app* a, sb_view_result* r, double wall, double simulated, uint64_t steps) {
    *r = (sb_view_result){
        .picked = a->controls.pick, .frames = a->frames, .camera = a->camera, .width = a->width, .height = a->height};
    memcpy(r->target, a->controls.target, sizeof r->target);
    r->frame_seconds = a->frames ? a->draw_seconds / a->frames : 0.0;
    r->steps_per_second = wall > 0 ? steps / wall : 0.0;
    r->realtime_factor = wall > 0 ? simulated / wall : 0.0;
    if (!a->shown) return;
    uint32_t n = a->shown->vertex_count;
    r->vertex_count = n;
    r->time = a->shown->time;
    r->step = a->shown->step;
    r->positions = malloc(3 * ((size_t)n + 1) * sizeof *r->positions);
    r->velocities = malloc(3 * ((size_t)n + 1) * sizeof *r->velocities);
    for (size_t k = 0; k < 3 * (size_t)n && r->positions && r->velocities; k++) {
        r->positions[k] = a->shown->positions[k];
        r->velocities[k] = a->shown->velocities[k];
    }
}

static void finish(view_app* a) {
    release_simulation(a);
    if (a->window) {
        sb_overlay_free(&a->overlay);
        sb_collider_draw_free(&a->colliders);
        sb_mesh_draw_free(&a->mesh);
        sb_shaders_free(&a->shaders);
        sb_window_close(a->window);
    }
    sb_input_script_free(&a->script);
}

sb_status sb_view_run(const sb_view_options* options, sb_view_result* result, sb_error* err) {
    view_app a = {.options = options, .tool_index = -1};
    sb_status status = options->script ? sb_input_script_load(options->script, &a.script, err) : SB_OK;
    if (status == SB_OK) status = start_simulation(&a, err);
    if (status == SB_OK) status = start_drawing(&a, err);
    if (status == SB_OK) status = sb_scene_haptics_start(&a.sim.haptics, "/dev/null", err);
    double wall = sb_wall_seconds(), simulated = 0.0;
    uint64_t steps = 0;
    if (status == SB_OK) {
        early_events(&a);
        status = sb_sim_thread_start(&a.thread, err);
    }
    if (status == SB_OK) status = frame_loop(&a, err);
    sb_sim_thread_stop(&a.thread);
    /* the solver's failure, as softbond run gives it (the window showed it too) */
    const char* failure = a.thread.report.failure[0] ? a.thread.report.failure : a.report.failure;
    if (status == SB_OK && failure[0]) status = sb_error_set(err, SB_ERR_UNSTABLE, "%s", failure);
    wall = sb_wall_seconds() - wall;
    if (a.sim.solver) {
        simulated = sb_solver_time(a.sim.solver);
        steps = sb_solver_step_count(a.sim.solver);
    }
    if (result) fill_result(&a, result, wall, simulated, steps);
    finish(&a);
    return status;
}

void sb_view_result_free(sb_view_result* r) {
    free(r->positions);
    free(r->velocities);
    *r = (sb_view_result){0};
}
