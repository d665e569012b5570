/* Devices (softbond/haptics.h): the four calls, and the built-in kinds by
 * name. Every device, built-in or a program's own, is a table of calls and
 * its data. */
#include "haptics/device.h"
#include "common/error.h"

#include <stdlib.h>
#include <string.h>

struct sb_haptic_device {
    sb_haptic_device_ops ops;
    void* user;
};

static const struct {
    const char* kind;
    sb_device_open_fn open;
} sb_device_kinds[] = {
    {"none", sb_device_none_open},
    {"scripted", sb_device_scripted_open},
    {"udp", sb_device_udp_open},
    {"mouse", sb_device_mouse_open},
};

sb_haptic_device_def sb_default_haptic_device_def(void) {
    return (sb_haptic_device_def){.kind = "none", .port = 47000};
}

bool sb_haptic_device_kind_known(const char* kind) {
    for (size_t i = 0; i < sizeof sb_device_kinds / sizeof sb_device_kinds[0]; i++)
        if (kind && strcmp(kind, sb_device_kinds[i].kind) == 0) return true;
    return false;
}

sb_haptic_device* sb_haptic_device_open(const sb_haptic_device_def* def, sb_error* err) {
    for (size_t i = 0; i < sizeof sb_device_kinds / sizeof sb_device_kinds[0]; i++)
        if (def->kind && strcmp(def->kind, sb_device_kinds[i].kind) == 0) return sb_device_kinds[i].open(def, err);
    sb_error_set(err, SB_ERR_INVALID, "haptic device: unknown kind '%s' (none, scripted, udp, mouse)",
                 def->kind ? def->kind : "(null)");
    return NULL;
}

sb_haptic_device* sb_haptic_device_custom(const sb_haptic_device_ops* ops, void* user, sb_error* err) {
    if (!ops || !ops->read || !ops->write) {
        sb_error_set(err, SB_ERR_INVALID, "haptic device: read and write are required");
        return NULL;
    }
    sb_haptic_device* d = malloc(sizeof *d);
    if (!d) {
        sb_error_set(err, SB_ERR_NOMEM, "haptic device: out of memory");
        return NULL;
    }
    d->ops = *ops;
    d->user = user;
    return d;
}

sb_status sb_haptic_device_read(sb_haptic_device* device, double time, sb_haptic_pose* pose) {
    return device->ops.read(device->user, time, pose);
}

sb_status sb_haptic_device_write(sb_haptic_device* device, double time, const double force[3]) {
    return device->ops.write(device->user, time, force);
}

void* sb_haptic_device_user_if(const sb_haptic_device* device,
                               sb_status (*read)(void* user, double time, sb_haptic_pose* pose)) {
    return device && device->ops.read == read ? device->user : NULL;
}

void sb_haptic_device_close(sb_haptic_device* device) {
    if (!device) return;
    if (device->ops.close) device->ops.close(device->user);
    free(device);
}
