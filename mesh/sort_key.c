#include "mesh/sort_key.h"

int sb_sort_key_compare(const void* a, const void* b) {
    const sb_sort_key *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return x->index < y->index ? -1 : (x->index > y->index);
}
