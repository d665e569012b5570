/* The frame formats a scene may ask for (output.formats): their names and
 * the set of them a scene's text names. The loader checks the key with it;
 * the program's frame writer (cli/frame_export.c) writes each format. */
#ifndef SB_FRAME_FORMATS_H
#define SB_FRAME_FORMATS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* A set of formats: one bit per format, in the order sb_frame_formats_known
 * lists them (bit 0 is vtu). */
typedef uint32_t sb_frame_formats;

enum { SB_FRAME_VTU = 1u << 0, SB_FRAME_FORMAT_COUNT = 7 };

/* The name of format bit i (i < SB_FRAME_FORMAT_COUNT): "vtu", "ply", ... */
const char* sb_frame_format_name(uint32_t i);

/* "vtu, ply, obj, gltf, glb, irit, pov". */
const char* sb_frame_formats_known(void);

/* Parses names joined by commas ("vtu,pov"; a name given twice counts
 * once). On an unknown or empty name returns false and copies that name
 * into bad. */
bool sb_frame_formats_parse(const char* text, sb_frame_formats* out, char* bad, size_t bad_size);

#endif
