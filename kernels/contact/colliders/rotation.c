/* A rotation from three angles in degrees (rotation.h). */
#include "kernels/contact/colliders/rotation.h"

#include <math.h>

/* sin and cos of an angle in degrees, exact at multiples of 90. */
static void sb_sincos_degrees(double degrees, double* s, double* c) {
    double r = fmod(degrees, 360.0);
    if (r < 0.0) r += 360.0;
    if (r == 0.0 || r == 90.0 || r == 180.0 || r == 270.0) {
        static const double sines[4] = {0.0, 1.0, 0.0, -1.0}, cosines[4] = {1.0, 0.0, -1.0, 0.0};
        int q = (int)(r / 90.0);
        *s = sines[q];
        *c = cosines[q];
        return;
    }
    double radians = r * (3.14159265358979323846 / 180.0);
    *s = sin(radians);
    *c = cos(radians);
}

static void sb_mat3_mul(const double a[9], const double b[9], double out[9]) {
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            out[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
}

void sb_collider_rotation(const double degrees[3], double r[9]) {
    double sx, cx, sy, cy, sz, cz;
    sb_sincos_degrees(degrees[0], &sx, &cx);
    sb_sincos_degrees(degrees[1], &sy, &cy);
    sb_sincos_degrees(degrees[2], &sz, &cz);
    const double rx[9] = {1, 0, 0, 0, cx, -sx, 0, sx, cx};
    const double ry[9] = {cy, 0, sy, 0, 1, 0, -sy, 0, cy};
    const double rz[9] = {cz, -sz, 0, sz, cz, 0, 0, 0, 1};
    double zy[9];
    sb_mat3_mul(rz, ry, zy);
    sb_mat3_mul(zy, rx, r);
}
