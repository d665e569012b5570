/* Byte model: the memory traffic of one Verlet step of the fast path as
 * it is laid out (kernels/state/solver_fast.c), with s = sizeof(sb_real) (4 in
 * float, 8 in double) and 4-byte vertex indices. It assumes the gathers of
 * a vertex's neighbours hit cache (the blocked coloring keeps a block's
 * vertices there), so each array crosses the memory bus once per pass that
 * streams it. The working state is packed x y z w, 4 s per vertex and array;
 * mass and inverse mass are one real a vertex, s each:
 *   per vertex   drift: reads mass, inverse mass (2 s), x, Δ, f and writes
 *                Δ, x, f (6 packed arrays; the half-step velocity stays in
 *                cache when nothing reads it before the kick, and the
 *                gravitational energy and the position check use the chunk
 *                in cache); forces: x read, f read and written (3); kick:
 *                reads mass, inverse mass (2 s), f, Δ (the half-step
 *                velocity is Δ / dt) and writes v (3): 12 packed arrays of
 *                4 s and 4 scalars = 52 s (gravity m g is the mass times a
 *                constant, no stream of its own)
 *   per triangle 3 indices (12 B) + 3 rest cosines + 3 rest lengths (6 s)
 *                + 1 byte of flags: which of its edges' bonds it owns
 *                (kernels/forces/fast_model.h; every bond of these meshes is on a
 *                triangle's edge, and an owned bond's rest length is the
 *                edge's, so its constants, uniform, cost nothing more)
 *   per bond     only the bonds no triangle owns: none on these meshes
 *   per hinge    (--all-terms only) fused into a triangle that is its
 *                wing (kernels/forces/fast_corners.c): its other vertex (4 B) +
 *                φ0 (s), and a byte per triangle for the edges it carries
 *   damping      (--all-terms) the drift writes the half-step velocities
 *                and the force pass reads them (the kick reads them instead
 *                of Δ): 8 s per vertex
 *   carries      (float only: kernels/state/vertex_state.h) the positions'
 *                rounding carries, packed like them: the drift reads and
 *                writes them, the force pass reads them (3 packed arrays):
 *                12 s per vertex
 * Uniform constants are one value, not an array, and cost nothing.
 * Float, default terms: 256 B per vertex (208 without the carries), 37 B
 * per triangle; a 1M-vertex sheet (2M triangles) moves about 330 MB per
 * step (282 MB without the carries, 362 MB when the kick read the positions
 * and the drift wrote the velocities every step).
 * Writes are counted once (no write-allocate), as STREAM counts them.
 *
 * Flop model: add, subtract, multiply, divide and square root each count 1
 * (an FMA counts 2); energies are not counted (a step need not compute
 * them). From the formulas in DESIGN.md:
 *   bond stretch: d = xj − xi (3), r² (5), r = √ (1), r − r0 (1),
 *     k(r − r0) (1), /r (1), f = that · d (3), fi += f, fj −= f (6): 21
 *   damped spring (--all-terms, sharing r and d): ks (r − r0) and the sum
 *     (2), vj − vi (3), its dot with d (5), d/r times it (2): 12 more
 *   triangle, shared by its three corners: 3 edge vectors (9), their
 *     squared lengths (15), 3 √ (3), 3 reciprocals (3), 3 unit vectors (9),
 *     3 length deviations (3): 42
 *   per corner: c = â·b̂ (5), c − c0 (1), S (1), g = kθ dc + ksb S (3),
 *     h = ksb dc (1), F_j = −(g/A)(b̂ − c â) − h â (1 + 3 + 3 + 3 + 3 + 3 =
 *     16), F_k likewise (16), F_i = −F_j − F_k (3), three accumulations (9):
 *     55, so 42 + 3 · 55 = 207 per triangle, 69 per angle
 *   hinge (--all-terms): the dihedral (edge, two normals, atan2) and its
 *     gradient on four vertices: about 120
 *   per vertex: gravity m g (3), Verlet x⁺ = x + (x − x⁻) σ + w f and
 *     v = (x⁺ − x)/dt (3 · 7 + 1): 25
 * So the default step costs 21 per bond + 207 per triangle + 25 per vertex:
 * about 0.5 Gflop per step on the 1M-vertex sheet, 56 per element. */
#include "bench/bench_model.h"

#define SB_FLOPS_BOND 21.0
#define SB_FLOPS_SPRING 12.0
#define SB_FLOPS_TRIANGLE 207.0
#define SB_FLOPS_HINGE 120.0
#define SB_FLOPS_VERTEX 25.0

sb_bench_counts sb_bench_count(const sb_model* model, bool all_terms) {
    sb_bench_counts c = {0};
    const double s = sizeof(sb_real);
    c.vertices = sb_model_vertex_count(model);
    c.bonds = sb_model_bond_count(model);
    c.triangles = sb_model_triangle_count(model);
    c.hinges = sb_model_hinge_count(model);
    c.elements = c.bonds + 3 * c.triangles + c.hinges;
    double vertex_bytes = (52.0 + (SB_DOUBLE ? 0.0 : 12.0) + (all_terms ? 8.0 : 0.0)) * s;
    double triangle_bytes = 12.0 + 6.0 * s + (all_terms ? 2.0 : 1.0), hinge_bytes = 4.0 + s;
    c.bytes_per_step = vertex_bytes * c.vertices + triangle_bytes * c.triangles + hinge_bytes * c.hinges;
    double bond_flops = SB_FLOPS_BOND + (all_terms ? SB_FLOPS_SPRING : 0.0);
    c.flops_per_step = SB_FLOPS_VERTEX * c.vertices + bond_flops * c.bonds + SB_FLOPS_TRIANGLE * c.triangles +
                       SB_FLOPS_HINGE * c.hinges;
    return c;
}

const char* sb_bench_byte_model_text(void) {
    return "bytes/step = 52s per vertex (12 packed x y z w streams and 4 of one real, mass and inverse mass,"
           " over drift, forces, kick; in float +12s, the positions' carries read and written by the drift and read"
           " by the forces) + (13+6s) per"
           " triangle (indices, rest cosines and lengths, a byte of owned-bond flags; every bond fused) [with"
           " --all-terms: +8s per vertex (half-step velocities written and read for damping), (4+s) per hinge fused "
           "into a triangle and a byte per"
           " triangle for the edges it carries]; s = sizeof(sb_real);"
           " gathers assumed cached, writes counted once";
}

const char* sb_bench_flop_model_text(void) {
    return "flops/step = 21 per bond + 207 per triangle (3 corners of angle bend + stretch-bend) + 25 per vertex"
           " (gravity + Verlet) [+12 per bond, 120 per hinge with --all-terms]; FMA = 2, sqrt = div = 1";
}
