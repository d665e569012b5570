/* The solver beside other threads: the wait policies and pinning never
 * change a result; the state buffer hands whole snapshots to readers while
 * the writer goes on. Run under the thread sanitizer too (make test). */
#define _GNU_SOURCE
#include "test_util.h"

#include <sched.h>
#include "kernels/runtime/team.h"

#include <pthread.h>
#include <stdio.h>
#include <stdatomic.h>
#include <string.h>
#include <time.h>

/* Under the thread sanitizer every memory access is checked: smaller runs. */
#if defined(__SANITIZE_THREAD__)
enum { SHEET_SIDE = 24, STEPS = 20, PUBLICATIONS = 2000, BUFFER_VERTICES = 200 };
#else
enum { SHEET_SIDE = 60, STEPS = 100, PUBLICATIONS = 20000, BUFFER_VERTICES = 2000 };
#endif

/* A SHEET_SIDE x SHEET_SIDE sheet with bond, angle and stretch-bend terms: blocks of each
 * color enough for two threads. */
static sb_model* make_sheet_model(sb_mesh* mesh) {
    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = SHEET_SIDE;
    sheet.jitter = 0.2;
    sb_error err;
    assert_int_equal(sb_mesh_generate_sheet(&sheet, mesh, &err), SB_OK);
    sb_material_def material = sb_default_material_def();
    material.bond_k = 50.0;
    material.angle_k = 0.3;
    material.stretch_bend_k = 2.0;
    sb_builder* builder = sb_builder_create();
    assert_int_equal(sb_builder_add_mesh(builder, mesh, &material, &err), SB_OK);
    sb_vertex_def* corner = sb_builder_vertex(builder, 0);
    corner->fixed = true;
    sb_model* model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    assert_non_null(model);
    return model;
}

static uint64_t hash_after_steps(const sb_model* model, sb_runtime_def runtime, sb_integrator integrator) {
    sb_solver_def def = sb_default_solver_def();
    def.kernels = SB_KERNELS_FAST;
    def.integrator = integrator;
    def.runtime = runtime;
    sb_solver* solver = tu_solver(model, &def);
    tu_advance(solver, 1e-4, STEPS);
    uint64_t h = tu_state_hash(solver);
    sb_solver_destroy(solver);
    return h;
}

typedef struct team_job {
    atomic_int calls, sum, after_barrier;
    int64_t covered[3];
} team_job;

/* Each worker of the job counts itself, covers its share of 999 items, and
 * after a barrier checks that all the others counted themselves. */
static void team_work(void* context, const sb_worker* w) {
    team_job* job = context;
    atomic_fetch_add(&job->calls, 1);
    atomic_fetch_add(&job->sum, w->index + 1);
    int64_t begin, end;
    sb_worker_range(w, 999, &begin, &end);
    job->covered[w->index] = end - begin;
    sb_worker_barrier(w);
    if (atomic_load(&job->calls) == w->width) atomic_fetch_add(&job->after_barrier, 1);
}

/* A team of 3 running jobs 1, 2 or 3 wide in turn, under each policy: only
 * the job's workers run it, the barrier holds, the shares cover the items,
 * and a narrow job after a wide one never mixes them up. */
static void test_team_runs_jobs_of_any_width(void** state) {
    (void)state;
    for (int p = 0; p < SB_WAIT_COUNT; p++) {
        sb_error err;
        sb_runtime_def def = {.threads = 3, .wait = (sb_wait_policy)p};
        sb_team* team = sb_team_create(&def, &err);
        assert_non_null(team);
        assert_int_equal(sb_team_size(team), 3);
        for (int round = 0; round < 300; round++) {
            int width = 1 + round % 3;
            team_job job = {0};
            sb_team_run(team, width, team_work, &job);
            assert_int_equal(atomic_load(&job.calls), width);
            assert_int_equal(atomic_load(&job.sum), width * (width + 1) / 2);
            assert_int_equal(atomic_load(&job.after_barrier), width);
            int64_t covered = 0;
            for (int i = 0; i < width; i++) covered += job.covered[i];
            assert_int_equal(covered, 999);
        }
        sb_team_destroy(team);
    }
}

