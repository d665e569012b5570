/* What can be checked of a PLY file before assimp reads it (see
 * mesh_readers.h): its header ends, and the elements it declares fit the
 * bytes after it.
 *
 * Each element of N items needs at least N times the sum of its
 * properties' smallest sizes: in a binary file the scalar's size (char 1,
 * short 2, int and float 4, double 8) and for a list the size of its count;
 * in an ASCII file two bytes a value (a digit and a separator); an item of
 * no properties at least one byte. A file
 * whose declared counts need more bytes than it has is refused before
 * assimp allocates for those counts (a 190-byte file declaring 10^9
 * vertices made it allocate gigabytes). A header that never ends made
 * assimp's PLY reader spin. */
#define _POSIX_C_SOURCE 200809L
#include "common/error.h"
#include "mesh/io/mesh_readers.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum { PLY_MAX_HEADER = 65536 };

typedef struct ply_header {
    const char* path;
    bool ascii;
    double needed;                       /* bytes the elements need after the header */
    char elements[160];                  /* "N 'name', ..." for the message */
    double element_count, element_bytes; /* the element being declared */
    size_t line;
} ply_header;

static double scalar_size(const char* type) {
    static const struct {
        const char* name;
        int size;
    } types[] = {{"char", 1},   {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
                 {"int16", 2},  {"uint16", 2},  {"int", 4},    {"uint", 4},   {"float", 4}, {"int32", 4},
                 {"uint32", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(type, types[i].name) == 0) return types[i].size;
    return 1; /* assimp judges an unknown type */
}

/* An item takes at least a byte even without properties: a file declaring
 * 10^9 items of nothing made assimp spin. */
static void close_element(ply_header* h) {
    h->needed += h->element_count * (h->element_bytes > 1.0 ? h->element_bytes : 1.0);
}

/* "element NAME COUNT", "property TYPE NAME" or "property list COUNT_TYPE ITEM_TYPE NAME". */
static sb_status header_line(ply_header* h, char* line, sb_error* err) {
    char* save = NULL;
    const char* word = strtok_r(line, " \t\r", &save);
    if (!word) return SB_OK;
    if (strcmp(word, "format") == 0) {
        const char* format = strtok_r(NULL, " \t\r", &save);
        h->ascii = format && strcmp(format, "ascii") == 0;
    } else if (strcmp(word, "element") == 0) {
        close_element(h);
        const char* name = strtok_r(NULL, " \t\r", &save);
        const char* count = strtok_r(NULL, " \t\r", &save);
        char* end = NULL;
        h->element_count = count ? strtod(count, &end) : -1.0;
        if (!name || !count || *end != '\0' || !(h->element_count >= 0.0))
            return sb_error_at(err, SB_ERR_PARSE, h->path, h->line, "expected 'element NAME COUNT'");
        size_t used = strlen(h->elements);
        snprintf(h->elements + used, sizeof h->elements - used, "%s%s '%.40s'", used ? ", " : "", count, name);
        h->element_bytes = 0.0;
    } else if (strcmp(word, "property") == 0) {
        const char* type = strtok_r(NULL, " \t\r", &save);
        if (type && strcmp(type, "list") == 0) type = strtok_r(NULL, " \t\r", &save);
        h->element_bytes += h->ascii ? 2.0 : type ? scalar_size(type) : 1.0;
    }
    return SB_OK;
}

static sb_status check_header(ply_header* h, char* text, size_t length, double body, sb_error* err) {
    if (strncmp(text, "ply", 3) != 0 || (text[3] != '\n' && text[3] != '\r'))
        return sb_error_at(err, SB_ERR_PARSE, h->path, 1, "not a PLY file (it must begin with a line 'ply')");
    char* line = text;
    for (h->line = 1; line < text + length; h->line++) {
        char* newline = memchr(line, '\n', (size_t)(text + length - line));
        if (!newline) break;
        *newline = '\0';
        if (strncmp(line, "end_header", 10) == 0 && strspn(line + 10, " \t\r") == strlen(line + 10)) {
            close_element(h);
            body -= (double)(newline + 1 - text);
            if (h->needed <= body) return SB_OK;
            return sb_error_at(err, SB_ERR_PARSE, h->path, h->line,
                               "the header declares %s: at least %.0f bytes, more than the %.0f bytes after it",
                               h->elements, h->needed, body);
        }
        sb_status status = header_line(h, line, err);
        if (status != SB_OK) return status;
        line = newline + 1;
    }
    return sb_error_at(err, SB_ERR_PARSE, h->path, 0,
                       "the PLY header does not end (no 'end_header' line in its first %d bytes)", PLY_MAX_HEADER);
}

sb_status sb_ply_check(const char* path, sb_error* err) {
    FILE* file = fopen(path, "rb");
    if (!file) return sb_error_at(err, SB_ERR_IO, path, 0, "cannot open: %s", strerror(errno));
    struct stat info;
    char* text = malloc(PLY_MAX_HEADER + 1);
    size_t length = text ? fread(text, 1, PLY_MAX_HEADER, file) : 0;
    bool sized = fstat(fileno(file), &info) == 0;
    fclose(file);
    if (!text) return sb_error_at(err, SB_ERR_NOMEM, path, 0, "out of memory");
    text[length] = '\0';
    ply_header h = {.path = path};
    sb_status status = sized ? check_header(&h, text, length, (double)info.st_size, err) : SB_OK;
    free(text);
    return status;
}
