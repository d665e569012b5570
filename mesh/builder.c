/* Construction mode: growable arrays of element definitions. Nothing is
 * validated here; sb_builder_compile (mesh/compile.c) checks everything. */
#include "mesh/builder_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sb_vertex_def sb_default_vertex_def(void) { return (sb_vertex_def){.mass = 1.0}; }

sb_bond_def sb_default_bond_def(void) { return (sb_bond_def){.rest_length = -1.0, .break_max = INFINITY}; }

double sb_strain_break_length(const sb_mesh* mesh, uint32_t a, uint32_t b, double strain) {
    if (strain == 0.0) return INFINITY;
    const double *p = mesh->positions + 3 * (size_t)a, *q = mesh->positions + 3 * (size_t)b;
    return sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2])) *
           (1.0 + strain);
}

sb_triangle_def sb_default_triangle_def(void) { return (sb_triangle_def){0}; }

sb_builder* sb_builder_create(void) { return calloc(1, sizeof(sb_builder)); }

void sb_builder_destroy(sb_builder* builder) {
    if (!builder) return;
    free(builder->vertices.items);
    free(builder->bonds.items);
    free(builder->triangles.items);
    free(builder->hinges.items);
    free(builder->tets.items);
    free(builder->membranes.items);
    free(builder->plates.items);
    free(builder->faces.items);
    free(builder);
}

/* Appends one item of item_size bytes to a growable array; returns its index
 * or -1 when out of memory. */
static int64_t sb_array_push(sb_array* array, const void* item, size_t item_size) {
    if (array->count == array->capacity) {
        size_t capacity = array->capacity ? 2 * array->capacity : 64;
        if (capacity > UINT32_MAX) return -1;
        void* items = realloc(array->items, capacity * item_size);
        if (!items) return -1;
        array->items = items;
        array->capacity = capacity;
    }
    memcpy((char*)array->items + array->count * item_size, item, item_size);
    return (int64_t)array->count++;
}

int64_t sb_builder_add_vertex(sb_builder* builder, const sb_vertex_def* def) {
    return sb_array_push(&builder->vertices, def, sizeof *def);
}

int64_t sb_builder_add_bond(sb_builder* builder, const sb_bond_def* def) {
    return sb_array_push(&builder->bonds, def, sizeof *def);
}

int64_t sb_builder_add_triangle(sb_builder* builder, const sb_triangle_def* def) {
    return sb_array_push(&builder->triangles, def, sizeof *def);
}

int64_t sb_builder_add_hinge(sb_builder* builder, const sb_hinge_def* def) {
    return sb_array_push(&builder->hinges, def, sizeof *def);
}

int64_t sb_builder_add_face(sb_builder* builder, const uint32_t corners[3]) {
    return sb_array_push(&builder->faces, corners, 3 * sizeof *corners);
}

int64_t sb_builder_add_tet(sb_builder* builder, const sb_tet_def* def) {
    return sb_array_push(&builder->tets, def, sizeof *def);
}

int64_t sb_builder_add_plate(sb_builder* builder, const sb_plate_def* def) {
    return sb_array_push(&builder->plates, def, sizeof *def);
}

int64_t sb_builder_add_membrane(sb_builder* builder, const sb_membrane_def* def) {
    return sb_array_push(&builder->membranes, def, sizeof *def);
}

uint32_t sb_builder_vertex_count(const sb_builder* builder) { return (uint32_t)builder->vertices.count; }

sb_vertex_def* sb_builder_vertex(sb_builder* builder, uint32_t index) {
    if (index >= builder->vertices.count) return NULL;
    return (sb_vertex_def*)builder->vertices.items + index;
}
