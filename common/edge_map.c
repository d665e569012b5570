#include "common/edge_map.h"

#include <stdlib.h>

bool sb_edge_map_init(sb_edge_map* map, size_t expected) {
    size_t capacity = 16;
    while (capacity < 2 * expected) capacity *= 2;
    map->keys = calloc(capacity, sizeof *map->keys);
    map->values = malloc(capacity * sizeof *map->values);
    map->capacity = capacity;
    if (map->keys && map->values) return true;
    sb_edge_map_free(map);
    return false;
}

void sb_edge_map_free(sb_edge_map* map) {
    free(map->keys);
    free(map->values);
    *map = (sb_edge_map){0};
}

static uint64_t sb_edge_hash(uint64_t key) {
    key ^= key >> 33;
    key *= 0xff51afd7ed558ccdULL;
    key ^= key >> 33;
    return key;
}

/* The slot holding edge (a, b), or the empty slot where it would go. */
static size_t sb_edge_slot(const sb_edge_map* map, uint32_t a, uint32_t b, uint64_t* key_out) {
    uint64_t lo = a < b ? a : b, hi = a < b ? b : a;
    uint64_t key = (lo << 32 | hi) + 1;
    size_t mask = map->capacity - 1;
    size_t slot = sb_edge_hash(key) & mask;
    while (map->keys[slot] != 0 && map->keys[slot] != key) slot = (slot + 1) & mask;
    *key_out = key;
    return slot;
}

uint32_t* sb_edge_map_find(const sb_edge_map* map, uint32_t a, uint32_t b) {
    uint64_t key;
    size_t slot = sb_edge_slot(map, a, b, &key);
    return map->keys[slot] == key ? &map->values[slot] : NULL;
}

uint32_t* sb_edge_map_upsert(sb_edge_map* map, uint32_t a, uint32_t b, uint32_t value, bool* inserted) {
    uint64_t key;
    size_t slot = sb_edge_slot(map, a, b, &key);
    *inserted = map->keys[slot] == 0;
    if (*inserted) {
        map->keys[slot] = key;
        map->values[slot] = value;
    }
    return &map->values[slot];
}
