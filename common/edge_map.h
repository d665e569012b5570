/* Private: an open-addressing hash map from an undirected edge (a, b) to a
 * 32-bit value, for finding the unique edges of a mesh in linear time. */
#ifndef SB_EDGE_MAP_H
#define SB_EDGE_MAP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct sb_edge_map {
    uint64_t* keys; /* (lo << 32 | hi) + 1; 0 marks an empty slot */
    uint32_t* values;
    size_t capacity; /* a power of two */
} sb_edge_map;

/* Room for expected edges at a load factor of at most one half. */
bool sb_edge_map_init(sb_edge_map* map, size_t expected);
void sb_edge_map_free(sb_edge_map* map);

/* Returns a pointer to the value of edge (a, b) — the same for (b, a) —
 * inserting value if the edge is new; *inserted tells which happened. */
uint32_t* sb_edge_map_upsert(sb_edge_map* map, uint32_t a, uint32_t b, uint32_t value, bool* inserted);

/* The value of edge (a, b), or NULL when it is not in the map. */
uint32_t* sb_edge_map_find(const sb_edge_map* map, uint32_t a, uint32_t b);

#endif
