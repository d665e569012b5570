/* The "udp" device: poses arrive and forces leave as datagrams on
 * 127.0.0.1 (haptics/udp_protocol.h has the packets). A read takes every
 * datagram waiting, without blocking, and keeps the newest pose; a write
 * answers the address the last pose came from. Before the first pose the
 * handle is at rest at the origin and forces go nowhere; a pose older than
 * SB_UDP_TIMEOUT on the servo's clock is a device error (the sender is
 * gone), which ramps the force down. The socket is opened at open; the
 * servo's loop makes only recvfrom and sendto calls, the device's I/O. */
#include "haptics/device.h"
#include "haptics/udp_protocol.h"
#include "common/error.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <netinet/in.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <unistd.h>

#define SB_UDP_TIMEOUT 0.25 /* s */

typedef struct udp_device {
    int socket;
    struct sockaddr_in sender;
    bool heard;
    double heard_at; /* s, servo clock */
    sb_udp_pose last;
} udp_device;

static bool udp_pose_finite(const sb_udp_pose* p) {
    bool ok = isfinite(p->time);
    for (int k = 0; k < 3; k++) ok = ok && isfinite(p->position[k]);
    for (int k = 0; k < 4; k++) ok = ok && isfinite(p->orientation[k]);
    return ok;
}

static sb_status udp_read(void* user, double time, sb_haptic_pose* pose) {
    udp_device* u = user;
    unsigned char packet[128];
    for (;;) {
        struct sockaddr_in from;
        socklen_t length = sizeof from;
        ssize_t n = recvfrom(u->socket, packet, sizeof packet, MSG_DONTWAIT, (struct sockaddr*)&from, &length);
        if (n < 0) break;
        sb_udp_pose p;
        if (!sb_udp_pose_unpack(packet, (long)n, &p)) continue;
        u->last = p;
        u->sender = from;
        u->heard = true;
        u->heard_at = time;
    }
    *pose = (sb_haptic_pose){.time = time, .orientation = {1, 0, 0, 0}};
    if (!u->heard) return SB_OK;
    for (int k = 0; k < 3; k++) pose->position[k] = u->last.position[k];
    for (int k = 0; k < 4; k++) pose->orientation[k] = u->last.orientation[k];
    pose->buttons = u->last.buttons;
    if (!udp_pose_finite(&u->last)) return SB_ERR_INVALID;
    return time - u->heard_at > SB_UDP_TIMEOUT ? SB_ERR_IO : SB_OK;
}

static sb_status udp_write(void* user, double time, const double force[3]) {
    udp_device* u = user;
    if (!u->heard) return SB_OK;
    unsigned char packet[SB_UDP_FORCE_SIZE];
    sb_udp_force_pack(u->last.sequence, time, force, packet);
    ssize_t n = sendto(u->socket, packet, sizeof packet, MSG_DONTWAIT, (struct sockaddr*)&u->sender, sizeof u->sender);
    return n == (ssize_t)sizeof packet || errno == EAGAIN ? SB_OK : SB_ERR_IO;
}

static void udp_close(void* user) {
    udp_device* u = user;
    close(u->socket);
    free(u);
}

sb_haptic_device* sb_device_udp_open(const sb_haptic_device_def* def, sb_error* err) {
    if (def->port < 1 || def->port > 65535) {
        sb_error_set(err, SB_ERR_INVALID, "udp device: port must be from 1 to 65535 (got %d)", def->port);
        return NULL;
    }
    udp_device* u = calloc(1, sizeof *u);
    if (!u) {
        sb_error_set(err, SB_ERR_NOMEM, "udp device: out of memory");
        return NULL;
    }
    u->socket = socket(AF_INET, SOCK_DGRAM, 0);
    struct sockaddr_in address = {.sin_family = AF_INET, .sin_port = htons((uint16_t)def->port)};
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (u->socket < 0 || bind(u->socket, (struct sockaddr*)&address, sizeof address) != 0) {
        sb_error_set(err, SB_ERR_IO, "udp device: cannot listen on 127.0.0.1:%d: %s", def->port, strerror(errno));
        if (u->socket >= 0) close(u->socket);
        free(u);
        return NULL;
    }
    static const sb_haptic_device_ops ops = {udp_read, udp_write, udp_close};
    sb_haptic_device* d = sb_haptic_device_custom(&ops, u, err);
    if (!d) udp_close(u);
    return d;
}
