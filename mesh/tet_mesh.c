/* Tetrahedral meshes: volumes, the validity check and the boundary surface
 * (loading is in mesh/io/tet_readers.c). */
#include "softbond/volume.h"
#include "common/error.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void sb_tet_mesh_free(sb_tet_mesh* mesh) {
    free(mesh->positions);
    free(mesh->tets);
    *mesh = (sb_tet_mesh){0};
}

double sb_tet_volume(const double* a, const double* b, const double* c, const double* d) {
    double u[3], v[3], w[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = d[k] - a[k];
    }
    return (u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
            u[2] * (v[0] * w[1] - v[1] * w[0])) /
           6.0;
}

static double sb_tet_of(const sb_tet_mesh* m, uint32_t t) {
    const uint32_t* v = m->tets + 4 * (size_t)t;
    const double* p = m->positions;
    return sb_tet_volume(p + 3 * (size_t)v[0], p + 3 * (size_t)v[1], p + 3 * (size_t)v[2], p + 3 * (size_t)v[3]);
}

static double sb_longest_edge(const sb_tet_mesh* m, uint32_t t) {
    const uint32_t* v = m->tets + 4 * (size_t)t;
    double longest = 0.0;
    for (int a = 0; a < 4; a++)
        for (int b = a + 1; b < 4; b++) {
            const double *p = m->positions + 3 * (size_t)v[a], *q = m->positions + 3 * (size_t)v[b];
            double d =
                sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
            longest = fmax(longest, d);
        }
    return longest;
}

/* 0 = proper, 1 = zero volume, 2 = inverted against sign, 3 = too large
 * to compute (the volume or the edge overflows: 'zero volume (inf m^3)'
 * it said). */
static int sb_tet_defect(const sb_tet_mesh* m, uint32_t t, int sign, double* volume) {
    *volume = sb_tet_of(m, t);
    double l = sb_longest_edge(m, t);
    if (!isfinite(*volume) || !isfinite(l * l * l)) return 3;
    if (!(fabs(*volume) > 1e-12 * l * l * l)) return 1;
    return (*volume > 0.0 ? 1 : -1) == sign ? 0 : 2;
}

static sb_status sb_tet_check_indices(const sb_tet_mesh* m, sb_error* err) {
    for (size_t i = 0; i < 3 * (size_t)m->vertex_count; i++)
        if (!isfinite(m->positions[i]))
            return sb_error_set(err, SB_ERR_INVALID, "vertex %zu: non-finite position", i / 3);
    for (uint32_t t = 0; t < m->tet_count; t++) {
        const uint32_t* v = m->tets + 4 * (size_t)t;
        for (int a = 0; a < 4; a++) {
            if (v[a] >= m->vertex_count)
                return sb_error_set(err, SB_ERR_INVALID, "tetrahedron %u: vertex index %u out of range (%u vertices)",
                                    t, v[a], m->vertex_count);
            for (int b = 0; b < a; b++)
                if (v[a] == v[b])
                    return sb_error_set(err, SB_ERR_INVALID, "tetrahedron %u: vertex %u repeated", t, v[a]);
        }
    }
    return SB_OK;
}

