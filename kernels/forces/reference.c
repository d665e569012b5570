/* The scalar reference's entry points: one term, or all enabled terms. */
#include "softbond/reference.h"
#include "kernels/forces/reference_edges.h"
#include "kernels/forces/reference_corners.h"
#include "kernels/forces/reference_hinges.h"
#include "kernels/forces/reference_tets.h"
#include "kernels/forces/reference_membranes.h"
#include "kernels/forces/plate.h"
#include "common/error.h"

#include <string.h>

double sb_energies_internal(const sb_energies* e) {
    double sum = 0.0;
    for (int t = 0; t < SB_TERM_COUNT; t++) sum += e->term[t];
    return sum;
}

double sb_energies_total(const sb_energies* e) { return sb_energies_internal(e) + e->kinetic + e->gravity; }

sb_status sb_reference_term(const sb_model* m, sb_term term, const double* x, const double* v, double* f,
                            double* energy, sb_error* err) {
    *energy = 0.0;
    if (!sb_model_term_enabled(m, term)) return SB_OK;
    switch (term) {
    case SB_TERM_BOND: return sb_reference_edges(m, false, x, v, f, energy, err);
    case SB_TERM_SPRING: return sb_reference_edges(m, true, x, v, f, energy, err);
    case SB_TERM_ANGLE: return sb_reference_corners(m, 1.0, 0.0, x, f, energy, err);
    case SB_TERM_STRETCH_BEND: return sb_reference_corners(m, 0.0, 1.0, x, f, energy, err);
    case SB_TERM_BEND: { /* a curved sheet's hinges and a flat sheet's plates */
        sb_status status = sb_reference_hinges(m, x, f, energy, err);
        *energy += sb_reference_plates(m, x, f);
        return status;
    }
    case SB_TERM_COROTATED: return sb_reference_tets(m, x, v, f, energy, err);
    case SB_TERM_MEMBRANE: return sb_reference_membranes(m, x, v, f, energy, err);
    default: return sb_error_set(err, SB_ERR_INVALID, "unknown term %d", (int)term);
    }
}

sb_status sb_reference_forces(const sb_model* m, const double* x, const double* v, double* f, sb_energies* energies,
                              sb_error* err) {
    memset(f, 0, 3 * (size_t)m->vertex_count * sizeof *f);
    memset(energies, 0, sizeof *energies);
    for (int t = 0; t < SB_TERM_COUNT; t++) {
        sb_status status = sb_reference_term(m, (sb_term)t, x, v, f, &energies->term[t], err);
        if (status != SB_OK) return status;
    }
    return SB_OK;
}
