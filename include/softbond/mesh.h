/** @file
 * An indexed triangle mesh: what generators and importers produce and what
 * the factory turns into a model. Positions are double, metres. */
#ifndef SOFTBOND_MESH_H
#define SOFTBOND_MESH_H

#include "softbond/export.h"

#include "softbond/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A triangle mesh. One the library made owns its two arrays (malloc'd:
 * sb_mesh_free releases them). A zeroed sb_mesh is the empty mesh. */
typedef struct sb_mesh {
    uint32_t vertex_count;   /**< vertices in positions */
    double* positions;       /**< 3 * vertex_count, x y z interleaved */
    uint32_t triangle_count; /**< triangles in triangles */
    uint32_t* triangles;     /**< 3 * triangle_count vertex indices */
} sb_mesh;

/** Releases the arrays and zeroes the struct; safe on a zeroed mesh. */
SB_API void sb_mesh_free(sb_mesh* mesh);

/** A rectangular sheet in the z = 0 plane, x in [0, width], y in [0, height],
 * nx × ny vertices in row-major order (vertex = row * nx + column, row along
 * y), each quad split into two triangles along alternating diagonals.
 * Interior vertices are moved by up to jitter × spacing in x and y, with a
 * deterministic generator seeded by seed. */
typedef struct sb_sheet_def {
    /** @var nx
     * vertices along x, >= 2
     * @var ny
     * vertices along y, >= 2 */
    uint32_t nx, ny;
    /** @var width
     * m, the extent along x, > 0
     * @var height
     * m, the extent along y, > 0 */
    double width, height;
    double jitter; /**< in [0, 0.5), a fraction of the spacing along each axis; 0 = a regular grid */
    uint64_t seed; /**< the jitter's generator: the same seed, the same sheet */
    /** false (the default): the cells cut along alternating diagonals, a
     * checkerboard; true: every cell along the same diagonal, so that a
     * flat sheet of factory membrane gets the plate bending, which honours
     * ν (docs/materials.md, "Sheets") */
    bool parallel_diagonals;
} sb_sheet_def;

/** 10 × 10 vertices on 1 m × 1 m, no jitter, seed 1, alternating diagonals. */
SB_API sb_sheet_def sb_default_sheet_def(void);
/** Generates the sheet into *out (the caller frees it with sb_mesh_free).
 * SB_ERR_INVALID for nx or ny below 2, a width or height not positive and
 * finite, a jitter outside [0, 0.5), more than 2^32 − 1 vertices or
 * triangles; SB_ERR_NOMEM. On failure *out is empty. */
SB_API sb_status sb_mesh_generate_sheet(const sb_sheet_def* def, sb_mesh* out, sb_error* err);

/** An icosphere: an icosahedron subdivided `subdivisions` times, projected
 * onto a sphere of the given radius centred at the origin. It has
 * 10 * 4^s + 2 vertices and 20 * 4^s triangles, outward-facing. */
SB_API sb_status sb_mesh_generate_icosphere(uint32_t subdivisions, double radius, sb_mesh* out, sb_error* err);

/** Reads a triangle mesh from a file. OBJ and OFF are read by softbond's own
 * readers, which keep the file's vertex order and count exactly (polygons are
 * fan-triangulated); every other format goes through assimp (triangulated,
 * identical vertices joined, all meshes of the file merged). A tetrahedral
 * mesh (".node"/".ele", ".msh": softbond/volume.h) gives its boundary
 * surface with every vertex kept. IRIT text data (".itd", ".irit"): the
 * polygons of every OBJECT, fan-triangulated, identical vertices joined,
 * freeform geometry refused. POV-Ray (".pov"): every mesh2 object
 * (softbond/pov.h), vertices as in the file, merged by concatenation
 * (nothing joined). Errors name the file and, where there is one, the
 * line. */
SB_API sb_status sb_mesh_load(const char* path, sb_mesh* out, sb_error* err);

/** Options of sb_mesh_load_ex. */
typedef struct sb_mesh_load_def {
    /** false (the default): every mesh of the file is merged into one object,
     * identical positions joined across meshes (sb_mesh_load's behaviour).
     * true: each placed mesh of the file (each node's use of a mesh, with
     * the node's transform) becomes its own object, joined within itself
     * only; an OBJ file is then checked by softbond's strict reader and
     * split by assimp (one object per group or material). OFF and
     * tetrahedral files are always one object. */
    bool separate_objects;
} sb_mesh_load_def;

