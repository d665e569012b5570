/* The sweep answer shared by the built-in shapes (sweep.h). */
#include "kernels/contact/colliders/sweep.h"

#include <string.h>

static void sb_copy3(double out[3], const double v[3]) { memcpy(out, v, 3 * sizeof *out); }

bool sb_sweep_from_inside(const sb_sweep_end* from_end, const sb_sweep_end* to_end, const double from[3],
                          const double to[3], double* fraction, double* depth, double normal[3]) {
    const double* n = from_end->normal;
    double flip = to_end->normal[0] * n[0] + to_end->normal[1] * n[1] + to_end->normal[2] * n[2];
    if (to_end->inside && flip >= 0.0) { /* resting: keep the move, push `to` out */
        *fraction = 1.0;
        *depth = to_end->depth;
        sb_copy3(normal, to_end->normal);
        return true;
    }
    /* `to` outside, or inside but past the middle of the body (its way out
     * faces the other way: pushing it out there would pass it through) */
    double heading = (to[0] - from[0]) * n[0] + (to[1] - from[1]) * n[1] + (to[2] - from[2]) * n[2];
    if (!to_end->inside && heading >= 0.0) return false; /* leaving */
    *fraction = 0.0;
    *depth = from_end->depth;
    sb_copy3(normal, n);
    return true;
}

bool sb_sweep_from_outside(bool entered, double lo, double hi, const double lo_normal[3], const sb_sweep_end* to_end,
                           double* fraction, double* depth, double normal[3]) {
    if (!to_end->inside && !(entered && lo <= 1.0 && hi >= 0.0 && lo < hi)) return false;
    if (!entered) { /* `to` is inside but rounding lost the crossing: the end */
        *fraction = 1.0;
        sb_copy3(normal, to_end->normal);
    } else {
        *fraction = lo < 0.0 ? 0.0 : lo > 1.0 ? 1.0 : lo;
        sb_copy3(normal, lo_normal);
    }
    *depth = 0.0;
    return true;
}
