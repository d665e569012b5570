/* The triangles of a body's surface: see kernels/contact/surface_triangles.h.
 *
 * A sheet's surface is its triangles (the molecular terms' or the
 * membranes'); a volume's is its faces (the tissue factory's boundary,
 * which a volume of springs needs: it has no other triangles), or else the
 * faces its tetrahedra do not share, found once at rest (tetrahedra do
 * not tear). A quadratic tetrahedron's face
 * has a vertex at the middle of each edge, which its elasticity moves like
 * any other: the face is split there into four, so that the contact's
 * impulse reaches the vertices that carry the face. */
#include "kernels/contact/surface_triangles.h"
#include "common/edge_map.h"
#include "common/error.h"
#include "softbond/volume.h"

#include <stdlib.h>
#include <string.h>

bool sb_surface_triangles_exist(const sb_model* m) {
    return m->triangle_count > 0 || m->membrane_count > 0 || m->face_count > 0 || m->tet_count > 0;
}

static bool sb_surface_alloc(sb_surface_triangles* out, uint32_t count) {
    out->count = count;
    for (int c = 0; c < 3; c++) out->v[c] = out->owned[c] = malloc(((size_t)count + 1) * sizeof(uint32_t));
    return out->owned[0] && out->owned[1] && out->owned[2];
}

/* The corners' faces that no two tetrahedra share, outward. */
static sb_status sb_corner_faces(const sb_model* m, sb_mesh* faces, sb_error* err) {
    sb_tet_mesh corners = {.vertex_count = m->vertex_count, .tet_count = m->tet_count};
    corners.positions = malloc((3 * (size_t)m->vertex_count + 1) * sizeof(double));
    corners.tets = malloc((4 * (size_t)m->tet_count + 1) * sizeof(uint32_t));
    sb_status status = SB_OK;
    if (!corners.positions || !corners.tets) {
        status = sb_error_set(err, SB_ERR_NOMEM, "out of memory finding the surface of %u tetrahedra", m->tet_count);
    } else {
        for (uint32_t i = 0; i < m->vertex_count; i++) {
            corners.positions[3 * (size_t)i] = m->rest_x[i];
            corners.positions[3 * (size_t)i + 1] = m->rest_y[i];
            corners.positions[3 * (size_t)i + 2] = m->rest_z[i];
        }
        for (uint32_t t = 0; t < m->tet_count; t++)
            for (int c = 0; c < 4; c++) corners.tets[4 * (size_t)t + c] = m->tet_v[c][t];
        status = sb_tet_mesh_surface(&corners, faces, err);
    }
    sb_tet_mesh_free(&corners);
    return status;
}

/* Edge (a, b) of the tetrahedra → the vertex at its middle (quadratic
 * ones only). */
static bool sb_middles(const sb_model* m, sb_edge_map* middles) {
    static const int ends[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    if (!sb_edge_map_init(middles, 6 * (size_t)m->tet_count)) return false;
    for (uint32_t t = 0; t < m->tet_count; t++)
        for (int e = 0; m->tet_nodes[t] == SB_TET_NODES && e < 6; e++) {
            bool inserted;
            sb_edge_map_upsert(middles, m->tet_v[ends[e][0]][t], m->tet_v[ends[e][1]][t], m->tet_v[4 + e][t],
                               &inserted);
        }
    return true;
}

/* Face (a b c) into out from triangle `at` on: itself, or its four quarters
 * when its edges have middles (ab bc ca); returns how many. */
static uint32_t sb_put_face(sb_surface_triangles* out, uint32_t at, const uint32_t v[3], const sb_edge_map* middles) {
    uint32_t mid[3], n = 1;
    uint32_t quarters[4][3] = {{v[0], v[1], v[2]}};
    const uint32_t* found[3];
    for (int c = 0; c < 3; c++) found[c] = sb_edge_map_find(middles, v[c], v[(c + 1) % 3]);
    if (found[0] && found[1] && found[2]) {
        for (int c = 0; c < 3; c++) mid[c] = *found[c];
        uint32_t split[4][3] = {
            {v[0], mid[0], mid[2]}, {mid[0], v[1], mid[1]}, {mid[2], mid[1], v[2]}, {mid[0], mid[1], mid[2]}};
        memcpy(quarters, split, sizeof split);
        n = 4;
    }
    for (uint32_t q = 0; out->owned[0] && q < n; q++)
        for (int c = 0; c < 3; c++) out->owned[c][at + q] = quarters[q][c];
    return n;
}

static sb_status sb_tet_surface(const sb_model* m, sb_surface_triangles* out, sb_error* err) {
    sb_mesh faces;
    sb_status status = sb_corner_faces(m, &faces, err);
    if (status != SB_OK) return status;
    sb_edge_map middles = {0};
    uint32_t count = 0;
    if (!sb_middles(m, &middles)) status = sb_error_set(err, SB_ERR_NOMEM, "out of memory for the surface contact");
    for (uint32_t t = 0; status == SB_OK && t < faces.triangle_count; t++) /* count */
        count += sb_put_face(out, count, faces.triangles + 3 * (size_t)t, &middles);
    if (status == SB_OK && !sb_surface_alloc(out, count))
        status = sb_error_set(err, SB_ERR_NOMEM, "out of memory for the surface contact");
    for (uint32_t t = 0, at = 0; status == SB_OK && t < faces.triangle_count; t++) /* fill */
        at += sb_put_face(out, at, faces.triangles + 3 * (size_t)t, &middles);
    sb_edge_map_free(&middles);
    sb_mesh_free(&faces);
    return status;
}

sb_status sb_surface_triangles_make(const sb_model* m, sb_surface_triangles* out, sb_error* err) {
    memset(out, 0, sizeof *out);
    const uint32_t* const* in_place = m->triangle_count   ? (const uint32_t* const*)m->tri_v
                                      : m->membrane_count ? (const uint32_t* const*)m->membrane_v
                                      : m->face_count     ? (const uint32_t* const*)m->face_v
                                                          : NULL;
    if (in_place) {
        out->count = m->triangle_count ? m->triangle_count : m->membrane_count ? m->membrane_count : m->face_count;
        for (int c = 0; c < 3; c++) out->v[c] = in_place[c];
        return SB_OK;
    }
    sb_status status = sb_tet_surface(m, out, err);
    if (status != SB_OK) sb_surface_triangles_free(out);
    return status;
}

void sb_surface_triangles_free(sb_surface_triangles* s) {
    for (int c = 0; c < 3; c++) free(s->owned[c]);
    memset(s, 0, sizeof *s);
}
