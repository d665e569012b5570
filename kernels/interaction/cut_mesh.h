/* Private: cutting through triangles by local remeshing
 * (kernels/interaction/cut_mesh.c), on breakage's working copy. */
#ifndef SB_CUT_MESH_H
#define SB_CUT_MESH_H

#include "mesh/model_internal.h"
#include "common/sections.h"

struct sb_solver;
typedef struct sb_cut_mesh sb_cut_mesh;

/* For the working copy `live`, whose vertex arrays have spare slots after
 * its model_vertices: its bond and triangle arrays again, with room for
 * the new elements (4 bonds and 2 triangles a spare vertex). NULL and
 * *ok false when out of memory. */
sb_cut_mesh* sb_cut_mesh_create(sb_model* live, uint32_t model_vertices, bool* ok);
void sb_cut_mesh_destroy(sb_cut_mesh* cut);

/* A blade's edge met bond `bond` at fraction f from its first end: the
 * bond is refined there (or its end put on the cut, or a bond on no
 * triangle severed). `before` holds 3 forces a vertex slot, moved with the
 * masses (the Verlet re-kick's). */
void sb_cut_mesh_cross(struct sb_solver* solver, sb_cut_mesh* cut, uint32_t bond, double f, double* before);

/* After the step's crossings: the edges along the cut are cut and the
 * vertices on it split, one per fan of triangles. */
void sb_cut_mesh_separate(struct sb_solver* solver, sb_cut_mesh* cut, double* before);

/* The vertices in use (the model's, then the new ones). */
uint32_t sb_cut_mesh_vertex_count(const sb_cut_mesh* cut);
/* Refinements and splits not made for want of room. */
uint32_t sb_cut_mesh_refused(const sb_cut_mesh* cut);
/* Per bond slot: 1 where the blades no longer look (cut or severed). */
const uint8_t* sb_cut_mesh_skip(const sb_cut_mesh* cut);

/* The saved state (kernels/solver/solver_state.c): counts, flags, and the
 * working copy's vertex and element arrays. */
void sb_cut_mesh_save(const sb_cut_mesh* cut, sb_sections_writer* w);
void sb_cut_mesh_load(struct sb_solver* solver, sb_cut_mesh* cut, sb_cursor* r);

/* Shared with cutting through tetrahedra (kernels/interaction/cut_volume.c).
 * Vertex w gets (1 − f) of u's values plus f of v's: rest, initial
 * velocity, state, Verlet displacement and compensation (f = 0: a copy of u). */
void sb_blend_vertex(struct sb_solver* solver, uint32_t u, uint32_t v, double f, uint32_t w);
/* Moves `share` kg of u's mass (and that part of its force in `before`) to w. */
void sb_give_mass(struct sb_solver* solver, uint32_t u, uint32_t w, double share, double* before);

#endif
