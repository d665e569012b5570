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
 * assimp's PLY reader spin.
 *
 * An ASCII file is then checked whole: an item a line, every token a
 * number of its property's declared type (an integer type: digits with a
 * sign only if signed, within the type's range; a float type: a finite
 * decimal number), a list's count and items so, a face's vertex index
 * below the vertex count, and no line beyond the elements; a message names
 * file:line. assimp's reader took a face index 'abc', 'nan' or '1e3' as 0
 * and dropped the face as degenerate, read a coordinate '1,5' as 1, and
 * turned NaN coordinates into 'No meshes remaining'. */
#define _POSIX_C_SOURCE 200809L
#include "common/error.h"
#include "mesh/io/mesh_readers.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

enum { PLY_MAX_HEADER = 65536, PLY_MAX_ELEMENTS = 16, PLY_MAX_PROPERTIES = 64 };

typedef struct ply_property {
    char type[16], count_type[16]; /* count_type[0] == 0: a scalar */
    bool vertex_index;             /* a face's vertex_indices / vertex_index */
} ply_property;

typedef struct ply_element {
    char name[41];
    double count;
    uint32_t property_count;
    ply_property properties[PLY_MAX_PROPERTIES];
} ply_element;

typedef struct ply_header {
    const char* path;
    bool ascii;
    uint32_t element_count_declared;
    ply_element elements_list[PLY_MAX_ELEMENTS];
    size_t body_at, body_line; /* the body's offset and first line */
    bool too_many; /* more elements or properties than kept: the body is left to assimp */
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
        if (h->element_count_declared == PLY_MAX_ELEMENTS) {
            h->too_many = true;
        } else {
            ply_element* e = &h->elements_list[h->element_count_declared++];
            snprintf(e->name, sizeof e->name, "%s", name);
            e->count = h->element_count;
            e->property_count = 0;
        }
    } else if (strcmp(word, "property") == 0) {
        const char* type = strtok_r(NULL, " \t\r", &save);
        const char* count_type = NULL;
        if (type && strcmp(type, "list") == 0) {
            count_type = type = strtok_r(NULL, " \t\r", &save);
            type = strtok_r(NULL, " \t\r", &save);
        }
        const char* name = type ? strtok_r(NULL, " \t\r", &save) : NULL;
        h->element_bytes += h->ascii ? 2.0 : (count_type ? scalar_size(count_type) : type ? scalar_size(type) : 1.0);
        if (h->element_count_declared == 0 || !type || (count_type && !type)) {
            h->too_many = true; /* a property outside an element or without a type: assimp judges */
        } else {
            ply_element* e = &h->elements_list[h->element_count_declared - 1];
            if (e->property_count == PLY_MAX_PROPERTIES) {
                h->too_many = true;
            } else {
                ply_property* p = &e->properties[e->property_count++];
                snprintf(p->type, sizeof p->type, "%s", type);
                snprintf(p->count_type, sizeof p->count_type, "%s", count_type ? count_type : "");
                p->vertex_index = count_type && name && strcmp(e->name, "face") == 0 &&
                                  (strcmp(name, "vertex_indices") == 0 || strcmp(name, "vertex_index") == 0);
            }
        }
    }
    return SB_OK;
}

/* The range of an integer type (lowest, highest), or false for a float type. */
static bool integer_range(const char* type, double* lowest, double* highest) {
    static const struct {
        const char* name;
        double lowest, highest;
    } types[] = {{"char", -128, 127},          {"int8", -128, 127},        {"uchar", 0, 255},
                 {"uint8", 0, 255},            {"short", -32768, 32767},   {"int16", -32768, 32767},
                 {"ushort", 0, 65535},         {"uint16", 0, 65535},       {"int", -2147483648.0, 2147483647.0},
                 {"int32", -2147483648.0, 2147483647.0}, {"uint", 0, 4294967295.0}, {"uint32", 0, 4294967295.0}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(type, types[i].name) == 0) {
            *lowest = types[i].lowest;
            *highest = types[i].highest;
            return true;
        }
    return false;
}

typedef struct ply_cursor {
    const ply_header* h;
    char* at;   /* the next token on the line */
    size_t line;
} ply_cursor;

/* The next token of the line as a number of `type`, or an error naming
 * file:line, the element, its item and what the token is. */
