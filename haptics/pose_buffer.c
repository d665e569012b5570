/* The pose buffer (softbond/haptics.h): the device pose from the servo
 * thread to the simulation, in a record (haptics/record.c). */
#include "softbond/haptics.h"
#include "common/error.h"
#include "haptics/record.h"

#include <stdlib.h>

_Static_assert(sizeof(sb_haptic_pose) <= SB_RECORD_WORDS * 8, "a pose fits a record");

struct sb_pose_buffer {
    sb_record record;
};

sb_pose_buffer* sb_pose_buffer_create(sb_error* err) {
    sb_pose_buffer* b = malloc(sizeof *b);
    if (!b) {
        sb_error_set(err, SB_ERR_NOMEM, "pose buffer: out of memory");
        return NULL;
    }
    sb_record_init(&b->record);
    return b;
}

void sb_pose_buffer_destroy(sb_pose_buffer* buffer) { free(buffer); }

void sb_pose_buffer_write(sb_pose_buffer* buffer, const sb_haptic_pose* pose) {
    sb_record_write(&buffer->record, pose, sizeof *pose);
}

bool sb_pose_buffer_read(sb_pose_buffer* buffer, sb_haptic_pose* pose) {
    return sb_record_read(&buffer->record, pose, sizeof *pose);
}

uint64_t sb_pose_buffer_writes(const sb_pose_buffer* buffer) { return sb_record_writes(&buffer->record); }