/** separate_objects false: sb_mesh_load's behaviour. */
SB_API sb_mesh_load_def sb_default_mesh_load_def(void);

/** What an import did. */
typedef struct sb_mesh_load_report {
    const char* reader;          /**< "assimp", "obj", "off", "tetrahedral", "irit" or "pov"
                                    (static text) */
    uint32_t source_meshes;      /**< meshes placed from the file (1 for the own readers) */
    uint32_t object_count;       /**< objects returned */
    uint32_t degenerate_faces;   /**< triangles dropped (assimp): two corners joined, or
                                    collinear corners, |(b-a)x(c-a)| <= 1e-12 (longest edge)^2;
                                    (irit): two corners joined */
    uint32_t ignored_primitives; /**< points and lines of the file, ignored (assimp) */
} sb_mesh_load_report;

/** sb_mesh_load with options and a report: *objects receives an array of
 * *object_count meshes (at least one on success), to release with
 * sb_mesh_objects_free. def and report may be NULL (defaults; no report).
 * softbond's own OBJ and OFF readers drop nothing: a face with a repeated
 * vertex is kept and reported when a model is compiled. */
SB_API sb_status sb_mesh_load_ex(const char* path, const sb_mesh_load_def* def, sb_mesh** objects,
                                 uint32_t* object_count, sb_mesh_load_report* report, sb_error* err);

/** Frees each mesh and the array; safe on NULL. */
SB_API void sb_mesh_objects_free(sb_mesh* objects, uint32_t count);

/** The meshes one after the other in one mesh (separate bodies, nothing
 * joined): mesh i's vertices follow mesh i-1's and its triangles' indices
 * are shifted by as much. On failure *out is left empty. */
SB_API sb_status sb_mesh_concatenate(const sb_mesh* meshes, uint32_t count, sb_mesh* out, sb_error* err);

/** How a triangle mesh's edges are shared: unique edges, boundary edges (on
 * one triangle) and non-manifold edges (on three or more). The surface is
 * closed when it has triangles and neither of the two. */
typedef struct sb_mesh_edge_counts {
    /** @var edges
     * unique edges (an edge is a pair of vertices, either direction)
     * @var boundary
     * edges on exactly one triangle
     * @var non_manifold
     * edges on three or more triangles */
    uint32_t edges, boundary, non_manifold;
    bool closed; /**< triangles, and no boundary or non-manifold edge */
} sb_mesh_edge_counts;

/** Counts the mesh's edges into *out (from the triangles; positions are not
 * read). SB_ERR_NOMEM when out of memory (then *out is zeros). */
SB_API sb_status sb_mesh_count_edges(const sb_mesh* mesh, sb_mesh_edge_counts* out, sb_error* err);

/** Placement of a mesh: p' = translate + Rz Ry Rx (scale * p). Scale per
 * axis about the origin first, then rotate by rotate[0] degrees about x,
 * rotate[1] about y, rotate[2] about z (fixed world axes, in that order,
 * right-handed), then translate (m). An odd number of negative scale
 * factors mirrors the mesh and reverses the triangles' winding so that
 * outward stays outward. Errors: a non-finite value or a zero scale. */
typedef struct sb_mesh_transform_def {
    double scale[3];     /**< default 1, 1, 1 */
    double rotate[3];    /**< degrees about x, y, z; default 0 */
    double translate[3]; /**< m; default 0 */
} sb_mesh_transform_def;

/** The identity: scale 1, 1, 1, no rotation, no translation. */
SB_API sb_mesh_transform_def sb_default_mesh_transform_def(void);
/** Places the mesh in place as sb_mesh_transform_def says (positions, and
 * the winding when mirrored). SB_ERR_INVALID, with the mesh unchanged, for
 * a NULL mesh or def, a non-finite value or a zero scale factor. */
SB_API sb_status sb_mesh_transform(sb_mesh* mesh, const sb_mesh_transform_def* def, sb_error* err);

/** Level of detail: fewer vertices, by quadric edge collapse
 * (meshoptimizer). Vertices on the boundary (an edge of one triangle) are
 * never moved or removed, nor are the locked vertices and their ring of
 * neighbours. Give a vertex count, an error, or both (the count is then
 * reached only while the error stays below target_error). The result keeps
 * the vertices still used in their original order; when origin is not NULL
 * it receives for each new vertex its old index (room for the old vertex
 * count). With keep_locked_indices each locked vertex keeps its own index
 * (an error if that index is beyond the new vertex count). A target at or
 * above the vertex count leaves the mesh as it is, minus unused vertices. */
