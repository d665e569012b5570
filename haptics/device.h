/* The built-in devices, one file each (haptics/device_*.c); haptics/device.c
 * finds them by name. A vendor's device is one more file with an open
 * function of this type and one line in device.c's table, behind a CMake
 * option (docs/haptics.md). */
#ifndef SB_HAPTICS_DEVICE_H
#define SB_HAPTICS_DEVICE_H

#include "softbond/haptics.h"

typedef sb_haptic_device* (*sb_device_open_fn)(const sb_haptic_device_def* def, sb_error* err);

sb_haptic_device* sb_device_none_open(const sb_haptic_device_def* def, sb_error* err);
sb_haptic_device* sb_device_scripted_open(const sb_haptic_device_def* def, sb_error* err);
sb_haptic_device* sb_device_udp_open(const sb_haptic_device_def* def, sb_error* err);
sb_haptic_device* sb_device_mouse_open(const sb_haptic_device_def* def, sb_error* err);

/* The device's user data when its read call is `read` (it is of that kind), else NULL. */
void* sb_haptic_device_user_if(const sb_haptic_device* device,
                               sb_status (*read)(void* user, double time, sb_haptic_pose* pose));

#endif
