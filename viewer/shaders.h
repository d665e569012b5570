/* The viewer's three GLSL 3.30 programs: lit surfaces (the bodies' faces,
 * optionally textured, and the colliders), coloured lines and points (the
 * edges and vertices), and flat 2-D shapes in pixels (the overlay). */
#ifndef SB_VIEWER_SHADERS_H
#define SB_VIEWER_SHADERS_H

#include "softbond/softbond.h"

#include <epoxy/gl.h>

/* Attribute locations shared by the programs. */
enum { SB_ATTR_POSITION = 0, SB_ATTR_NORMAL = 1, SB_ATTR_COLOR = 2, SB_ATTR_UV = 3 };

typedef struct sb_shaders {
    GLuint surface, lines, flat;
    /* uniforms */
    GLint surface_matrix, surface_light, surface_textured, surface_texture;
    GLint lines_matrix, lines_point_size;
    GLint flat_screen;
} sb_shaders;

sb_status sb_shaders_build(sb_shaders* shaders, sb_error* err);
void sb_shaders_free(sb_shaders* shaders);

#endif
