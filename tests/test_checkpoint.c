/* The solver's saved state (sb_solver_save_state, sb_solver_load_state):
 * a run saved at some step and loaded into a new solver (new colliders and
 * handles, made as the first were, on two threads instead of one) goes on
 * bitwise as the uninterrupted run: positions, velocities, forces,
 * energies, clock, statistics, contact forces, the colliders' and the
 * handles' state at every step after — for a Verlet sheet on a floor
 * under a spinning dynamic ball, an adaptive run that rejects sub-steps,
 * xpbd on a floor, vbd and the fast implicit Euler on a floor (each
 * carries its first guess over), hard and soft handles (one released
 * before the save),
 * a sheet torn by its handles (bonds broken and vertices split before and
 * after the save) and
 * the reference kernels with a generic integrator. Bad input is refused
 * with one line and leaves the solver as it was: every truncation tried, a
 * flipped byte anywhere, another model, another set-up, the other
 * precision, a buffer too small to save into.
 *
 * The program: `softbond run --checkpoint-every T` of a committed scene,
 * then the crash of a kill -9 made by hand (the frames from the
 * checkpoint's on removed, one left half written, a half row at the end of
 * log.csv), then `--resume DIR`: every file of the folder is then byte
 * for byte the uninterrupted run's (frames, log.csv, frames.pvd) — for a
 * net catching a dynamic ball (Verlet, contact), an adaptive bouncing
 * ball, a cloth draped with xpbd, a hook that lets go, a sheet torn
 * apart. A truncated or corrupt checkpoint, one of another scene or of
 * other --set values, a missing one: one line, exit 2. */
#define _DEFAULT_SOURCE
#include "test_util.h"
#include "pulled_sheet.h"

#include <dirent.h>
#include <limits.h>
#include <stdlib.h>
#include <sys/stat.h>

#include "common/sections.h"
#include "tests/test_files.h"

#define SIDE 12
#define CRACK_SAVE 1200 /* steps: the crack runs */

/* What one run owns; a case builds it the same way every time. */
typedef struct rig {
    sb_model* model;
    sb_collider* colliders[2];
    uint32_t collider_count;
    sb_handle* handles[2];
    uint32_t handle_count;
    uint32_t rows[2][SIDE];
    sb_solver* solver;
} rig;

typedef void (*rig_make)(rig* r, int threads);

static sb_model* sheet(double break_strain) { return ps_sheet_model(SIDE, 0.1, break_strain); }

static sb_collider* collider(const sb_collider_def* def) {
    sb_error err;
    sb_collider* c = sb_collider_create(def, &err);
    if (!c) fail_msg("%s", err.message);
    return c;
}

/* A floor 5 mm under the sheet (the sheet lies in z = 0 about its center). */
static sb_collider* floor_plane(void) {
    sb_collider_def d = sb_default_collider_def();
    d.shape = SB_COLLIDER_PLANE;
    d.name = "floor";
    d.point[2] = -0.005;
    d.normal[2] = 1.0;
    d.friction = 0.3;
    return collider(&d);
}

/* A spinning ball thrown down onto the middle of the sheet. */
static sb_collider* thrown_ball(void) {
    sb_collider_def d = sb_default_collider_def();
    d.shape = SB_COLLIDER_SPHERE;
    d.name = "ball";
    d.radius = 0.02;
    d.center[2] = 0.022;
    d.mass = 0.05;
    d.velocity[2] = -1.0;
    d.angular_velocity[2] = 20.0;
    d.friction = 0.5;
    return collider(&d);
}

static sb_solver_def rig_def(rig* r, sb_integrator integrator, int threads) {
    sb_solver_def def = sb_default_solver_def();
    def.integrator = integrator;
    def.runtime.threads = threads;
    def.colliders = r->colliders;
    def.collider_count = r->collider_count;
    def.handles = r->handles;
    def.handle_count = r->handle_count;
    return def;
}

static void verlet_ball(rig* r, int threads) {
    r->model = sheet(0.0);
    r->colliders[0] = floor_plane();
    r->colliders[1] = thrown_ball();
    r->collider_count = 2;
    sb_solver_def def = rig_def(r, SB_INTEGRATOR_VERLET, threads);
    r->solver = tu_solver(r->model, &def);
}

static void adaptive_ball(rig* r, int threads) {
    r->model = sheet(0.0);
    r->colliders[0] = thrown_ball();
    r->collider_count = 1;
    sb_solver_def def = rig_def(r, SB_INTEGRATOR_VERLET, threads);
    def.adaptive = true;
    def.drag = 1.0;
    r->solver = tu_solver(r->model, &def);
}

static void xpbd_floor(rig* r, int threads) {
    r->model = sheet(0.0);
    r->colliders[0] = floor_plane();
    r->collider_count = 1;
    sb_solver_def def = rig_def(r, SB_INTEGRATOR_XPBD, threads);
    r->solver = tu_solver(r->model, &def);
}

/* implicit Euler on the fast kernels with CG, a sheet falling onto a floor:
 * its first guess is the last step's Δv. */
static void implicit_fast_floor(rig* r, int threads) {
    r->model = sheet(0.0);
    r->colliders[0] = floor_plane();
    r->collider_count = 1;
    sb_solver_def def = rig_def(r, SB_INTEGRATOR_IMPLICIT_EULER, threads);
    def.implicit_solver = SB_LINEAR_CG;
    def.implicit_tolerance = 1e-2;
    r->solver = tu_solver(r->model, &def);
}

