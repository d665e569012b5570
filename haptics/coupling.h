/* The virtual coupling's arithmetic (haptics/coupling.c): the proxy from the
 * local contact model, the spring-damper's force, its clamp. Pure
 * functions, shared by the servo tick and the simulation thread. */
#ifndef SB_HAPTICS_COUPLING_H
#define SB_HAPTICS_COUPLING_H

#include "common/geometry.h"

#include <stdbool.h>
#include <stdint.h>

/* What the simulation's last step found at the tool (simulation -> servo). */
typedef struct sb_contact_model {
    uint64_t step;
    double time;      /* s, the servo's clock when it was sensed */
    double proxy[3];  /* m, world: where the tool was */
    double normal[3]; /* unit: the way the tissue pushed it */
    double force;     /* N, >= 0: how hard */
    double stiffness; /* N/m, >= 0: how much harder per m further in */
} sb_contact_model;

/* Where the proxy balances the coupling spring (stiffness K, pulling it to
 * the device) against the tissue's push max(0, force − stiffness s) along
 * the normal (s: its displacement along the normal from the model's proxy).
 * Along the surface it follows the device; out of contact it is the device. */
void sb_coupling_proxy(const sb_contact_model* model, double K, const double device[3], double proxy[3]);

/* K (proxy − device) + b (v_proxy − v_device), velocities over the last
 * period T from the previous positions, its length clamped to max_force. */
void sb_coupling_force(double K, double b, double T, const double device[3], const double device_before[3],
                       const double proxy[3], const double proxy_before[3], double max_force, double force[3]);

/* The rotation (degrees about x, then y, then z) of a unit quaternion w x y z. */
void sb_quaternion_to_degrees(const double q[4], double degrees[3]);

#endif
