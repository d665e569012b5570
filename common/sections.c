/* Tagged sections (see sections.h). */
#include "common/sections.h"
#include "common/error.h"

#include <string.h>

enum { SB_HEADER_SIZE = 32, SB_SECTION_HEAD = 16 };
static const uint32_t sb_byte_order = 0x01020304u;
static const char sb_sum_tag[4] = {'S', 'U', 'M', '!'};

uint64_t sb_hash(uint64_t hash, const void* data, size_t size) {
    const uint8_t* p = data;
    for (size_t k = 0; k < size; k++) hash = (hash ^ p[k]) * 0x100000001b3ull;
    return hash;
}

/* Writes at offset when it fits (a counting writer never does; an empty
 * array may be NULL). */
static void sb_write_at(sb_sections_writer* w, size_t offset, const void* bytes, size_t size) {
    if (w->data && size > 0 && offset <= w->capacity && size <= w->capacity - offset)
        memcpy(w->data + offset, bytes, size);
}

void sb_sections_put(sb_sections_writer* w, const void* bytes, size_t size) {
    sb_write_at(w, w->size, bytes, size);
    w->size += size;
}

void sb_sections_begin(sb_sections_writer* w, void* data, size_t capacity, const sb_sections_header* h) {
    *w = (sb_sections_writer){.data = data, .capacity = capacity};
    uint32_t words[4] = {h->version, h->real_size, h->vertex_count, sb_byte_order};
    sb_sections_put(w, h->magic, sizeof h->magic);
    sb_sections_put(w, words, sizeof words);
    sb_sections_put(w, &h->hash, sizeof h->hash);
}

void sb_sections_open(sb_sections_writer* w, const char tag[4]) {
    w->open = w->size;
    uint8_t head[SB_SECTION_HEAD] = {0};
    memcpy(head, tag, 4);
    sb_sections_put(w, head, sizeof head);
}

void sb_sections_close(sb_sections_writer* w) {
    uint64_t length = w->size - w->open - SB_SECTION_HEAD;
    sb_write_at(w, w->open + 8, &length, sizeof length);
    static const uint8_t zeros[8] = {0};
    sb_sections_put(w, zeros, (8 - w->size % 8) % 8);
}

bool sb_sections_end(sb_sections_writer* w) {
    bool fits = w->data && w->size + SB_SECTION_HEAD + 8 <= w->capacity;
    sb_sections_open(w, sb_sum_tag);
    uint64_t sum = fits ? sb_hash(SB_HASH_START, w->data, w->open) : 0;
    sb_sections_put(w, &sum, sizeof sum);
    sb_sections_close(w);
    return fits;
}

/* The section at offset: its tag and payload; false when it runs past the end. */
static bool sb_section_at(const sb_sections_reader* r, size_t offset, char tag[4], sb_cursor* payload) {
    if (r->size - offset < SB_SECTION_HEAD) return false;
    uint64_t length;
    memcpy(tag, r->data + offset, 4);
    memcpy(&length, r->data + offset + 8, sizeof length);
    if (length > r->size - offset - SB_SECTION_HEAD) return false;
    *payload = (sb_cursor){r->data + offset + SB_SECTION_HEAD, (size_t)length};
    return true;
}

static size_t sb_section_end(size_t offset, const sb_cursor* payload) {
    size_t end = offset + SB_SECTION_HEAD + payload->left;
    return end + (8 - end % 8) % 8;
}

/* Walks the sections to the checksum, which must match and be last. */
static sb_status sb_sections_check(const sb_sections_reader* r, const char* what, sb_error* err) {
    size_t offset = SB_HEADER_SIZE;
    for (;;) {
        char tag[4];
        sb_cursor payload;
        uint32_t reserved;
        if (offset >= r->size || !sb_section_at(r, offset, tag, &payload))
            return sb_error_set(err, SB_ERR_PARSE, "%s: truncated (a section runs past the end at byte %zu of %zu)",
                                what, offset, r->size);
        memcpy(&reserved, r->data + offset + 4, sizeof reserved);
        if (reserved != 0) /* the checksum's own header is not summed: every header is checked so */
            return sb_error_set(err, SB_ERR_PARSE, "%s: corrupt (a section header at byte %zu)", what, offset);
        if (memcmp(tag, sb_sum_tag, 4) != 0) {
            offset = sb_section_end(offset, &payload);
            continue;
        }
        uint64_t stored, sum = sb_hash(SB_HASH_START, r->data, offset);
        if (payload.left != sizeof stored || sb_section_end(offset, &payload) != r->size)
            return sb_error_set(err, SB_ERR_PARSE, "%s: corrupt (bytes after the checksum at byte %zu)", what, offset);
        memcpy(&stored, payload.at, sizeof stored);
        if (stored != sum)
            return sb_error_set(err, SB_ERR_PARSE, "%s: corrupt (the checksum does not match the contents)", what);
        return SB_OK;
    }
}

sb_status sb_sections_read(sb_sections_reader* r, const void* data, size_t size, const char magic[8], uint32_t version,
                           const char* what, sb_error* err) {
    *r = (sb_sections_reader){.data = data, .size = size};
    if (size < SB_HEADER_SIZE || memcmp(data, magic, 8) != 0)
        return sb_error_set(err, SB_ERR_PARSE, "%s: not a softbond %.8s file (%s)", what, magic,
                            size < SB_HEADER_SIZE ? "too short" : "wrong magic bytes");
    uint32_t words[4];
    memcpy(r->header.magic, data, 8);
    memcpy(words, r->data + 8, sizeof words);
    memcpy(&r->header.hash, r->data + 24, sizeof r->header.hash);
    if (words[3] != sb_byte_order)
        return sb_error_set(err, SB_ERR_PARSE, "%s: written on a machine of another byte order", what);
    if (words[0] != version)
        return sb_error_set(err, SB_ERR_PARSE, "%s: format version %u, this build reads version %u", what, words[0],
                            version);
    r->header.version = words[0];
    r->header.real_size = words[1];
    r->header.vertex_count = words[2];
    return sb_sections_check(r, what, err);
}

bool sb_sections_find(const sb_sections_reader* r, const char tag[4], sb_cursor* out) {
    char at[4];
    for (size_t offset = SB_HEADER_SIZE; offset < r->size && sb_section_at(r, offset, at, out);
         offset = sb_section_end(offset, out))
        if (memcmp(at, tag, 4) == 0) return true;
    return false;
}

bool sb_cursor_take(sb_cursor* c, void* out, size_t size) {
    if (size > c->left) return false;
    if (size > 0) memcpy(out, c->at, size); /* an empty array may be NULL */
    c->at += size;
    c->left -= size;
    return true;
}

void sb_ranges_put(sb_sections_writer* w, const sb_range* ranges, int count) {
    for (int k = 0; k < count; k++) sb_sections_put(w, ranges[k].at, ranges[k].bytes);
}

void sb_ranges_take(sb_cursor* c, const sb_range* ranges, int count) {
    for (int k = 0; k < count; k++) sb_cursor_take(c, ranges[k].at, ranges[k].bytes);
}
