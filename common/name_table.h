/* Private: the names of an enumeration, looked up both ways. */
#ifndef SB_NAME_TABLE_H
#define SB_NAME_TABLE_H

/* The index of `name` among names[0 .. count), or -1. */
int sb_name_index(const char* const* names, int count, const char* name);
/* names[value], or "unknown" outside [0, count). */
const char* sb_name_of(const char* const* names, int count, int value);

#endif