static void reference_floor(rig* r, int threads) {
    r->model = sheet(0.0);
    r->colliders[0] = floor_plane();
    r->collider_count = 1;
    sb_solver_def def = rig_def(r, SB_INTEGRATOR_SYMPLECTIC_EULER, threads);
    def.kernels = SB_KERNELS_REFERENCE;
    r->solver = tu_solver(r->model, &def);
}

/* vbd on a sheet falling onto a floor: its first guess carries the last
 * step's velocities over. */
static void vbd_floor(rig* r, int threads) {
    r->model = sheet(0.0);
    r->colliders[0] = floor_plane();
    r->collider_count = 1;
    sb_solver_def def = rig_def(r, SB_INTEGRATOR_VBD, threads);
    r->solver = tu_solver(r->model, &def);
}

static sb_handle* row_handle(rig* r, int k, uint32_t row, double stiffness, double release, double pull) {
    for (uint32_t i = 0; i < SIDE; i++) r->rows[k][i] = row * SIDE + i;
    sb_keyframe path[2] = {{0.0, {0, 0, 0}, {0, 0, 0}}, {0.05, {0, pull, 0.01}, {0, 0, 10}}};
    sb_handle_def def = sb_default_handle_def();
    def.name = k ? "soft" : "hard";
    def.vertices = r->rows[k];
    def.vertex_count = SIDE;
    def.stiffness = stiffness;
    def.damping = stiffness > 0 ? 0.05 : 0.0;
    def.path = path;
    def.path_count = 2;
    def.release_time = release;
    sb_error err;
    sb_handle* h = sb_handle_create(&def, &err);
    if (!h) fail_msg("%s", err.message);
    return h;
}

/* The hard handle lets go at 5 ms, before the save; the soft one holds. */
static void handles(rig* r, int threads) {
    r->model = sheet(0.0);
    r->handles[0] = row_handle(r, 0, 0, 0.0, 0.005, -0.01);
    r->handles[1] = row_handle(r, 1, SIDE - 1, 50.0, INFINITY, 0.01);
    r->handle_count = 2;
    sb_solver_def def = rig_def(r, SB_INTEGRATOR_VERLET, threads);
    r->solver = tu_solver(r->model, &def);
}

/* tests/pulled_sheet.h's sheet, its rows pulled apart 10 cm in 0.5 s: it
 * tears, shattering (bonds broken, vertices split) or as a crack. */
static void pulled(rig* r, int threads, bool shatter) {
    r->model = ps_sheet_model(SIDE, 0.2, 0.3);
    ps_handles(SIDE, r->handles, r->rows[0]);
    r->handle_count = 2;
    sb_solver_def def = rig_def(r, SB_INTEGRATOR_VERLET, threads);
    def.drag = 5.0;
    def.gravity[2] = 0.0;
    def.shatter = shatter;
    r->solver = tu_solver(r->model, &def);
}

static void torn(rig* r, int threads) { pulled(r, threads, true); }
static void cracked(rig* r, int threads) { pulled(r, threads, false); }

static void rig_free(rig* r) {
    sb_solver_destroy(r->solver);
    for (uint32_t c = 0; c < r->collider_count; c++) sb_collider_destroy(r->colliders[c]);
    for (uint32_t k = 0; k < r->handle_count; k++) sb_handle_destroy(r->handles[k]);
    sb_model_destroy(r->model);
    *r = (rig){0};
}

/* A hash of everything a program can see of the run after a step. */
static uint64_t observed(const rig* r) {
    const sb_solver* s = r->solver;
    size_t n = 3 * (size_t)sb_solver_vertex_capacity(s);
    double* values = calloc(3 * n, sizeof *values);
    sb_solver_get_positions(s, values);
    sb_solver_get_velocities(s, values + n);
    sb_solver_get_forces(s, values + 2 * n);
    uint64_t h = sb_hash(SB_HASH_START, values, 3 * n * sizeof *values);
    free(values);
    sb_energies e = sb_solver_energies(s);
    sb_step_stats stats = sb_solver_last_step(s);
    double clock[4] = {sb_solver_time(s), stats.last_substep, stats.min_substep, (double)sb_solver_step_count(s)};
    uint32_t counts[5] = {stats.substeps, stats.rejected, stats.contacts, sb_solver_broken_count(s),
                          sb_solver_vertex_count(s)};
    h = sb_hash(h, &e, sizeof e);
    h = sb_hash(h, clock, sizeof clock);
    h = sb_hash(h, counts, sizeof counts);
    for (uint32_t c = 0; c < r->collider_count; c++) {
        double body[21];
        sb_collider_state(r->colliders[c], body, body + 3);
        sb_collider_orientation(r->colliders[c], body + 6, body + 15);
        sb_solver_contact_force(s, c, body + 18);
        h = sb_hash(h, body, sizeof body);
    }
    for (uint32_t k = 0; k < r->handle_count; k++) {
        double force[3], target[3];
        bool held = sb_handle_held(r->handles[k]);
        sb_handle_force(r->handles[k], force);
        sb_handle_target(r->handles[k], 0, target);
        h = sb_hash(h, &held, sizeof held);
        h = sb_hash(h, force, sizeof force);
        h = sb_hash(h, target, sizeof target);
    }
    return h;
}

