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
 * zero), so F = k (φ − φ0) u. A wing that collapses (|n| → 0) is reported. */
#include "kernels/reference_terms.h"
#include "common/error.h"
#include "common/geometry.h"

/* A wing whose height is below this fraction of its edge has collapsed. */
#define SB_MIN_WING_RATIO 1e-12

sb_status sb_reference_hinges(const sb_model* m, const double* x, double* f, double* energy, sb_error* err) {
    double total = 0.0;
    for (uint32_t h = 0; h < m->hinge_count; h++) {
        double k = m->hinge_k[h];
        if (k == 0.0) continue;
        uint32_t e0 = m->hinge_e0[h], e1 = m->hinge_e1[h], o0 = m->hinge_o0[h], o1 = m->hinge_o1[h];
        sb_vec3 pe0 = sb_v3(x + 3 * e0), pe1 = sb_v3(x + 3 * e1), po0 = sb_v3(x + 3 * o0), po1 = sb_v3(x + 3 * o1);
        sb_hinge_geometry g = sb_hinge_measure(pe0, pe1, po0, po1);
        double n0_sq = sb_v3_dot(g.n0, g.n0), n1_sq = sb_v3_dot(g.n1, g.n1), edge_sq = g.edge_length * g.edge_length;
        double limit = SB_MIN_WING_RATIO * edge_sq;
        if (!(g.edge_length > 0.0) || !(n0_sq > limit * limit) || !(n1_sq > limit * limit))
            return sb_error_set(err, SB_ERR_DEGENERATE, "hinge %u (edge %u-%u): a wing collapsed", h, e0, e1);
        sb_vec3 w0 = sb_v3_scale(g.n0, 1.0 / n0_sq), w1 = sb_v3_scale(g.n1, 1.0 / n1_sq);
        sb_vec3 unit_edge = sb_v3_scale(g.edge, 1.0 / g.edge_length);
        sb_vec3 u_o0 = sb_v3_scale(w0, g.edge_length), u_o1 = sb_v3_scale(w1, g.edge_length);
        sb_vec3 u_e0 = sb_v3_add(sb_v3_scale(w0, sb_v3_dot(sb_v3_sub(po0, pe1), unit_edge)),
                                 sb_v3_scale(w1, sb_v3_dot(sb_v3_sub(po1, pe1), unit_edge)));
        sb_vec3 u_e1 = sb_v3_add(sb_v3_scale(w0, -sb_v3_dot(sb_v3_sub(po0, pe0), unit_edge)),
                                 sb_v3_scale(w1, -sb_v3_dot(sb_v3_sub(po1, pe0), unit_edge)));
        double delta = sb_angle_difference(g.phi, m->hinge_phi0[h]);
        sb_v3_add_to(f + 3 * o0, u_o0, k * delta);
        sb_v3_add_to(f + 3 * o1, u_o1, k * delta);
        sb_v3_add_to(f + 3 * e0, u_e0, k * delta);
        sb_v3_add_to(f + 3 * e1, u_e1, k * delta);
        total += 0.5 * k * delta * delta;
    }
    *energy = total;
    return SB_OK;
}
