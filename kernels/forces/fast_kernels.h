/* Private: what the fast force kernels share; each kernel is declared in
 * its own header (kernels/forces/fast_bonds.h, fast_corners.h, fast_hinges.h).
 * Each processes the elements [begin, end) of one color of its group in
 * blocks of SB_WIDTH lanes (one lane at a time when serial, for the
 * overflow color), adds forces to frame->f and its energies to energy[],
 * and returns its flags: SB_KERNEL_COLLAPSED when an edge collapsed,
 * SB_KERNEL_NEAR_LIMIT when a bond's length is at or past the margin of its
 * break limits (kernels/interaction/breakage.c then checks them exactly;
 * without, it need not look). Forces are the same formulas as the scalar
 * reference (kernels/reference_*.c), in sb_real. */
#ifndef SB_FAST_KERNELS_H
#define SB_FAST_KERNELS_H

#include "kernels/forces/fast_model.h"
#include "kernels/runtime/team.h"

/* What the kernels read and write: positions, velocities (for damping) and
 * forces, packed x y z w per vertex (see kernels/runtime/wide.h). carries4
 * holds the compensated drifts' carries, packed alike (zero in a double
 * build): the force kernels evaluate at positions + carries, as the
 * reference does (kernels/forces/fast_block.h, sb_wv_vertex_at). */
typedef struct sb_fast_frame {
    const sb_real* positions4;
    const sb_real* carries4;
    const sb_real* velocities4;
    sb_real* forces4;
} sb_fast_frame;

enum { SB_KERNEL_COLLAPSED = 1, SB_KERNEL_NEAR_LIMIT = 2 };

typedef int (*sb_fast_kernel)(const sb_fast_model*, const sb_fast_frame*, uint32_t, uint32_t, bool, double*);

#endif
