/* The viewer's 2-D overlay (viewer/overlay.h). stb_easy_font builds each
 * glyph from quads; they are split into triangles for the core profile. */
#include "viewer/overlay.h"
#include "common/error.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

enum { GLYPH_BUFFER = 64 * 1024, FLOATS = 6, LINE_HEIGHT = 12 /* stb_easy_font's, pixels */ };

sb_status sb_overlay_create(sb_overlay* o, sb_error* err) {
    *o = (sb_overlay){.capacity = 1 << 16};
    if (!(o->vertices = malloc(o->capacity * FLOATS * sizeof *o->vertices)))
        return sb_error_set(err, SB_ERR_NOMEM, "view: out of memory");
    glGenVertexArrays(1, &o->vao);
    glBindVertexArray(o->vao);
    glGenBuffers(1, &o->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, o->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(o->capacity * FLOATS * sizeof(float)), NULL, GL_STREAM_DRAW);
    glEnableVertexAttribArray(SB_ATTR_POSITION);
    glVertexAttribPointer(SB_ATTR_POSITION, 2, GL_FLOAT, GL_FALSE, FLOATS * sizeof(float), 0);
    glEnableVertexAttribArray(SB_ATTR_COLOR);
    glVertexAttribPointer(SB_ATTR_COLOR, 4, GL_FLOAT, GL_FALSE, FLOATS * sizeof(float),
                          (const void*)(2 * sizeof(float)));
    glBindVertexArray(0);
    return SB_OK;
}

void sb_overlay_free(sb_overlay* o) {
    if (o->vao) {
        glDeleteBuffers(1, &o->vbo);
        glDeleteVertexArrays(1, &o->vao);
    }
    free(o->vertices);
    *o = (sb_overlay){0};
}

void sb_overlay_clear(sb_overlay* o) { o->count = 0; }

static void corner(sb_overlay* o, float x, float y, const float rgba[4]) {
    if (o->count >= o->capacity) return;
    float* v = o->vertices + FLOATS * o->count++;
    v[0] = x, v[1] = y;
    memcpy(v + 2, rgba, 4 * sizeof *v);
}

/* The quad (x0, y0)–(x1, y1) as two triangles. */
static void quad(sb_overlay* o, float x0, float y0, float x1, float y1, const float rgba[4]) {
    if (o->count + 6 > o->capacity) return;
    corner(o, x0, y0, rgba), corner(o, x1, y0, rgba), corner(o, x1, y1, rgba);
    corner(o, x0, y0, rgba), corner(o, x1, y1, rgba), corner(o, x0, y1, rgba);
}

void sb_overlay_rect(sb_overlay* o, float x, float y, float w, float h, const float rgba[4]) {
    quad(o, x, y, x + w, y + h, rgba);
}

/* One line (stb's buffer holds about 240 characters' quads). */
static void text_line(sb_overlay* o, float x, float y, float scale, const char* line, size_t length,
                      const float rgba[4]) {
    static char glyphs[GLYPH_BUFFER];
    char copy[256];
    snprintf(copy, sizeof copy, "%.*s", (int)length, line);
    int quads = stb_easy_font_print(0, 0, copy, NULL, glyphs, sizeof glyphs);
    for (int q = 0; q < quads; q++) {
        const float* a = (const float*)(glyphs + 64 * q);      /* corner 0: x y z, then 4 colour bytes */
        const float* c = (const float*)(glyphs + 64 * q + 32); /* corner 2, opposite */
        quad(o, x + scale * a[0], y + scale * a[1], x + scale * c[0], y + scale * c[1], rgba);
    }
}

void sb_overlay_text(sb_overlay* o, float x, float y, float scale, const char* text, const float rgba[4]) {
    for (const char* line = text;; y += LINE_HEIGHT * scale) {
        size_t length = strcspn(line, "\n");
        text_line(o, x, y, scale, line, length, rgba);
        if (!line[length]) break;
        line += length + 1;
    }
}

void sb_overlay_measure(const char* text, float scale, float* width, float* height) {
    char copy[1024];
    snprintf(copy, sizeof copy, "%s", text);
    *width = scale * (float)stb_easy_font_width(copy);
    *height = scale * (float)stb_easy_font_height(copy);
}

static float width_of(const char* text, size_t length, float scale) {
    char copy[1024];
    snprintf(copy, sizeof copy, "%.*s", (int)length, text);
    return scale * (float)stb_easy_font_width(copy);
}

/* text with a '\n' put where a line would pass max_width: at the last space
 * before it, or inside a word longer than the line. */
static void wrap(const char* text, float max_width, float scale, char* out, size_t size) {
    size_t used = 0, line_start = 0, last_space = 0;
    bool has_space = false;
    for (const char* p = text; *p && used + 2 < size; p++) {
        out[used++] = *p;
        if (*p == '\n') {
            line_start = used, has_space = false;
            continue;
        }
        if (*p == ' ') last_space = used - 1, has_space = true;
        if (width_of(out + line_start, used - line_start, scale) <= max_width || used - line_start < 2) continue;
        if (has_space) {
            out[last_space] = '\n';
            line_start = last_space + 1;
        } else { /* cut the word before this character */
            out[used - 1] = '\n';
            if (used + 2 < size) out[used++] = *p;
            line_start = used - 1;
        }
        has_space = false;
    }
    out[used] = '\0';
}

float sb_overlay_panel(sb_overlay* o, float x, float y, float max_width, float scale, const char* text,
                       const float ink[4], const float paper[4]) {
    char wrapped[2048];
    wrap(text, max_width, scale, wrapped, sizeof wrapped);
    float w = 0.0f, lines = 0.0f;
    for (const char* line = wrapped;; line += strcspn(line, "\n") + 1) {
        size_t length = strcspn(line, "\n");
        w = width_of(line, length, scale) > w ? width_of(line, length, scale) : w;
        lines += 1.0f;
        if (!line[length]) break;
    }
    /* a glyph is 7 of a line's 12 pixels: the paper ends 3 pixels (scaled) below the last one's */
    float h = (lines * LINE_HEIGHT - (LINE_HEIGHT - 7) + 3) * scale;
    sb_overlay_rect(o, x - 6, y - 3, w + 12, h + 3, paper);
    sb_overlay_text(o, x, y, scale, wrapped, ink);
    return h + 6;
}

void sb_overlay_draw(sb_overlay* o, const sb_shaders* s, int width, int height) {
    if (o->count == 0) return;
    glBindBuffer(GL_ARRAY_BUFFER, o->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(o->count * FLOATS * sizeof(float)), o->vertices);
    glUseProgram(s->flat);
    glUniform2f(s->flat_screen, (float)width, (float)height);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(o->vao);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)o->count);
    glBindVertexArray(0);
    glEnable(GL_DEPTH_TEST);
}