static void advance(rig* r, double dt) {
    if (sb_solver_advance(r->solver, dt) != SB_OK) fail_msg("%s", sb_solver_error(r->solver));
}

/* What the uninterrupted run showed about the case after the save. */
typedef struct after_save {
    uint32_t contacts, rejected, broken_at_save, broken_at_end, vertices_at_save, vertices_at_end;
    bool hard_held;
} after_save;

/* Runs `make` for `steps` steps of dt on one thread, saving after `save`;
 * a new rig on two threads loads it and must observe the same after every
 * later step. */
static after_save check_resume(rig_make make, double dt, int save, int steps) {
    rig a = {0}, b = {0};
    make(&a, 1);
    for (int k = 0; k < save; k++) advance(&a, dt);
    size_t size = sb_solver_state_size(a.solver);
    void* saved = malloc(size);
    sb_error err = {0};
    assert_int_equal(sb_solver_save_state(a.solver, saved, size, &err), SB_OK);
    after_save seen = {.broken_at_save = sb_solver_broken_count(a.solver),
                       .vertices_at_save = sb_solver_vertex_count(a.solver)};
    uint64_t* expected = malloc((size_t)steps * sizeof *expected);
    for (int k = save; k < steps; k++) {
        advance(&a, dt);
        expected[k] = observed(&a);
        seen.contacts += sb_solver_last_step(a.solver).contacts;
        seen.rejected += sb_solver_last_step(a.solver).rejected;
    }
    seen.broken_at_end = sb_solver_broken_count(a.solver);
    seen.vertices_at_end = sb_solver_vertex_count(a.solver);
    print_message("saved at step %d: %u contacts, %u rejected after; %u broken and %u vertices at the save, %u and %u "
                  "at the end\n",
                  save, seen.contacts, seen.rejected, seen.broken_at_save, seen.vertices_at_save, seen.broken_at_end,
                  seen.vertices_at_end);
    seen.hard_held = a.handle_count && sb_handle_held(a.handles[0]);
    rig_free(&a);

    make(&b, 2);
    if (sb_solver_load_state(b.solver, saved, size, &err) != SB_OK) fail_msg("%s", err.message);
    assert_int_equal(sb_solver_step_count(b.solver), save);
    for (int k = save; k < steps; k++) {
        advance(&b, dt);
        if (observed(&b) != expected[k])
            fail_msg("step %d after a load at step %d: not the uninterrupted run", k + 1, save);
    }
    rig_free(&b);
    free(expected);
    free(saved);
    return seen;
}

static void test_verlet_contact_dynamic_ball(void** state) {
    (void)state;
    after_save seen = check_resume(verlet_ball, 1e-4, 60, 200);
    assert_true(seen.contacts > 0);
}

static void test_adaptive(void** state) {
    (void)state;
    after_save seen = check_resume(adaptive_ball, 2e-2, 2, 6);
    assert_true(seen.rejected > 0); /* the step size carried over is what matters */
}

static void test_xpbd(void** state) {
    (void)state;
    after_save seen = check_resume(xpbd_floor, 1e-3, 20, 60);
    assert_true(seen.contacts > 0);
}

static void test_vbd(void** state) {
    (void)state;
    after_save seen = check_resume(vbd_floor, 1e-3, 20, 60);
    assert_true(seen.contacts > 0);
}

static void test_implicit_fast(void** state) {
    (void)state;
    after_save seen = check_resume(implicit_fast_floor, 1e-3, 20, 60);
    assert_true(seen.contacts > 0);
}

static void test_reference_kernels(void** state) {
    (void)state;
    after_save seen = check_resume(reference_floor, 5e-4, 50, 100);
    assert_true(seen.contacts > 0);
}

static void test_handles(void** state) {
    (void)state;
    after_save seen = check_resume(handles, 1e-4, 100, 250);
    assert_false(seen.hard_held); /* released before the save */
}

static void test_breaking(void** state) {
    (void)state;
    after_save seen = check_resume(torn, 1e-4, 1500, 2500);
    assert_true(seen.broken_at_save > 0);
    assert_true(seen.broken_at_end > seen.broken_at_save);
    assert_true(seen.vertices_at_save > SIDE * SIDE);          /* split before the save */
    assert_true(seen.vertices_at_end > seen.vertices_at_save); /* and after */
}

/* Saved while the crack runs: its tips carry over. */
static void test_cracking(void** state) {
    (void)state;
    after_save seen = check_resume(cracked, 1e-4, CRACK_SAVE, 2500);
    print_message("broken at the save %u, at the end %u\n", seen.broken_at_save, seen.broken_at_end);
    assert_true(seen.broken_at_save > 0);
    assert_true(seen.broken_at_end > seen.broken_at_save);
}

/* ---- refusals ------------------------------------------------------------- */

/* A rig advanced 50 steps and its saved state. */
static void* saved_ball(rig* r, size_t* size) {
    verlet_ball(r, 1);
    for (int k = 0; k < 50; k++) advance(r, 1e-4);
    *size = sb_solver_state_size(r->solver);
    void* data = malloc(*size);
    assert_int_equal(sb_solver_save_state(r->solver, data, *size, NULL), SB_OK);
    return data;
}

