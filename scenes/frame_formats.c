/* The frame formats' names (see frame_formats.h). */
#include "scenes/frame_formats.h"

#include <stdio.h>
#include <string.h>

/* The bit order: cli/frame_export.c's writers follow it. */
static const char* const names[SB_FRAME_FORMAT_COUNT] = {"vtu", "ply", "obj", "gltf", "glb", "irit", "pov"};

const char* sb_frame_format_name(uint32_t i) { return names[i]; }

/* The names joined by ", ", made on the first call. */
const char* sb_frame_formats_known(void) {
    static char known[96];
    if (known[0]) return known;
    for (uint32_t i = 0; i < SB_FRAME_FORMAT_COUNT; i++)
        snprintf(known + strlen(known), sizeof known - strlen(known), "%s%s", i ? ", " : "", names[i]);
    return known;
}

static bool find_format(const char* name, size_t length, uint32_t* index) {
    for (uint32_t i = 0; i < SB_FRAME_FORMAT_COUNT; i++) {
        if (strlen(names[i]) == length && strncmp(names[i], name, length) == 0) {
            *index = i;
            return true;
        }
    }
    return false;
}

bool sb_frame_formats_parse(const char* text, sb_frame_formats* out, char* bad, size_t bad_size) {
    *out = 0;
    for (const char* name = text;; name++) {
        size_t length = strcspn(name, ",");
        uint32_t index;
        if (!find_format(name, length, &index)) {
            snprintf(bad, bad_size, "%.*s", (int)length, name);
            return false;
        }
        *out |= 1u << index;
        name += length;
        if (*name == '\0') return true;
    }
}
