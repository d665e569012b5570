/* The UDP device's packets (docs/haptics.md), shared by the device and
 * the test client. Little-endian, packed, no padding:
 *   pose  (to softbond, 76 bytes): "SBP1", u32 sequence, f64 time (s),
 *         f64 x y z (m), f64 qw qx qy qz, u32 buttons;
 *   force (from softbond to the sender of the last pose, 40 bytes): "SBF1",
 *         u32 the sequence of the last pose, f64 time (s, softbond's servo
 *         clock), f64 fx fy fz (N). */
#ifndef SB_HAPTICS_UDP_PROTOCOL_H
#define SB_HAPTICS_UDP_PROTOCOL_H

#include <stdint.h>
#include <string.h>

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the UDP haptic protocol is written for little-endian hosts"
#endif

enum { SB_UDP_POSE_SIZE = 76, SB_UDP_FORCE_SIZE = 40 };

typedef struct sb_udp_pose {
    uint32_t sequence;
    double time, position[3], orientation[4];
    uint32_t buttons;
} sb_udp_pose;

static inline void sb_udp_pose_pack(const sb_udp_pose* p, unsigned char out[SB_UDP_POSE_SIZE]) {
    memcpy(out, "SBP1", 4);
    memcpy(out + 4, &p->sequence, 4);
    memcpy(out + 8, &p->time, 8);
    memcpy(out + 16, p->position, 24);
    memcpy(out + 40, p->orientation, 32);
    memcpy(out + 72, &p->buttons, 4);
}

/* 0 when the packet is not a pose. */
static inline int sb_udp_pose_unpack(const unsigned char* in, long size, sb_udp_pose* p) {
    if (size != SB_UDP_POSE_SIZE || memcmp(in, "SBP1", 4) != 0) return 0;
    memcpy(&p->sequence, in + 4, 4);
    memcpy(&p->time, in + 8, 8);
    memcpy(p->position, in + 16, 24);
    memcpy(p->orientation, in + 40, 32);
    memcpy(&p->buttons, in + 72, 4);
    return 1;
}

static inline void sb_udp_force_pack(uint32_t sequence, double time, const double force[3],
                                     unsigned char out[SB_UDP_FORCE_SIZE]) {
    memcpy(out, "SBF1", 4);
    memcpy(out + 4, &sequence, 4);
    memcpy(out + 8, &time, 8);
    memcpy(out + 16, force, 24);
}

static inline int sb_udp_force_unpack(const unsigned char* in, long size, uint32_t* sequence, double* time,
                                      double force[3]) {
    if (size != SB_UDP_FORCE_SIZE || memcmp(in, "SBF1", 4) != 0) return 0;
    memcpy(sequence, in + 4, 4);
    memcpy(time, in + 8, 8);
    memcpy(force, in + 16, 24);
    return 1;
}

#endif
