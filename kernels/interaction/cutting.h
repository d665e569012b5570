/* Private: blades that sever bonds (kernels/interaction/cutting.c). */
#ifndef SB_CUTTING_H
#define SB_CUTTING_H

#include "softbond/blade.h"
#include "mesh/model_internal.h"

typedef struct sb_cutting sb_cutting;

/* The blades checked and copied (paths included) into *out; an error
 * naming the blade when one is bad. */
sb_status sb_cutting_create(const sb_blade_def* blades, uint32_t count, sb_cutting** out, sb_error* err);
void sb_cutting_destroy(sb_cutting* cutting);

/* Room for the step-start positions of vertex_count vertices; false when
 * out of memory. */
bool sb_cutting_room(sb_cutting* cutting, uint32_t vertex_count);

/* Keeps the packed positions p (4 per vertex) as the step's start. */
void sb_cutting_start(sb_cutting* cutting, const sb_real* p, uint32_t vertex_count);

/* Calls meet(user, bond, along) for each bond not skipped that meets a
 * blade's edge while both move over the step from t0 to t1: the bond's
 * ends from their positions at the step's start (sb_cutting_start) to the
 * packed positions p, the edge along its path; `along` is where along the
 * bond they met, a fraction from its first end. Blades in order, bonds in
 * bond order. Returns the bonds met. */
uint32_t sb_cutting_pass(const sb_cutting* cutting, const sb_model* model, const sb_real* p, const uint8_t* skip,
                         double t0, double t1, void (*meet)(void* user, uint32_t bond, double along), void* user);

/* The planes the blades' edges sweep over the step from t0 to t1 (exact
 * for a blade that translates), 4 numbers each into planes: the unit
 * normal n and −n · (a point on it), so that n · x + that is the signed
 * distance of x. A blade whose edge stands still or moves along itself
 * sweeps no plane and is left out. Returns the planes written. */
uint32_t sb_cutting_planes(const sb_cutting* cutting, double t0, double t1, double* planes);
/* The blades. */
uint32_t sb_cutting_count(const sb_cutting* cutting);

#endif
