/* Reads vertex positions from CSV: a header `x,y,z`, then one row of three
 * numbers per vertex, in the mesh's vertex order. Blank lines are skipped.
 * Errors name the file and line: a missing header, a row that is not three
 * finite numbers, too many or too few rows. */
#ifndef SB_POSITIONS_CSV_H
#define SB_POSITIONS_CSV_H

#include "softbond/types.h"

/* Fills out[3 * vertex_count] (x y z interleaved). */
sb_status sb_positions_read(const char* path, uint32_t vertex_count, double* out, sb_error* err);

#endif
