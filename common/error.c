#include "common/error.h"

#include <stdarg.h>
#include <stdio.h>

sb_status sb_error_vset(sb_error* err, sb_status status, const char* format, va_list args) {
    if (err) {
        vsnprintf(err->message, sizeof err->message, format, args);
    }
    return status;
}

sb_status sb_error_set(sb_error* err, sb_status status, const char* format, ...) {
    va_list args;
    va_start(args, format);
    sb_error_vset(err, status, format, args);
    va_end(args);
    return status;
}

sb_status sb_error_at(sb_error* err, sb_status status, const char* path, size_t line, const char* format, ...) {
    if (!err) {
        return status;
    }
    int used = line > 0 ? snprintf(err->message, sizeof err->message, "%s:%zu: ", path, line)
                        : snprintf(err->message, sizeof err->message, "%s: ", path);
    if (used < 0) {
        used = 0;
    }
    if ((size_t)used < sizeof err->message) {
        va_list args;
        va_start(args, format);
        vsnprintf(err->message + used, sizeof err->message - (size_t)used, format, args);
        va_end(args);
    }
    return status;
}

sb_status sb_error_prefix(sb_error* err, sb_status status, const char* prefix) {
    if (!err) {
        return status;
    }
    sb_error prefixed; /* formatted aside: snprintf's sources and destination must not overlap */
    sb_error_set(&prefixed, status, "%s: %s", prefix, err->message);
    *err = prefixed;
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
    case SB_ERR_BUSY: return "busy";
    }
    return "unknown";
}
