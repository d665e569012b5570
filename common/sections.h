/* Private: a versioned binary file of tagged sections, the layout of the
 * solver's saved state (kernels/solver/solver_state.c) and of the program's
 * checkpoint (cli/checkpoint.c).
 *
 *   header   8  magic (what kind of file)
 *            4  version
 *            4  sizeof(sb_real) of the writer
 *            4  vertex count
 *            4  0x01020304 in the writer's byte order
 *            8  hash of what the file belongs to (a model, a scene)
 *   section  4  tag (four characters)
 *            4  0
 *            8  payload length n
 *            n  payload, then zeros to a multiple of 8 bytes
 *   ...
 *   last     the section "SUM!" whose payload is the 8-byte FNV-1a hash of
 *            every byte before it
 *
 * Values are written in the host's byte order (the mark says which). A
 * reader finds sections by tag, so a later version adds a section without
 * moving the others; one that misses a section it needs says which. */
#ifndef SB_SECTIONS_H
#define SB_SECTIONS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "softbond/types.h"

typedef struct sb_sections_header {
    char magic[8];
    uint32_t version, real_size, vertex_count;
    uint64_t hash;
} sb_sections_header;

/* FNV-1a, 64 bits: sb_hash(SB_HASH_START, data, n), chained by passing
 * the last value back. */
#define SB_HASH_START 0xcbf29ce484222325ull
uint64_t sb_hash(uint64_t hash, const void* data, size_t size);

/* Writes into data[0 .. capacity), or only counts with data NULL: the
 * same calls give the size and then the bytes. */
typedef struct sb_sections_writer {
    uint8_t* data;
    size_t capacity, size;
    size_t open; /* the open section's header offset */
} sb_sections_writer;

void sb_sections_begin(sb_sections_writer* w, void* data, size_t capacity, const sb_sections_header* header);
void sb_sections_open(sb_sections_writer* w, const char tag[4]);
void sb_sections_put(sb_sections_writer* w, const void* bytes, size_t size);
void sb_sections_close(sb_sections_writer* w);
/* Adds the checksum; true when everything fit in the capacity. */
bool sb_sections_end(sb_sections_writer* w);

typedef struct sb_sections_reader {
    const uint8_t* data;
    size_t size;
    sb_sections_header header;
} sb_sections_reader;

/* Checks the magic, the version, the byte order, that every section lies
 * inside the bytes and that the checksum matches; the message starts with
 * `what` (the file's name). The caller checks the header's real_size,
 * vertex_count and hash itself. */
sb_status sb_sections_read(sb_sections_reader* r, const void* data, size_t size, const char magic[8], uint32_t version,
                           const char* what, sb_error* err);

/* A section's payload, read in order. */
typedef struct sb_cursor {
    const uint8_t* at;
    size_t left;
} sb_cursor;

/* The section of that tag (the first), or false. */
bool sb_sections_find(const sb_sections_reader* r, const char tag[4], sb_cursor* out);
/* Copies the next size bytes to out; false (nothing copied) when fewer are left. */
bool sb_cursor_take(sb_cursor* c, void* out, size_t size);

/* A state written and read as a list of byte ranges: the same list
 * writes (sb_ranges_put) and reads (sb_ranges_take). */
typedef struct sb_range {
    void* at;
    size_t bytes;
} sb_range;

void sb_ranges_put(sb_sections_writer* w, const sb_range* ranges, int count);
void sb_ranges_take(sb_cursor* c, const sb_range* ranges, int count);

#endif
