/* The "mouse" device: the pose the program last gave it (the viewer maps
 * its cursor into the tool's frame, viewer/view.c), through a pose buffer,
 * so the program's thread never waits for the servo nor the servo for it.
 * Before the first move the handle is at rest at the origin. Forces are
 * dropped: a mouse cannot push back. */
#include "haptics/device.h"

static sb_status mouse_read(void* user, double time, sb_haptic_pose* pose) {
    if (!sb_pose_buffer_read(user, pose)) *pose = (sb_haptic_pose){.orientation = {1, 0, 0, 0}};
    pose->time = time;
    return SB_OK;
}

static sb_status mouse_write(void* user, double time, const double force[3]) {
    (void)user, (void)time, (void)force;
    return SB_OK;
}

static void mouse_close(void* user) { sb_pose_buffer_destroy(user); }

sb_haptic_device* sb_device_mouse_open(const sb_haptic_device_def* def, sb_error* err) {
    (void)def;
    static const sb_haptic_device_ops ops = {mouse_read, mouse_write, mouse_close};
    sb_pose_buffer* poses = sb_pose_buffer_create(err);
    sb_haptic_device* device = poses ? sb_haptic_device_custom(&ops, poses, err) : NULL;
    if (!device) sb_pose_buffer_destroy(poses);
    return device;
}

void sb_haptic_device_move(sb_haptic_device* device, const sb_haptic_pose* pose) {
    sb_pose_buffer* poses = sb_haptic_device_user_if(device, mouse_read);
    if (poses) sb_pose_buffer_write(poses, pose);
}
