/* Private to mesh/: softbond's own OBJ and OFF readers and the helpers they
 * share with sb_mesh_load (growable arrays, number parsing).
 *
 * The readers parse a whole file already in memory. They keep the file's
 * vertex order and count exactly and fan-triangulate polygons
 * (v0, vk, vk+1). Every error is one line "FILE:LINE: what" in err
 * (sb_error_at, common/error.h). */
#ifndef SB_MESH_READERS_H
#define SB_MESH_READERS_H

#include "softbond/mesh.h"

/* Growable arrays for building an sb_mesh; sizes are checked for overflow. */
typedef struct sb_mesh_builder {
    double* positions;
    size_t vertex_count, vertex_capacity;
    uint32_t* triangles;
    size_t triangle_count, triangle_capacity;
} sb_mesh_builder;

/* Return false when out of memory or past the uint32 limit. */
bool sb_mesh_builder_add_vertex(sb_mesh_builder* b, double x, double y, double z);
bool sb_mesh_builder_add_triangle(sb_mesh_builder* b, uint32_t i, uint32_t j, uint32_t k);
/* Joins vertices with bitwise-identical positions (-0 equals +0): open
 * addressing over the builder's vertex indices, kept at most half full.
 * Zero-initialise; free slots with free(). */
typedef struct sb_weld_table {
    uint32_t* slots; /* vertex index + 1; 0 = empty */
    size_t capacity; /* a power of two */
} sb_weld_table;

/* The index of the vertex at p: an earlier one at the same position, or a
 * new one added to b. False when out of memory or past the uint32 limit.
 * Every vertex of b must have been added through the same table. */
bool sb_mesh_builder_weld_vertex(sb_mesh_builder* b, sb_weld_table* weld, const double p[3], uint32_t* index);
/* Moves the arrays into out (which then owns them) and resets b. */
void sb_mesh_builder_finish(sb_mesh_builder* b, sb_mesh* out);
void sb_mesh_builder_free(sb_mesh_builder* b);

/* A cursor over one line of text (no terminator inside [p, end)). */
typedef struct sb_text_line {
    const char* p;
    const char* end;
} sb_text_line;

/* Skips blanks; returns the next whitespace-delimited token, or false. */
bool sb_text_next_token(sb_text_line* line, const char** token, size_t* length);
/* Parses a whole token as a double (any finite or non-finite value). */
bool sb_text_parse_double(const char* token, size_t length, double* out);
/* Parses a whole token as a signed decimal integer. */
bool sb_text_parse_integer(const char* token, size_t length, long long* out);

/* The whole file, NUL-terminated (caller frees); errors name the path. */
sb_status sb_read_whole_file(const char* path, char** text, size_t* size, sb_error* err);
/* Whether the file name ends in extension (".obj"; lower case), ignoring case. */
bool sb_path_has_extension(const char* path, const char* extension);

sb_status sb_obj_parse(const char* path, const char* text, size_t size, sb_mesh* out, sb_error* err);
sb_status sb_off_parse(const char* path, const char* text, size_t size, sb_mesh* out, sb_error* err);

/* IRIT text data (irit_reader.c): each OBJECT's polygons a mesh
 * (separate) or all in one (merged), vertices joined, polygons
 * fan-triangulated; *dropped counts triangles whose corners joined. */
sb_status sb_irit_load(const char* path, bool separate, sb_mesh** objects, uint32_t* object_count, uint32_t* dropped,
                       sb_error* err);
/* POV-Ray mesh2 objects (pov_reader.c, softbond/pov.h): each a mesh
 * (separate) or all concatenated, nothing joined (merged). */
sb_status sb_pov_load_meshes(const char* path, bool separate, sb_mesh** meshes, uint32_t* count, sb_error* err);

/* A PLY file's header ends and its declared counts fit the file
 * (ply_check.c); run before assimp reads it. */
sb_status sb_ply_check(const char* path, sb_error* err);

#endif
