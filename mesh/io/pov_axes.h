/* Private: POV-Ray's axes (y up, left-handed) from a scene's up direction,
 * shared by the POV-Ray frame writer and the film maker. */
#ifndef SB_POV_AXES_H
#define SB_POV_AXES_H

/* POV-Ray's coordinate k is sign[k] times the scene's coordinate axis[k]. */
typedef struct sb_pov_axes {
    int axis[3];
    double sign[3];
} sb_pov_axes;

/* The scene's axis nearest `up` becomes POV-Ray's y, the other two x and z
 * in order, signs keeping the picture unmirrored. */
sb_pov_axes sb_pov_axes_for(const double up[3]);
/* p in POV-Ray's coordinates. */
void sb_pov_point(const sb_pov_axes* axes, const double p[3], double out[3]);

#endif
