/* Private: the scalar reference for the bending term (kernels/forces/reference_hinges.c). */
#ifndef SB_REFERENCE_HINGES_H
#define SB_REFERENCE_HINGES_H

#include "mesh/model_internal.h"

/* Dihedral hinges. */
sb_status sb_reference_hinges(const sb_model* m, const double* x, double* f, double* energy, sb_error* err);

#endif