/* Loading `data` fails with a message starting with `start` and leaves the solver as it was. */
static void assert_refused(rig* r, const void* data, size_t size, const char* start) {
    uint64_t before = observed(r);
    sb_error err = {0};
    assert_int_not_equal(sb_solver_load_state(r->solver, data, size, &err), SB_OK);
    if (strncmp(err.message, start, strlen(start)) != 0) fail_msg("'%s' does not start with '%s'", err.message, start);
    assert_null(strchr(err.message, '\n'));
    assert_true(observed(r) == before);
}

static void test_truncated_and_corrupt_are_refused(void** state) {
    (void)state;
    rig a = {0}, fresh = {0};
    size_t size;
    uint8_t* data = saved_ball(&a, &size);
    verlet_ball(&fresh, 1);
    for (size_t cut = 0; cut < size; cut += cut < 64 ? 1 : 97) assert_refused(&fresh, data, cut, "solver state: ");
    assert_refused(&fresh, data, size - 1, "solver state: ");
    /* every 13th byte, and every byte of the header and of the checksum's section */
    for (size_t at = 0; at < size; at = at < 32 || at + 33 >= size ? at + 1 : at + 13) {
        data[at] ^= 0x10;
        assert_refused(&fresh, data, size, "solver state: ");
        data[at] ^= 0x10;
    }
    assert_refused(&fresh, data, 8, "solver state: not a softbond SBSOLVER file (too short)");
    data[8] ^= 1; /* the version */
    assert_refused(&fresh, data, size, "solver state: format version");
    data[8] ^= 1;
    data[size / 2] ^= 0x80;
    assert_refused(&fresh, data, size, "solver state: corrupt (the checksum does not match the contents)");
    data[size / 2] ^= 0x80;
    sb_error err;
    assert_int_equal(sb_solver_load_state(fresh.solver, data, size, &err), SB_OK); /* whole again */
    free(data);
    rig_free(&a);
    rig_free(&fresh);
}

/* The solver state's format version (SB_STATE_VERSION, kernels/solver/solver_state.c). */
enum { STATE_VERSION = 6 };

/* The header rewritten and the checksum made to match: what another build would write. */
static void reseal(uint8_t* data, size_t size) {
    uint64_t sum = sb_hash(SB_HASH_START, data, size - 24);
    memcpy(data + size - 8, &sum, sizeof sum);
}

/* Where the saved state's section `tag` starts in data. */
static uint8_t* section_in(uint8_t* data, size_t size, const char tag[4]) {
    sb_sections_reader r;
    sb_cursor section;
    sb_error err;
    assert_int_equal(sb_sections_read(&r, data, size, "SBSOLVER", STATE_VERSION, "state", &err), SB_OK);
    assert_true(sb_sections_find(&r, tag, &section));
    return data + (section.at - (const uint8_t*)data);
}

/* A step array's value that is not finite is refused on load, naming the
 * array and the vertex, whatever the checksum says (it was taken, and the
 * first step after it failed). */
static void test_state_not_finite_is_refused(void** state) {
    (void)state;
    rig a = {0}, fresh = {0};
    size_t size;
    uint8_t* data = saved_ball(&a, &size);
    verlet_ball(&fresh, 1);
    sb_error err;
    size_t n = sb_solver_vertex_capacity(fresh.solver); /* the arrays' length: x y z, then vx */
    uint8_t* vy = section_in(data, size, "ARRS") + (4 * n + 2) * sizeof(sb_real);
    sb_real saved, bad = (sb_real)NAN;
    memcpy(&saved, vy, sizeof saved);
    memcpy(vy, &bad, sizeof bad);
    reseal(data, size);
    assert_refused(&fresh, data, size, "solver state: the step arrays' vy of vertex 2 is not finite");
    memcpy(vy, &saved, sizeof saved);
    reseal(data, size);
    assert_int_equal(sb_solver_load_state(fresh.solver, data, size, &err), SB_OK);
    free(data);
    rig_free(&a);
    rig_free(&fresh);
}

/* A crack of a saved state that names a bond the model does not have is
 * refused whatever the checksum says, naming the vertex. */
static void test_crack_out_of_range_is_refused(void** state) {
    (void)state;
    rig a = {0}, fresh = {0};
    cracked(&a, 1);
    for (int k = 0; k < CRACK_SAVE; k++) advance(&a, 1e-4);
    size_t size = sb_solver_state_size(a.solver);
    uint8_t* data = malloc(size);
    assert_int_equal(sb_solver_save_state(a.solver, data, size, NULL), SB_OK);
    cracked(&fresh, 1);
    uint32_t broken, tips, bonds = sb_model_bond_count(fresh.model);
    uint8_t* section = section_in(data, size, "BRKN");
    memcpy(&broken, section, 4);
    memcpy(&tips, section + 4 + 4 * (size_t)broken, 4);
    uint8_t* crack = section + 8 + 4 * ((size_t)broken + tips); /* vertex 0's: the bond at, the pull */
    uint32_t saved, bad = bonds + 5;
    memcpy(&saved, crack, 4);
    memcpy(crack, &bad, 4);
    reseal(data, size);
    assert_refused(&fresh, data, size, "solver state: vertex 0's crack names bonds");
    memcpy(crack, &saved, 4);
    reseal(data, size);
    sb_error err;
    assert_int_equal(sb_solver_load_state(fresh.solver, data, size, &err), SB_OK);
    free(data);
    rig_free(&a);
    rig_free(&fresh);
}

