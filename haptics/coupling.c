/* The virtual coupling (haptics/coupling.h; softbond/haptics.h has the
 * model). Why a quasi-static proxy: the tool is kinematic, so the proxy has
 * no mass of its own to integrate; it is put where the forces on it balance,
 * with the tissue linearized about the last step (its push and the local
 * stiffness the simulation thread measured between its last two steps).
 * Solving the balance, not stepping towards it, keeps the proxy stable for
 * any tissue stiffness, and the force the hand feels is then
 * K (proxy − device) = (tissue push) − K k / (K + k) (further depth): the
 * tissue's static answer in series with the coupling spring. */
#include "haptics/coupling.h"

#include <math.h>

void sb_coupling_proxy(const sb_contact_model* model, double K, const double device[3], double proxy[3]) {
    const double* n = model->normal;
    double s0 = 0;
    for (int k = 0; k < 3; k++) s0 += n[k] * (device[k] - model->proxy[k]);
    double s = (K * s0 + model->force) / (K + model->stiffness);
    bool touching = model->force > 0 && model->force - model->stiffness * s > 0;
    for (int k = 0; k < 3; k++) proxy[k] = device[k] + (touching ? (s - s0) * n[k] : 0);
}

void sb_coupling_force(double K, double b, double T, const double device[3], const double device_before[3],
                       const double proxy[3], const double proxy_before[3], double max_force, double force[3]) {
    double length2 = 0;
    for (int k = 0; k < 3; k++) {
        double relative_velocity = ((proxy[k] - proxy_before[k]) - (device[k] - device_before[k])) / T;
        force[k] = K * (proxy[k] - device[k]) + b * relative_velocity;
        length2 += force[k] * force[k];
    }
    if (length2 > max_force * max_force) {
        double scale = max_force / sqrt(length2);
        for (int k = 0; k < 3; k++) force[k] *= scale;
    }
}

void sb_quaternion_to_degrees(const double q[4], double degrees[3]) {
    double w = q[0], x = q[1], y = q[2], z = q[3];
    double r00 = 1 - 2 * (y * y + z * z), r10 = 2 * (x * y + w * z), r20 = 2 * (x * z - w * y);
    double r21 = 2 * (y * z + w * x), r22 = 1 - 2 * (x * x + y * y);
    const double to_degrees = 180 / 3.14159265358979323846;
    degrees[0] = atan2(r21, r22) * to_degrees;
    degrees[1] = asin(fmax(-1, fmin(1, -r20))) * to_degrees;
    degrees[2] = atan2(r10, r00) * to_degrees;
}
