/* Private: what the per-term scalar reference functions behind
 * sb_reference_term share. Each is declared in its own header
 * (kernels/forces/reference_edges.h, reference_corners.h,
 * reference_hinges.h), adds its forces to f (3n interleaved) and returns its
 * energy through *energy; velocities may be NULL. */
#ifndef SB_REFERENCE_TERMS_H
#define SB_REFERENCE_TERMS_H

/* An edge shorter than this fraction of its rest length has collapsed. */
#define SB_COLLAPSE_RATIO 1e-9

#endif
