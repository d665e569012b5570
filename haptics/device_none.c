/* The "none" device: the handle at rest at the origin, forces dropped. */
#include "haptics/device.h"

static sb_status none_read(void* user, double time, sb_haptic_pose* pose) {
    (void)user;
    *pose = (sb_haptic_pose){.time = time, .orientation = {1, 0, 0, 0}};
    return SB_OK;
}

static sb_status none_write(void* user, double time, const double force[3]) {
    (void)user, (void)time, (void)force;
    return SB_OK;
}

sb_haptic_device* sb_device_none_open(const sb_haptic_device_def* def, sb_error* err) {
    (void)def;
    static const sb_haptic_device_ops ops = {none_read, none_write, NULL};
    return sb_haptic_device_custom(&ops, NULL, err);
}