/* The clock of a saved state is range-checked whatever
 * its checksum says (a NaN time was taken). */
static void test_clock_out_of_range_is_refused(void** state) {
    (void)state;
    rig a = {0}, fresh = {0};
    size_t size;
    uint8_t* data = saved_ball(&a, &size);
    verlet_ball(&fresh, 1);
    sb_error err;
    double* time = (double*)section_in(data, size, "CLCK");
    double saved = *time, bad[] = {NAN, INFINITY, -1};
    for (int k = 0; k < 3; k++) {
        *time = bad[k];
        reseal(data, size);
        char message[100];
        snprintf(message, sizeof message, "solver state: the clock's time is out of range (%g)", bad[k]);
        assert_refused(&fresh, data, size, message);
    }
    *time = saved;
    reseal(data, size);
    assert_int_equal(sb_solver_load_state(fresh.solver, data, size, &err), SB_OK);
    free(data);
    rig_free(&a);
    rig_free(&fresh);
}

static void test_other_model_setup_or_precision_is_refused(void** state) {
    (void)state;
    rig a = {0}, other = {0};
    size_t size;
    uint8_t* data = saved_ball(&a, &size);
    other.model = sheet(0.0);
    other.colliders[0] = floor_plane();
    other.colliders[1] = floor_plane(); /* not the dynamic ball */
    other.collider_count = 2;
    sb_solver_def def = rig_def(&other, SB_INTEGRATOR_VERLET, 1);
    other.solver = tu_solver(other.model, &def);
    assert_refused(&other, data, size, "solver state: saved from another model or solver set-up");
    rig_free(&other);
    xpbd_floor(&other, 1);
    assert_refused(&other, data, size, "solver state: saved from another model or solver set-up");
    rig_free(&other);
    uint32_t real_size = sizeof(sb_real) == 8 ? 4 : 8;
    memcpy(data + 12, &real_size, sizeof real_size);
    reseal(data, size);
    verlet_ball(&other, 1);
    assert_refused(&other, data, size,
                   sizeof(sb_real) == 8 ? "solver state: written by a float build, this one is double"
                                        : "solver state: written by a double build, this one is float");
    rig_free(&other);
    sb_error err;
    uint8_t small[64];
    assert_int_equal(sb_solver_save_state(a.solver, small, sizeof small, &err), SB_ERR_INVALID);
    assert_non_null(strstr(err.message, "too small"));
    free(data);
    rig_free(&a);
}

/* ---- the program ------------------------------------------------------------ */

/* Runs softbond and fails the test unless it exits 0. */
static void run_ok(const char* const* args) {
    tu_result r = tu_run(args);
    if (r.code != 0) fail_msg("softbond %s %s: exit %d: %s", args[0], args[1], r.code, r.err);
    tu_result_free(&r);
}

static void shell(const char* format, const char* a, const char* b) {
    char command[1200];
    snprintf(command, sizeof command, format, a, b);
    assert_int_equal(system(command), 0);
}

/* The frames the checkpoint in dir says were written. */
static uint64_t checkpoint_frames(const char* dir) {
    char path[64];
    snprintf(path, sizeof path, "%s/checkpoint.sbck", dir);
    char* data = tu_read_file(tu_tmp_path(path));
    assert_non_null(data);
    struct stat info;
    assert_int_equal(stat(tu_tmp_path(path), &info), 0);
    sb_sections_reader r;
    sb_cursor run;
    sb_error err;
    assert_int_equal(sb_sections_read(&r, data, (size_t)info.st_size, "SBCHKPNT", 1, path, &err), SB_OK);
    assert_true(sb_sections_find(&r, "RUN ", &run));
    uint64_t frames;
    assert_true(sb_cursor_take(&run, &frames, sizeof frames));
    free(data);
    return frames;
}

/* What a kill -9 after the checkpoint's frame could leave in dir: frame
 * `first` half written, the later ones not yet, a half row in log.csv. */
static void crash(const char* dir, uint64_t first) {
    DIR* d = opendir(tu_tmp_path(dir));
    assert_non_null(d);
    for (struct dirent* e; (e = readdir(d));) {
        unsigned long k;
        char path[128];
        if (sscanf(e->d_name, "frame_%lu", &k) != 1 || k < first) continue;
        snprintf(path, sizeof path, "%s/%.100s", dir, e->d_name);
        assert_int_equal(k == first ? truncate(tu_tmp_path(path), 10) : unlink(tu_tmp_path(path)), 0);
    }
    closedir(d);
    shell("printf '0.9,12' >> '%s/%s/log.csv'", tu_tmp_dir, dir);
}

/* Every file of a is in b with the same bytes, and b has no other. */
static void assert_same_folders(const char* a, const char* b) {
    shell("diff -r -x run.yaml '%s' '%s' >&2", tu_tmp_path(a), tu_tmp_path(b)); /* run.yaml: the command differs */
}

/* The scene run whole with checkpoints into "whole", the same into
 * "resumed", crashed after its last checkpoint and resumed. */
