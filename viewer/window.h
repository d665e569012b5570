/* The viewer's window: GLFW, an OpenGL 3.3 core context (functions through
 * libepoxy), and its input turned into sb_view_events. */
#ifndef SB_VIEWER_WINDOW_H
#define SB_VIEWER_WINDOW_H

#include "softbond/types.h"
#include "viewer/input.h"

typedef struct sb_window sb_window;

/* A width × height window titled title, its context current. Without a
 * display (or without OpenGL 3.3) an error that says so. */
sb_window* sb_window_open(int width, int height, const char* title, sb_error* err);
void sb_window_close(sb_window* window);
/* Collects the window's input since the last call; then *count events are
 * in *events (valid until the next call). A closed window gives SB_EVENT_QUIT. */
void sb_window_poll(sb_window* window, const sb_view_event** events, size_t* count);
void sb_window_size(const sb_window* window, int* width, int* height);
void sb_window_swap(sb_window* window);

#endif
