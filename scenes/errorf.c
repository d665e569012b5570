/* sb_errorf (see errorf.h). */
#include "scenes/errorf.h"

#include <stdio.h>

sb_status sb_verrorf(sb_error* err, sb_status status, const char* format, va_list args) {
    vsnprintf(err->message, sizeof err->message, format, args);
    return status;
}

sb_status sb_errorf(sb_error* err, sb_status status, const char* format, ...) {
    va_list args;
    va_start(args, format);
    sb_verrorf(err, status, format, args);
    va_end(args);
    return status;
}

sb_status sb_error_prefix(sb_error* err, sb_status status, const char* prefix) {
    sb_error original = *err;
    return sb_errorf(err, status, "%s: %s", prefix, original.message);
}
