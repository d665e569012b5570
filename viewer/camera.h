/* The viewer's camera: it orbits a target point at a distance, its up the
 * scene's up (against gravity); the mouse orbits, pans and zooms it. A
 * perspective projection of a fixed vertical field of view. */
#ifndef SB_VIEWER_CAMERA_H
#define SB_VIEWER_CAMERA_H

typedef struct sb_camera {
    double target[3];
    double distance;                  /* m */
    double yaw, pitch;                /* rad: about up, from the first horizontal axis; above the horizon */
    double up[3], axis1[3], axis2[3]; /* unit: up, and two horizontal axes (axis2 = up × axis1) */
    double fov;                       /* rad, vertical */
} sb_camera;

/* Looks at the box [lo, hi] extended by its size along −up (where a held
 * body hangs or a dropped one falls), from the side in front of axis2's
 * negative direction and a little above, all of it in view. */
sb_camera sb_camera_fit(const double lo[3], const double hi[3], const double up[3]);
void sb_camera_eye(const sb_camera* camera, double eye[3]);
/* Unit vector from the eye to the target. */
void sb_camera_forward(const sb_camera* camera, double forward[3]);
/* Column-major 4 × 4 projection × view for an aspect ratio width / height. */
void sb_camera_matrix(const sb_camera* camera, double aspect, float out[16]);
/* Pixel coordinates (x right, y down, from the top left) of a point in a
 * width × height view; false when it is behind the eye. */
bool sb_camera_project(const sb_camera* camera, const double p[3], int width, int height, double pixel[2]);
/* The ray through pixel (x, y): the eye and a unit direction. */
void sb_camera_ray(const sb_camera* camera, double x, double y, int width, int height, double origin[3],
                   double direction[3]);

/* Mouse motions, in pixels of a view height pixels tall. */
void sb_camera_orbit(sb_camera* camera, double dx, double dy);
void sb_camera_pan(sb_camera* camera, double dx, double dy, int height);
/* Scroll steps: positive comes closer. */
void sb_camera_zoom(sb_camera* camera, double steps);

#endif
