/* A small record shared between threads: one writer, any number of readers,
 * no lock (haptics/record.c has the design). The device pose and the
 * contact model travel in one each. */
#ifndef SB_HAPTICS_RECORD_H
#define SB_HAPTICS_RECORD_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

enum { SB_RECORD_WORDS = 16 };

typedef struct sb_record {
    atomic_uint_least64_t sequence; /* odd while the writer writes */
    atomic_uint_least64_t words[SB_RECORD_WORDS];
} sb_record;

void sb_record_init(sb_record* record);
/* Writer: copies size bytes (at most SB_RECORD_WORDS * 8) in. */
void sb_record_write(sb_record* record, const void* data, size_t size);
/* Reader: the last write whole into data, true; false before the first
 * write or when overtaken on every try. */
bool sb_record_read(const sb_record* record, void* data, size_t size);
/* Writes so far. */
uint64_t sb_record_writes(const sb_record* record);

#endif
