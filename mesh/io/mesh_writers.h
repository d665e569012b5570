/* Private to mesh/: the writers behind sb_mesh_export. Each writes the mesh
 * at the given positions (never NULL here) in place; the assimp writer
 * removes what it wrote on failure and fills err naming the path, the text
 * writers leave errors to their stream. */
#ifndef SB_MESH_WRITERS_H
#define SB_MESH_WRITERS_H

#include <stdio.h>

#include "softbond/mesh.h"

/* Through assimp's exporter; format_id is assimp's ("plyb", "obj", ...). */
sb_status sb_assimp_write(const char* path, const char* format_id, const sb_mesh* mesh, const double* positions,
                          sb_error* err);
/* IRIT text polygons (irit_writer.c). */
void sb_irit_write(FILE* f, const sb_mesh* mesh, const sb_mesh_export_def* def);
/* A POV-Ray scene that renders as is, def->up shown up (pov_writer.c). */
void sb_pov_write(FILE* f, const sb_mesh* mesh, const sb_mesh_export_def* def);

#endif
