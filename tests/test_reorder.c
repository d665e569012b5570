/* Morton reordering keeps the geometry and brings neighbours together. */
#include "test_util.h"

/* Mean |i − j| over the triangles' edges: small when neighbours are near in memory. */
static double mean_index_gap(const sb_mesh* mesh) {
    double sum = 0.0;
    for (uint32_t f = 0; f < mesh->triangle_count; f++)
        for (int c = 0; c < 3; c++) {
            double a = mesh->triangles[3 * f + c], b = mesh->triangles[3 * f + (c + 1) % 3];
            sum += fabs(a - b);
        }
    return sum / (3.0 * mesh->triangle_count);
}

/* Shuffles vertex numbers at random (Fisher-Yates): a worst case for locality. */
static void shuffle(sb_mesh* mesh, uint64_t seed) {
    tu_rng rng = {seed};
    uint32_t n = mesh->vertex_count, *perm = malloc(n * sizeof *perm), *inverse = malloc(n * sizeof *inverse);
    for (uint32_t i = 0; i < n; i++) perm[i] = i;
    for (uint32_t i = n - 1; i > 0; i--) {
        uint32_t j = (uint32_t)(tu_next(&rng) % (i + 1)), t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
    double* positions = malloc(3 * n * sizeof *positions);
    for (uint32_t i = 0; i < n; i++) {
        memcpy(positions + 3 * i, mesh->positions + 3 * perm[i], 3 * sizeof *positions);
        inverse[perm[i]] = i;
    }
    memcpy(mesh->positions, positions, 3 * n * sizeof *positions);
    for (uint32_t k = 0; k < 3 * mesh->triangle_count; k++) mesh->triangles[k] = inverse[mesh->triangles[k]];
    free(perm);
    free(inverse);
    free(positions);
}

/* A triangle as one number: rotated so its smallest index comes first. */
static uint64_t canonical(const uint32_t t[3]) {
    int first = t[0] < t[1] ? (t[0] < t[2] ? 0 : 2) : (t[1] < t[2] ? 1 : 2);
    return (uint64_t)t[first] << 42 | (uint64_t)t[(first + 1) % 3] << 21 | t[(first + 2) % 3];
}

static int compare_u64(const void* a, const void* b) {
    uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
    return x < y ? -1 : x > y;
}

static void test_reorder_keeps_geometry_and_gains_locality(void** state) {
    (void)state;
    sb_mesh mesh = {0}, original = {0};
    sb_error err;
    assert_int_equal(sb_mesh_generate_icosphere(4, 1.0, &mesh, &err), SB_OK);
    shuffle(&mesh, 7);
    assert_int_equal(sb_mesh_generate_icosphere(4, 1.0, &original, &err), SB_OK);
    shuffle(&original, 7);
    uint32_t n = mesh.vertex_count, *order = malloc(n * sizeof *order);
    double before = mean_index_gap(&mesh);
    assert_int_equal(sb_mesh_reorder(&mesh, order, &err), SB_OK);
    double after = mean_index_gap(&mesh);
    print_message("mean index gap along edges: %.1f shuffled, %.1f after reordering (%u vertices)\n", before, after, n);
    TU_ASSERT_LE(after * 10.0, before); /* at least ten times closer */
    /* order is a permutation and moves positions with their vertices */
    uint8_t* seen = calloc(n, 1);
    for (uint32_t i = 0; i < n; i++) {
        assert_true(order[i] < n && !seen[order[i]]);
        seen[order[i]] = 1;
        for (int c = 0; c < 3; c++) assert_true(mesh.positions[3 * i + c] == original.positions[3 * order[i] + c]);
    }
    /* every triangle is still there, with its orientation: map each new
     * triangle back to old numbers, rotate its smallest index first, and
     * compare the sorted lists */
    uint64_t *mapped = malloc(mesh.triangle_count * sizeof *mapped),
             *expected = malloc(mesh.triangle_count * sizeof *expected);
    for (uint32_t f = 0; f < mesh.triangle_count; f++) {
        uint32_t back[3], old[3];
        for (int c = 0; c < 3; c++) {
            back[c] = order[mesh.triangles[3 * f + c]];
            old[c] = original.triangles[3 * f + c];
        }
        mapped[f] = canonical(back);
        expected[f] = canonical(old);
    }
    qsort(mapped, mesh.triangle_count, sizeof *mapped, compare_u64);
    qsort(expected, mesh.triangle_count, sizeof *expected, compare_u64);
    assert_memory_equal(mapped, expected, mesh.triangle_count * sizeof *mapped);
    free(mapped);
    free(expected);
    for (uint32_t f = 0; f < mesh.triangle_count; f++) {
        uint32_t lowest = UINT32_MAX;
        for (int c = 0; c < 3; c++) lowest = mesh.triangles[3 * f + c] < lowest ? mesh.triangles[3 * f + c] : lowest;
        if (f > 0) {
            uint32_t previous = UINT32_MAX;
            for (int c = 0; c < 3; c++)
                previous = mesh.triangles[3 * (f - 1) + c] < previous ? mesh.triangles[3 * (f - 1) + c] : previous;
            assert_true(previous <= lowest); /* sorted by lowest vertex */
        }
    }
    free(seen);
    free(order);
    sb_mesh_free(&mesh);
    sb_mesh_free(&original);
}

int main(void) {
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_reorder_keeps_geometry_and_gains_locality)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
