/* A libFuzzer harness for one entry of entries.c, chosen when it is built
 * (-DSB_FUZZ_ENTRY="obj"): see tests/fuzz/run.sh. */
#include <stdio.h>
#include <stdlib.h>

#include "tests/fuzz/entries.h"

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const sb_fuzz_entry* entry;
    if (!entry && !(entry = sb_fuzz_entry_find(SB_FUZZ_ENTRY))) {
        fprintf(stderr, "sb_fuzz: no entry '%s'\n", SB_FUZZ_ENTRY);
        abort();
    }
    return entry->run(data, size);
}
