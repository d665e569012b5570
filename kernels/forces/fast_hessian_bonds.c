/* The bonds' second derivatives (kernels/forces/fast_hessian.h): the force of
 * kernels/forces/fast_bonds.c, bond stretch and the damped spring's spring part
 * F_i = (k_bond + k_spring)(r − r0) u, F_j = −F_i, on wide duals; the
 * spring's damping c ((v_j − v_i)·u) u contributes its velocity derivative
 * c ((ẋ_j − ẋ_i)·u) u (D's product), weighted by `damping`. */
#include "kernels/forces/fast_hessian_bonds.h"
#include "kernels/forces/fast_hessian.h"

static void sb_wdual_bond(const sb_fast_model* m, uint32_t s, sb_wide damping, const sb_wdvec3* x, sb_wdvec3* f) {
    sb_wide k = sb_w_add(sb_w_constant(m->bond_k, s), sb_w_constant(m->spring_k, s));
    sb_wide c = m->has_damping ? sb_w_constant(m->spring_damping, s) : sb_w_set(0);
    f[0] = sb_wdual_bond_force(x[0], x[1], k, sb_w_load(m->bond_r0 + s), c, damping);
    f[1] = sb_wdv_neg(f[0]);
}

int sb_fast_bonds_hessian(const sb_fast_model* m, const sb_fast_frame* frame, uint32_t begin, uint32_t end, bool serial,
                          double* unused) {
    (void)unused;
    uint32_t* const vertex[2] = {m->bond_i, m->bond_j};
    sb_hessian_pass(m, frame, begin, end, serial, 2, vertex, sb_wdual_bond);
    return 0;
}
