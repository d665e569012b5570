/* The bond's elastic force on dual numbers (kernels/forces/hessian.h): bond
 * stretch and the damped spring's spring part, E = ½ (k_bond + k_spring)
 * (r − r0)², F_i = k (r − r0) u, F_j = −F_i; and the spring's damping
 * block. The same formulas as kernels/forces/reference_edges.c. */
#include "kernels/forces/hessian_edges.h"
#include "kernels/forces/hessian.h"
#include "kernels/forces/reference_terms.h"

static double sb_bond_stiffness(const sb_model* m, uint32_t bond) {
    double k = 0.0;
    if (m->term_enabled[SB_TERM_BOND]) k += m->bond_k[bond];
    if (m->term_enabled[SB_TERM_SPRING]) k += m->spring_k[bond];
    return k;
}

void sb_bond_forces_dual(const sb_model* m, uint32_t bond, const sb_dvec3* x, sb_dvec3* f, bool* collapsed) {
    double k = sb_bond_stiffness(m, bond), r0 = m->bond_r0[bond];
    sb_dvec3 delta = sb_dv3_sub(x[1], x[0]);
    sb_dual r = sb_dv3_length(delta);
    *collapsed = !(r.v >= SB_COLLAPSE_RATIO * r0);
    if (*collapsed) return;
    sb_dvec3 u = sb_dv3_scale(delta, sb_d_div(sb_d_const(1.0), r));
    sb_dual magnitude = sb_d_scale(sb_d_sub(r, sb_d_const(r0)), k);
    f[0] = sb_dv3_scale(u, magnitude);
    f[1] = sb_dv3_scale(u, sb_d_scale(magnitude, -1.0));
}

bool sb_bond_damping_block(const sb_model* m, uint32_t bond, const double* x, double* block) {
    double d = m->term_enabled[SB_TERM_SPRING] ? m->spring_damping[bond] : 0.0;
    if (d == 0.0) return false;
    uint32_t i = m->bond_i[bond], j = m->bond_j[bond];
    sb_vec3 delta = sb_v3_sub(sb_v3(x + 3 * j), sb_v3(x + 3 * i));
    double r = sb_v3_length(delta);
    if (!(r >= SB_COLLAPSE_RATIO * m->bond_r0[bond])) return false;
    double u[3] = {delta.x / r, delta.y / r, delta.z / r};
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) block[3 * a + b] = d * u[a] * u[b];
    return true;
}

/* The bond's stiffness block k (u uᵀ + σ (I − u uᵀ)) on x_j − x_i,
 * σ = 1 − r0/r, in closed form (`definite` clamps σ at 0,
 * kernels/forces/hessian.h), and its force on vertex i, k (r − r0) u; false when
 * the bond collapsed. */
static bool sb_bond_block(const sb_model* m, uint32_t bond, const sb_vec3* x, bool definite, double* h,
                          sb_vec3* force_on_i) {
    double stiffness = sb_bond_stiffness(m, bond), r0 = m->bond_r0[bond];
    sb_vec3 delta = sb_v3_sub(x[1], x[0]);
    double r = sb_v3_length(delta);
    if (!(r >= SB_COLLAPSE_RATIO * r0)) return false;
    double u[3] = {delta.x / r, delta.y / r, delta.z / r}, sideways = 1.0 - r0 / r;
    if (definite) sideways = fmax(0.0, sideways);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            h[3 * a + b] = stiffness * ((1.0 - sideways) * u[a] * u[b] + (a == b ? sideways : 0.0));
    *force_on_i = sb_v3_scale(delta, stiffness * (r - r0) / r);
    return true;
}

/* The 6 × 6 matrix [[H, −H], [−H, H]] of the bond's block. */
static bool sb_bond_matrix(const sb_model* m, uint32_t bond, const sb_vec3* x, bool definite, double* k) {
    double h[9];
    sb_vec3 force;
    if (!sb_bond_block(m, bond, x, definite, h, &force)) return false;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            k[a * 6 + b] = k[(a + 3) * 6 + b + 3] = h[3 * a + b];
            k[a * 6 + b + 3] = k[(a + 3) * 6 + b] = -h[3 * a + b];
        }
    return true;
}

bool sb_bond_stiffness_matrix(const sb_model* m, uint32_t bond, const sb_vec3* x, double* k) {
    return sb_bond_matrix(m, bond, x, false, k);
}

bool sb_bond_jacobian_blocks(const sb_model* m, uint32_t bond, const sb_vec3* x, bool definite, double dt,
                             double* blocks) {
    double stiffness = sb_bond_stiffness(m, bond), r0 = m->bond_r0[bond];
    double damping = m->term_enabled[SB_TERM_SPRING] ? m->spring_damping[bond] : 0.0;
    sb_vec3 delta = sb_v3_sub(x[1], x[0]);
    double r = sb_v3_length(delta);
    if (!(r >= SB_COLLAPSE_RATIO * r0)) return false;
    double u[3] = {delta.x / r, delta.y / r, delta.z / r}, sideways = 1.0 - r0 / r;
    if (definite) sideways = fmax(0.0, sideways);
    /* dt² k (u uᵀ + σ (I − u uᵀ)) + dt d u uᵀ = s I + t u uᵀ */
    double s = dt * dt * stiffness * sideways, t = dt * dt * stiffness * (1.0 - sideways) + dt * damping;
    double* h = blocks; /* (0, 0); (1, 1) the same, (0, 1) and (1, 0) its negative */
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) h[3 * a + b] = t * u[a] * u[b] + (a == b ? s : 0.0);
    for (int k = 0; k < 9; k++) blocks[27 + k] = h[k], blocks[9 + k] = blocks[18 + k] = -h[k];
    return true;
}

bool sb_bond_vertex_share(const sb_model* m, uint32_t bond, const sb_vec3* x, int place, double* f, double* block) {
    double h[9];
    sb_vec3 force;
    if (!sb_bond_block(m, bond, x, true, h, &force)) return false;
    double sign = place == 0 ? 1.0 : -1.0; /* a stretched bond pulls i towards j */
    f[0] += sign * force.x, f[1] += sign * force.y, f[2] += sign * force.z;
    for (int k = 0; k < 9; k++) block[k] += h[k]; /* both diagonal blocks are H */
    return true;
}

void sb_bond_definite(const sb_model* m, uint32_t bond, const sb_vec3* x, double* k) {
    if (!sb_bond_matrix(m, bond, x, true, k)) k[0] = NAN;
}