typedef struct sb_simplify_def {
    uint32_t target_vertices; /**< 0 = no count target */
    double target_error;      /**< relative to the mesh's extent (0.01 = 1%); 0 = none */
    const uint32_t* locked;   /**< vertices to keep, e.g. the fixed ones */
    uint32_t locked_count;    /**< entries in locked; each below the vertex count */
    bool keep_locked_indices; /**< each locked vertex keeps its index (see above) */
} sb_simplify_def;

/** What sb_mesh_simplify did. */
typedef struct sb_simplify_report {
    /** @var vertices_before
     * the mesh's vertex count before
     * @var vertices_after
     * after (the vertices still used) */
    uint32_t vertices_before, vertices_after;
    /** @var triangles_before
     * the mesh's triangle count before
     * @var triangles_after
     * after */
    uint32_t triangles_before, triangles_after;
    double error; /**< meshopt's resulting error, relative to the extent */
} sb_simplify_report;

/** No targets (the mesh is left as it is, minus unused vertices), nothing
 * locked. */
SB_API sb_simplify_def sb_default_simplify_def(void);
/** Simplifies the mesh in place as sb_simplify_def says (the arrays are
 * replaced); origin (may be NULL) and report (may be NULL) as described
 * there. SB_ERR_INVALID for a NULL mesh or def, a negative or non-finite
 * target_error, a locked vertex out of range, a locked index beyond the
 * new vertex count with keep_locked_indices; SB_ERR_NOMEM. On failure the
 * mesh is unchanged and the report not written. */
SB_API sb_status sb_mesh_simplify(sb_mesh* mesh, const sb_simplify_def* def, uint32_t* origin,
                                  sb_simplify_report* report, sb_error* err);

/** Renumbers the vertices along a Morton (Z-order) curve through the
 * bounding box and sorts the triangles by their lowest vertex, so that
 * vertices near in space are near in memory and the elements built from the
 * mesh visit them in order: the fast kernels' gathers and scatters then hit
 * the cache. When order is not NULL it receives, for each new vertex, its
 * old index (vertex_count entries). */
SB_API sb_status sb_mesh_reorder(sb_mesh* mesh, uint32_t* order, sb_error* err);

/** Options of sb_mesh_export. */
typedef struct sb_mesh_export_def {
    const double* positions; /**< 3 * vertex_count interleaved, m; NULL (the
                                default): the mesh's own */
    double up[3];            /**< pov: the direction shown up, e.g. against
                                gravity; the nearest axis is used; default
                                0, 0, 1 */
    /** pov: the camera's eye and the point it looks at (m, in the mesh's
     * coordinates), both or neither; NULL (the default): looking at the
     * bounding box's centre from the front, above and the right, far enough
     * to see all of it (a film keeps one camera for every frame) */
    const double* eye;
    const double* target; /**< pov: the point the camera looks at (m); see eye */
} sb_mesh_export_def;

/** The mesh's own positions, up +z, the camera placed automatically. */
SB_API sb_mesh_export_def sb_default_mesh_export_def(void);

/** Writes the mesh to path (def NULL: the defaults) in one of these formats:
 *   "ply"   binary PLY (assimp's "plyb")
 *   "obj"   Wavefront OBJ (assimp), with a material library NAME.mtl beside it
 *   "gltf"  glTF 2.0 JSON (assimp's "gltf2"), with its buffer NAME.bin beside it
 *   "glb"   binary glTF 2.0 in one file (assimp's "glb2")
 *   "irit"  IRIT text polygons (.itd): one object, a POLYGON with its PLANE
 *           per triangle, as the Spring Systems demo dumps its frames
 *   "pov"   a POV-Ray 3.7 scene: the mesh as a mesh2 object (positions as
 *           they are), placed by an axis permutation that turns def->up into
 *           POV-Ray's up (+y), a camera framing its bounding box, a light and
 *           a plain texture, so that `povray frame.pov` renders it
 * The assimp formats store positions as float. The file is written in place,
 * not atomically. Errors name the path. */
SB_API sb_status sb_mesh_export(const char* path, const char* format, const sb_mesh* mesh,
                                const sb_mesh_export_def* def, sb_error* err);

/** The file extension of an export format (".ply", ".obj", ".gltf", ".glb",
 * ".itd", ".pov"); NULL when sb_mesh_export does not know the format. */
SB_API const char* sb_mesh_export_extension(const char* format);

#ifdef __cplusplus
}
#endif
#endif
