/* The fuzzed parsers' entry points, shared by the libFuzzer harnesses
 * (harness.c, one program per entry) and the corpus replay (replay.c, a
 * ctest): each takes bytes, feeds them to one parser through the same call
 * the program makes, and returns 0 whether the parser accepted them or
 * refused them with a message. A crash, a sanitizer report, a leak or a
 * hang is the failure. */
#ifndef SB_FUZZ_ENTRIES_H
#define SB_FUZZ_ENTRIES_H

#include <stddef.h>
#include <stdint.h>

typedef struct sb_fuzz_entry {
    const char* name; /* the harness's name and its corpus folder */
    int (*run)(const uint8_t* data, size_t size);
} sb_fuzz_entry;

extern const sb_fuzz_entry sb_fuzz_entries[];
extern const size_t sb_fuzz_entry_count;

/* The entry of that name, or NULL. */
const sb_fuzz_entry* sb_fuzz_entry_find(const char* name);

#endif
