/* Scalar reference for the per-edge terms.
 *
 * Bond stretch (Eq. 3): E = ½ k (r − r0)², F_i = k (r − r0) u, F_j = −F_i,
 * u = (x_j − x_i)/r. The damped spring (Eq. 2) adds d (v_j − v_i)·u along u;
 * its dissipation rate is −Σ d ((v_j − v_i)·u)². */
#include "kernels/forces/reference_edges.h"
#include "kernels/forces/reference_terms.h"
#include "common/error.h"
#include "common/geometry.h"

sb_status sb_reference_edges(const sb_model* m, bool spring, const double* x, const double* v, double* f,
                             double* energy, sb_error* err) {
    const double* stiffness = spring ? m->spring_k : m->bond_k;
    double total = 0.0;
    for (uint32_t e = 0; e < m->bond_count; e++) {
        double k = stiffness[e], d = spring ? m->spring_damping[e] : 0.0;
        if (k == 0.0 && d == 0.0) continue;
        uint32_t i = m->bond_i[e], j = m->bond_j[e];
        sb_vec3 delta = sb_v3_sub(sb_v3(x + 3 * j), sb_v3(x + 3 * i));
        double r = sb_v3_length(delta), r0 = m->bond_r0[e];
        if (!(r >= SB_COLLAPSE_RATIO * r0))
            return sb_error_set(err, SB_ERR_DEGENERATE, "bond %u (%u, %u) collapsed: length %g m, rest %g m", e, i, j,
                                r, r0);
        sb_vec3 u = sb_v3_scale(delta, 1.0 / r);
        double magnitude = k * (r - r0);
        if (v && d != 0.0) magnitude += d * sb_v3_dot(sb_v3_sub(sb_v3(v + 3 * j), sb_v3(v + 3 * i)), u);
        sb_v3_add_to(f + 3 * i, u, magnitude);
        sb_v3_add_to(f + 3 * j, u, -magnitude);
        total += 0.5 * k * (r - r0) * (r - r0);
    }
    *energy = total;
    return SB_OK;
}
