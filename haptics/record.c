/* A small record between threads (haptics/record.h).
 *
 * Design: a sequence lock whose words are themselves atomics. The writer
 * makes the sequence odd, stores the words, makes it even again; a reader
 * reads the sequence, the words, the sequence again, and keeps the copy
 * when both reads agree and are even. A record is a few dozen bytes, so the
 * reader's copy costs less than taking and handing back a slot (the state
 * buffer's way, made for megabytes read in place), and the writer never
 * waits at all. The words are relaxed atomics ordered by fences, so there
 * is no data race in C11's sense and the thread sanitizer sees none. A
 * reader retries only when the writer wrote during its copy; after
 * SB_RECORD_TRIES such tries it gives up (false) rather than wait. */
#include "haptics/record.h"

#include <string.h>

enum { SB_RECORD_TRIES = 8 };

void sb_record_init(sb_record* record) {
    atomic_init(&record->sequence, 0);
    for (int i = 0; i < SB_RECORD_WORDS; i++) atomic_init(&record->words[i], 0);
}

void sb_record_write(sb_record* record, const void* data, size_t size) {
    uint64_t words[SB_RECORD_WORDS] = {0};
    memcpy(words, data, size);
    uint64_t s = atomic_load_explicit(&record->sequence, memory_order_relaxed);
    atomic_store_explicit(&record->sequence, s + 1, memory_order_relaxed);
    atomic_thread_fence(memory_order_release);
    for (size_t i = 0; i < (size + 7) / 8; i++)
        atomic_store_explicit(&record->words[i], words[i], memory_order_relaxed);
    atomic_store_explicit(&record->sequence, s + 2, memory_order_release);
}

bool sb_record_read(const sb_record* record, void* data, size_t size) {
    uint64_t words[SB_RECORD_WORDS];
    for (int t = 0; t < SB_RECORD_TRIES; t++) {
        uint64_t before = atomic_load_explicit(&record->sequence, memory_order_acquire);
        if (before == 0) return false;
        if (before & 1) continue;
        for (size_t i = 0; i < (size + 7) / 8; i++)
            words[i] = atomic_load_explicit(&record->words[i], memory_order_relaxed);
        atomic_thread_fence(memory_order_acquire);
        if (atomic_load_explicit(&record->sequence, memory_order_relaxed) == before) {
            memcpy(data, words, size);
            return true;
        }
    }
    return false;
}

uint64_t sb_record_writes(const sb_record* record) {
    return atomic_load_explicit(&record->sequence, memory_order_acquire) / 2;
}
