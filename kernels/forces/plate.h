/* Private: a flat sheet's plate bending, one stencil per membrane
 * (kernels/forces/plate.c; the model's layout in mesh/model_internal.h). */
#ifndef SB_PLATE_H
#define SB_PLATE_H

#include "common/geometry.h"
#include "mesh/model_internal.h"

/* Plate t at its vertices' positions x[plate_nodes[t]]: its energy; its
 * forces −H (x − rest) into f (3 per vertex, may be NULL) and its constant
 * stiffness H ⊗ I₃ into k (row-major, 3 nodes square, may be NULL). */
double sb_plate_element(const sb_model* m, uint32_t t, const sb_vec3* x, double* f, double* k);

/* Every plate's forces added to f (3n interleaved); the energy. */
double sb_reference_plates(const sb_model* m, const double* x, double* f);

#endif
