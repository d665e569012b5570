/* The folder a run writes into, made with its parents (mkdir -p). */
#ifndef SB_OUTPUT_DIR_H
#define SB_OUTPUT_DIR_H

#include "softbond/types.h"

typedef struct sb_output_dir {
    char* dir;
    char path[4096]; /* the last path returned by sb_output_dir_path */
} sb_output_dir;

/* Creates `requested`, or out/<scene_name> when it is NULL. */
sb_status sb_output_dir_create(sb_output_dir* out, const char* requested, const char* scene_name, sb_error* err);
/* "DIR/file", valid until the next call. */
const char* sb_output_dir_path(sb_output_dir* out, const char* file);
void sb_output_dir_free(sb_output_dir* out);

#endif
