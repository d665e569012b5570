/* The writing of one frame in each format `softbond run` writes
 * (output.formats, scenes/frame_formats.h), every file appearing whole. */
#ifndef SB_FRAME_EXPORT_H
#define SB_FRAME_EXPORT_H

#include "cli/output_dir.h"
#include "cli/vtk.h"
#include "scenes/frame_formats.h"

/* What to write: the formats, and for pov the direction shown up
 * (sb_mesh_export_def's up; `softbond run` gives the one against gravity). */
typedef struct sb_frame_export_def {
    sb_frame_formats formats;
    double up[3];
    sb_vtk_encoding vtu; /* output.vtu */
} sb_frame_export_def;

/* Writes frame `index` (frame_000042.<ext>) in each format of the set into
 * the output folder. */
sb_status sb_frame_export(const sb_frame_export_def* def, const sb_output_dir* out, uint32_t index,
                          const sb_vtk_frame* frame, sb_error* err);

#endif
