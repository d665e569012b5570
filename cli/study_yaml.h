/* The YAML files of `softbond sweep` and `softbond fit`: a document read
 * whole (libyaml's document API keeps every node's line), and helpers that
 * read a map's entries and fail with one line, "FILE:LINE: message" (the
 * scenes' form). Each file's own module says which keys it takes; a key it
 * does not know is refused with the nearest known one. */
#ifndef SB_STUDY_YAML_H
#define SB_STUDY_YAML_H

#include <stdbool.h>
#include <stddef.h>
#include <yaml.h>

#include "softbond/types.h"

typedef struct sb_study_yaml {
    yaml_document_t doc;
    char* path;  /* as given */
    bool loaded; /* doc holds a document */
    sb_error* err;
} sb_study_yaml;

/* Reads path (at most 1 MiB) into y; the root must be a map. */
sb_status sb_study_yaml_load(sb_study_yaml* y, const char* path, sb_error* err);
void sb_study_yaml_free(sb_study_yaml* y);
yaml_node_t* sb_study_yaml_root(sb_study_yaml* y);

/* "PATH:LINE: message" into y->err; returns SB_ERR_PARSE. */
sb_status sb_study_yaml_fail(sb_study_yaml* y, const yaml_node_t* node, const char* format, ...)
    __attribute__((format(printf, 3, 4)));

/* Refuses a key of map not in `known` (NULL-terminated), naming the nearest. */
sb_status sb_study_yaml_check_keys(sb_study_yaml* y, const yaml_node_t* map, const char* const* known);
/* The value of key in map, or NULL. */
yaml_node_t* sb_study_yaml_get(sb_study_yaml* y, const yaml_node_t* map, const char* key);
/* Item i of a sequence. */
yaml_node_t* sb_study_yaml_item(sb_study_yaml* y, const yaml_node_t* seq, size_t i);
size_t sb_study_yaml_count(const yaml_node_t* seq);

/* Typed reads of a node; each fails naming the node's line and `what`. */
sb_status sb_study_yaml_text(sb_study_yaml* y, const yaml_node_t* node, const char* what, const char** out);
sb_status sb_study_yaml_number(sb_study_yaml* y, const yaml_node_t* node, const char* what, double* out);
sb_status sb_study_yaml_whole(sb_study_yaml* y, const yaml_node_t* node, const char* what, long lo, long hi, long* out);
sb_status sb_study_yaml_bool(sb_study_yaml* y, const yaml_node_t* node, const char* what, bool* out);
/* A sequence (of any length >= 1), or fails. */
sb_status sb_study_yaml_sequence(sb_study_yaml* y, const yaml_node_t* node, const char* what);
sb_status sb_study_yaml_map(sb_study_yaml* y, const yaml_node_t* node, const char* what);
/* A scalar that is one of `choices` (NULL-terminated); its index. */
sb_status sb_study_yaml_choice(sb_study_yaml* y, const yaml_node_t* node, const char* what, const char* const* choices,
                               int* out);

/* The path of a file named in the YAML file: relative to the file's folder
 * (malloc'd; NULL when out of memory). */
char* sb_study_yaml_relative(const sb_study_yaml* y, const char* name);

#endif
