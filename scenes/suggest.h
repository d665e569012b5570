/* "Did you mean": the known name nearest to a misspelt one. */
#ifndef SB_SUGGEST_H
#define SB_SUGGEST_H

#include <stddef.h>

/* The name of `names` nearest to `word` in edits (a character inserted,
 * deleted, replaced, or two neighbours swapped), when it is near enough to
 * be a slip: at most one edit for words of up to 4 characters, two for
 * longer ones. NULL when none is. */
const char* sb_suggest(const char* word, const char* const* names, size_t count);

/* " (did you mean 'NAME'?)" for the name of `list` nearest to `word`
 * (list: names separated by commas, spaces and the word "or", as the
 * messages spell them: "sheet, icosphere or file"), or "" when none is
 * near; into out, which is returned. */
const char* sb_suggest_hint(const char* word, const char* list, char* out, size_t size);

#endif
