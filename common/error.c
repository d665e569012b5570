#include "common/error.h"

#include <stdarg.h>
#include <stdio.h>

sb_status sb_error_set(sb_error* err, sb_status status, const char* format, ...) {
    if (err) {
        va_list args;
        va_start(args, format);
        vsnprintf(err->message, sizeof err->message, format, args);
        va_end(args);
    }
    return status;
}

const char* sb_status_name(sb_status status) {
    switch (status) {
    case SB_OK: return "ok";
    case SB_ERR_INVALID: return "invalid";
    case SB_ERR_IO: return "io";
    case SB_ERR_PARSE: return "parse";
    case SB_ERR_NOMEM: return "out of memory";
    case SB_ERR_DEGENERATE: return "degenerate";
    case SB_ERR_UNSTABLE: return "unstable";
    }
    return "unknown";
}