static void check_program_resume(const char* scene, const char* every, const char* const* sets) {
    char path[500];
    snprintf(path, sizeof path, "%s/scenes/%s", SB_SOURCE_DIR, scene);
    const char* args[24] = {"run", path, "--checkpoint-every", every, "--output", "whole"};
    int n = 6;
    for (; *sets; sets++) {
        args[n++] = "--set";
        args[n++] = *sets;
    }
    shell("rm -rf '%s' '%s'", tu_tmp_path("whole"), tu_tmp_path("resumed"));
    run_ok(args);
    shell("cp -r '%s' '%s'", tu_tmp_path("whole"), tu_tmp_path("resumed"));
    uint64_t frames = checkpoint_frames("resumed");
    print_message("%s: the checkpoint after frame %llu\n", scene, (unsigned long long)frames - 1);
    crash("resumed", frames);
    args[2] = "--resume", args[3] = "resumed", args[4] = args[5] = NULL;
    for (int k = 6; k < n; k++) args[k - 2] = args[k];
    args[n - 2] = NULL;
    run_ok(args);
    assert_same_folders("whole", "resumed");
}

static void test_program_verlet_dynamic_ball(void** state) {
    (void)state;
    check_program_resume("ball_net.yaml", "0.2", (const char*[]){"duration=0.3", NULL});
}

static void test_program_adaptive(void** state) {
    (void)state;
    check_program_resume("bouncing_ball.yaml", "0.6", (const char*[]){"adaptive=true", "dt=0.004", "duration=1", NULL});
}

static void test_program_xpbd(void** state) {
    (void)state;
    check_program_resume("draped_sheet.yaml", "0.3",
                         (const char*[]){"integrator=xpbd", "dt=0.002", "duration=0.5", NULL});
}

static void test_program_handles(void** state) {
    (void)state;
    check_program_resume("hook_pull.yaml", "2.6", (const char*[]){"duration=3", NULL}); /* released at 2.5 s */
}

static void test_program_breaking(void** state) {
    (void)state;
    check_program_resume("tearing_sheet.yaml", "0.6", (const char*[]){NULL}); /* bonds break from 0.4 s */
}

static void test_program_cutting(void** state) {
    (void)state;
    check_program_resume("blade_cut.yaml", "0.4", (const char*[]){"duration=0.6", NULL}); /* the blade half way */
}

static void assert_fails(const char* const* args, const char* message) {
    tu_result r = tu_run(args);
    char expected[700];
    snprintf(expected, sizeof expected, "softbond: %s\n", message);
    assert_string_equal(r.err, expected);
    assert_int_equal(r.code, 2);
    tu_result_free(&r);
}

static void test_program_refusals(void** state) {
    (void)state;
    char scene[500], other[500];
    snprintf(scene, sizeof scene, "%s/scenes/hook_pull.yaml", SB_SOURCE_DIR);
    snprintf(other, sizeof other, "%s/scenes/tearing_sheet.yaml", SB_SOURCE_DIR);
    shell("rm -rf '%s' '%s'", tu_tmp_path("c"), tu_tmp_path("d"));
    run_ok((const char*[]){"run", scene, "--set", "duration=0.1", "--checkpoint-every", "0.05", "--output", "c", NULL});
    shell("cp '%s' '%s'", tu_tmp_path("c/checkpoint.sbck"), tu_tmp_path("saved.sbck"));
    assert_fails((const char*[]){"run", other, "--resume", "c", NULL},
                 "c/checkpoint.sbck: written for another scene (a key other than duration differs)");
    assert_fails((const char*[]){"run", scene, "--set", "duration=0.1", "--set", "drag=0.5", "--resume", "c", NULL},
                 "c/checkpoint.sbck: written for another scene (a key other than duration differs)");
    assert_fails((const char*[]){"run", scene, "--set", "duration=0.1", "--resume", "nowhere", NULL},
                 "nowhere/checkpoint.sbck: cannot open: No such file or directory");
    assert_fails((const char*[]){"run", scene, "--resume", "c", "--output", "d", NULL},
                 "--resume DIR writes into DIR: leave out --output");
    assert_fails((const char*[]){"run", scene, "--checkpoint-every", "0", NULL},
                 "--checkpoint-every: expected seconds > 0, got '0'");
    shell("head -c 1000 '%s' > '%s'", tu_tmp_path("saved.sbck"), tu_tmp_path("c/checkpoint.sbck"));
    tu_result r = tu_run((const char*[]){"run", scene, "--set", "duration=0.1", "--resume", "c", NULL});
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "c/checkpoint.sbck: truncated"));
    tu_result_free(&r);
    shell("cp '%s' '%s'", tu_tmp_path("saved.sbck"), tu_tmp_path("c/checkpoint.sbck"));
    FILE* f = fopen(tu_tmp_path("c/checkpoint.sbck"), "r+b");
    assert_non_null(f);
    fseek(f, 3000, SEEK_SET);
    fputc('x', f);
    fclose(f);
    assert_fails((const char*[]){"run", scene, "--set", "duration=0.1", "--resume", "c", NULL},
                 "c/checkpoint.sbck: corrupt (the checksum does not match the contents)");
}

/* saved.sbck with size bytes at `offset` of its RUN section's payload
 * replaced by value and the checksum recomputed, as c/checkpoint.sbck. */
