/* The viewer's GLSL programs (viewer/shaders.h). Surfaces are lit from a
 * light at the eye's side with both faces lit alike (a sheet has no
 * inside), so a face seen edge-on is dark and one facing the eye bright. */
#include "viewer/shaders.h"
#include "common/error.h"

static const char* surface_vertex =
    "#version 330 core\n"
    "layout(location = 0) in vec3 position;\n"
    "layout(location = 1) in vec3 normal;\n"
    "layout(location = 2) in vec4 color;\n"
    "layout(location = 3) in vec2 uv;\n"
    "uniform mat4 matrix;\n"
    "out vec3 v_normal; out vec4 v_color; out vec2 v_uv;\n"
    "void main() { gl_Position = matrix * vec4(position, 1.0); v_normal = normal; v_color = color; v_uv = uv; }\n";

static const char* surface_fragment = "#version 330 core\n"
                                      "in vec3 v_normal; in vec4 v_color; in vec2 v_uv;\n"
                                      "uniform vec3 light; uniform int textured; uniform sampler2D tex;\n"
                                      "out vec4 color;\n"
                                      "void main() {\n"
                                      "  float lambert = abs(dot(normalize(v_normal), light));\n"
                                      "  vec4 base = textured != 0 ? texture(tex, v_uv) : v_color;\n"
                                      "  color = vec4(base.rgb * (0.35 + 0.65 * lambert), base.a);\n"
                                      "}\n";

static const char* lines_vertex = "#version 330 core\n"
                                  "layout(location = 0) in vec3 position;\n"
                                  "layout(location = 2) in vec4 color;\n"
                                  "uniform mat4 matrix; uniform float point_size;\n"
                                  "out vec4 v_color;\n"
                                  "void main() { gl_Position = matrix * vec4(position, 1.0);\n"
                                  "  gl_Position.z -= 1e-4 * gl_Position.w; /* drawn over the faces they bound */\n"
                                  "  gl_PointSize = point_size; v_color = color; }\n";

static const char* flat_vertex = "#version 330 core\n"
                                 "layout(location = 0) in vec2 position;\n"
                                 "layout(location = 2) in vec4 color;\n"
                                 "uniform vec2 screen;\n"
                                 "out vec4 v_color;\n"
                                 "void main() { gl_Position = vec4(2.0 * position.x / screen.x - 1.0,\n"
                                 "  1.0 - 2.0 * position.y / screen.y, 0.0, 1.0); v_color = color; }\n";

static const char* color_fragment = "#version 330 core\n"
                                    "in vec4 v_color; out vec4 color;\n"
                                    "void main() { color = v_color; }\n";

static GLuint compile(GLenum kind, const char* source, sb_error* err) {
    GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &source, NULL);
    glCompileShader(s);
    GLint ok;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (ok) return s;
    char log[512];
    glGetShaderInfoLog(s, sizeof log, NULL, log);
    glDeleteShader(s);
    sb_error_set(err, SB_ERR_INVALID, "view: a shader did not compile: %s", log);
    return 0;
}

static GLuint link(const char* vertex, const char* fragment, sb_error* err) {
    GLuint v = compile(GL_VERTEX_SHADER, vertex, err);
    GLuint f = v ? compile(GL_FRAGMENT_SHADER, fragment, err) : 0;
    if (!f) {
        glDeleteShader(v);
        return 0;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (ok) return p;
    glDeleteProgram(p);
    sb_error_set(err, SB_ERR_INVALID, "view: a shader program did not link");
    return 0;
}

sb_status sb_shaders_build(sb_shaders* s, sb_error* err) {
    *s = (sb_shaders){0};
    s->surface = link(surface_vertex, surface_fragment, err);
    s->lines = s->surface ? link(lines_vertex, color_fragment, err) : 0;
    s->flat = s->lines ? link(flat_vertex, color_fragment, err) : 0;
    if (!s->flat) {
        sb_shaders_free(s);
        return SB_ERR_INVALID;
    }
    s->surface_matrix = glGetUniformLocation(s->surface, "matrix");
    s->surface_light = glGetUniformLocation(s->surface, "light");
    s->surface_textured = glGetUniformLocation(s->surface, "textured");
    s->surface_texture = glGetUniformLocation(s->surface, "tex");
    s->lines_matrix = glGetUniformLocation(s->lines, "matrix");
    s->lines_point_size = glGetUniformLocation(s->lines, "point_size");
    s->flat_screen = glGetUniformLocation(s->flat, "screen");
    return SB_OK;
}

void sb_shaders_free(sb_shaders* s) {
    if (s->surface) glDeleteProgram(s->surface);
    if (s->lines) glDeleteProgram(s->lines);
    if (s->flat) glDeleteProgram(s->flat);
    *s = (sb_shaders){0};
}
