/* The viewer's key names and meanings (viewer/input.h): one table, read by
 * the script parser and by the help overlay. */
#include "viewer/input.h"

#include <strings.h>

static const struct {
    const char* name;
    const char* meaning;
} keys[SB_VKEY_COUNT] = {
    [SB_VKEY_F1] = {"F1", "vertices on/off"},
    [SB_VKEY_F2] = {"F2", "edges on/off"},
    [SB_VKEY_F3] = {"F3", "edges coloured by strain, with the scale"},
    [SB_VKEY_F4] = {"F4", "faces (lit) on/off"},
    [SB_VKEY_F5] = {"F5", "texture on/off"},
    [SB_VKEY_R] = {"r", "reverse gravity"},
    [SB_VKEY_S] = {"s", "stop the bodies / resume"},
    [SB_VKEY_G] = {"g", "gravity on/off"},
    [SB_VKEY_SPACE] = {"space", "pause / run"},
    [SB_VKEY_N] = {"n", "one step (and pause)"},
    [SB_VKEY_BACKSPACE] = {"backspace", "reset: bodies back to rest"},
    [SB_VKEY_P] = {"p", "save a screenshot (SCENE_NNN.png)"},
    [SB_VKEY_L] = {"l", "reload the scene file"},
    [SB_VKEY_H] = {"h", "this list"},
    [SB_VKEY_O] = {"o", "statistics on/off"},
    [SB_VKEY_C] = {"c", "camera back to the start"},
    [SB_VKEY_ESCAPE] = {"escape", "quit"},
};

sb_view_key sb_view_key_from_name(const char* name) {
    for (int k = SB_VKEY_NONE + 1; k < SB_VKEY_COUNT; k++)
        if (strcasecmp(name, keys[k].name) == 0) return (sb_view_key)k;
    return SB_VKEY_NONE;
}

const char* sb_view_key_name(sb_view_key key) {
    return key > SB_VKEY_NONE && key < SB_VKEY_COUNT ? keys[key].name : "";
}

const char* sb_view_key_meaning(sb_view_key key) {
    return key > SB_VKEY_NONE && key < SB_VKEY_COUNT ? keys[key].meaning : "";
}
