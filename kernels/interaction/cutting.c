/* Cutting: a blade's edge swept over a step severs the bonds it crosses.
 *
 * The swept surface of a step is the quadrilateral of the edge at the
 * step's start and at its end, (a0, b0, b1, a1), taken as the two
 * triangles (a0, b0, b1) and (a0, b1, a1): exact for a blade that
 * translates, and the usual approximation of the ruled surface when it
 * turns (the steps are short). A bond is tested at the step's end
 * positions, after the integrator moved it: a segment–triangle test
 * (Möller–Trumbore, in double) against each triangle, behind a bounding-box
 * test of the bond against the quadrilateral, so a step costs one box test
 * per unbroken bond and blade. Bonds that move as fast as the blade can
 * slip through, as they could through a collider's thickness. */
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
    free(c);
}

/* Whether segment p → q meets triangle (a, b, c) (Möller–Trumbore). */
static bool sb_segment_meets_triangle(sb_vec3 p, sb_vec3 q, const double* a, const double* b, const double* c) {
    sb_vec3 d = sb_v3_sub(q, p), e1 = sb_v3_sub(sb_v3(b), sb_v3(a)), e2 = sb_v3_sub(sb_v3(c), sb_v3(a));
    sb_vec3 h = sb_v3_cross(d, e2);
    double det = sb_v3_dot(e1, h);
    if (det == 0.0) return false; /* parallel: a bond in the swept surface's plane is not across it */
    double f = 1.0 / det;
    sb_vec3 s = sb_v3_sub(p, sb_v3(a));
    double u = f * sb_v3_dot(s, h);
    if (u < 0.0 || u > 1.0) return false;
    sb_vec3 r = sb_v3_cross(s, e1);
    double v = f * sb_v3_dot(d, r), t = f * sb_v3_dot(e2, r);
    return v >= 0.0 && u + v <= 1.0 && t >= 0.0 && t <= 1.0;
}

/* The quadrilateral blade k swept from t0 to t1 (a0, b0, b1, a1) and its box. */
static void sb_swept(const sb_blade* b, double t0, double t1, double quad[4][3], double lo[3], double hi[3]) {
    double pose[12];
    sb_path_pose(b->path, b->path_count, b->interpolation, b->center, t0, pose);
    sb_pose_apply(pose, b->a, quad[0]);
    sb_pose_apply(pose, b->b, quad[1]);
    sb_path_pose(b->path, b->path_count, b->interpolation, b->center, t1, pose);
    sb_pose_apply(pose, b->b, quad[2]);
    sb_pose_apply(pose, b->a, quad[3]);
    for (int i = 0; i < 3; i++) {
        lo[i] = fmin(fmin(quad[0][i], quad[1][i]), fmin(quad[2][i], quad[3][i]));
        hi[i] = fmax(fmax(quad[0][i], quad[1][i]), fmax(quad[2][i], quad[3][i]));
    }
}

static sb_vec3 sb_point(const sb_real* x) { return (sb_vec3){x[0], x[1], x[2]}; }

uint32_t sb_cutting_pass(const sb_cutting* c, const sb_model* m, const sb_real* p, const uint8_t* broken, double t0,
                         double t1, void (*sever)(void* user, uint32_t bond), void* user) {
    uint32_t severed = 0;
    for (uint32_t k = 0; k < c->count; k++) {
        double quad[4][3], lo[3], hi[3];
        sb_swept(&c->blades[k], t0, t1, quad, lo, hi);
        for (uint32_t e = 0; e < m->bond_count; e++) {
            if (broken[e]) continue;
            const sb_real *x = p + 4 * (size_t)m->bond_i[e], *y = p + 4 * (size_t)m->bond_j[e];
            int apart = 0; /* the bond's box off the quadrilateral's */
            for (int i = 0; i < 3; i++) apart |= (x[i] < lo[i] && y[i] < lo[i]) | (x[i] > hi[i] && y[i] > hi[i]);
            if (apart || !(sb_segment_meets_triangle(sb_point(x), sb_point(y), quad[0], quad[1], quad[2]) ||
                           sb_segment_meets_triangle(sb_point(x), sb_point(y), quad[0], quad[2], quad[3])))
                continue;
            sever(user, e);
            severed++;
        }
    }
    return severed;
}
