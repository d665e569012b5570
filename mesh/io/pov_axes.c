/* POV-Ray's axes from a scene's up direction (pov_axes.h). */
#include "mesh/io/pov_axes.h"

#include <math.h>

sb_pov_axes sb_pov_axes_for(const double up[3]) {
    int a = 2;
    for (int k = 0; k < 2; k++)
        if (fabs(up[k]) > fabs(up[a])) a = k;
    double s = up[a] < 0.0 ? -1.0 : 1.0;
    int b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2; /* the other two, in order */
    return (sb_pov_axes){{b, a, c}, {1.0, s, s}};
}

void sb_pov_point(const sb_pov_axes* axes, const double p[3], double out[3]) {
    for (int k = 0; k < 3; k++) out[k] = axes->sign[k] * p[axes->axis[k]];
}
