/* Private: cutting through tetrahedra by local remeshing
 * (kernels/interaction/cut_volume.c), on breakage's working copy. */
#ifndef SB_CUT_VOLUME_H
#define SB_CUT_VOLUME_H

#include "mesh/model_internal.h"
#include "common/sections.h"

struct sb_solver;
struct sb_cutting;
typedef struct sb_cut_volume sb_cut_volume;

/* Whether cutting through can run on model m's tetrahedra; NULL when it
 * can, else what it needs (for the refusal's message). */
const char* sb_cut_volume_missing(const sb_model* m);

/* For the working copy `live` (its vertex arrays with spare slots after its
 * model_vertices): its tetrahedron and face arrays again, with room for the
 * new elements, and the tetrahedra's edges. NULL and *ok false when out of
 * memory. */
sb_cut_volume* sb_cut_volume_create(sb_model* live, uint32_t model_vertices, const struct sb_cutting* cutting,
                                    bool* ok);
void sb_cut_volume_destroy(sb_cut_volume* cut);

/* The tetrahedra's unique edges as a model's bonds (bond_count, bond_i,
 * bond_j only), for the blades' sweep (sb_cutting_pass), and its skip
 * array (all 0). */
const sb_model* sb_cut_volume_edges(const sb_cut_volume* cut);
const uint8_t* sb_cut_volume_skip(const sb_cut_volume* cut);

/* The step's swept planes (sb_cutting_planes), by which an edge's end is
 * judged near the cut. */
void sb_cut_volume_sweeps(sb_cut_volume* cut, double t0, double t1);

/* A blade's edge met edge `edge` at fraction f from its first end: the
 * edge is refined there (each tetrahedron on it bisected), or its end put
 * on the cut. `before` holds 3 forces a vertex slot, moved with the masses. */
void sb_cut_volume_cross(struct sb_solver* solver, sb_cut_volume* cut, uint32_t edge, double f, double* before);

/* After the step's crossings: the vertices on the cut split, one per group
 * of tetrahedra joined through faces that are not cut; then the edges and
 * the boundary faces found again. */
void sb_cut_volume_separate(struct sb_solver* solver, sb_cut_volume* cut, double* before);

/* The vertices in use (the model's, then the new ones). */
uint32_t sb_cut_volume_vertex_count(const sb_cut_volume* cut);
/* The tetrahedron slots (in use and reserved). */
uint32_t sb_cut_volume_capacity(const sb_cut_volume* cut);
/* The face slots (in use and reserved). */
uint32_t sb_cut_volume_face_capacity(const sb_cut_volume* cut);
/* Refinements and splits not made for want of room. */
uint32_t sb_cut_volume_refused(const sb_cut_volume* cut);

/* The saved state (kernels/solver/solver_state.c): counts, flags, and the
 * working copy's vertex, tetrahedron and face arrays. */
void sb_cut_volume_save(const sb_cut_volume* cut, sb_sections_writer* w);
void sb_cut_volume_load(struct sb_solver* solver, sb_cut_volume* cut, sb_cursor* r);

#endif
