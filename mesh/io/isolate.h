/* Private to mesh/io: runs a function in a child process under limits, so
 * that a crash, an abort, a hang or an allocation storm inside it (a large
 * third-party parser given a hostile file: assimp) ends the child, not the
 * caller. See isolate.c. */
#ifndef SB_ISOLATE_H
#define SB_ISOLATE_H

#include <stddef.h>

#include "softbond/types.h"

typedef struct sb_isolate_limits {
    double seconds;      /* wall-clock time before the child is killed */
    size_t memory_bytes; /* address space the child may add to what it inherits */
} sb_isolate_limits;

/* The answer a child sends back: bytes, owned by whoever holds them. */
typedef struct sb_blob {
    unsigned char* data;
    size_t size;
} sb_blob;

/* Runs in the child: fills *answer (malloc'd data, or none). */
typedef void (*sb_isolated_fn)(void* arg, sb_blob* answer);

/* Runs fn(arg) in a forked child under limits and returns its answer in
 * *answer (the caller frees answer->data). When the child dies, is killed
 * or sends no whole answer, returns SB_ERR_IO with why saying how
 * ("killed by signal 11, Segmentation fault", "no answer within 30 s"). */
sb_status sb_isolate_run(sb_isolated_fn fn, void* arg, const sb_isolate_limits* limits, sb_blob* answer, char* why,
                         size_t why_size);

#endif
