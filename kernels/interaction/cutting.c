/* Cutting: a blade's edge severs the bonds it crosses over a step.
 *
 * The sweep is continuous in time: over a step both the blade's edge and
 * each bond move, the edge's ends between its poses at the step's start
 * and end, the bond's ends between their positions at the step's start
 * (kept by the begin hook) and at its end, each linearly in the step's
 * time tau in [0, 1]. The bond crosses the edge when the two segments meet
 * at some tau: they are then coplanar, so the volume
 * V(tau) = (b - a) . ((x - a) x (y - a)) of the edge (a, b) and the bond
 * (x, y) vanishes there. V is a cubic in tau whose coefficients come from
 * the ends' start values and motions; it is split into monotone pieces at
 * the roots of V' and each piece whose ends differ in sign is bisected to
 * its root (a fixed count of halvings: the same answer for any thread
 * count), where the two segments' closest points must lie within both.
 * So a bond that moves as fast as the blade, or faster, cannot slip past
 * it, and a blade held still cuts tissue pulled across it; for a bond at
 * rest it is the test of the bond against the surface the edge swept (exact
 * for a blade that translates; the usual linear approximation of the
 * ruled surface when it turns over a short step). A bounding-box test of
 * the bond's start and end ends against the edge's comes first, so a step
 * costs one box test per unbroken bond and blade; the rest is in double. */
#include "kernels/interaction/cutting.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "common/error.h"
#include "common/geometry.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct sb_blade {
    double a[3], b[3], center[3];
    sb_keyframe* path;
    uint32_t path_count;
    sb_interpolation interpolation;
} sb_blade;

struct sb_cutting {
    sb_blade* blades;
    uint32_t count;
    sb_real* start; /* the vertices' positions at the step's start, packed x y z w */
};

static sb_status sb_blade_check(uint32_t k, const sb_blade_def* d, sb_error* err) {
    char owner[48];
    snprintf(owner, sizeof owner, "blade %u", k);
    double length2 = 0.0;
    for (int c = 0; c < 3; c++) {
        if (!isfinite(d->a[c]) || !isfinite(d->b[c]))
            return sb_error_set(err, SB_ERR_INVALID, "%s: its ends a and b must be finite", owner);
        length2 += (d->b[c] - d->a[c]) * (d->b[c] - d->a[c]);
    }
    if (!(length2 > 0.0)) return sb_error_set(err, SB_ERR_INVALID, "%s: its ends a and b are the same point", owner);
    return sb_path_check(owner, d->path, d->path_count, d->interpolation, err);
}

sb_status sb_cutting_create(const sb_blade_def* defs, uint32_t count, sb_cutting** out, sb_error* err) {
    *out = NULL;
    if (count > 0 && !defs) return sb_error_set(err, SB_ERR_INVALID, "blade_count is %u but blades is NULL", count);
    for (uint32_t k = 0; k < count; k++) {
        sb_status status = sb_blade_check(k, &defs[k], err);
        if (status != SB_OK) return status;
    }
    sb_cutting* c = calloc(1, sizeof *c);
    if (c) c->blades = calloc(count ? count : 1, sizeof *c->blades);
    bool ok = c && c->blades;
    for (uint32_t k = 0; ok && k < count; k++) {
        sb_blade* b = &c->blades[k];
        c->count++;
        const sb_blade_def* d = &defs[k];
        for (int i = 0; i < 3; i++) b->a[i] = d->a[i], b->b[i] = d->b[i], b->center[i] = 0.5 * (d->a[i] + d->b[i]);
        b->interpolation = d->interpolation;
        b->path_count = d->path_count;
        b->path = malloc((d->path_count ? d->path_count : 1) * sizeof *b->path);
        ok = b->path != NULL;
        if (ok && d->path_count) memcpy(b->path, d->path, d->path_count * sizeof *b->path);
    }
    if (!ok) {
        sb_cutting_destroy(c);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory for %u blades", count);
    }
    *out = c;
    return SB_OK;
}

void sb_cutting_destroy(sb_cutting* c) {
    if (!c) return;
    for (uint32_t k = 0; k < c->count; k++) free(c->blades[k].path);
    free(c->blades);
    free(c->start);
    free(c);
}

/* The edge's ends at the step's start and end: a0, b0, a1, b1. */
static void sb_edge_poses(const sb_blade* b, double t0, double t1, double ends[4][3]) {
    double pose[12];
    sb_path_pose(b->path, b->path_count, b->interpolation, b->center, t0, pose);
    sb_pose_apply(pose, b->a, ends[0]);
    sb_pose_apply(pose, b->b, ends[1]);
    sb_path_pose(b->path, b->path_count, b->interpolation, b->center, t1, pose);
    sb_pose_apply(pose, b->a, ends[2]);
    sb_pose_apply(pose, b->b, ends[3]);
}

