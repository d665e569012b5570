/* The viewer's camera (viewer/camera.h), worked in double: a look-at view
 * and a perspective projection, the same matrices for drawing and for
 * turning the cursor into rays. */
#include <stdbool.h>

#include "viewer/camera.h"

#include <math.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

static double dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross(const double a[3], const double b[3], double out[3]) {
    double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(out, c, sizeof c);
}
static void normalize(double v[3]) {
    double n = sqrt(dot(v, v));
    for (int k = 0; k < 3; k++) v[k] = n > 0 ? v[k] / n : 0.0;
}

/* Two horizontal axes: the world axis least along up, made perpendicular to it. */
static void horizontal_axes(sb_camera* c) {
    int least = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(c->up[k]) < fabs(c->up[least])) least = k;
    double axis[3] = {0, 0, 0};
    axis[least] = 1.0;
    double along = dot(axis, c->up);
    for (int k = 0; k < 3; k++) c->axis1[k] = axis[k] - along * c->up[k];
    normalize(c->axis1);
    cross(c->up, c->axis1, c->axis2);
}

sb_camera sb_camera_fit(const double lo[3], const double hi[3], const double up[3]) {
    sb_camera c = {.fov = 40.0 * PI / 180.0, .yaw = -PI / 2, .pitch = 25.0 * PI / 180.0};
    memcpy(c.up, up, sizeof c.up);
    normalize(c.up);
    horizontal_axes(&c);
    double size = 0.0, half[3];
    for (int k = 0; k < 3; k++) size = fmax(size, hi[k] - lo[k]);
    for (int k = 0; k < 3; k++) {
        c.target[k] = 0.5 * (lo[k] + hi[k]) - 0.5 * size * c.up[k];
        half[k] = 0.5 * (hi[k] - lo[k]) + 0.5 * size * fabs(c.up[k]);
    }
    double radius = fmax(sqrt(dot(half, half)), 1e-3);
    c.distance = 1.15 * radius / sin(0.5 * c.fov);
    return c;
}

void sb_camera_eye(const sb_camera* c, double eye[3]) {
    for (int k = 0; k < 3; k++)
        eye[k] = c->target[k] + c->distance * (cos(c->pitch) * (cos(c->yaw) * c->axis1[k] + sin(c->yaw) * c->axis2[k]) +
                                               sin(c->pitch) * c->up[k]);
}

void sb_camera_forward(const sb_camera* c, double forward[3]) {
    double eye[3];
    sb_camera_eye(c, eye);
    for (int k = 0; k < 3; k++) forward[k] = c->target[k] - eye[k];
    normalize(forward);
}

/* The view's right and true up (unit), from the forward direction. */
static void view_basis(const sb_camera* c, const double forward[3], double right[3], double up[3]) {
    cross(forward, c->up, right);
    normalize(right);
    cross(right, forward, up);
}

static void clip_range(const sb_camera* c, double* near, double* far) {
    *near = 0.01 * c->distance;
    *far = 100.0 * c->distance;
}

/* Projection × view, row-major doubles: the view looks along −z_view =
 * f·(x − eye); z_clip = a z_view + b, w_clip = −z_view. */
static void matrix(const sb_camera* c, double aspect, double m[4][4]) {
    double eye[3], f[3], r[3], u[3], near, far;
    sb_camera_eye(c, eye);
    sb_camera_forward(c, f);
    view_basis(c, f, r, u);
    clip_range(c, &near, &far);
    double fy = 1.0 / tan(0.5 * c->fov), fx = fy / aspect;
    double a = (far + near) / (near - far), b = 2.0 * far * near / (near - far);
    double rows[4][4] = {{fx * r[0], fx * r[1], fx * r[2], -fx * dot(r, eye)},
                         {fy * u[0], fy * u[1], fy * u[2], -fy * dot(u, eye)},
                         {-a * f[0], -a * f[1], -a * f[2], a * dot(f, eye) + b},
                         {f[0], f[1], f[2], -dot(f, eye)}};
    memcpy(m, rows, sizeof rows);
}

void sb_camera_matrix(const sb_camera* c, double aspect, float out[16]) {
    double m[4][4];
    matrix(c, aspect, m);
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) out[4 * col + row] = (float)m[row][col];
}

bool sb_camera_project(const sb_camera* c, const double p[3], int width, int height, double pixel[2]) {
    double m[4][4], clip[4];
    matrix(c, (double)width / height, m);
    for (int row = 0; row < 4; row++) clip[row] = m[row][0] * p[0] + m[row][1] * p[1] + m[row][2] * p[2] + m[row][3];
    if (clip[3] <= 0.0) return false;
    pixel[0] = (0.5 + 0.5 * clip[0] / clip[3]) * width;
    pixel[1] = (0.5 - 0.5 * clip[1] / clip[3]) * height;
    return true;
}

void sb_camera_ray(const sb_camera* c, double x, double y, int width, int height, double origin[3],
                   double direction[3]) {
    double f[3], r[3], u[3];
    sb_camera_eye(c, origin);
    sb_camera_forward(c, f);
    view_basis(c, f, r, u);
    double t = tan(0.5 * c->fov), aspect = (double)width / height;
    double sx = (2.0 * x / width - 1.0) * t * aspect, sy = (1.0 - 2.0 * y / height) * t;
    for (int k = 0; k < 3; k++) direction[k] = f[k] + sx * r[k] + sy * u[k];
    normalize(direction);
}

void sb_camera_orbit(sb_camera* c, double dx, double dy) {
    const double per_pixel = 0.01, limit = 0.49 * PI;
    c->yaw -= per_pixel * dx;
    c->pitch = fmax(-limit, fmin(limit, c->pitch + per_pixel * dy));
}

void sb_camera_pan(sb_camera* c, double dx, double dy, int height) {
    double f[3], r[3], u[3];
    sb_camera_forward(c, f);
    view_basis(c, f, r, u);
    double per_pixel = 2.0 * c->distance * tan(0.5 * c->fov) / height;
    for (int k = 0; k < 3; k++) c->target[k] += per_pixel * (-dx * r[k] + dy * u[k]);
}

void sb_camera_zoom(sb_camera* c, double steps) { c->distance *= pow(0.9, steps); }
