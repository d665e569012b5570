/* Private: filling an sb_error. Every function here accepts err == NULL
 * (then it only returns status), formats printf-style, silently truncates
 * to the message's size, and returns status so callers can write
 * `return sb_error_set(err, SB_ERR_INVALID, "bond %u: ...", b);` */
#ifndef SB_ERROR_H
#define SB_ERROR_H

#include <stdarg.h>
#include <stddef.h>

#include "softbond/types.h"

/* The message is the formatted text. */
sb_status sb_error_set(sb_error* err, sb_status status, const char* format, ...) __attribute__((format(printf, 3, 4)));
sb_status sb_error_vset(sb_error* err, sb_status status, const char* format, va_list args)
    __attribute__((format(printf, 3, 0)));
/* The message is "PATH:LINE: text" (line 0: "PATH: text"). */
sb_status sb_error_at(sb_error* err, sb_status status, const char* path, size_t line, const char* format, ...)
    __attribute__((format(printf, 5, 6)));
/* Turns the message already in err into "PREFIX: message". */
sb_status sb_error_prefix(sb_error* err, sb_status status, const char* prefix);

#endif