/* Claimed passes (sb_worker_claim) of several sizes, one after another
 * between barriers: every item is run once, and worker 0, which waits
 * after its first claim of the last pass until another worker has taken
 * an item of its share (at most 5 s), is relieved of the rest of it. */
enum { CLAIM_PASSES = 4 };
static const int64_t claim_counts[CLAIM_PASSES] = {0, 1, 7, 999};

typedef struct claim_job {
    atomic_int runs[CLAIM_PASSES][999];
    atomic_int taken_from_first; /* items of worker 0's share of the last pass run by another */
} claim_job;

static void claim_work(void* context, const sb_worker* w) {
    claim_job* job = context;
    sb_worker first_worker = {w->team, 0, w->width};
    for (int pass = 0; pass < CLAIM_PASSES; pass++) {
        int64_t share_begin, share_end, begin, end;
        sb_worker_range(&first_worker, claim_counts[pass], &share_begin, &share_end);
        sb_claims claims = sb_worker_claims(claim_counts[pass]);
        for (int claim = 0; sb_worker_claim(w, &claims, &begin, &end); claim++) {
            for (int64_t i = begin; i < end; i++) {
                atomic_fetch_add(&job->runs[pass][i], 1);
                if (w->index != 0 && i >= share_begin && i < share_end) atomic_fetch_add(&job->taken_from_first, 1);
            }
            bool last_pass = pass == CLAIM_PASSES - 1;
            for (int waited = 0; last_pass && w->width > 1 && w->index == 0 && claim == 0 &&
                                 atomic_load(&job->taken_from_first) == 0 && waited < 5000;
                 waited++)
                nanosleep(&(struct timespec){0, 1000000}, NULL);
        }
        sb_worker_barrier(w);
    }
}

static void test_claims_run_every_item_once(void** state) {
    (void)state;
    sb_error err;
    sb_runtime_def def = {.threads = 3, .wait = SB_WAIT_PASSIVE};
    sb_team* team = sb_team_create(&def, &err);
    assert_non_null(team);
    for (int round = 0; round < 30; round++) {
        int width = 1 + round % 3;
        static claim_job job;
        memset(&job, 0, sizeof job);
        sb_team_run(team, width, claim_work, &job);
        for (int pass = 0; pass < CLAIM_PASSES; pass++)
            for (int64_t i = 0; i < 999; i++)
                if (atomic_load(&job.runs[pass][i]) != (i < claim_counts[pass]))
                    fail_msg("width %d, pass of %lld items: item %lld ran %d times", width,
                             (long long)claim_counts[pass], (long long)i, atomic_load(&job.runs[pass][i]));
        if (width > 1) assert_true(atomic_load(&job.taken_from_first) > 0);
    }
    sb_team_destroy(team);
}

/* A job that is slow on the worker named by its context's `slow_alone`
 * (1: on the caller alone, 0: when shared): it sleeps 20 ms there, more
 * than a busy machine's scheduling delays add to the job otherwise, and
 * covers its items as team_work does. */
typedef struct lopsided_job {
    bool slow_alone;
    atomic_llong covered;
    atomic_int widest; /* the largest width a worker saw */
} lopsided_job;

static void lopsided_work(void* context, const sb_worker* w) {
    lopsided_job* job = context;
    if ((w->width == 1) == job->slow_alone && w->index == 0) nanosleep(&(struct timespec){0, 20000000}, NULL);
    int64_t begin, end;
    sb_worker_range(w, 999, &begin, &end);
    atomic_fetch_add(&job->covered, end - begin);
    int seen = atomic_load(&job->widest);
    while (seen < w->width && !atomic_compare_exchange_weak(&job->widest, &seen, w->width)) {
    }
    sb_worker_barrier(w);
}

/* sb_team_run_adaptive runs a job at the width it measured faster, trying
 * the other now and then: of 256 runs, at most a few go at the slow width
 * (the first measurement and one probe every 64 runs), and every run
 * covers all the items whichever width ran it. */
