/* The nearest name (see suggest.h): the optimal string alignment distance
 * (Levenshtein with swaps of neighbours), three rows of a table at a time.
 * The first nearest name in the list wins a tie. */
#define _POSIX_C_SOURCE 200809L
#include "scenes/suggest.h"

#include <stdio.h>
#include <string.h>

enum { MAX_WORD = 128 };

static size_t min3(size_t a, size_t b, size_t c) {
    size_t m = a < b ? a : b;
    return m < c ? m : c;
}

static size_t distance(const char* a, size_t n, const char* b, size_t m) {
    size_t rows[3][MAX_WORD + 1];
    size_t *before = rows[0], *previous = rows[1], *current = rows[2];
    for (size_t j = 0; j <= m; j++) previous[j] = j;
    for (size_t i = 1; i <= n; i++) {
        current[0] = i;
        for (size_t j = 1; j <= m; j++) {
            size_t cost = a[i - 1] != b[j - 1];
            current[j] = min3(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + cost);
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && before[j - 2] + 1 < current[j])
                current[j] = before[j - 2] + 1;
        }
        size_t* oldest = before;
        before = previous;
        previous = current;
        current = oldest;
    }
    return previous[m];
}

const char* sb_suggest(const char* word, const char* const* names, size_t count) {
    size_t n = strlen(word);
    if (n == 0 || n > MAX_WORD) return NULL;
    size_t allowed = n <= 4 ? 1 : 2;
    const char* best = NULL;
    size_t best_distance = allowed + 1;
    for (size_t i = 0; i < count; i++) {
        size_t m = strlen(names[i]);
        if (m > MAX_WORD || (m > n ? m - n : n - m) > allowed) continue;
        size_t d = distance(word, n, names[i], m);
        if (d < best_distance) {
            best = names[i];
            best_distance = d;
        }
    }
    return best;
}

enum { MAX_LIST_NAMES = 64 };

const char* sb_suggest_hint(const char* word, const char* list, char* out, size_t size) {
    char copy[1024];
    snprintf(copy, sizeof copy, "%s", list);
    const char* names[MAX_LIST_NAMES];
    size_t count = 0;
    char* save = NULL;
    for (char* name = strtok_r(copy, ", ", &save); name && count < MAX_LIST_NAMES; name = strtok_r(NULL, ", ", &save))
        if (strcmp(name, "or") != 0) names[count++] = name;
    const char* near = sb_suggest(word, names, count);
    if (near && strcmp(near, word) != 0)
        snprintf(out, size, " (did you mean '%s'?)", near);
    else if (size)
        out[0] = '\0';
    return out;
}
