/* The buffers between threads under load: one writer and two readers of the
 * state buffer (at least 10^7 reads between the readers) and of the pose
 * buffer; every field of every snapshot and pose is written from its
 * sequence number, so a read that mixed two writes shows. Run under the
 * thread sanitizer too (make test, label thread). */
#include "test_util.h"

#include <pthread.h>
#include <stdatomic.h>

enum { VERTICES = 2, READERS = 2 };
#define READS_EACH 5000000L /* 10^7 between the two readers */

typedef struct stress {
    sb_state_buffer* snapshots;
    sb_pose_buffer* poses;
    atomic_bool done;
    long torn[READERS], reads[READERS], empty[READERS];
    uint64_t last_seen[READERS];
    bool went_back[READERS];
} stress;

/* Every field of write number s: exact in float for s below 2^20. */
static double field(uint64_t s, int i) { return (double)(s % 65536) * 4 + i; }

static void* snapshot_writer(void* context) {
    stress* st = context;
    for (uint64_t s = 1; !atomic_load(&st->done); s++) {
        sb_snapshot* snap = sb_state_buffer_begin(st->snapshots);
        if (!snap) continue;
        snap->step = s;
        snap->time = (double)s;
        for (int i = 0; i < 3 * VERTICES; i++) {
            snap->positions[i] = (sb_real)field(s, i % 4);
            snap->velocities[i] = (sb_real)-field(s, i % 4);
        }
        sb_state_buffer_commit(st->snapshots, snap);
        sb_haptic_pose pose = {.time = (double)s, .buttons = (uint32_t)s};
        for (int k = 0; k < 3; k++) pose.position[k] = field(s, k);
        for (int k = 0; k < 4; k++) pose.orientation[k] = -field(s, k);
        sb_pose_buffer_write(st->poses, &pose);
    }
    return NULL;
}

static bool snapshot_whole(const sb_snapshot* snap) {
    bool whole = snap->time == (double)snap->step;
    for (int i = 0; i < 3 * VERTICES; i++)
        whole = whole && snap->positions[i] == (sb_real)field(snap->step, i % 4) &&
                snap->velocities[i] == (sb_real)-field(snap->step, i % 4);
    return whole;
}

static bool pose_whole(const sb_haptic_pose* p) {
    uint64_t s = (uint64_t)p->time;
    bool whole = p->buttons == (uint32_t)s;
    for (int k = 0; k < 3; k++) whole = whole && p->position[k] == field(s, k);
    for (int k = 0; k < 4; k++) whole = whole && p->orientation[k] == -field(s, k);
    return whole;
}

typedef struct reader_arg {
    stress* st;
    int index;
} reader_arg;

static void* reader(void* context) {
    reader_arg* a = context;
    stress* st = a->st;
    for (long r = 0; r < READS_EACH; r++) {
        const sb_snapshot* snap = sb_state_buffer_acquire(st->snapshots);
        if (!snap) {
            st->empty[a->index]++;
            continue;
        }
        if (!snapshot_whole(snap)) st->torn[a->index]++;
        if (snap->step < st->last_seen[a->index]) st->went_back[a->index] = true;
        st->last_seen[a->index] = snap->step;
        sb_state_buffer_release(st->snapshots, snap);
        st->reads[a->index]++;
        if (r % 8 == 0) {
            sb_haptic_pose pose;
            if (sb_pose_buffer_read(st->poses, &pose) && !pose_whole(&pose)) st->torn[a->index]++;
        }
    }
    return NULL;
}

static void test_buffers_never_tear(void** state) {
    (void)state;
    sb_error err;
    stress st = {0};
    st.snapshots = sb_state_buffer_create(VERTICES, READERS, &err);
    st.poses = sb_pose_buffer_create(&err);
    assert_non_null(st.snapshots);
    assert_non_null(st.poses);
    atomic_init(&st.done, false);
    pthread_t writer, readers[READERS];
    reader_arg args[READERS];
    assert_int_equal(pthread_create(&writer, NULL, snapshot_writer, &st), 0);
    for (int i = 0; i < READERS; i++) {
        args[i] = (reader_arg){&st, i};
        assert_int_equal(pthread_create(&readers[i], NULL, reader, &args[i]), 0);
    }
    for (int i = 0; i < READERS; i++) pthread_join(readers[i], NULL);
    atomic_store(&st.done, true);
    pthread_join(writer, NULL);
    long reads = 0;
    for (int i = 0; i < READERS; i++) {
        assert_int_equal(st.torn[i], 0);
        assert_false(st.went_back[i]);
        reads += st.reads[i];
    }
    print_message("%ld whole reads, %ld before the first snapshot, %llu snapshots, %llu poses\n", reads,
                  st.empty[0] + st.empty[1], (unsigned long long)sb_state_buffer_published(st.snapshots),
                  (unsigned long long)sb_pose_buffer_writes(st.poses));
    assert_true(reads + st.empty[0] + st.empty[1] >= 10000000L);
    assert_true(sb_state_buffer_published(st.snapshots) > 1);
    sb_state_buffer_destroy(st.snapshots);
    sb_pose_buffer_destroy(st.poses);
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_buffers_never_tear)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
