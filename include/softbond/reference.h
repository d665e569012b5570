/** @file
 * The scalar reference: every force term in double precision, plain loops,
 * the exact negative gradient of each energy. It is the yardstick the fast
 * kernels are tested against and what `softbond eval` uses by default. */
#ifndef SOFTBOND_REFERENCE_H
#define SOFTBOND_REFERENCE_H

#include "softbond/export.h"

#include "softbond/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Energies in joules: the potential of each term, and for a solver's state
 * the kinetic energy and the gravitational potential (−Σ m g·x). */
typedef struct sb_energies {
    double term[SB_TERM_COUNT]; /**< J, each term's potential, indexed by sb_term (0 for a term that is off) */
    double kinetic;             /**< J, Σ ½ m |v|² */
    double gravity;             /**< J, −Σ m g·x */
} sb_energies;

/** Sum of the term potentials (without kinetic and gravity). */
SB_API double sb_energies_internal(const sb_energies* energies);
/** internal + kinetic + gravity. */
SB_API double sb_energies_total(const sb_energies* energies);

/** Adds one term's forces to `forces` (3n, x y z interleaved) and stores its
 * energy in *energy. positions are 3n interleaved; velocities (3n or NULL for
 * zero) only matter for the spring's damping. A term that is off adds
 * nothing. Returns SB_ERR_DEGENERATE, naming the element, when an edge the
 * term needs has collapsed (length below 1e-9 of its rest length): the
 * direction is then undefined and is never divided by. */
SB_API sb_status sb_reference_term(const sb_model* model, sb_term term, const double* positions,
                                   const double* velocities, double* forces, double* energy, sb_error* err);

/** All enabled terms: overwrites forces and fills energies->term[]. */
SB_API sb_status sb_reference_forces(const sb_model* model, const double* positions, const double* velocities,
                                     double* forces, sb_energies* energies, sb_error* err);

#ifdef __cplusplus
}
#endif
#endif