/* A moving segment: its ends at tau = 0 (p, q) and their motions over the step (dp, dq). */
typedef struct sb_moving {
    sb_vec3 p, q, dp, dq;
} sb_moving;

static sb_vec3 sb_at(sb_vec3 start, sb_vec3 motion, double tau) { return sb_v3_add(start, sb_v3_scale(motion, tau)); }

/* The coefficients k[0] + k[1] tau + k[2] tau^2 + k[3] tau^3 of V(tau) for
 * the edge e and the bond s. */
static void sb_volume_cubic(const sb_moving* e, const sb_moving* s, double k[4]) {
    sb_vec3 e0 = sb_v3_sub(e->q, e->p), e1 = sb_v3_sub(e->dq, e->dp);
    sb_vec3 p0 = sb_v3_sub(s->p, e->p), p1 = sb_v3_sub(s->dp, e->dp);
    sb_vec3 q0 = sb_v3_sub(s->q, e->p), q1 = sb_v3_sub(s->dq, e->dp);
    sb_vec3 c0 = sb_v3_cross(p0, q0), c1 = sb_v3_add(sb_v3_cross(p0, q1), sb_v3_cross(p1, q0)),
            c2 = sb_v3_cross(p1, q1);
    k[0] = sb_v3_dot(e0, c0);
    k[1] = sb_v3_dot(e0, c1) + sb_v3_dot(e1, c0);
    k[2] = sb_v3_dot(e0, c2) + sb_v3_dot(e1, c1);
    k[3] = sb_v3_dot(e1, c2);
}

static double sb_cubic(const double k[4], double tau) { return ((k[3] * tau + k[2]) * tau + k[1]) * tau + k[0]; }

/* Whether the segments e and s, coplanar at tau, meet there: their closest
 * points lie within both (*along: where along s). Parallel ones do not cross. */
static bool sb_meet_at(const sb_moving* e, const sb_moving* s, double tau, double* along) {
    sb_vec3 a = sb_at(e->p, e->dp, tau), u = sb_v3_sub(sb_at(e->q, e->dq, tau), a);
    sb_vec3 x = sb_at(s->p, s->dp, tau), w = sb_v3_sub(sb_at(s->q, s->dq, tau), x), r = sb_v3_sub(x, a);
    double uu = sb_v3_dot(u, u), ww = sb_v3_dot(w, w), uw = sb_v3_dot(u, w), ur = sb_v3_dot(u, r), wr = sb_v3_dot(w, r);
    double det = uu * ww - uw * uw;
    if (!(det > 1e-12 * uu * ww)) return false;
    double along_edge = (ur * ww - wr * uw) / det, along_bond = (ur * uw - wr * uu) / det;
    *along = along_bond;
    return along_edge >= 0.0 && along_edge <= 1.0 && along_bond >= 0.0 && along_bond <= 1.0;
}