static void patch_run(size_t offset, const void* value, size_t size) {
    char* data = tu_read_file(tu_tmp_path("saved.sbck"));
    assert_non_null(data);
    struct stat info;
    assert_int_equal(stat(tu_tmp_path("saved.sbck"), &info), 0);
    sb_sections_reader r;
    sb_cursor run;
    sb_error err;
    assert_int_equal(sb_sections_read(&r, data, (size_t)info.st_size, "SBCHKPNT", 1, "saved", &err), SB_OK);
    assert_true(sb_sections_find(&r, "RUN ", &run));
    memcpy((uint8_t*)run.at + offset, value, size);
    reseal((uint8_t*)data, (size_t)info.st_size);
    FILE* f = fopen(tu_tmp_path("c/checkpoint.sbck"), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, (size_t)info.st_size, f), (size_t)info.st_size);
    fclose(f);
    free(data);
}

/* Every value of a checkpoint's run section is
 * range-checked on load, the checksum recomputed notwithstanding. Before,
 * log_bytes 0 cut log.csv to nothing with exit 0, and a non-finite or
 * negative stop value or interval was taken. */
static void test_program_run_section_range_checked(void** state) {
    (void)state;
    char scene[500];
    snprintf(scene, sizeof scene, "%s/scenes/hook_pull.yaml", SB_SOURCE_DIR);
    shell("rm -rf '%s' '%s'", tu_tmp_path("c"), tu_tmp_path("d"));
    run_ok((const char*[]){"run", scene, "--set", "duration=0.1", "--checkpoint-every", "0.05", "--output", "c", NULL});
    shell("cp '%s' '%s'", tu_tmp_path("c/checkpoint.sbck"), tu_tmp_path("saved.sbck"));
    shell("cp '%s' '%s'", tu_tmp_path("c/log.csv"), tu_tmp_path("saved.csv"));
    const char* const resume[] = {"run", scene, "--set", "duration=0.1", "--resume", "c", NULL};
    /* the RUN payload: frames, log_bytes (u64), every, next, kinetic_energy, min_time, max_time, duration, time,
     * kinetic (f64), reason (u32) */
    static const struct {
        size_t offset;
        double value;
        const char* message;
    } doubles[] = {
        {56, NAN, "c/checkpoint.sbck: the run's state is out of range (stop.duration = nan)"},
        {56, INFINITY, "c/checkpoint.sbck: the run's state is out of range (stop.duration = inf)"},
        {56, -1, "c/checkpoint.sbck: the run's state is out of range (stop.duration = -1)"},
        {48, NAN, "c/checkpoint.sbck: the run's state is out of range (stop.max_time = nan)"},
        {16, INFINITY, "c/checkpoint.sbck: the run's state is out of range (the checkpoint interval = inf)"},
        {24, -5, "c/checkpoint.sbck: the run's state is out of range (the next checkpoint's time = -5)"},
        {32, NAN, "c/checkpoint.sbck: the run's state is out of range (stop.kinetic_energy = nan)"},
    };
    for (size_t i = 0; i < sizeof doubles / sizeof doubles[0]; i++) {
        patch_run(doubles[i].offset, &doubles[i].value, sizeof(double));
        assert_fails(resume, doubles[i].message);
    }
    uint64_t zero = 0;
    patch_run(8, &zero, sizeof zero);
    assert_fails(resume, "c/checkpoint.sbck: the run's state is out of range (log.csv's length 0 bytes for 3 frames)");
    char* log = tu_read_file(tu_tmp_path("c/log.csv"));
    assert_non_null(log);
    assert_true(strlen(log) > 100); /* log.csv untouched */
    free(log);
    /* a length inside the rows: not a header and the frames' rows */
    uint64_t inside = 60;
    patch_run(8, &inside, sizeof inside);
    tu_result r = tu_run(resume);
    assert_int_equal(r.code, 2);
    assert_non_null(strstr(r.err, "c/log.csv: its first 60 bytes are not a header and 3 rows"));
    tu_result_free(&r);
    /* the solver's step count not its time's (the checksums inside and out recomputed) */
    {
        char* data = tu_read_file(tu_tmp_path("saved.sbck"));
        struct stat info;
        assert_int_equal(stat(tu_tmp_path("saved.sbck"), &info), 0);
        size_t size = (size_t)info.st_size;
        sb_sections_reader outer, inner;
        sb_cursor solver, clock;
        sb_error err;
        assert_int_equal(sb_sections_read(&outer, data, size, "SBCHKPNT", 1, "saved", &err), SB_OK);
        assert_true(sb_sections_find(&outer, "SOLV", &solver));
        assert_int_equal(sb_sections_read(&inner, solver.at, solver.left, "SBSOLVER", STATE_VERSION, "state", &err),
                         SB_OK);
        assert_true(sb_sections_find(&inner, "CLCK", &clock));
        uint64_t steps = 7;
        memcpy((uint8_t*)clock.at + 6 * sizeof(double), &steps, sizeof steps);
        reseal((uint8_t*)solver.at, solver.left);
        reseal((uint8_t*)data, size);
        FILE* f = fopen(tu_tmp_path("c/checkpoint.sbck"), "wb");
        assert_non_null(f);
        assert_int_equal(fwrite(data, 1, size, f), size);
        fclose(f);
        free(data);
        tu_result bad = tu_run(resume);
        assert_int_equal(bad.code, 2);
        if (!strstr(bad.err, "c/checkpoint.sbck: the run's state is out of range (the solver at t = "))
            fail_msg("got: %s", bad.err);
        assert_non_null(strstr(bad.err, " after 7 steps of "));
        tu_result_free(&bad);
    }
    /* the untouched checkpoint still resumes */
    shell("cp '%s' '%s'", tu_tmp_path("saved.sbck"), tu_tmp_path("c/checkpoint.sbck"));
    run_ok(resume);
}

