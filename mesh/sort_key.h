/* Private: a 64-bit key with the index of what it belongs to, sorted by key
 * and then by index (so qsort's result is the same on every platform). */
#ifndef SB_SORT_KEY_H
#define SB_SORT_KEY_H

#include <stdint.h>

typedef struct sb_sort_key {
    uint64_t key;
    uint32_t index;
} sb_sort_key;

int sb_sort_key_compare(const void* a, const void* b);

#endif
