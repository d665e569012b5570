/* embed: the solver on the main thread, a reader thread on the state buffer.
 * The main thread advances a sheet and publishes each step's state; the
 * reader, as a haptic loop or a renderer would, takes the newest snapshot
 * whenever it likes, never blocking the solver, and checks that what it sees
 * only moves forward. Build:
 *   cc embed.c $(pkg-config --cflags --libs softbond) -pthread -o embed */
#define _POSIX_C_SOURCE 200809L /* nanosleep */
#include <softbond/softbond.h>

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

typedef struct reader {
    sb_state_buffer* buffer;
    atomic_bool stop;
    uint64_t seen;      /* distinct snapshots read */
    uint64_t last_step; /* the newest step seen */
    bool went_back;     /* a snapshot older than one seen before: a bug */
    double lowest_z;    /* the lowest vertex of the newest snapshot, m */
} reader;

static void* read_snapshots(void* arg) {
    reader* r = arg;
    uint64_t last_sequence = 0;
    for (;;) {
        bool stopping = atomic_load(&r->stop);                     /* then one last look: the newest snapshot */
        const sb_snapshot* s = sb_state_buffer_acquire(r->buffer); /* NULL before the first publish */
        if (s) {
            if (s->sequence < last_sequence || s->step < r->last_step) r->went_back = true;
            if (s->sequence != last_sequence) {
                r->seen++;
                last_sequence = s->sequence;
                r->last_step = s->step;
                double low = s->positions[2];
                for (uint32_t v = 1; v < s->vertex_count; v++)
                    if (s->positions[3 * v + 2] < low) low = s->positions[3 * v + 2];
                r->lowest_z = low;
            }
            sb_state_buffer_release(r->buffer, s);
        }
        if (stopping) break;
        nanosleep(&(struct timespec){.tv_nsec = 200000}, NULL); /* a 5 kHz loop */
    }
    return NULL;
}

int main(void) {
    sb_error err;
    sb_mesh mesh = {0};
    sb_builder* builder = NULL;
    sb_model* model = NULL;
    sb_solver* solver = NULL;
    sb_state_buffer* buffer = NULL;
    int code = EXIT_FAILURE;

    sb_sheet_def sheet = sb_default_sheet_def();
    sheet.nx = sheet.ny = 32;
    if (sb_mesh_generate_sheet(&sheet, &mesh, &err) != SB_OK) goto fail;
    builder = sb_builder_create();
    if (!builder) goto out;
    sb_material_def material = sb_default_material_def();
    if (sb_builder_add_mesh(builder, &mesh, &material, &err) != SB_OK) goto fail;
    sb_builder_vertex(builder, 0)->fixed = true;
    sb_builder_vertex(builder, sheet.nx - 1)->fixed = true; /* two corners held */
    model = sb_builder_compile(builder, &err);
    if (!model) goto fail;

    sb_solver_def def = sb_default_solver_def();
    def.runtime.threads = 1; /* leave the other core to the reader */
    solver = sb_solver_create(model, &def, &err);
    if (!solver) goto fail;
    /* One reader holds a snapshot at a time. */
    buffer = sb_state_buffer_create(sb_model_vertex_count(model), 1, &err);
    if (!buffer) goto fail;

    reader r = {.buffer = buffer};
    pthread_t thread;
    if (pthread_create(&thread, NULL, read_snapshots, &r) != 0) {
        fprintf(stderr, "embed: cannot start the reader thread\n");
        goto out;
    }
    sb_status status = SB_OK;
    for (int i = 0; i < 2000 && status == SB_OK; i++) {
        status = sb_solver_advance_published(solver, 1e-4, buffer);                 /* never blocks, never allocates */
        if (i % 100 == 99) nanosleep(&(struct timespec){.tv_nsec = 1000000}, NULL); /* let the reader look */
    }
    atomic_store(&r.stop, true);
    pthread_join(thread, NULL);
    if (status != SB_OK) {
        fprintf(stderr, "embed: %s\n", sb_solver_error(solver));
        goto out;
    }
    printf("embed: the solver published %llu steps; the reader saw %llu snapshots, the newest of step %llu, "
           "its lowest vertex at z = %.4f m; order kept: %s\n",
           (unsigned long long)sb_state_buffer_published(buffer), (unsigned long long)r.seen,
           (unsigned long long)r.last_step, r.lowest_z, r.went_back ? "no" : "yes");
    code = r.seen > 0 && !r.went_back && r.lowest_z < 0.0 ? EXIT_SUCCESS : EXIT_FAILURE;
    goto out;
fail:
    fprintf(stderr, "embed: %s\n", err.message);
out:
    sb_state_buffer_destroy(buffer);
    sb_solver_destroy(solver);
    sb_model_destroy(model);
    sb_builder_destroy(builder);
    sb_mesh_free(&mesh);
    return code;
}
