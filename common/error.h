/* Private: filling an sb_error. */
#ifndef SB_ERROR_H
#define SB_ERROR_H

#include "softbond/types.h"

/* printf-style; err may be NULL. Returns status so callers can write
 * `return sb_error_set(err, SB_ERR_INVALID, "bond %u: ...", b);` */
sb_status sb_error_set(sb_error* err, sb_status status, const char* format, ...) __attribute__((format(printf, 3, 4)));

#endif
