/* The colliders against the body's surface: a tool smaller than the
 * mesh's spacing stops at the triangles between the vertices.
 *
 * Design. The vertex pass (kernels/contact/contact.c) answers each
 * vertex's move; a collider that fits between vertices meets none of
 * them. This pass, after it, takes each triangle and each collider that
 * meets the surface (the built-in sphere, capsule and box,
 * sb_collider_meets_surface): the collider names the material point of the
 * triangle nearest its core, by barycentric weights w — the point its
 * center, segment or edges came nearest in the step, or went through
 * (kernels/contact/colliders/triangle_point.c) — and that point, which
 * moved from Σ w_i x0_i to Σ w_i x1_i, is answered as a vertex is: the
 * collider's own sweep and the same velocity and position answers
 * (restitution, Coulomb friction, the push out), so the point of contact
 * stops, swept: a fast tool does not pass a sheet in a step. A point at a
 * corner (a weight of 1) is the vertex the vertex pass answered.
 *
 * The point's change of velocity Δv and position Δx are spread over the
 * corners as an impulse would be: corner i takes w_i m_i⁻¹ / W of them, W =
 * Σ w_j² m_j⁻¹ (a fixed or held corner, m⁻¹ = 0, none), which moves the
 * point by exactly Δv and Δx (Σ w_i · w_i m_i⁻¹ / W = 1), and gives the body
 * the momentum Σ m_i Δv_i = Δv Σ_free w_i / W, the opposite of what the
 * collider receives: momentum is conserved. Along the normal Δx is the
 * answer's push; along the surface, dt times the change of velocity (the
 * rest of the step at the answered velocity), so a corner is not dragged
 * along the surface by the point's reset. A corrected corner takes d = v dt
 * as its Verlet displacement, as in the vertex pass. A corner the push
 * carried into the collider (a sheet wrapped round a thin capsule: the
 * normal at the point of contact is not the way out at the corner) is then
 * answered as a vertex, by the same collider.
 *
 * One thread, triangles in order and each triangle's colliders in order,
 * each answer seen by the next (Gauss-Seidel): the same for any thread
 * count. A broad phase keeps it cheap: a triangle whose move's box, grown
 * by the contact thickness, reaches no such collider's step bounds costs
 * the box. */
#include "kernels/contact/surface.h"
#include "kernels/contact/contact.h"
#include "kernels/contact/colliders/collider_internal.h"
#include "kernels/state/solver_fast.h"

#include <string.h>

bool sb_surface_active(const sb_solver* s) {
    if (s->model->triangle_count == 0) return false;
    for (uint32_t c = 0; c < s->def.collider_count; c++)
        if (sb_collider_meets_surface(s->def.colliders[c])) return true;
    return false;
}

sb_surface_view sb_surface_view_packed(sb_solver* s) {
    sb_surface_view view = {.stride = 4, .from = NULL};
    for (int k = 0; k < 3; k++) {
        view.x[k] = s->positions4 + k;
        view.v[k] = s->velocities4 + k;
        view.d[k] = s->displacements4 + k;
        view.f[k] = s->forces4 + k;
    }
    return view;
}

sb_surface_view sb_surface_view_state(sb_solver* s, const double* from) {
    sb_state* st = &s->state;
    return (sb_surface_view){.x = {st->x, st->y, st->z},
                             .v = {st->vx, st->vy, st->vz},
                             .d = {s->disp_x, s->disp_y, s->disp_z},
                             .f = {NULL, NULL, NULL},
                             .stride = 1,
                             .from = from};
}

/* A triangle's corners at the start and the end of the step, their
 * velocities and inverse masses. */
typedef struct sb_corners {
    uint32_t vertex[3];
    double from[3][3], to[3][3], v[3][3], inv_mass[3];
} sb_corners;

static void sb_read_corners(const sb_solver* s, const sb_surface_view* view, uint32_t t, sb_corners* c) {
    const double* inv_mass = sb_inv_mass(s);
    for (int j = 0; j < 3; j++) {
        uint32_t i = c->vertex[j] = s->model->tri_v[j][t];
        size_t at = view->stride * i;
        for (int k = 0; k < 3; k++) {
            c->to[j][k] = view->x[k][at];
            c->v[j][k] = view->v[k][at];
            c->from[j][k] = view->from ? view->from[3 * (size_t)i + k] : c->to[j][k] - view->d[k][at];
        }
        c->inv_mass[j] = inv_mass[i];
    }
}

/* The box around the corners' moves. */
static void sb_corners_box(const sb_corners* c, double lo[3], double hi[3]) {
    for (int k = 0; k < 3; k++) {
        lo[k] = hi[k] = c->to[0][k];
        for (int j = 0; j < 3; j++) {
            double a = c->from[j][k], b = c->to[j][k];
            lo[k] = a < lo[k] ? a : lo[k], lo[k] = b < lo[k] ? b : lo[k];
            hi[k] = a > hi[k] ? a : hi[k], hi[k] = b > hi[k] ? b : hi[k];
        }
    }
}

/* Σ w_j p_j */
static void sb_blend(const double w[3], const double p[3][3], double out[3]) {
    for (int k = 0; k < 3; k++) out[k] = w[0] * p[0][k] + w[1] * p[1][k] + w[2] * p[2][k];
}

