/* Private to mesh/: the writers behind sb_mesh_export. Each writes the mesh,
 * at `positions` (3 * vertex_count, never NULL here), to path in place; on
 * failure it removes what it wrote and fills err naming the path. */
#ifndef SB_MESH_WRITERS_H
#define SB_MESH_WRITERS_H

#include <stdio.h>

#include "softbond/mesh.h"

/* Through assimp's exporter; format_id is assimp's ("plyb", "obj", ...). */
sb_status sb_assimp_write(const char* path, const char* format_id, const sb_mesh* mesh,
                          const double* positions, sb_error* err);
/* IRIT text polygons (irit_writer.c). */
void sb_irit_write(FILE* f, const sb_mesh* mesh, const double* positions);
/* A POV-Ray scene that renders as is (pov_writer.c). */
void sb_pov_write(FILE* f, const sb_mesh* mesh, const double* positions);

#endif
