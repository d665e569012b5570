/* Pins by place: geometric selections of a mesh's vertices, taken from its
 * bounding box, for scenes that hold a sheet by its corners or an edge.
 *
 * A side is the vertices whose coordinate lies within 1e-9 x size of the
 * box's face (size = the box's largest extent): top = max y, bottom = min y,
 * left = min x, right = max x. `<side>_edge` pins all of them;
 * `<side>_corners` pins the two at the ends of the side (min and max x for
 * top and bottom, min and max y for left and right; the first in vertex
 * order on a tie). `<side>_clamp` pins the side and every vertex of a
 * triangle touching it (its neighbours along the mesh): a single line of
 * held points lets a sheet turn about it at no cost in energy, two rows
 * hold the rotation too. `none` pins nothing. */
#ifndef SB_PIN_H
#define SB_PIN_H

#include "softbond/softbond.h"

bool sb_pin_known(const char* name);
/* The names, comma-separated, for messages and help. */
const char* sb_pin_names(void);
/* Marks the selected vertices fixed; name must be known. */
void sb_pin_apply(const char* name, const sb_mesh* mesh, sb_builder* builder);

#endif
