/* The built-in devices, one file each (haptics/device_*.c); haptics/device.c
 * finds them by name. A vendor's device is one more file with an open
 * function of this type and one line in device.c's table, behind a CMake
 * option (README, "Haptics"). */
#ifndef SB_HAPTICS_DEVICE_H
#define SB_HAPTICS_DEVICE_H

#include "softbond/haptics.h"

typedef sb_haptic_device* (*sb_device_open_fn)(const sb_haptic_device_def* def, sb_error* err);

sb_haptic_device* sb_device_none_open(const sb_haptic_device_def* def, sb_error* err);
sb_haptic_device* sb_device_scripted_open(const sb_haptic_device_def* def, sb_error* err);
sb_haptic_device* sb_device_udp_open(const sb_haptic_device_def* def, sb_error* err);

#endif