static void test_adaptive_runs_take_the_faster_width(void** state) {
    (void)state;
    for (int slow_alone = 0; slow_alone < 2; slow_alone++) {
        sb_error err;
        sb_runtime_def def = {.threads = 2, .wait = SB_WAIT_PASSIVE};
        sb_team* team = sb_team_create(&def, &err);
        assert_non_null(team);
        enum { RUNS = 256, SLOW_AT_MOST = 16 };
        for (int run = 0; run < RUNS; run++) {
            lopsided_job job = {.slow_alone = slow_alone};
            sb_team_run_adaptive(team, 2, lopsided_work, &job);
            assert_int_equal(atomic_load(&job.covered), 999);
        }
        uint64_t runs, alone;
        sb_team_adaptive_counts(team, &runs, &alone);
        assert_int_equal(runs, RUNS);
        if (slow_alone)
            assert_in_range(alone, 1, SLOW_AT_MOST);
        else
            assert_in_range(alone, RUNS - SLOW_AT_MOST, RUNS - 1);
        sb_team_destroy(team);
    }
}

/* With fixed_width the team never narrows: every run of a job that is
 * slow on two threads (the adaptive team would move it to the caller
 * alone, as the test above checks) goes on the configured two. */
static void test_fixed_width_never_narrows(void** state) {
    (void)state;
    sb_error err;
    sb_runtime_def def = {.threads = 2, .wait = SB_WAIT_PASSIVE, .fixed_width = true};
    sb_team* team = sb_team_create(&def, &err);
    assert_non_null(team);
    for (int run = 0; run < 8; run++) {
        lopsided_job job = {.slow_alone = false};
        sb_team_run_adaptive(team, 2, lopsided_work, &job);
        assert_int_equal(atomic_load(&job.covered), 999);
        assert_int_equal(atomic_load(&job.widest), 2);
    }
    uint64_t runs, alone;
    sb_team_adaptive_counts(team, &runs, &alone);
    assert_int_equal(alone, 0);
    sb_team_destroy(team);
}

/* A pinned team binds the thread that creates it to core 0 and gives it its
 * own binding back when destroyed (a host thread made later from it must
 * not inherit core 0). */
static void test_pinning_gives_the_binding_back(void** state) {
    (void)state;
    cpu_set_t before, during, after;
    assert_int_equal(sched_getaffinity(0, sizeof before, &before), 0);
    if (CPU_COUNT(&before) < 2) skip(); /* nothing to narrow on one processor */
    sb_error err;
    sb_runtime_def def = {.threads = 2, .pin = true, .wait = SB_WAIT_PASSIVE};
    sb_team* team = sb_team_create(&def, &err);
    assert_non_null(team);
    assert_int_equal(sched_getaffinity(0, sizeof during, &during), 0);
    sb_team_destroy(team);
    assert_int_equal(sched_getaffinity(0, sizeof after, &after), 0);
    print_message("processors: %d before, %d pinned, %d after\n", CPU_COUNT(&before), CPU_COUNT(&during),
                  CPU_COUNT(&after));
    assert_true(CPU_COUNT(&during) < CPU_COUNT(&before));
    assert_true(CPU_EQUAL(&before, &after));
}

static void test_default_runtime_shares_the_machine(void** state) {
    (void)state;
    sb_runtime_def def = sb_default_runtime_def();
    assert_int_equal(def.threads, 0);
    assert_false(def.pin);
    assert_int_equal(def.wait, SB_WAIT_PASSIVE);
    sb_solver_def solver = sb_default_solver_def();
    assert_int_equal(solver.runtime.wait, SB_WAIT_PASSIVE);
    assert_false(solver.runtime.pin);
}

static void test_wait_policy_names(void** state) {
    (void)state;
    for (int p = 0; p < SB_WAIT_COUNT; p++) {
        sb_wait_policy back;
        assert_true(sb_wait_policy_from_name(sb_wait_policy_name((sb_wait_policy)p), &back));
        assert_int_equal(back, p);
    }
    sb_wait_policy ignored;
    assert_false(sb_wait_policy_from_name("busy", &ignored));
}

