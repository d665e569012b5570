/** @file
 * Basic types shared by every softbond module: precision, status codes, errors. */
#ifndef SOFTBOND_TYPES_H
#define SOFTBOND_TYPES_H

#include "softbond/export.h"

#include <stddef.h>
#include <stdint.h>
#include <stdbool.h>

#include "softbond/config.h"

#ifdef __cplusplus
extern "C" {
#endif

/** State and fast kernels use sb_real: float by default, double when the
 * library was configured with SB_DOUBLE=ON. The scalar reference is double. */
#if SB_DOUBLE
typedef double sb_real;
#else
typedef float sb_real;
#endif

/** What a library call returns: SB_OK, or why it failed (the call's
 * sb_error, when it takes one, says more). */
typedef enum sb_status {
    SB_OK = 0,         /**< success */
    SB_ERR_INVALID,    /**< bad argument or bad model data */
    SB_ERR_IO,         /**< a file could not be read or written */
    SB_ERR_PARSE,      /**< malformed file contents */
    SB_ERR_NOMEM,      /**< allocation failed */
    SB_ERR_DEGENERATE, /**< a collapsed edge or triangle met during a step */
    SB_ERR_UNSTABLE,   /**< the state became non-finite or ran away */
    SB_ERR_BUSY        /**< a lock-free buffer had no free slot: nothing was written */
} sb_status;

/** Filled by a failing library call: one line naming the file, line or
 * element. The library never prints; callers decide what to do with it. */
typedef struct sb_error {
    char message[512]; /**< NUL-terminated, cut to 511 bytes; written only by a call that fails */
} sb_error;

/** A short name for a status code ("invalid", "io", ...). */
SB_API const char* sb_status_name(sb_status status);

#ifdef __cplusplus
}
#endif
#endif
