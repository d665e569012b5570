/* softbond_haptic_client: plays a trajectory to softbond's "udp" device, as
 * a program holding a real device would (docs/haptics.md).
 *
 *   softbond_haptic_client PORT TRAJECTORY.csv [RATE_HZ]
 *
 * The trajectory is the scripted device's CSV (time,x,y,z[,qw,qx,qy,qz]
 * [,button]), interpolated the same way (it is read by that device). It
 * sends a pose packet to 127.0.0.1:PORT at RATE_HZ (default 1000) until the
 * trajectory's last time, and prints each force packet it gets back as a
 * CSV row: time,fx,fy,fz (softbond's servo clock, N). A vendor's bridge
 * would do the same with the device's SDK in place of the file. */
#define _POSIX_C_SOURCE 200809L
#include "softbond/haptics.h"
#include "haptics/udp_protocol.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

static double last_time(const char* path) {
    FILE* f = fopen(path, "r");
    char line[1024];
    double t = 0;
    while (f && fgets(line, sizeof line, f)) t = atof(line) > t ? atof(line) : t;
    if (f) fclose(f);
    return t;
}

static void print_forces(int s) {
    unsigned char packet[64];
    ssize_t n;
    while ((n = recv(s, packet, sizeof packet, MSG_DONTWAIT)) > 0) {
        uint32_t sequence;
        double time, force[3];
        if (sb_udp_force_unpack(packet, (long)n, &sequence, &time, force))
            printf("%.6f,%.6g,%.6g,%.6g\n", time, force[0], force[1], force[2]);
    }
}

int main(int argc, char** argv) {
    if (argc < 3 || argc > 4) {
        fprintf(stderr, "usage: softbond_haptic_client PORT TRAJECTORY.csv [RATE_HZ]\n");
        return 2;
    }
    int port = atoi(argv[1]);
    double rate = argc == 4 ? atof(argv[3]) : 1000;
    sb_haptic_device_def def = sb_default_haptic_device_def();
    def.kind = "scripted";
    def.file = argv[2];
    sb_error err;
    sb_haptic_device* script = sb_haptic_device_open(&def, &err);
    if (!script || port < 1 || port > 65535 || !(rate > 0)) {
        fprintf(stderr, "softbond_haptic_client: %s\n", script ? "bad PORT or RATE_HZ" : err.message);
        sb_haptic_device_close(script);
        return 2;
    }
    int s = socket(AF_INET, SOCK_DGRAM, 0);
    struct sockaddr_in to = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    printf("time,fx,fy,fz\n");
    double end = last_time(argv[2]);
    struct timespec deadline;
    clock_gettime(CLOCK_MONOTONIC, &deadline);
    for (uint32_t i = 0; (double)i / rate <= end; i++) {
        sb_haptic_pose pose;
        sb_haptic_device_read(script, (double)i / rate, &pose);
        sb_udp_pose p = {.sequence = i, .time = pose.time, .buttons = pose.buttons};
        for (int k = 0; k < 3; k++) p.position[k] = pose.position[k];
        for (int k = 0; k < 4; k++) p.orientation[k] = pose.orientation[k];
        unsigned char packet[SB_UDP_POSE_SIZE];
        sb_udp_pose_pack(&p, packet);
        if (sendto(s, packet, sizeof packet, 0, (struct sockaddr*)&to, sizeof to) < 0 && errno != ECONNREFUSED)
            perror("softbond_haptic_client: sendto");
        print_forces(s);
        long ns = deadline.tv_nsec + (long)(1e9 / rate);
        deadline.tv_sec += ns / 1000000000L;
        deadline.tv_nsec = ns % 1000000000L;
        clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, NULL);
    }
    print_forces(s);
    close(s);
    sb_haptic_device_close(script);
    return 0;
}