/* Every policy, pinned or not, on 2 or 3 threads gives bitwise the state of
 * one thread, for the fused Verlet step, a generic integrator on the fast
 * forces and pbd (all three run on the team). */
static void test_policies_do_not_change_results(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_model* model = make_sheet_model(&mesh);
    const sb_integrator integrators[3] = {SB_INTEGRATOR_VERLET, SB_INTEGRATOR_SYMPLECTIC_EULER, SB_INTEGRATOR_XPBD};
    for (int k = 0; k < 3; k++) {
        uint64_t one = hash_after_steps(model, (sb_runtime_def){.threads = 1}, integrators[k]);
        /* each policy on 2 threads (pinned for spin), and passive on 3: more
         * threads than this machine's 2 cores, which only passive stands */
        for (int p = 0; p <= SB_WAIT_COUNT; p++) {
            int threads = p < SB_WAIT_COUNT ? 2 : 3;
            sb_wait_policy wait = p < SB_WAIT_COUNT ? (sb_wait_policy)p : SB_WAIT_PASSIVE;
            sb_runtime_def runtime = {.threads = threads, .pin = wait == SB_WAIT_SPIN, .wait = wait};
            uint64_t h = hash_after_steps(model, runtime, integrators[k]);
            if (h != one)
                fail_msg("%s, %d threads, wait %s: state differs from one thread's", sb_integrator_name(integrators[k]),
                         threads, sb_wait_policy_name(wait));
        }
    }
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

static void test_unknown_wait_policy_is_refused(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_model* model = make_sheet_model(&mesh);
    sb_solver_def def = sb_default_solver_def();
    def.runtime.wait = (sb_wait_policy)7;
    sb_error err = {0};
    assert_null(sb_solver_create(model, &def, &err));
    assert_string_equal(err.message, "unknown wait policy 7");
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* One bound on the thread count, SB_MAX_THREADS, for the solver's def,
 * sb_runtime_threads and SOFTBOND_THREADS, and the messages say it. */
static void test_one_thread_bound(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_model* model = make_sheet_model(&mesh);
    sb_solver_def def = sb_default_solver_def();
    def.runtime.threads = SB_MAX_THREADS + 1;
    sb_error err = {0};
    assert_null(sb_solver_create(model, &def, &err));
    char expected[128];
    snprintf(expected, sizeof expected, "threads must be from 0 to %d (got %d)", SB_MAX_THREADS, SB_MAX_THREADS + 1);
    assert_string_equal(err.message, expected);
    assert_int_equal(sb_runtime_threads(SB_MAX_THREADS + 1, &err), -1);
    assert_int_equal(sb_runtime_threads(SB_MAX_THREADS, &err), SB_MAX_THREADS);
    char* saved = getenv("SOFTBOND_THREADS") ? strdup(getenv("SOFTBOND_THREADS")) : NULL;
    char value[32];
    snprintf(value, sizeof value, "%d", SB_MAX_THREADS + 1);
    setenv("SOFTBOND_THREADS", value, 1);
    assert_int_equal(sb_runtime_threads(0, &err), -1);
    snprintf(expected, sizeof expected, "SOFTBOND_THREADS='%d' is not a thread count from 1 to %d", SB_MAX_THREADS + 1,
             SB_MAX_THREADS);
    assert_string_equal(err.message, expected);
    unsetenv("SOFTBOND_THREADS");
    int automatic = sb_runtime_threads(0, &err);
    assert_true(automatic >= 1 && automatic <= SB_MAX_THREADS);
    if (saved) setenv("SOFTBOND_THREADS", saved, 1);
    free(saved);
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* The published snapshot is the solver's state at that step, exactly. */
static void test_publish_copies_the_state(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_model* model = make_sheet_model(&mesh);
    uint32_t n = sb_model_vertex_count(model);
    for (int kernels = 0; kernels < 2; kernels++) {
        sb_solver_def def = sb_default_solver_def();
        def.kernels = kernels ? SB_KERNELS_FAST : SB_KERNELS_REFERENCE;
        def.runtime.threads = 2;
        sb_solver* solver = tu_solver(model, &def);
        sb_error err;
        sb_state_buffer* buffer = sb_state_buffer_create(n, 2, &err);
        assert_non_null(buffer);
        assert_null(sb_state_buffer_acquire(buffer)); /* nothing published yet */
        tu_advance(solver, 1e-4, 7);
        assert_int_equal(sb_solver_publish(solver, buffer), SB_OK);
        const sb_snapshot* snap = sb_state_buffer_acquire(buffer);
        assert_non_null(snap);
        double* x = malloc(6 * (size_t)n * sizeof *x);
        sb_solver_get_positions(solver, x);
        sb_solver_get_velocities(solver, x + 3 * (size_t)n);
        for (size_t k = 0; k < 3 * (size_t)n; k++) {
            assert_true((double)snap->positions[k] == x[k]);
            assert_true((double)snap->velocities[k] == x[3 * (size_t)n + k]);
        }
        assert_int_equal(snap->sequence, 1);
        assert_int_equal(snap->step, 7);
        assert_int_equal(snap->vertex_count, n);
        assert_true(snap->time == sb_solver_time(solver));
        assert_true(snap->energies.kinetic == sb_solver_energies(solver).kinetic);
        assert_true(snap->energies.term[SB_TERM_ANGLE] == sb_solver_energies(solver).term[SB_TERM_ANGLE]);
        sb_state_buffer_release(buffer, snap);
        free(x);
        sb_state_buffer_destroy(buffer);
        sb_solver_destroy(solver);
    }
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* The snapshot of sb_solver_advance_published is bitwise the one of an
 * advance and sb_solver_publish, whether the fused step writes it (verlet,
 * fast) or it is copied (symplectic Euler; adaptive Verlet). */
static void test_advance_published_equals_publish(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_model* model = make_sheet_model(&mesh);
    size_t n3 = 3 * (size_t)sb_model_vertex_count(model);
    const sb_integrator integrators[3] = {SB_INTEGRATOR_VERLET, SB_INTEGRATOR_SYMPLECTIC_EULER, SB_INTEGRATOR_VERLET};
    for (int k = 0; k < 3; k++) {
        sb_solver_def def = sb_default_solver_def();
        def.integrator = integrators[k];
        def.adaptive = k == 2;
        def.runtime.threads = 2;
        sb_solver *a = tu_solver(model, &def), *b = tu_solver(model, &def);
        sb_error err;
        sb_state_buffer *fused = sb_state_buffer_create(sb_model_vertex_count(model), 1, &err),
                        *copied = sb_state_buffer_create(sb_model_vertex_count(model), 1, &err);
        for (int step = 0; step < 5; step++) {
            assert_int_equal(sb_solver_advance_published(a, 1e-4, fused), SB_OK);
            assert_int_equal(sb_solver_advance(b, 1e-4), SB_OK);
            assert_int_equal(sb_solver_publish(b, copied), SB_OK);
        }
        const sb_snapshot *x = sb_state_buffer_acquire(fused), *y = sb_state_buffer_acquire(copied);
        assert_int_equal(x->sequence, 5);
        assert_int_equal(x->step, y->step);
        assert_true(x->time == y->time);
        assert_memory_equal(x->positions, y->positions, n3 * sizeof(sb_real));
        assert_memory_equal(x->velocities, y->velocities, n3 * sizeof(sb_real));
        assert_true(x->energies.kinetic == y->energies.kinetic);
        assert_int_equal(tu_state_hash(a), tu_state_hash(b));
        sb_state_buffer_release(fused, x);
        sb_state_buffer_release(copied, y);
        sb_state_buffer_destroy(fused);
        sb_state_buffer_destroy(copied);
        sb_solver_destroy(a);
        sb_solver_destroy(b);
    }
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* With every slot held the advance still runs and the skip is counted. */
static void test_advance_published_skips_when_full(void** state) {
    (void)state;
    sb_mesh mesh = {0};
    sb_model* model = make_sheet_model(&mesh);
    sb_solver_def def = sb_default_solver_def();
    sb_solver* s = tu_solver(model, &def);
    sb_error err;
    sb_state_buffer* b = sb_state_buffer_create(sb_model_vertex_count(model), 1, &err); /* 3 slots */
    assert_int_equal(sb_solver_advance_published(s, 1e-4, b), SB_OK);
    const sb_snapshot* first = sb_state_buffer_acquire(b);
    assert_int_equal(sb_solver_advance_published(s, 1e-4, b), SB_OK);
    const sb_snapshot* second = sb_state_buffer_acquire(b);           /* a second holder: beyond max_readers */
    assert_int_equal(sb_solver_advance_published(s, 1e-4, b), SB_OK); /* the third slot */
    assert_int_equal(sb_solver_advance_published(s, 1e-4, b), SB_OK); /* none free: skipped */
    assert_int_equal(sb_solver_step_count(s), 4);
    assert_int_equal(sb_state_buffer_published(b), 3);
    assert_int_equal(sb_state_buffer_skipped(b), 1);
    assert_int_equal(sb_solver_publish(s, b), SB_ERR_BUSY);
    assert_int_equal(sb_state_buffer_skipped(b), 2);
    sb_state_buffer_release(b, first);
    sb_state_buffer_release(b, second);
    sb_state_buffer_destroy(b);
    sb_solver_destroy(s);
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

/* Fills a snapshot with the pattern of publication k. */
static void fill(sb_snapshot* s, uint64_t k) {
    s->step = k;
    s->time = (double)k;
    for (size_t i = 0; i < 3 * (size_t)s->vertex_count; i++) {
        s->positions[i] = (sb_real)(k % 1000);
        s->velocities[i] = -(sb_real)(k % 1000);
    }
}

/* Whether a snapshot is whole: every value from one publication. */
static bool whole(const sb_snapshot* s) {
    sb_real want = (sb_real)(s->step % 1000);
    for (size_t i = 0; i < 3 * (size_t)s->vertex_count; i++)
        if (s->positions[i] != want || s->velocities[i] != -want) return false;
    return s->time == (double)s->step;
}

/* A held snapshot does not change while the writer publishes on; with every
 * slot held the writer is told, not blocked. */
static void test_held_snapshot_is_left_alone(void** state) {
    (void)state;
    sb_error err;
    sb_state_buffer* b = sb_state_buffer_create(100, 1, &err); /* 3 slots */
    assert_non_null(b);
    sb_snapshot* w = sb_state_buffer_begin(b);
    fill(w, 1);
    sb_state_buffer_commit(b, w);
    const sb_snapshot* held = sb_state_buffer_acquire(b);
    for (uint64_t k = 2; k < 20; k++) {
        w = sb_state_buffer_begin(b);
        assert_non_null(w);
        assert_ptr_not_equal(w, held);
        fill(w, k);
        sb_state_buffer_commit(b, w);
    }
    assert_int_equal(held->step, 1);
    assert_true(whole(held));
    const sb_snapshot* second = sb_state_buffer_acquire(b); /* a second reader: more than max_readers */
    assert_int_equal(second->step, 19);
    assert_int_equal(sb_state_buffer_published(b), 19);
    w = sb_state_buffer_begin(b); /* one slot latest and held, one held: the third is free */
    assert_non_null(w);
    fill(w, 20);
    sb_state_buffer_commit(b, w);
    assert_null(sb_state_buffer_begin(b)); /* latest, and two held */
    sb_state_buffer_release(b, held);
    sb_state_buffer_release(b, second);
    assert_non_null(sb_state_buffer_begin(b));
    sb_state_buffer_destroy(b);
}

typedef struct stress {
    sb_state_buffer* buffer;
    atomic_int done;
    uint64_t publications;
    atomic_ullong reads, torn, backwards;
} stress;

static void* writer_main(void* arg) {
    stress* s = arg;
    for (uint64_t k = 1; k <= s->publications; k++) {
        sb_snapshot* w = sb_state_buffer_begin(s->buffer);
        if (!w) fail_msg("the writer found no free slot with 3 readers and 5 slots");
        fill(w, k);
        sb_state_buffer_commit(s->buffer, w);
    }
    atomic_store(&s->done, 1);
    return NULL;
}

static void* reader_main(void* arg) {
    stress* s = arg;
    uint64_t last = 0;
    while (!atomic_load(&s->done)) {
        const sb_snapshot* r = sb_state_buffer_acquire(s->buffer);
        if (!r) continue;
        atomic_fetch_add(&s->reads, 1);
        if (!whole(r)) atomic_fetch_add(&s->torn, 1);
        if (r->sequence < last) atomic_fetch_add(&s->backwards, 1);
        last = r->sequence;
        sb_state_buffer_release(s->buffer, r);
    }
    return NULL;
}

/* One writer publishing as fast as it can, three readers checking every
 * snapshot they get: none is torn, none goes back in time. */
static void test_readers_never_see_a_torn_snapshot(void** state) {
    (void)state;
    sb_error err;
    stress s = {.publications = PUBLICATIONS};
    s.buffer = sb_state_buffer_create(BUFFER_VERTICES, 3, &err);
    assert_non_null(s.buffer);
    pthread_t writer, readers[3];
    for (int r = 0; r < 3; r++) assert_int_equal(pthread_create(&readers[r], NULL, reader_main, &s), 0);
    assert_int_equal(pthread_create(&writer, NULL, writer_main, &s), 0);
    pthread_join(writer, NULL);
    for (int r = 0; r < 3; r++) pthread_join(readers[r], NULL);
    print_message("%llu snapshots read during %d publications\n", (unsigned long long)atomic_load(&s.reads),
                  PUBLICATIONS);
    assert_true(atomic_load(&s.reads) > 0);
    assert_int_equal(atomic_load(&s.torn), 0);
    assert_int_equal(atomic_load(&s.backwards), 0);
    assert_int_equal(sb_state_buffer_published(s.buffer), PUBLICATIONS);
    sb_state_buffer_destroy(s.buffer);
}

static void test_buffer_checks_its_arguments(void** state) {
    (void)state;
    sb_error err = {0};
    assert_null(sb_state_buffer_create(10, 0, &err));
    assert_string_equal(err.message, "state buffer: max_readers must be from 1 to 64 (got 0)");
    sb_mesh mesh = {0};
    sb_model* model = make_sheet_model(&mesh);
    sb_solver_def def = sb_default_solver_def();
    sb_solver* solver = tu_solver(model, &def);
    sb_state_buffer* b = sb_state_buffer_create(10, 1, &err);
    assert_int_equal(sb_solver_publish(solver, b), SB_ERR_INVALID); /* the sheet into a buffer of 10 */
    assert_int_equal(sb_state_buffer_published(b), 0);
    sb_state_buffer_destroy(b);
    sb_solver_destroy(solver);
    sb_model_destroy(model);
    sb_mesh_free(&mesh);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_team_runs_jobs_of_any_width),
        cmocka_unit_test(test_claims_run_every_item_once),
        cmocka_unit_test(test_adaptive_runs_take_the_faster_width),
        cmocka_unit_test(test_fixed_width_never_narrows),
        cmocka_unit_test(test_pinning_gives_the_binding_back),
        cmocka_unit_test(test_default_runtime_shares_the_machine),
        cmocka_unit_test(test_wait_policy_names),
        cmocka_unit_test(test_policies_do_not_change_results),
        cmocka_unit_test(test_unknown_wait_policy_is_refused),
        cmocka_unit_test(test_one_thread_bound),
        cmocka_unit_test(test_publish_copies_the_state),
        cmocka_unit_test(test_held_snapshot_is_left_alone),
        cmocka_unit_test(test_advance_published_equals_publish),
        cmocka_unit_test(test_advance_published_skips_when_full),
        cmocka_unit_test(test_readers_never_see_a_torn_snapshot),
        cmocka_unit_test(test_buffer_checks_its_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
