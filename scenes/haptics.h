/* A scene's haptic device and tool: the `haptics` map (device, file, port,
 * rate, tool, coupling.stiffness, coupling.damping, max_force, realtime).
 * With haptics.tool set, `softbond run` runs the servo thread beside the
 * simulation, paces the simulation to the wall clock (unless
 * haptics.realtime is false), and writes haptics.csv, a row per servo tick:
 * time,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,step. */
#ifndef SB_SCENE_HAPTICS_H
#define SB_SCENE_HAPTICS_H

#include "scenes/colliders.h"
#include "scenes/scene.h"

#include <stdio.h>

typedef struct sb_scene_haptics {
    bool enabled; /* haptics.tool names a collider */
    sb_haptic_device* device;
    sb_haptics* haptics;
    FILE* csv;
    bool paced;
    double rate;       /* Hz */
    double wall_start; /* s, monotonic, when the servo started */
    uint32_t faults;   /* the last faults said */
} sb_scene_haptics;

/* sb_scene_validate's check: the keys, each error naming where it was set. */
sb_status sb_scene_haptics_check(const sb_scene* scene, sb_error* err);
/* Opens the device and couples it to the tool (a collider of the scene,
 * kinematic: not a plane, not dynamic). Nothing when haptics.tool is ''. */
sb_status sb_scene_haptics_create(sb_scene_haptics* h, const sb_scene* scene, const sb_scene_colliders* colliders,
                                  sb_error* err);
/* Opens haptics.csv at path and starts the servo thread; says on stdout
 * whether it runs at real-time priority. */
sb_status sb_scene_haptics_start(sb_scene_haptics* h, const char* path, sb_error* err);
/* Before a step: waits for the wall clock to reach the simulated time (when
 * paced), then drives the tool to the proxy. */
void sb_scene_haptics_before_step(sb_scene_haptics* h, const sb_solver* solver);
/* After a step: the contact model to the servo, its ticks to haptics.csv,
 * and a line on stderr when the force starts ramping down and why. */
sb_status sb_scene_haptics_after_step(sb_scene_haptics* h, const sb_solver* solver, sb_error* err);
/* Stops the servo, writes its last ticks, closes haptics.csv and prints the
 * servo's measurements. */
sb_status sb_scene_haptics_finish(sb_scene_haptics* h, sb_error* err);
void sb_scene_haptics_free(sb_scene_haptics* h);

#endif
