/* The YAML files of sweep and fit (see study_yaml.h). */
#define _POSIX_C_SOURCE 200809L
#include "cli/study_yaml.h"
#include "common/error.h"
#include "scenes/suggest.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { STUDY_MAX_BYTES = 1 << 20 };

static sb_status read_whole(const char* path, unsigned char** out, size_t* size, sb_error* err) {
    FILE* f = fopen(path, "rb");
    if (!f) return sb_error_set(err, SB_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
    unsigned char* text = malloc(STUDY_MAX_BYTES + 1);
    size_t n = text ? fread(text, 1, STUDY_MAX_BYTES + 1, f) : 0;
    fclose(f);
    if (!text) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    if (n > STUDY_MAX_BYTES) {
        free(text);
        return sb_error_set(err, SB_ERR_PARSE, "%s: larger than %d bytes", path, STUDY_MAX_BYTES);
    }
    *out = text;
    *size = n;
    return SB_OK;
}

sb_status sb_study_yaml_load(sb_study_yaml* y, const char* path, sb_error* err) {
    *y = (sb_study_yaml){.err = err, .path = strdup(path)};
    if (!y->path) return sb_error_set(err, SB_ERR_NOMEM, "out of memory");
    unsigned char* text = NULL;
    size_t size = 0;
    sb_status status = read_whole(path, &text, &size, err);
    if (status != SB_OK) return status;
    yaml_parser_t parser;
    yaml_parser_initialize(&parser);
    yaml_parser_set_input_string(&parser, text, size);
    y->loaded = yaml_parser_load(&parser, &y->doc) != 0;
    if (!y->loaded)
        status = sb_error_set(err, SB_ERR_PARSE, "%s:%zu: %s", path, parser.problem_mark.line + 1,
                              parser.problem ? parser.problem : "malformed YAML");
    yaml_parser_delete(&parser);
    free(text);
    if (status != SB_OK) return status;
    yaml_node_t* root = yaml_document_get_root_node(&y->doc);
    if (!root) return sb_error_set(err, SB_ERR_PARSE, "%s: empty file", path);
    return sb_study_yaml_map(y, root, "the file");
}

void sb_study_yaml_free(sb_study_yaml* y) {
    if (y->loaded) yaml_document_delete(&y->doc);
    free(y->path);
    y->path = NULL;
    y->loaded = false;
}

yaml_node_t* sb_study_yaml_root(sb_study_yaml* y) { return yaml_document_get_root_node(&y->doc); }

sb_status sb_study_yaml_fail(sb_study_yaml* y, const yaml_node_t* node, const char* format, ...) {
    char message[sizeof y->err->message];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    return sb_error_set(y->err, SB_ERR_PARSE, "%s:%zu: %s", y->path, node->start_mark.line + 1, message);
}

static const char* scalar(const yaml_node_t* node) {
    return node->type == YAML_SCALAR_NODE ? (const char*)node->data.scalar.value : NULL;
}

sb_status sb_study_yaml_check_keys(sb_study_yaml* y, const yaml_node_t* map, const char* const* known) {
    size_t count = 0;
    while (known[count]) count++;
    for (yaml_node_pair_t* p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top; p++) {
        yaml_node_t* key = yaml_document_get_node(&y->doc, p->key);
        const char* name = scalar(key);
        bool found = false;
        for (size_t k = 0; name && k < count && !found; k++) found = strcmp(name, known[k]) == 0;
        if (found) continue;
        const char* near = name ? sb_suggest(name, known, count) : NULL;
        return sb_study_yaml_fail(y, key, "unknown key '%s'%s%s%s", name ? name : "?", near ? " (did you mean '" : "",
                                  near ? near : "", near ? "'?)" : "");
    }
    return SB_OK;
}

yaml_node_t* sb_study_yaml_get(sb_study_yaml* y, const yaml_node_t* map, const char* key) {
    for (yaml_node_pair_t* p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top; p++) {
        const char* name = scalar(yaml_document_get_node(&y->doc, p->key));
        if (name && strcmp(name, key) == 0) return yaml_document_get_node(&y->doc, p->value);
    }
    return NULL;
}

yaml_node_t* sb_study_yaml_item(sb_study_yaml* y, const yaml_node_t* seq, size_t i) {
    return yaml_document_get_node(&y->doc, seq->data.sequence.items.start[i]);
}

size_t sb_study_yaml_count(const yaml_node_t* seq) {
    return seq->type == YAML_SEQUENCE_NODE ? (size_t)(seq->data.sequence.items.top - seq->data.sequence.items.start)
                                           : 0;
}

/* "a map", "a sequence" or the scalar's text, for messages. */
static void describe(const yaml_node_t* node, char* out, size_t size) {
    if (node->type == YAML_MAPPING_NODE)
        snprintf(out, size, "a map");
    else if (node->type == YAML_SEQUENCE_NODE)
        snprintf(out, size, "a sequence");
    else
        snprintf(out, size, "'%.60s'", scalar(node));
}

static sb_status expected(sb_study_yaml* y, const yaml_node_t* node, const char* what, const char* kind) {
    char got[80];
    describe(node, got, sizeof got);
    return sb_study_yaml_fail(y, node, "%s: expected %s, got %s", what, kind, got);
}

sb_status sb_study_yaml_text(sb_study_yaml* y, const yaml_node_t* node, const char* what, const char** out) {
    if (!scalar(node) || !scalar(node)[0]) return expected(y, node, what, "text");
    *out = scalar(node);
    return SB_OK;
}

sb_status sb_study_yaml_number(sb_study_yaml* y, const yaml_node_t* node, const char* what, double* out) {
    const char* text = scalar(node);
    char* end = NULL;
    if (text) *out = strtod(text, &end);
    if (!text || end == text || *end != '\0' || !isfinite(*out)) return expected(y, node, what, "a number");
    return SB_OK;
}

sb_status sb_study_yaml_whole(sb_study_yaml* y, const yaml_node_t* node, const char* what, long lo, long hi,
                              long* out) {
    const char* text = scalar(node);
    char* end = NULL;
    if (text) *out = strtol(text, &end, 10);
    if (!text || end == text || *end != '\0' || *out < lo || *out > hi) {
        char kind[96];
        snprintf(kind, sizeof kind, "a whole number from %ld to %ld", lo, hi);
        return expected(y, node, what, kind);
    }
    return SB_OK;
}

sb_status sb_study_yaml_bool(sb_study_yaml* y, const yaml_node_t* node, const char* what, bool* out) {
    int index;
    static const char* const choices[] = {"false", "true", NULL};
    sb_status status = sb_study_yaml_choice(y, node, what, choices, &index);
    *out = index == 1;
    return status;
}

sb_status sb_study_yaml_sequence(sb_study_yaml* y, const yaml_node_t* node, const char* what) {
    if (node->type != YAML_SEQUENCE_NODE || sb_study_yaml_count(node) == 0)
        return expected(y, node, what, "a sequence of at least one item");
    return SB_OK;
}

sb_status sb_study_yaml_map(sb_study_yaml* y, const yaml_node_t* node, const char* what) {
    return node->type == YAML_MAPPING_NODE ? SB_OK : expected(y, node, what, "a map");
}

sb_status sb_study_yaml_choice(sb_study_yaml* y, const yaml_node_t* node, const char* what, const char* const* choices,
                               int* out) {
    const char* text = scalar(node);
    for (int i = 0; text && choices[i]; i++)
        if (strcmp(text, choices[i]) == 0) {
            *out = i;
            return SB_OK;
        }
    char kind[256] = "one of";
    for (int i = 0; choices[i]; i++)
        snprintf(kind + strlen(kind), sizeof kind - strlen(kind), "%s %s", i ? "," : "", choices[i]);
    *out = 0;
    return expected(y, node, what, kind);
}

char* sb_study_yaml_relative(const sb_study_yaml* y, const char* name) {
    const char* slash = strrchr(y->path, '/');
    if (name[0] == '/' || !slash) return strdup(name);
    size_t size = (size_t)(slash - y->path) + strlen(name) + 2;
    char* out = malloc(size);
    if (out) snprintf(out, size, "%.*s/%s", (int)(slash - y->path), y->path, name);
    return out;
}
