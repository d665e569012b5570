/* Filling an sb_error in the program's modules: printf-style, silently
 * truncated to the message's size. */
#ifndef SB_ERRORF_H
#define SB_ERRORF_H

#include <stdarg.h>

#include "softbond/types.h"

/* Formats the message and returns status. */
sb_status sb_errorf(sb_error* err, sb_status status, const char* format, ...) __attribute__((format(printf, 3, 4)));
sb_status sb_verrorf(sb_error* err, sb_status status, const char* format, va_list args);
/* Turns the message into "prefix: message"; returns status. */
sb_status sb_error_prefix(sb_error* err, sb_status status, const char* prefix);

#endif
