/** @file
 * POV-Ray scenes as the Spring Systems film maker reads them (Juhasz &
 * Bercovici): every mesh2 object of a .pov file with its spring-system
 * locals, to build one body per object with its own constants. */
#ifndef SOFTBOND_POV_H
#define SOFTBOND_POV_H

#include "softbond/export.h"

#include "softbond/types.h"
#include "softbond/mesh.h"
#include "softbond/builder.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Which spring_system_* locals an object gave (bits of sb_pov_object.given). */
enum {
    SB_POV_KS = 1u << 0,       /**< spring_system_ks: stretch stiffness, N/m */
    SB_POV_KB = 1u << 1,       /**< spring_system_kb: bend stiffness, N/m */
    SB_POV_DS = 1u << 2,       /**< spring_system_ds: stretch damping, N·s/m */
    SB_POV_DB = 1u << 3,       /**< spring_system_db: bend damping, N·s/m */
    SB_POV_MASS = 1u << 4,     /**< spring_system_mass: the object's total mass, kg */
    SB_POV_VICINITY = 1u << 5, /**< spring_system_vicinity: vicinity distance, m */
    SB_POV_FIXED = 1u << 6     /**< spring_system_fixed: true or false */
};

/** One mesh2 object: its mesh (vertex_vectors in the file's order and
 * count, face_indices as triangles) and the locals it gave; a value whose
 * bit is not in `given` is 0 (false for fixed). */
typedef struct sb_pov_object {
    char name[64];  /**< the `#declare`d (or `#local`d) name, cut to 63 bytes; "" for a bare mesh2 */
    size_t line;    /**< the line of its `mesh2` keyword */
    sb_mesh mesh;   /**< the object's mesh, owned by the object (sb_pov_objects_free) */
    unsigned given; /**< SB_POV_* bits */
    /** N/m: spring_system_ks, the stretch springs' stiffness */
    double stretch_k, bend_k; /**< N/m */
    /** N·s/m: spring_system_ds, the stretch springs' damping */
    double stretch_damping, bend_damping; /**< N·s/m */
    double mass;                          /**< kg, the whole object */
    double vicinity;                      /**< m */
    bool fixed; /**< spring_system_fixed: every vertex of the object is to be fixed (the scene loader pins them) */
} sb_pov_object;

/** Reads every mesh2 of a POV-Ray file, in file order: declared
 * (`#declare Name = mesh2 { ... }`), bare, or inside `object { }`. A
 * declared mesh2 is one object however many times `object { Name }` places
 * it, and transforms (translate, rotate, scale) are not applied. Inside a
 * mesh2: vertex_vectors { n, <x,y,z>, ... } and face_indices { m, <a,b,c>
 * [, texture indices], ... } (indices from 0) are read; normal_vectors,
 * uv_vectors, texture_list, normal_indices, uv_indices, inside_vector and
 * texture/pigment/finish blocks are skipped; `#local spring_system_ks =
 * 600;` (also _kb, _ds, _db, _mass, _vicinity, a number >= 0, and _fixed:
 * true/false, on/off, yes/no or a number) sets the object's locals. Every
 * other statement (camera, light_source, plane, `#include`, ...) is skipped:
 * `#include` is not followed, as in the film maker. Numbers are literals
 * (no expressions). Coordinates are taken as they are (POV-Ray's up is
 * +y). Errors are "FILE:LINE: what": a count that disagrees
 * with the list, an index out of range, a non-number, an unclosed brace,
 * a mesh2 without vertices or faces, a file without any mesh2. */
SB_API sb_status sb_pov_load(const char* path, sb_pov_object** objects, uint32_t* object_count, sb_error* err);

/** Whether the path names a POV-Ray file (".pov", ignoring case). */
SB_API bool sb_pov_path(const char* path);

/** Frees each object's mesh and the array; safe on NULL. */
SB_API void sb_pov_objects_free(sb_pov_object* objects, uint32_t count);

/** The spring factory's constants for one object: `defaults` with the
 * object's locals put over it. ks/ds are the stretch springs', kb/db the
 * bend springs'; a given vicinity also gives the vicinity springs the
 * object's stretch constants (the film maker has no others); a given mass
 * is the whole object's, spread evenly: mass / vertex_count per vertex
 * (density 0). spring_system_fixed is not a constant: see `fixed`. */
SB_API sb_spring_mesh_def sb_pov_object_springs(const sb_pov_object* object, const sb_spring_mesh_def* defaults);

#ifdef __cplusplus
}
#endif
#endif
