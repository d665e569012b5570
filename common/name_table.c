/* The names of an enumeration, looked up both ways. */
#include "common/name_table.h"

#include <string.h>

int sb_name_index(const char* const* names, int count, const char* name) {
    for (int i = 0; i < count; i++)
        if (strcmp(name, names[i]) == 0) return i;
    return -1;
}

const char* sb_name_of(const char* const* names, int count, int value) {
    return value >= 0 && value < count ? names[value] : "unknown";
}
