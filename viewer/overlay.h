/* The viewer's 2-D overlay: text in stb_easy_font's built-in bitmap font
 * (Debian's libstb-dev) and filled rectangles, in pixels from the top left,
 * collected for a frame and drawn over the scene in one call. */
#ifndef SB_VIEWER_OVERLAY_H
#define SB_VIEWER_OVERLAY_H

#include "viewer/shaders.h"

typedef struct sb_overlay {
    float* vertices; /* x y r g b a per corner, 3 corners a triangle */
    size_t count, capacity;
    GLuint vao, vbo;
} sb_overlay;

sb_status sb_overlay_create(sb_overlay* o, sb_error* err);
void sb_overlay_free(sb_overlay* o);
void sb_overlay_clear(sb_overlay* o);
void sb_overlay_rect(sb_overlay* o, float x, float y, float w, float h, const float rgba[4]);
/* Text (lines split at '\n') at scale times the font's 7-pixel height. */
void sb_overlay_text(sb_overlay* o, float x, float y, float scale, const char* text, const float rgba[4]);
/* The text's size in pixels at that scale. */
void sb_overlay_measure(const char* text, float scale, float* width, float* height);
/* Text word-wrapped to at most max_width pixels (a word longer than that
 * is cut), on a rectangle of `paper` 6 pixels wider on each side, from 3
 * pixels above the text to 3 (scaled) below its last glyphs; returns the
 * height it took, paper included. */
float sb_overlay_panel(sb_overlay* o, float x, float y, float max_width, float scale, const char* text,
                       const float ink[4], const float paper[4]);
void sb_overlay_draw(sb_overlay* o, const sb_shaders* s, int width, int height);

#endif
