/* Private: the scalar reference for the per-edge terms (kernels/forces/reference_edges.c). */
#ifndef SB_REFERENCE_EDGES_H
#define SB_REFERENCE_EDGES_H

#include "mesh/model_internal.h"

/* Bond stretch (Eq. 3) when spring is false; damped spring (Eq. 2) when true. */
sb_status sb_reference_edges(const sb_model* m, bool spring, const double* x, const double* v, double* f,
                             double* energy, sb_error* err);

#endif
