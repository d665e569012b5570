/* The viewer's input events, from the window or from a script alike, and
 * the names of its keys (as the script and the help list write them). */
#ifndef SB_VIEWER_INPUT_H
#define SB_VIEWER_INPUT_H

#include <stdbool.h>
#include <stddef.h>

typedef enum sb_view_key {
    SB_VKEY_NONE = 0,
    SB_VKEY_F1,        /* vertices */
    SB_VKEY_F2,        /* edges */
    SB_VKEY_F3,        /* edges coloured by strain, with the colour scale */
    SB_VKEY_F4,        /* faces, lit */
    SB_VKEY_F5,        /* texture */
    SB_VKEY_R,         /* reverse gravity */
    SB_VKEY_S,         /* stop the bodies / resume */
    SB_VKEY_G,         /* gravity on / off */
    SB_VKEY_SPACE,     /* pause / run */
    SB_VKEY_N,         /* one step, paused */
    SB_VKEY_BACKSPACE, /* reset: the bodies back to rest */
    SB_VKEY_P,         /* save a screenshot */
    SB_VKEY_L,         /* reload the scene file */
    SB_VKEY_H,         /* the list of keys */
    SB_VKEY_O,         /* the statistics overlay on / off */
    SB_VKEY_C,         /* the camera back to where it started */
    SB_VKEY_ESCAPE,    /* quit */
    SB_VKEY_COUNT
} sb_view_key;

typedef enum sb_view_event_kind {
    SB_EVENT_KEY,     /* key pressed */
    SB_EVENT_PRESS,   /* a mouse button down at (x, y) */
    SB_EVENT_RELEASE, /* a mouse button up at (x, y) */
    SB_EVENT_MOVE,    /* the cursor at (x, y) */
    SB_EVENT_SCROLL,  /* y scroll steps */
    SB_EVENT_QUIT     /* the script's end, or the window closed */
} sb_view_event_kind;

enum { SB_BUTTON_LEFT = 0, SB_BUTTON_RIGHT = 1, SB_BUTTON_MIDDLE = 2 };

typedef struct sb_view_event {
    sb_view_event_kind kind;
    sb_view_key key;
    int button;
    bool shift; /* a modifier held with a press: shift pans, ctrl picks a vertex where the mouse drives a tool */
    bool ctrl;
    double x, y; /* pixels from the top left; scroll: y steps */
} sb_view_event;

/* "F1", "r", "space", "backspace", ... (case-insensitive); SB_VKEY_NONE when unknown. */
sb_view_key sb_view_key_from_name(const char* name);
const char* sb_view_key_name(sb_view_key key);
/* What the key does, one line for the help. */
const char* sb_view_key_meaning(sb_view_key key);

#endif
