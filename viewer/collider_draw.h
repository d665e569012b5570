/* Drawing the scene's colliders: each shape as triangles in the world at
 * rest (a plane as a square around the bodies, a sphere and a capsule from
 * an icosphere, a box, a mesh as loaded and placed), moved each frame by
 * the pose the simulation thread reported: p = R (p_rest − c_rest) + c. */
#ifndef SB_VIEWER_COLLIDER_DRAW_H
#define SB_VIEWER_COLLIDER_DRAW_H

#include "scenes/colliders.h"
#include "viewer/shaders.h"

typedef struct sb_collider_shape_draw {
    float* rest;    /* 9 floats a triangle: its corners at rest */
    float* normals; /* 3 a triangle, at rest */
    uint32_t triangle_count;
    double center[3]; /* the reported center at rest */
} sb_collider_shape_draw;

typedef struct sb_collider_draw {
    uint32_t count;
    sb_collider_shape_draw* shapes;
    float* vertices; /* the frame's (x y z nx ny nz) per corner, all shapes */
    uint32_t corner_count;
    GLuint vao, vbo;
} sb_collider_draw;

/* The shapes of `colliders` at rest (before the first step); extent (m)
 * sizes the plane's square. */
sb_status sb_collider_draw_create(sb_collider_draw* d, const sb_scene_colliders* colliders, double extent,
                                  const double center[3], sb_error* err);
void sb_collider_draw_free(sb_collider_draw* d);
/* poses: per collider a row-major rotation then a center (12 doubles). */
void sb_collider_draw_render(sb_collider_draw* d, const sb_shaders* s, const float matrix[16], const float light[3],
                             const double (*poses)[12], uint32_t pose_count);

#endif
