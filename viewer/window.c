/* The viewer's window (viewer/window.h). GLFW calls back on the thread
 * that polls; the callbacks only append to the window's event list. */
#include "viewer/window.h"
#include "common/error.h"

#include <GLFW/glfw3.h>
#include <stdlib.h>

enum { MAX_EVENTS = 256 };

struct sb_window {
    GLFWwindow* glfw;
    sb_view_event events[MAX_EVENTS];
    size_t count;
    double x, y; /* the cursor */
};

static void push(sb_window* w, sb_view_event e) {
    if (w->count < MAX_EVENTS) w->events[w->count++] = e;
}

static sb_view_key key_of(int key) {
    switch (key) {
    case GLFW_KEY_F1: return SB_VKEY_F1;
    case GLFW_KEY_F2: return SB_VKEY_F2;
    case GLFW_KEY_F3: return SB_VKEY_F3;
    case GLFW_KEY_F4: return SB_VKEY_F4;
    case GLFW_KEY_F5: return SB_VKEY_F5;
    case GLFW_KEY_R: return SB_VKEY_R;
    case GLFW_KEY_S: return SB_VKEY_S;
    case GLFW_KEY_G: return SB_VKEY_G;
    case GLFW_KEY_SPACE: return SB_VKEY_SPACE;
    case GLFW_KEY_BACKSPACE: return SB_VKEY_BACKSPACE;
    case GLFW_KEY_H: return SB_VKEY_H;
    case GLFW_KEY_O: return SB_VKEY_O;
    case GLFW_KEY_N: return SB_VKEY_N;
    case GLFW_KEY_P: return SB_VKEY_P;
    case GLFW_KEY_L: return SB_VKEY_L;
    case GLFW_KEY_C: return SB_VKEY_C;
    case GLFW_KEY_ESCAPE: return SB_VKEY_ESCAPE;
    default: return SB_VKEY_NONE;
    }
}

static void on_key(GLFWwindow* g, int key, int scancode, int action, int mods) {
    (void)scancode, (void)mods;
    sb_view_key k = key_of(key);
    if (action == GLFW_PRESS && k != SB_VKEY_NONE)
        push(glfwGetWindowUserPointer(g), (sb_view_event){.kind = SB_EVENT_KEY, .key = k});
}

static void on_button(GLFWwindow* g, int button, int action, int mods) {
    sb_window* w = glfwGetWindowUserPointer(g);
    int b = button == GLFW_MOUSE_BUTTON_RIGHT    ? SB_BUTTON_RIGHT
            : button == GLFW_MOUSE_BUTTON_MIDDLE ? SB_BUTTON_MIDDLE
                                                 : SB_BUTTON_LEFT;
    push(w, (sb_view_event){.kind = action == GLFW_PRESS ? SB_EVENT_PRESS : SB_EVENT_RELEASE,
                            .button = b,
                            .shift = (mods & GLFW_MOD_SHIFT) != 0,
                            .ctrl = (mods & GLFW_MOD_CONTROL) != 0,
                            .x = w->x,
                            .y = w->y});
}

static void on_move(GLFWwindow* g, double x, double y) {
    sb_window* w = glfwGetWindowUserPointer(g);
    w->x = x;
    w->y = y;
    push(w, (sb_view_event){.kind = SB_EVENT_MOVE, .x = x, .y = y});
}

static void on_scroll(GLFWwindow* g, double dx, double dy) {
    (void)dx;
    push(glfwGetWindowUserPointer(g), (sb_view_event){.kind = SB_EVENT_SCROLL, .y = dy});
}

sb_window* sb_window_open(int width, int height, const char* title, sb_error* err) {
    if (!glfwInit()) {
        const char* why = NULL;
        glfwGetError(&why); /* GLFW's own account, e.g. the display it could not open */
        sb_error_set(
            err, SB_ERR_INVALID,
            "view: no display to open a window on (is DISPLAY set? headless: xvfb-run -a softbond view ...)%s%s",
            why ? "; GLFW: " : "", why ? why : "");
        return NULL;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    sb_window* w = calloc(1, sizeof *w);
    GLFWwindow* g = w ? glfwCreateWindow(width, height, title, NULL, NULL) : NULL;
    if (!g) {
        free(w);
        glfwTerminate();
        sb_error_set(err, SB_ERR_INVALID, "view: cannot open a window with OpenGL 3.3 core on this display");
        return NULL;
    }
    w->glfw = g;
    glfwSetWindowUserPointer(g, w);
    glfwMakeContextCurrent(g);
    glfwSwapInterval(0); /* the viewer paces its own frames */
    glfwSetKeyCallback(g, on_key);
    glfwSetMouseButtonCallback(g, on_button);
    glfwSetCursorPosCallback(g, on_move);
    glfwSetScrollCallback(g, on_scroll);
    return w;
}

void sb_window_close(sb_window* w) {
    if (!w) return;
    glfwDestroyWindow(w->glfw);
    glfwTerminate();
    free(w);
}

void sb_window_poll(sb_window* w, const sb_view_event** events, size_t* count) {
    w->count = 0;
    glfwPollEvents();
    if (glfwWindowShouldClose(w->glfw)) push(w, (sb_view_event){.kind = SB_EVENT_QUIT});
    *events = w->events;
    *count = w->count;
}

void sb_window_size(const sb_window* w, int* width, int* height) { glfwGetFramebufferSize(w->glfw, width, height); }

void sb_window_swap(sb_window* w) { glfwSwapBuffers(w->glfw); }
