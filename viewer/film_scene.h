/* The film maker's drawing: each frame of `softbond film` as a POV-Ray
 * scene of the whole simulation, the bodies and every collider (planes,
 * spheres, capsules, boxes, meshes) at its pose of that moment (dynamic
 * and kinematic ones move), and one setting for the whole film (camera,
 * lights, sky, a checker floor) written once the run's bounds are known.
 *
 * A frame is `#include "film_setting.inc"` and its objects; povray finds
 * the setting through +L<the film's folder>. POV-Ray's up is +y: the
 * scene's up (against gravity) becomes +y by permuting the axes as the mesh
 * export does (mesh/io/pov_writer.c). Bodies are orange, colliders teal, a
 * plane collider is the checker floor (and without one a floor is laid
 * under the run's lowest point). */
#ifndef SB_VIEWER_FILM_SCENE_H
#define SB_VIEWER_FILM_SCENE_H

#include "scenes/simulation.h"

#define SB_FILM_SETTING "film_setting.inc"

typedef struct sb_film_scene {
    const sb_simulation* sim;
    double up[3];
    double (*rest_center)[3]; /* each collider's reported centre before the first step */
    uint32_t count;
    bool has_floor; /* a plane collider facing up */
} sb_film_scene;

/* Call before the first step: the colliders' rest centres. */
sb_status sb_film_scene_create(sb_film_scene* f, const sb_simulation* sim, sb_error* err);
void sb_film_scene_free(sb_film_scene* f);

/* Grows [lo, hi] (scene coordinates) by the bodies' n points and the
 * colliders but planes, at their poses now. */
void sb_film_scene_bounds(const sb_film_scene* f, const double* positions, uint32_t n, double lo[3], double hi[3]);

/* The frame now: the mesh at positions (3 a vertex) and the colliders at
 * their poses now, written atomically to path. */
sb_status sb_film_scene_write_frame(const sb_film_scene* f, const char* path, const sb_mesh* mesh,
                                    const double* positions, sb_error* err);

/* The setting (SB_FILM_SETTING) for an image of aspect width / height: the
 * camera at eye looking at target with the vertical field of view fov
 * (rad), lights, sky, and a floor under lo when the scene has none. */
sb_status sb_film_scene_write_setting(const sb_film_scene* f, const char* path, const double eye[3],
                                      const double target[3], double fov, double aspect, const double lo[3],
                                      const double hi[3], sb_error* err);

#endif
