/* Scalar reference for the bending term: a hinge on each interior edge.
 *
 * Why a dihedral term and not bend springs: a spring between the two
 * opposite vertices changes length only to second order in the fold angle
 * of a flat sheet, so its energy grows as φ⁴ and a flat sheet barely resists
 * small folds. E = ½ k (φ − φ0)² resists them at first order.
 *
 * φ is the signed dihedral angle of kernels/geometry.h. With E = e1 − e0 and
 * the wing normals n0, n1 (lengths twice the wing areas), the exact
 * gradient is −(u_o0, u_o1, u_e0, u_e1):
 *   u_o0 = |E| n0/|n0|²,  u_o1 = |E| n1/|n1|²,
 *   u_e0 = ((o0 − e1)·Ê) n0/|n0|² + ((o1 − e1)·Ê) n1/|n1|²,
 *   u_e1 = −((o0 − e0)·Ê) n0/|n0|² − ((o1 − e0)·Ê) n1/|n1|²,
 * (each 1/height of the moving vertex, along its wing's normal; they sum to
 * zero), so F = k (φ − φ0) u (common/geometry.h: sb_hinge_gradient). A wing
 * that collapses (|n| → 0: its height below SB_MIN_WING_RATIO of the edge)
 * is reported. */
#include "kernels/forces/reference_hinges.h"
#include "common/error.h"
#include "common/geometry.h"

sb_status sb_reference_hinges(const sb_model* m, const double* x, double* f, double* energy, sb_error* err) {
    double total = 0.0;
    for (uint32_t h = 0; h < m->hinge_count; h++) {
        double k = m->hinge_k[h];
        if (k == 0.0) continue;
        uint32_t e0 = m->hinge_e0[h], e1 = m->hinge_e1[h], o0 = m->hinge_o0[h], o1 = m->hinge_o1[h];
        const sb_vec3 p[4] = {sb_v3(x + 3 * e0), sb_v3(x + 3 * e1), sb_v3(x + 3 * o0), sb_v3(x + 3 * o1)};
        sb_vec3 u[4];
        double phi;
        if (!sb_hinge_gradient(p, &phi, u))
            return sb_error_set(err, SB_ERR_DEGENERATE, "hinge %u (edge %u-%u): a wing collapsed", h, e0, e1);
        double delta = sb_angle_difference(phi, m->hinge_phi0[h]);
        sb_v3_add_to(f + 3 * o0, u[2], k * delta);
        sb_v3_add_to(f + 3 * o1, u[3], k * delta);
        sb_v3_add_to(f + 3 * e0, u[0], k * delta);
        sb_v3_add_to(f + 3 * e1, u[1], k * delta);
        total += 0.5 * k * delta * delta;
    }
    *energy = total;
    return SB_OK;
}
