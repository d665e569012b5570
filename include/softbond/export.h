/** @file
 * SB_API marks the functions of the public API. The libraries are built with
 * hidden visibility, so only what carries SB_API is exported from
 * libsoftbond.so and libsoftbond_io.so; everything else stays internal. */
#ifndef SOFTBOND_EXPORT_H
#define SOFTBOND_EXPORT_H

#if defined(__GNUC__) || defined(__clang__)
#define SB_API __attribute__((visibility("default")))
#else
#define SB_API
#endif

#endif
