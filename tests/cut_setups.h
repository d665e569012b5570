/* What the cutting tests (test_cut_line.c, test_cut_volume.c) run each
 * check on: velocity Verlet on the scalar reference kernels and on the
 * fast ones (whose model is built again after each step that cut), and
 * implicit Euler, matrix-free on the fast kernels and with the assembled
 * matrix and its factorization (both built again after a cut) on the
 * reference ones; and the solver that cuts with one blade, no gravity. */
#ifndef CUT_SETUPS_H
#define CUT_SETUPS_H

#include "test_util.h"

enum { SETUPS = 4 };
static const struct {
    sb_kernels kernels;
    sb_integrator integrator;
    sb_linear_solver linear;
    const char* name;
} setups[SETUPS] = {
    {SB_KERNELS_REFERENCE, SB_INTEGRATOR_VELOCITY_VERLET, SB_LINEAR_AUTO, "reference kernels"},
    {SB_KERNELS_FAST, SB_INTEGRATOR_VELOCITY_VERLET, SB_LINEAR_AUTO, "fast kernels"},
    {SB_KERNELS_FAST, SB_INTEGRATOR_IMPLICIT_EULER, SB_LINEAR_CG, "implicit Euler, fast kernels, CG"},
    {SB_KERNELS_REFERENCE, SB_INTEGRATOR_IMPLICIT_EULER, SB_LINEAR_CHOLESKY, "implicit Euler, reference, Cholesky"}};

/* Setup k on `threads` threads, cutting through along `blade`, at most
 * `max_splits` splits. */
static inline sb_solver_def cut_setup_def(const sb_blade_def* blade, int threads, int k, int max_splits) {
    sb_solver_def def = sb_default_solver_def();
    def.kernels = setups[k].kernels;
    def.integrator = setups[k].integrator;
    def.implicit_solver = setups[k].linear;
    def.runtime.threads = threads;
    def.gravity[1] = 0.0;
    def.gravity[2] = 0.0;
    def.blades = blade;
    def.blade_count = 1;
    def.cut_through = true;
    def.max_splits = max_splits;
    return def;
}

#endif