/* The checkpoint's identity covers the files the scene
 * reads. scenes/mesh_bowl.yaml checkpointed, its collider's bowl.obj
 * edited (same vertex count): --resume is refused naming the file; put
 * back, it resumes. Before, the resume ran with exit 0 to a final frame
 * neither run's. */
static void test_program_changed_collider_file_refused(void** state) {
    (void)state;
    shell("rm -rf '%s' && mkdir '%s'", tu_tmp_path("bowl"), tu_tmp_path("bowl"));
    shell("cp '%s/scenes/mesh_bowl.yaml' '%s/bowl/'", SB_SOURCE_DIR, tu_tmp_dir);
    shell("cp '%s/scenes/bowl.obj' '%s/bowl/'", SB_SOURCE_DIR, tu_tmp_dir);
    char scene[500];
    snprintf(scene, sizeof scene, "%s", tu_tmp_path("bowl/mesh_bowl.yaml"));
    shell("rm -rf '%s' '%s'", tu_tmp_path("e"), tu_tmp_path("f"));
    run_ok(
        (const char*[]){"run", scene, "--set", "duration=0.08", "--checkpoint-every", "0.04", "--output", "e", NULL});
    const char* const resume[] = {"run", scene, "--set", "duration=0.08", "--resume", "e", NULL};
    shell("cp '%s' '%s'", tu_tmp_path("bowl/bowl.obj"), tu_tmp_path("bowl/saved.obj"));
    shell("sed -i 's/^v 0.000000 -0.157719 0.044805$/v 0.000000 -0.150000 0.044805/' '%s/%s'", tu_tmp_dir,
          "bowl/bowl.obj");
    shell("! cmp -s '%s' '%s'", tu_tmp_path("bowl/bowl.obj"), tu_tmp_path("bowl/saved.obj")); /* edited */
    tu_result r = tu_run(resume);
    char real[PATH_MAX], expected[PATH_MAX + 200];
    assert_non_null(realpath(tu_tmp_path("bowl/bowl.obj"), real));
    snprintf(expected, sizeof expected,
             "e/checkpoint.sbck: written for another scene (%s has changed since: a resumed run would match "
             "neither)\n",
             real);
    if (r.code != 2 || !strstr(r.err, expected))
        fail_msg("expected exit 2 and '%s', got %d: %s", expected, r.code, r.err);
    tu_result_free(&r);
    shell("cp '%s' '%s'", tu_tmp_path("bowl/saved.obj"), tu_tmp_path("bowl/bowl.obj"));
    run_ok(resume);
}

/* A full disk while writing a checkpoint says so (it
 * said 'Input/output error'): the checkpoint a link to /dev/full. */
static void test_program_full_disk_named(void** state) {
    (void)state;
    char scene[500];
    snprintf(scene, sizeof scene, "%s/scenes/hook_pull.yaml", SB_SOURCE_DIR);
    shell("rm -rf '%s' && mkdir '%s'", tu_tmp_path("full"), tu_tmp_path("full"));
    shell("ln -s /dev/full '%s/%s'", tu_tmp_dir, "full/checkpoint.sbck");
    tu_result r = tu_run(
        (const char*[]){"run", scene, "--set", "duration=0.1", "--checkpoint-every", "0.05", "--output", "full", NULL});
    assert_int_not_equal(r.code, 0);
    if (!strstr(r.err, "full/checkpoint.sbck: cannot write: No space left on device"))
        fail_msg("got %d: %s", r.code, r.err);
    tu_result_free(&r);
}

static int setup_dir(void** state) {
    (void)state;
    return tu_make_tmp_dir("sb_test_checkpoint");
}

static int teardown_dir(void** state) {
    (void)state;
    return tu_remove_tmp_dir();
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_verlet_contact_dynamic_ball),
        cmocka_unit_test(test_adaptive),
        cmocka_unit_test(test_xpbd),
        cmocka_unit_test(test_vbd),
        cmocka_unit_test(test_implicit_fast),
        cmocka_unit_test(test_reference_kernels),
        cmocka_unit_test(test_handles),
        cmocka_unit_test(test_breaking),
        cmocka_unit_test(test_cracking),
        cmocka_unit_test(test_crack_out_of_range_is_refused),
        cmocka_unit_test(test_truncated_and_corrupt_are_refused),
        cmocka_unit_test(test_other_model_setup_or_precision_is_refused),
        cmocka_unit_test(test_clock_out_of_range_is_refused),
        cmocka_unit_test(test_state_not_finite_is_refused),
        cmocka_unit_test(test_program_verlet_dynamic_ball),
        cmocka_unit_test(test_program_adaptive),
        cmocka_unit_test(test_program_xpbd),
        cmocka_unit_test(test_program_handles),
        cmocka_unit_test(test_program_breaking),
        cmocka_unit_test(test_program_cutting),
        cmocka_unit_test(test_program_refusals),
        cmocka_unit_test(test_program_run_section_range_checked),
        cmocka_unit_test(test_program_changed_collider_file_refused),
        cmocka_unit_test(test_program_full_disk_named),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