/* The root of V in [lo, hi], where V changes sign, by halving. */
static double sb_bisect(const double k[4], double lo, double hi) {
    double v_lo = sb_cubic(k, lo);
    for (int i = 0; i < 60; i++) {
        double mid = 0.5 * (lo + hi), v_mid = sb_cubic(k, mid);
        if ((v_mid <= 0.0) == (v_lo <= 0.0))
            lo = mid, v_lo = v_mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* The roots of V' in (0, 1), ascending, after 0 and before 1: the ends of
 * V's monotone pieces. Returns the count of ends. */
static int sb_monotone_ends(const double k[4], double ends[4]) {
    double a = 3.0 * k[3], b = 2.0 * k[2], c = k[1], roots[2];
    int n = 0, count = 0;
    if (a == 0.0) {
        if (b != 0.0) roots[n++] = -c / b;
    } else {
        double d = b * b - 4.0 * a * c;
        if (d > 0.0) {
            double q = -0.5 * (b + copysign(sqrt(d), b));
            roots[n++] = q / a;
            if (q != 0.0) roots[n++] = c / q;
        }
    }
    if (n == 2 && roots[1] < roots[0]) {
        double t = roots[0];
        roots[0] = roots[1], roots[1] = t;
    }
    ends[count++] = 0.0;
    for (int i = 0; i < n; i++)
        if (roots[i] > 0.0 && roots[i] < 1.0) ends[count++] = roots[i];
    ends[count++] = 1.0;
    return count;
}

/* Whether the moving edge and bond meet during the step (first), and where
 * along the bond (*along, a fraction from its first end). */
static bool sb_sweeps_meet(const sb_moving* edge, const sb_moving* bond, double* along) {
    double k[4], ends[4];
    sb_volume_cubic(edge, bond, k);
    if (k[0] == 0.0 && k[1] == 0.0 && k[2] == 0.0 && k[3] == 0.0) return false; /* coplanar throughout: not across */
    int count = sb_monotone_ends(k, ends);
    for (int i = 0; i + 1 < count; i++) {
        double lo = sb_cubic(k, ends[i]), hi = sb_cubic(k, ends[i + 1]);
        if ((lo > 0.0 && hi > 0.0) || (lo < 0.0 && hi < 0.0)) continue;
        double tau = lo == 0.0 ? ends[i] : hi == 0.0 ? ends[i + 1] : sb_bisect(k, ends[i], ends[i + 1]);
        if (sb_meet_at(edge, bond, tau, along)) return true;
    }
    return false;
}

static sb_vec3 sb_point(const sb_real* x) { return (sb_vec3){x[0], x[1], x[2]}; }

/* The bond from its ends' start positions (start, 4 per vertex) to their end ones (p). */
static sb_moving sb_bond_motion(const sb_real* start, const sb_real* p, uint32_t i, uint32_t j) {
    sb_vec3 p0 = sb_point(start + 4 * (size_t)i), q0 = sb_point(start + 4 * (size_t)j);
    return (sb_moving){p0, q0, sb_v3_sub(sb_point(p + 4 * (size_t)i), p0), sb_v3_sub(sb_point(p + 4 * (size_t)j), q0)};
}

/* Whether the four points x[4] all lie below lo or all above hi on some axis. */
static bool sb_box_apart(const sb_real* const x[4], const double lo[3], const double hi[3]) {
    int apart = 0;
    for (int a = 0; a < 3; a++) {
        int below = 1, above = 1;
        for (int c = 0; c < 4; c++) below &= x[c][a]<lo[a], above &= x[c][a]> hi[a];
        apart |= below | above;
    }
    return apart != 0;
}

bool sb_cutting_room(sb_cutting* c, uint32_t vertex_count) {
    c->start = calloc(4 * (size_t)vertex_count + 4, sizeof *c->start);
    return c->start != NULL;
}

void sb_cutting_start(sb_cutting* c, const sb_real* p, uint32_t vertex_count) {
    memcpy(c->start, p, 4 * (size_t)vertex_count * sizeof *c->start);
}

uint32_t sb_cutting_pass(const sb_cutting* c, const sb_model* m, const sb_real* p, const uint8_t* skip, double t0,
                         double t1, void (*meet)(void* user, uint32_t bond, double along), void* user) {
    uint32_t severed = 0;
    for (uint32_t k = 0; k < c->count; k++) {
        double ends[4][3], lo[3], hi[3];
        sb_edge_poses(&c->blades[k], t0, t1, ends);
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(fmin(ends[0][a], ends[1][a]), fmin(ends[2][a], ends[3][a]));
            hi[a] = fmax(fmax(ends[0][a], ends[1][a]), fmax(ends[2][a], ends[3][a]));
        }
        sb_moving edge = {sb_v3(ends[0]), sb_v3(ends[1]), sb_v3_sub(sb_v3(ends[2]), sb_v3(ends[0])),
                          sb_v3_sub(sb_v3(ends[3]), sb_v3(ends[1]))};
        for (uint32_t e = 0; e < m->bond_count; e++) {
            if (skip[e]) continue;
            uint32_t i = m->bond_i[e], j = m->bond_j[e];
            const sb_real* x[4] = {c->start + 4 * (size_t)i, c->start + 4 * (size_t)j, p + 4 * (size_t)i,
                                   p + 4 * (size_t)j};
            if (sb_box_apart(x, lo, hi)) continue;
            sb_moving bond = sb_bond_motion(c->start, p, i, j);
            double along;
            if (!sb_sweeps_meet(&edge, &bond, &along)) continue;
            meet(user, e, along);
            severed++;
        }
    }
    return severed;
}

uint32_t sb_cutting_planes(const sb_cutting* c, double t0, double t1, double* planes) {
    uint32_t count = 0;
    for (uint32_t k = 0; k < c->count; k++) {
        double ends[4][3];
        sb_edge_poses(&c->blades[k], t0, t1, ends);
        sb_vec3 a = sb_v3(ends[0]), along = sb_v3_sub(sb_v3(ends[1]), a);
        sb_vec3 motion = sb_v3_sub(sb_v3_add(sb_v3(ends[2]), sb_v3(ends[3])), sb_v3_add(a, sb_v3(ends[1])));
        sb_vec3 n = sb_v3_cross(along, motion);
        double length = sb_v3_length(n);
        if (!(length > 1e-9 * sb_v3_length(along) * sb_v3_length(motion))) continue;
        n = sb_v3_scale(n, 1.0 / length);
        double* plane = planes + 4 * (size_t)count++;
        plane[0] = n.x, plane[1] = n.y, plane[2] = n.z, plane[3] = -sb_v3_dot(n, a);
    }
    return count;
}

uint32_t sb_cutting_count(const sb_cutting* c) { return c->count; }