/* Corner j's new state: the share `share` of the point's Δx and Δv. */
static void sb_move_corner(const sb_solver* s, const sb_surface_view* view, const sb_corners* c, int j, double share,
                           const double dx[3], const double dv[3], double dt) {
    size_t at = view->stride * c->vertex[j];
    for (int k = 0; k < 3; k++) {
        double v = c->v[j][k] + share * dv[k];
        view->x[k][at] = (sb_real)(c->to[j][k] + share * dx[k]);
        view->v[k][at] = (sb_real)v;
        view->d[k][at] = (sb_real)(v * dt);
        if (view->f[k]) view->f[k][at] = sb_fast_initial_force(s, c->vertex[j], k, v);
    }
}

/* A corner the spread carried into the collider (a sheet wrapped round a
 * capsule: the push along the normal at the point of contact is not the
 * way out at the corner) is answered as the vertex pass answers a vertex. */
static void sb_answer_corner(const sb_solver* s, const sb_surface_view* view, uint32_t i, uint32_t index, double dt) {
    size_t at = view->stride * i;
    double x[3], v[3], from[3], impulse[3], point[3];
    for (int k = 0; k < 3; k++) {
        x[k] = view->x[k][at], v[k] = view->v[k][at];
        from[k] = view->from ? view->from[3 * (size_t)i + k] : x[k] - view->d[k][at];
    }
    if (sb_contact_vertex(s, i, (uint64_t)1 << index, from, x, v, impulse, point) < 0) return;
    for (int k = 0; k < 3; k++) {
        view->x[k][at] = (sb_real)x[k];
        view->v[k][at] = (sb_real)v[k];
        view->d[k][at] = (sb_real)(v[k] * dt);
        if (view->f[k]) view->f[k][at] = sb_fast_initial_force(s, i, k, v[k]);
    }
    sb_contact_record(s, 0, (int)index, impulse);
    sb_contact_record_torque(s, 0, (int)index, point, impulse);
}

/* The point's move: along the normal, where the answer puts it; along the
 * surface, the rest of the step at the change of velocity, dt Δv. */
static void sb_point_move(const sb_contact* contact, const double answered[3], const double to[3], const double dv[3],
                          double dt, double dx[3]) {
    double push = 0.0, slip = 0.0;
    for (int k = 0; k < 3; k++) {
        push += (answered[k] - to[k]) * contact->normal[k];
        slip += dv[k] * contact->normal[k];
    }
    for (int k = 0; k < 3; k++) dx[k] = push * contact->normal[k] + dt * (dv[k] - slip * contact->normal[k]);
}

/* The triangle against collider `index`: whether its point of contact was answered. */
static bool sb_surface_answer(const sb_solver* s, const sb_surface_view* view, const sb_corners* c, uint32_t index,
                              double dt) {
    const sb_collider* collider = s->def.colliders[index];
    double w[3];
    if (!sb_collider_triangle_point(collider, c->from, c->to, w)) return false;
    double W = 0.0, largest = 0.0;
    int nearest = 0;
    for (int j = 0; j < 3; j++) {
        W += w[j] * w[j] * c->inv_mass[j];
        if (w[j] > largest) largest = w[j], nearest = j;
    }
    if (largest >= 1.0 || !(W > 0.0)) return false; /* a vertex (the vertex pass), or held */
    sb_contact_query q = {
        .vertex = c->vertex[nearest], .t0 = s->time - s->step.dt, .t1 = s->time, .thickness = s->def.contact_thickness};
    sb_blend(w, c->from, q.from);
    sb_blend(w, c->to, q.to);
    sb_contact contact;
    if (!collider->collide(collider->user, &q, &contact)) return false;
    double v[3], before[3], x[3], dx[3], dv[3], taken = 0.0, impulse[3];
    sb_blend(w, c->v, v);
    memcpy(before, v, sizeof v);
    sb_contact_velocity(&contact, v);
    sb_contact_position(&contact, s->step.dt, q.from, q.to, v, x);
    for (int k = 0; k < 3; k++) dv[k] = v[k] - before[k];
    sb_point_move(&contact, x, q.to, dv, dt, dx);
    for (int j = 0; j < 3; j++) {
        double share = w[j] * c->inv_mass[j] / W;
        if (share > 0.0) sb_move_corner(s, view, c, j, share, dx, dv, dt);
        if (c->inv_mass[j] > 0.0) taken += w[j];
    }
    for (int k = 0; k < 3; k++) impulse[k] = dv[k] * taken / W;
    sb_contact_record(s, 0, (int)index, impulse);
    sb_contact_record_torque(s, 0, (int)index, contact.point, impulse);
    for (int j = 0; j < 3; j++)
        if (c->inv_mass[j] > 0.0) sb_answer_corner(s, view, c->vertex[j], index, dt);
    return true;
}

uint32_t sb_surface_pass(const sb_solver* s, const sb_surface_view* view, double dt) {
    uint64_t meets = 0;
    for (uint32_t c = 0; c < s->def.collider_count; c++)
        if (sb_collider_meets_surface(s->def.colliders[c])) meets |= (uint64_t)1 << c;
    uint32_t contacts = 0;
    for (uint32_t t = 0; t < s->model->triangle_count; t++) {
        sb_corners corners;
        double lo[3], hi[3];
        sb_read_corners(s, view, t, &corners);
        sb_corners_box(&corners, lo, hi);
        for (uint32_t c = 0; c < s->def.collider_count; c++) {
            if (!(meets >> c & 1) || !sb_contact_reaches(s, c, lo, hi)) continue;
            if (!sb_surface_answer(s, view, &corners, c, dt)) continue;
            contacts++;
            sb_read_corners(s, view, t, &corners); /* the next collider sees the answer */
        }
    }
    return contacts;
}