static sb_status take_number(ply_cursor* c, const char* type, const char* element, double item, double* value,
                             sb_error* err) {
    c->at += strspn(c->at, " \t\r");
    size_t length = strcspn(c->at, " \t\r");
    if (length == 0)
        return sb_error_at(err, SB_ERR_PARSE, c->h->path, c->line, "%s %.0f: too few values on the line", element,
                           item);
    char token[64];
    snprintf(token, sizeof token, "%.*s", (int)(length < 60 ? length : 60), c->at);
    char* end = NULL;
    double lowest, highest;
    bool integer = integer_range(type, &lowest, &highest);
    bool digits = strspn(c->at + (c->at[0] == '-' || c->at[0] == '+'), "0123456789") ==
                  length - (size_t)(c->at[0] == '-' || c->at[0] == '+');
    errno = 0;
    *value = strtod(c->at, &end);
    bool whole = end == c->at + length && length < 60;
    if (integer) {
        if (!whole || !digits || length == (size_t)(c->at[0] == '-' || c->at[0] == '+'))
            return sb_error_at(err, SB_ERR_PARSE, c->h->path, c->line, "%s %.0f: '%s' is not an integer (%s)",
                               element, item, token, type);
        if (*value < lowest || *value > highest)
            return sb_error_at(err, SB_ERR_PARSE, c->h->path, c->line, "%s %.0f: %s is out of %s's range", element,
                               item, token, type);
    } else {
        bool decimal = strspn(c->at, "0123456789+-.eE") == length; /* no nan, inf, hex or 1,5 */
        if (!whole || !decimal || !isfinite(*value))
            return sb_error_at(err, SB_ERR_PARSE, c->h->path, c->line, "%s %.0f: '%s' is not a finite number (%s)",
                               element, item, token, type);
    }
    c->at += length;
    return SB_OK;
}

/* An ASCII body: an item a line, every value of its declared type. */
static sb_status check_body(ply_header* h, char* body, size_t length, size_t first_line, sb_error* err) {
    double vertices = 0;
    for (uint32_t e = 0; e < h->element_count_declared; e++)
        if (strcmp(h->elements_list[e].name, "vertex") == 0) vertices = h->elements_list[e].count;
    char* line = body;
    char* stop = body + length;
    ply_cursor c = {.h = h, .line = first_line};
    for (uint32_t e = 0; e < h->element_count_declared; e++) {
        const ply_element* element = &h->elements_list[e];
        for (double item = 0; item < element->count; item++) {
            while (line < stop && strspn(line, " \t\r") == strcspn(line, "\n")) { /* blank lines */
                line += strcspn(line, "\n") + 1;
                c.line++;
            }
            if (line >= stop)
                return sb_error_at(err, SB_ERR_PARSE, h->path, c.line, "ends at %s %.0f of the %.0f declared",
                                   element->name, item, element->count);
            char* newline = memchr(line, '\n', (size_t)(stop - line));
            char* next = newline ? newline + 1 : stop;
            if (newline) *newline = '\0';
            if (memchr(line, '\0', (size_t)((newline ? newline : stop) - line)))
                return sb_error_at(err, SB_ERR_PARSE, h->path, c.line, "a NUL byte in %s %.0f", element->name, item);
            c.at = line;
            for (uint32_t p = 0; p < element->property_count; p++) {
                const ply_property* property = &element->properties[p];
                double value, count = 1;
                sb_status status;
                if (property->count_type[0]) {
                    status = take_number(&c, property->count_type, element->name, item, &count, err);
                    if (status != SB_OK) return status;
                }
                for (double k = 0; k < count; k++) {
                    status = take_number(&c, property->type, element->name, item, &value, err);
                    if (status != SB_OK) return status;
                    if (property->vertex_index && value >= vertices)
                        return sb_error_at(err, SB_ERR_PARSE, h->path, c.line,
                                           "%s %.0f: vertex index %.0f, but there are %.0f vertices", element->name,
                                           item, value, vertices);
                }
            }
            if (c.at[strspn(c.at, " \t\r")] != '\0')
                return sb_error_at(err, SB_ERR_PARSE, h->path, c.line,
                                   "%s %.0f: more values on the line than its %u properties", element->name, item,
                                   element->property_count);
            line = next;
            c.line++;
        }
    }
    for (; line < stop; line += strcspn(line, "\n") + 1, c.line++)
        if (strspn(line, " \t\r") != strcspn(line, "\n"))
            return sb_error_at(err, SB_ERR_PARSE, h->path, c.line, "a line after the %s the header declares",
                               h->elements);
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
            h->body_at = (size_t)(newline + 1 - text);
            h->body_line = h->line + 1;
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

/* The ASCII body, read whole and checked. */
static sb_status check_ascii(ply_header* h, sb_error* err) {
    FILE* file = fopen(h->path, "rb");
    if (!file) return sb_error_at(err, SB_ERR_IO, h->path, 0, "cannot open: %s", strerror(errno));
    struct stat info;
    char* text = NULL;
    size_t length = 0;
    if (fstat(fileno(file), &info) == 0 && (text = malloc((size_t)info.st_size + 1)))
        length = fread(text, 1, (size_t)info.st_size, file);
    fclose(file);
    if (!text) return sb_error_at(err, SB_ERR_NOMEM, h->path, 0, "out of memory");
    text[length] = '\0';
    sb_status status = h->body_at <= length ? check_body(h, text + h->body_at, length - h->body_at, h->body_line, err)
                                            : SB_OK;
    free(text);
    return status;
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
    ply_header* h = calloc(1, sizeof *h);
    if (!h) {
        free(text);
        return sb_error_at(err, SB_ERR_NOMEM, path, 0, "out of memory");
    }
    h->path = path;
    sb_status status = sized ? check_header(h, text, length, (double)info.st_size, err) : SB_OK;
    free(text);
    if (status == SB_OK && sized && h->ascii && !h->too_many) status = check_ascii(h, err);
    free(h);
    return status;
}