sb_status sb_tet_mesh_check(const sb_tet_mesh* m, sb_error* err) {
    if (m->tet_count == 0) return sb_error_set(err, SB_ERR_INVALID, "the mesh has no tetrahedra");
    sb_status status = sb_tet_check_indices(m, err);
    if (status != SB_OK) return status;
    uint32_t positive = 0, negative = 0;
    for (uint32_t t = 0; t < m->tet_count; t++) {
        double v = sb_tet_of(m, t);
        positive += v > 0.0;
        negative += v < 0.0;
    }
    int sign = positive >= negative ? 1 : -1;
    uint32_t bad = 0, first = 0;
    int first_kind = 0;
    double first_volume = 0.0;
    for (uint32_t t = 0; t < m->tet_count; t++) {
        double volume;
        int kind = sb_tet_defect(m, t, sign, &volume);
        if (kind == 3) {
            const uint32_t* v = m->tets + 4 * (size_t)t;
            return sb_error_set(err, SB_ERR_INVALID,
                                "tetrahedron %u (vertices %u %u %u %u): too large to compute (its longest edge %g m, "
                                "its volume overflows): a slip of units? (lengths are in metres)",
                                t, v[0], v[1], v[2], v[3], sb_longest_edge(m, t));
        }
    }
    for (uint32_t t = 0; t < m->tet_count; t++) {
        double volume;
        int kind = sb_tet_defect(m, t, sign, &volume);
        if (kind && bad++ == 0) {
            first = t;
            first_kind = kind;
            first_volume = volume;
        }
    }
    if (bad == 0) return SB_OK;
    const uint32_t* v = m->tets + 4 * (size_t)first;
    char more[64] = "";
    if (bad > 1) snprintf(more, sizeof more, " (%u bad tetrahedra in all)", bad);
    if (first_kind == 1)
        return sb_error_set(err, SB_ERR_INVALID, "tetrahedron %u (vertices %u %u %u %u): zero volume (%g m^3)%s", first,
                            v[0], v[1], v[2], v[3], first_volume, more);
    return sb_error_set(err, SB_ERR_INVALID,
                        "tetrahedron %u (vertices %u %u %u %u): inverted (volume %g m^3, most are %s)%s", first, v[0],
                        v[1], v[2], v[3], first_volume, sign > 0 ? "positive" : "negative", more);
}

/* ---- the boundary ---------------------------------------------------------- */

typedef struct sb_face {
    uint32_t key[3]; /* sorted vertices */
    uint32_t v[3];   /* facing out of its tetrahedron */
} sb_face;

static int sb_face_compare(const void* a, const void* b) {
    const sb_face *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x->key[k] != y->key[k]) return x->key[k] < y->key[k] ? -1 : 1;
    return 0;
}

static void sb_face_make(sb_face* f, uint32_t a, uint32_t b, uint32_t c) {
    f->v[0] = a;
    f->v[1] = b;
    f->v[2] = c;
    uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
    f->key[0] = c < lo ? c : lo;
    f->key[2] = c > hi ? c : hi;
    f->key[1] = a ^ b ^ c ^ f->key[0] ^ f->key[2];
}

static void sb_tet_faces(const sb_tet_mesh* m, uint32_t t, sb_face out[4]) {
    const uint32_t* v = m->tets + 4 * (size_t)t;
    uint32_t a = v[0], b = v[1], c = v[2], d = v[3];
    if (sb_tet_of(m, t) < 0.0) {
        uint32_t s = b;
        b = c;
        c = s;
    }
    /* outward for (b − a) · ((c − a) × (d − a)) > 0 */
    sb_face_make(&out[0], a, c, b);
    sb_face_make(&out[1], a, b, d);
    sb_face_make(&out[2], a, d, c);
    sb_face_make(&out[3], b, c, d);
}

sb_status sb_tet_mesh_surface(const sb_tet_mesh* m, sb_mesh* out, sb_error* err) {
    memset(out, 0, sizeof *out);
    sb_status status = sb_tet_check_indices(m, err);
    if (status != SB_OK) return status;
    size_t count = 4 * (size_t)m->tet_count;
    sb_face* faces = malloc((count ? count : 1) * sizeof *faces);
    out->positions = malloc((3 * (size_t)m->vertex_count + 1) * sizeof(double));
    out->triangles = malloc((3 * count + 1) * sizeof(uint32_t));
    if (!faces || !out->positions || !out->triangles) {
        free(faces);
        sb_mesh_free(out);
        return sb_error_set(err, SB_ERR_NOMEM, "out of memory finding the surface of %u tetrahedra", m->tet_count);
    }
    memcpy(out->positions, m->positions, 3 * (size_t)m->vertex_count * sizeof(double));
    out->vertex_count = m->vertex_count;
    for (uint32_t t = 0; t < m->tet_count; t++) sb_tet_faces(m, t, faces + 4 * (size_t)t);
    qsort(faces, count, sizeof *faces, sb_face_compare);
    uint32_t n = 0;
    for (size_t i = 0; i < count;) {
        size_t j = i + 1;
        while (j < count && sb_face_compare(&faces[i], &faces[j]) == 0) j++;
        if (j - i == 1) memcpy(out->triangles + 3 * (size_t)n++, faces[i].v, sizeof faces[i].v);
        i = j;
    }
    out->triangle_count = n;
    free(faces);
    return SB_OK;
}
