/* The formats `softbond run` writes each frame in (output.formats) and the
 * writing of one frame in all of them, every file appearing whole. */
#ifndef SB_FRAME_EXPORT_H
#define SB_FRAME_EXPORT_H

#include "scenes/output_dir.h"
#include "scenes/vtk.h"

/* A set of formats: one bit per format, in the order sb_frame_formats_known
 * lists them (bit 0 is vtu). */
typedef uint32_t sb_frame_formats;

enum { SB_FRAME_VTU = 1u << 0 };

/* "vtu, ply, obj, gltf, glb, irit, pov". */
const char* sb_frame_formats_known(void);

/* Parses names joined by commas ("vtu,pov"; a name given twice counts
 * once). On an unknown or empty name returns false and copies that name
 * into bad. */
bool sb_frame_formats_parse(const char* text, sb_frame_formats* out, char* bad, size_t bad_size);

/* What to write: the formats, and for pov the direction shown up
 * (sb_mesh_export_def's up; `softbond run` gives the one against gravity). */
typedef struct sb_frame_export_def {
    sb_frame_formats formats;
    double up[3];
} sb_frame_export_def;

/* Writes frame `index` (frame_000042.<ext>) in each format of the set into
 * the output folder. */
sb_status sb_frame_export(const sb_frame_export_def* def, const sb_output_dir* out, uint32_t index,
                          const sb_vtk_frame* frame, sb_error* err);

#endif
