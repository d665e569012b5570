/* Reading scene values from YAML: a scene file, or the value of one --set.
 *
 * Both go through libyaml's document API, which keeps the line of every
 * node. Nested maps are flattened into dotted names as they are walked: a
 * name that is a key takes the node as its value; a name that is not a key
 * but holds a map is a prefix and is walked into; anything else is unknown.
 * A key given twice in one source (`bond: {k: 1}` and `bond.k: 2`) is an
 * error; a later source (a --set) simply wins. A key of type SB_SCENE_LIST
 * (a sequence of maps: `colliders`) is not flattened: its node tree is
 * copied with every node's line (scene_node.h) and checked later by the
 * key's own module, since which keys an entry may have depends on the entry.
 *
 * Limits, checked before the document is loaded (libyaml's loader takes
 * time quadratic in the nesting depth): a scene file holds at most
 * SB_SCENE_MAX_BYTES; a first pass over libyaml's events refuses nesting
 * deeper than SB_SCENE_MAX_NESTING, aliases (`*name`: a few of them can
 * stand for billions of nodes) and explicit tags (`!!str 0.001` would
 * read as a number), each with its line. */
#define _POSIX_C_SOURCE 200809L
#include "scenes/scene.h"
#include "common/error.h"
#include "scenes/suggest.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <yaml.h>

enum { SB_SCENE_MAX_BYTES = 16 << 20, SB_SCENE_MAX_NESTING = 64 };

typedef struct yaml_source {
    sb_scene* scene;
    yaml_document_t* doc;
    const char* name;               /* the file's path, or "--set key=value" */
    bool has_lines;                 /* file: errors carry the node's line */
    const char* base_dir;           /* where relative paths point; NULL for cwd */
    size_t seen_line[SB_KEY_COUNT]; /* 1-based line a key was set at */
    bool seen[SB_KEY_COUNT];
    sb_error* err;
} yaml_source;

static void node_where(const yaml_source* src, const yaml_node_t* node, char* out, size_t size) {
    if (src->has_lines)
        snprintf(out, size, "%s:%zu", src->name, node->start_mark.line + 1);
    else
        snprintf(out, size, "%s", src->name);
}

static sb_status source_fail(const yaml_source* src, const yaml_node_t* node, const char* format, ...)
    __attribute__((format(printf, 3, 4)));
static sb_status source_fail(const yaml_source* src, const yaml_node_t* node, const char* format, ...) {
    char where[320];
    node_where(src, node, where, sizeof where);
    va_list args;
    va_start(args, format);
    sb_error_vset(src->err, SB_ERR_PARSE, format, args);
    va_end(args);
    return sb_error_prefix(src->err, SB_ERR_PARSE, where);
}

/* ---- scalars -------------------------------------------------------------- */

static const char* scalar_text(const yaml_node_t* node) { return (const char*)node->data.scalar.value; }

static bool is_plain_scalar(const yaml_node_t* node) {
    return node->type == YAML_SCALAR_NODE && node->data.scalar.style == YAML_PLAIN_SCALAR_STYLE &&
           node->data.scalar.length > 0;
}

static bool parse_number(const yaml_node_t* node, double* out) {
    return node->type == YAML_SCALAR_NODE &&
           sb_scene_scalar_number(scalar_text(node), node->data.scalar.style == YAML_PLAIN_SCALAR_STYLE, out);
}

static bool parse_integer(const yaml_node_t* node, int64_t* out) {
    if (!is_plain_scalar(node)) return false;
    char* end;
    errno = 0;
    long long value = strtoll(scalar_text(node), &end, 10);
    *out = value;
    return *end == '\0' && errno == 0;
}

static bool parse_bool(const yaml_node_t* node, bool* out) {
    static const char* const words[] = {"true", "True", "TRUE", "false", "False", "FALSE"};
    if (!is_plain_scalar(node)) return false;
    for (int i = 0; i < 6; i++) {
        if (strcmp(scalar_text(node), words[i]) == 0) {
            *out = i < 3;
            return true;
        }
    }
    return false;
}

static yaml_node_t* item_node(const yaml_source* src, const yaml_node_t* seq, size_t i) {
    return yaml_document_get_node(src->doc, seq->data.sequence.items.start[i]);
}

static size_t item_count(const yaml_node_t* seq) {
    return (size_t)(seq->data.sequence.items.top - seq->data.sequence.items.start);
}

/* What a node is, for "expects a number, got ..." messages. */
static void describe_node(const yaml_node_t* node, char* out, size_t size) {
    if (node->type == YAML_SEQUENCE_NODE)
        snprintf(out, size, "a sequence of %zu", item_count(node));
    else if (node->type == YAML_MAPPING_NODE)
        snprintf(out, size, "a map");
    else
        snprintf(out, size, "'%.80s'", scalar_text(node));
}

static sb_status type_fail(const yaml_source* src, const yaml_node_t* node, sb_scene_key key, const char* expected) {
    char got[100];
    describe_node(node, got, sizeof got);
    return source_fail(src, node, "'%s' expects %s, got %s", sb_scene_key_get(key)->name, expected, got);
}

/* ---- values of each type -------------------------------------------------- */

static bool parse_comma_vec3(const yaml_node_t* node, double out[3]) {
    return node->type == YAML_SCALAR_NODE &&
           sb_scene_comma_vec3(scalar_text(node), node->data.scalar.style == YAML_PLAIN_SCALAR_STYLE, out);
}

#define VEC3_FORMS SB_SCENE_VEC3_FORMS

static sb_status read_vec3(const yaml_source* src, const yaml_node_t* node, sb_scene_key key, sb_scene_value* out) {
    if (parse_comma_vec3(node, out->vec3)) return SB_OK;
    if (node->type != YAML_SEQUENCE_NODE || item_count(node) != 3) return type_fail(src, node, key, VEC3_FORMS);
    for (size_t i = 0; i < 3; i++) {
        yaml_node_t* item = item_node(src, node, i);
        if (!parse_number(item, &out->vec3[i])) return type_fail(src, item, key, "a number");
    }
    return SB_OK;
}

static sb_status read_indices(const yaml_source* src, const yaml_node_t* node, sb_scene_key key, sb_scene_value* out) {
    if (node->type != YAML_SEQUENCE_NODE) return type_fail(src, node, key, "a sequence of vertex indices");
    size_t count = item_count(node);
    if (count > UINT32_MAX) return source_fail(src, node, "too many indices");
    out->indices = malloc((count ? count : 1) * sizeof *out->indices);
    if (!out->indices) return source_fail(src, node, "out of memory");
    out->index_count = (uint32_t)count;
    for (size_t i = 0; i < count; i++) {
        yaml_node_t* item = item_node(src, node, i);
        int64_t index;
        if (!parse_integer(item, &index) || index < 0 || index > UINT32_MAX)
            return type_fail(src, item, key, "a vertex index (an integer >= 0)");
        out->indices[i] = (uint32_t)index;
    }
    return SB_OK;
}

static sb_status read_string(const yaml_source* src, const yaml_node_t* node, sb_scene_key key, sb_scene_value* out) {
    if (node->type != YAML_SCALAR_NODE) return type_fail(src, node, key, "a string");
    out->string = strdup(scalar_text(node));
    return out->string ? SB_OK : source_fail(src, node, "out of memory");
}

/* A scalar as it is, or a sequence of scalars joined with commas. */
static sb_status read_names(const yaml_source* src, const yaml_node_t* node, sb_scene_key key, sb_scene_value* out) {
    if (node->type == YAML_SCALAR_NODE) return read_string(src, node, key, out);
    if (node->type != YAML_SEQUENCE_NODE) return type_fail(src, node, key, "a sequence of names");
    size_t size = 1;
    for (size_t i = 0; i < item_count(node); i++) {
        yaml_node_t* item = item_node(src, node, i);
        if (item->type != YAML_SCALAR_NODE) return type_fail(src, item, key, "a name");
        size += item->data.scalar.length + 1;
    }
    if (!(out->string = calloc(size, 1))) return source_fail(src, node, "out of memory");
    for (size_t i = 0; i < item_count(node); i++) {
        if (i) strcat(out->string, ",");
        strcat(out->string, scalar_text(item_node(src, node, i)));
    }
    return SB_OK;
}

/* ---- structured values: a copy of the node tree ---------------------------- */

enum { MAX_DEPTH = 32 };

static sb_status copy_node(const yaml_source* src, const yaml_node_t* node, sb_scene_node* out, int depth);

/* The items of a sequence, or the keys and values of a map. */
static sb_status copy_children(const yaml_source* src, const yaml_node_t* node, sb_scene_node* out, int depth) {
    bool map = node->type == YAML_MAPPING_NODE;
    size_t count = map ? (size_t)(node->data.mapping.pairs.top - node->data.mapping.pairs.start) : item_count(node);
    out->items = calloc(count ? count : 1, sizeof *out->items);
    out->keys = map ? calloc(count ? count : 1, sizeof *out->keys) : NULL;
    if (!out->items || (map && !out->keys)) return source_fail(src, node, "out of memory");
    for (size_t i = 0; i < count; i++) {
        const yaml_node_pair_t* pair = map ? &node->data.mapping.pairs.start[i] : NULL;
        const yaml_node_t* value = map ? yaml_document_get_node(src->doc, pair->value) : item_node(src, node, i);
        out->count = i + 1; /* what is there to free */
        sb_status status = copy_node(src, value, &out->items[i], depth + 1);
        if (status == SB_OK && map) {
            const yaml_node_t* key = yaml_document_get_node(src->doc, pair->key);
            if (key->type != YAML_SCALAR_NODE) return source_fail(src, key, "a key must be a plain name");
            status = copy_node(src, key, &out->keys[i], depth + 1);
        }
        if (status != SB_OK) return status;
    }
    return SB_OK;
}

static sb_status copy_node(const yaml_source* src, const yaml_node_t* node, sb_scene_node* out, int depth) {
    if (depth > MAX_DEPTH) return source_fail(src, node, "nested more than %d deep", MAX_DEPTH);
    out->line = src->has_lines ? node->start_mark.line + 1 : 0;
    if (node->type == YAML_SCALAR_NODE) {
        out->kind = SB_NODE_SCALAR;
        out->plain = node->data.scalar.style == YAML_PLAIN_SCALAR_STYLE;
        out->text = strdup(scalar_text(node));
        return out->text ? SB_OK : source_fail(src, node, "out of memory");
    }
    out->kind = node->type == YAML_MAPPING_NODE ? SB_NODE_MAP : SB_NODE_SEQUENCE;
    return copy_children(src, node, out, depth);
}

/* A sequence (of maps: the key's own module checks the rest), kept whole. */
static sb_status read_list(const yaml_source* src, const yaml_node_t* node, sb_scene_key key, sb_scene_value* out) {
    if (node->type != YAML_SEQUENCE_NODE) return type_fail(src, node, key, "a sequence of maps");
    if (!(out->tree = calloc(1, sizeof *out->tree)) || !(out->tree->source = strdup(src->name)))
        return source_fail(src, node, "out of memory");
    return copy_node(src, node, &out->tree->root, 0);
}

static sb_status read_value(const yaml_source* src, const yaml_node_t* node, sb_scene_key key, sb_scene_value* out) {
    switch (sb_scene_key_get(key)->type) {
    case SB_SCENE_NUMBER: return parse_number(node, &out->number) ? SB_OK : type_fail(src, node, key, "a number");
    case SB_SCENE_INTEGER: return parse_integer(node, &out->integer) ? SB_OK : type_fail(src, node, key, "an integer");
    case SB_SCENE_BOOL: return parse_bool(node, &out->boolean) ? SB_OK : type_fail(src, node, key, "true or false");
    case SB_SCENE_STRING: return read_string(src, node, key, out);
    case SB_SCENE_VEC3: return read_vec3(src, node, key, out);
    case SB_SCENE_VEC3_OR_NUMBER:
        if (node->type != YAML_SCALAR_NODE) return read_vec3(src, node, key, out);
        if (parse_comma_vec3(node, out->vec3)) return SB_OK;
        if (!parse_number(node, &out->vec3[0])) return type_fail(src, node, key, "a number or " VEC3_FORMS);
        out->vec3[1] = out->vec3[2] = out->vec3[0];
        return SB_OK;
    case SB_SCENE_INDICES: return read_indices(src, node, key, out);
    case SB_SCENE_NAMES: return read_names(src, node, key, out);
    case SB_SCENE_LIST: return read_list(src, node, key, out);
    }
    return SB_ERR_INVALID;
}

static void value_release(sb_scene_value* value) {
    free(value->string);
    free(value->indices);
    free(value->base_dir);
    sb_scene_tree_free(value->tree);
}

/* ---- walking the document ------------------------------------------------- */

static sb_status assign(yaml_source* src, const yaml_node_t* key_node, const yaml_node_t* node, sb_scene_key key) {
    if (src->seen[key])
        return source_fail(src, key_node, "duplicate key '%s' (first set at line %zu)", sb_scene_key_get(key)->name,
                           src->seen_line[key]);
    src->seen[key] = true;
    src->seen_line[key] = key_node->start_mark.line + 1;
    sb_scene_value value = {0};
    sb_status status = read_value(src, node, key, &value);
    if (status == SB_OK && src->base_dir && !(value.base_dir = strdup(src->base_dir)))
        status = source_fail(src, node, "out of memory");
    if (status != SB_OK) {
        value_release(&value);
        return status;
    }
    node_where(src, node, value.where, sizeof value.where);
    value_release(&src->scene->values[key]);
    src->scene->values[key] = value;
    return SB_OK;
}

static sb_status walk_map(yaml_source* src, const yaml_node_t* map, const char* prefix);

/* The known key nearest to a misspelt name, or NULL. */
static const char* nearest_key(const char* name) {
    const char* names[SB_KEY_COUNT];
    for (int i = 0; i < SB_KEY_COUNT; i++) names[i] = sb_scene_key_get((sb_scene_key)i)->name;
    return sb_suggest(name, names, SB_KEY_COUNT);
}

static sb_status apply(yaml_source* src, const yaml_node_t* key_node, const char* name, const yaml_node_t* node) {
    sb_scene_key key;
    if (sb_scene_key_find(name, &key)) return assign(src, key_node, node, key);
    bool nonempty_map =
        node->type == YAML_MAPPING_NODE && node->data.mapping.pairs.top > node->data.mapping.pairs.start;
    if (nonempty_map) return walk_map(src, node, name);
    const char* near = nearest_key(name);
    if (near) return source_fail(src, key_node, "unknown key '%s' (did you mean '%s'?)", name, near);
    return source_fail(src, key_node, "unknown key '%s'", name);
}

static sb_status walk_pair(yaml_source* src, const yaml_node_pair_t* pair, const char* prefix) {
    const yaml_node_t* key_node = yaml_document_get_node(src->doc, pair->key);
    const yaml_node_t* value = yaml_document_get_node(src->doc, pair->value);
    if (key_node->type != YAML_SCALAR_NODE) return source_fail(src, key_node, "a key must be a plain name");
    char name[256];
    int length = snprintf(name, sizeof name, "%s%s%s", prefix, prefix[0] ? "." : "", scalar_text(key_node));
    if (length < 0 || (size_t)length >= sizeof name) return source_fail(src, key_node, "key too long");
    return apply(src, key_node, name, value);
}

static sb_status walk_map(yaml_source* src, const yaml_node_t* map, const char* prefix) {
    for (const yaml_node_pair_t* pair = map->data.mapping.pairs.start; pair < map->data.mapping.pairs.top; pair++) {
        sb_status status = walk_pair(src, pair, prefix);
        if (status != SB_OK) return status;
    }
    return SB_OK;
}

/* ---- entry points ---------------------------------------------------------- */

static sb_status yaml_fail(const yaml_source* src, const yaml_parser_t* parser) {
    const char* problem = parser->problem ? parser->problem : "unreadable";
    if (src->has_lines)
        return sb_error_at(src->err, SB_ERR_PARSE, src->name, parser->problem_mark.line + 1, "malformed YAML: %s",
                           problem);
    return sb_error_at(src->err, SB_ERR_PARSE, src->name, 0, "malformed value: %s", problem);
}

static sb_status line_fail(const yaml_source* src, size_t line, const char* what) {
    return sb_error_at(src->err, SB_ERR_PARSE, src->name, src->has_lines ? line + 1 : 0, "%s", what);
}

static bool has_tag(const yaml_event_t* event) {
    const yaml_char_t* tag = event->type == YAML_SCALAR_EVENT           ? event->data.scalar.tag
                             : event->type == YAML_SEQUENCE_START_EVENT ? event->data.sequence_start.tag
                             : event->type == YAML_MAPPING_START_EVENT  ? event->data.mapping_start.tag
                                                                        : NULL;
    return tag != NULL;
}

/* One event: the nesting it leaves, or what is refused in it. */
static sb_status check_event(const yaml_source* src, const yaml_event_t* event, int* depth) {
    yaml_event_type_t type = event->type;
    *depth += (type == YAML_SEQUENCE_START_EVENT || type == YAML_MAPPING_START_EVENT) -
              (type == YAML_SEQUENCE_END_EVENT || type == YAML_MAPPING_END_EVENT);
    size_t line = event->start_mark.line;
    if (*depth > SB_SCENE_MAX_NESTING) {
        char what[64];
        snprintf(what, sizeof what, "nested more than %d levels deep", SB_SCENE_MAX_NESTING);
        return line_fail(src, line, what);
    }
    if (type == YAML_ALIAS_EVENT) return line_fail(src, line, "aliases (*name) are not supported");
    if (has_tag(event)) return line_fail(src, line, "YAML tags (!!str, !name) are not supported");
    return SB_OK;
}

/* The first pass over the events (see the top of this file). */
static sb_status check_events(const yaml_source* src, const unsigned char* text, size_t size) {
    yaml_parser_t parser;
    yaml_parser_initialize(&parser);
    yaml_parser_set_input_string(&parser, text, size);
    sb_status status = SB_OK;
    int depth = 0;
    for (bool end = false; status == SB_OK && !end;) {
        yaml_event_t event;
        if (!yaml_parser_parse(&parser, &event)) {
            status = yaml_fail(src, &parser);
            break;
        }
        status = check_event(src, &event, &depth);
        end = event.type == YAML_STREAM_END_EVENT;
        yaml_event_delete(&event);
    }
    yaml_parser_delete(&parser);
    return status;
}

/* A file holds one document whose root is a map (an empty file is fine). */
static sb_status walk_file(yaml_source* src, yaml_parser_t* parser) {
    yaml_node_t* root = yaml_document_get_root_node(src->doc);
    if (!root) return SB_OK;
    if (root->type != YAML_MAPPING_NODE) return source_fail(src, root, "a scene must be a map of keys");
    sb_status status = walk_map(src, root, "");
    if (status != SB_OK) return status;
    yaml_document_t next;
    if (!yaml_parser_load(parser, &next)) return yaml_fail(src, parser);
    yaml_node_t* extra = yaml_document_get_root_node(&next);
    if (extra) status = source_fail(src, extra, "a scene file holds one YAML document");
    yaml_document_delete(&next);
    return status;
}

/* The directory part of path; NULL (the current directory) without one. */
static char* directory_of(const char* path) {
    const char* slash = strrchr(path, '/');
    if (!slash) return NULL;
    if (slash == path) return strdup("/");
    return strndup(path, (size_t)(slash - path));
}

static char* name_of(const char* path) {
    const char* slash = strrchr(path, '/');
    const char* base = slash ? slash + 1 : path;
    const char* dot = strrchr(base, '.');
    return strndup(base, dot && dot != base ? (size_t)(dot - base) : strlen(base));
}

static sb_status load_text(sb_scene* scene, const unsigned char* text, size_t size, const char* path, sb_error* err) {
    char* dir = directory_of(path);
    yaml_source src = {.scene = scene, .name = path, .has_lines = true, .base_dir = dir, .err = err};
    sb_status status = check_events(&src, text, size);
    if (status != SB_OK) {
        free(dir);
        return status;
    }
    yaml_parser_t parser;
    yaml_document_t doc;
    yaml_parser_initialize(&parser);
    yaml_parser_set_input_string(&parser, text, size);
    if (!yaml_parser_load(&parser, &doc))
        status = yaml_fail(&src, &parser);
    else {
        src.doc = &doc;
        status = walk_file(&src, &parser);
        yaml_document_delete(&doc);
    }
    yaml_parser_delete(&parser);
    free(dir);
    return status;
}

/* The whole file, at most SB_SCENE_MAX_BYTES; a directory is refused. */
static sb_status read_scene_file(FILE* file, const char* path, unsigned char** text, size_t* size, sb_error* err) {
    struct stat info;
    if (fstat(fileno(file), &info) == 0 && S_ISDIR(info.st_mode))
        return sb_error_set(err, SB_ERR_IO, "%s: is a directory", path);
    *text = malloc(SB_SCENE_MAX_BYTES + 1);
    if (!*text) return sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    *size = fread(*text, 1, SB_SCENE_MAX_BYTES + 1, file);
    if (ferror(file)) return sb_error_set(err, SB_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
    if (*size > SB_SCENE_MAX_BYTES)
        return sb_error_set(err, SB_ERR_PARSE, "%s: larger than %d MiB, the limit for a scene file", path,
                            SB_SCENE_MAX_BYTES >> 20);
    return SB_OK;
}

/* A POV-Ray scene of mesh2 objects (the Spring Systems film maker's input)
 * is a scene of its own: its bodies by the film maker's rules (the mesh
 * reader's), as scenes/film_bounce.yaml sets them: meeting by self-contact,
 * POV-Ray's down (-y) the gravity's, the film maker's step and duration. */
static bool is_pov(const char* path) {
    size_t n = strlen(path);
    return n > 4 && strcmp(path + n - 4, ".pov") == 0;
}

static unsigned char* pov_scene_text(const char* path, size_t* size) {
    const char* slash = strrchr(path, '/');
    char* text = malloc(strlen(path) + 512);
    if (!text) return NULL;
    int n = sprintf(text,
                    "mesh: {generator: file, file: '%s'}\n"
                    "self_collision: true\n"
                    "contact: {thickness: 0.01}\n"
                    "gravity: [0, -9.8, 0]\n"
                    "drag: 0.2\n"
                    "integrator: verlet\n"
                    "dt: 0.0002\n"
                    "duration: 2.0\n"
                    "frame_interval: 0.04\n",
                    slash ? slash + 1 : path);
    *size = (size_t)n;
    return (unsigned char*)text;
}

sb_status sb_scene_load(sb_scene* scene, const char* path, sb_error* err) {
    FILE* file = fopen(path, "rb");
    if (!file) return sb_error_set(err, SB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    unsigned char* text = NULL;
    size_t size = 0;
    sb_status status = is_pov(path) ? SB_OK : read_scene_file(file, path, &text, &size, err);
    fclose(file);
    if (status == SB_OK && is_pov(path) && !(text = pov_scene_text(path, &size)))
        status = sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    if (status == SB_OK) status = load_text(scene, text, size, path, err);
    free(text);
    if (status != SB_OK) return status;
    free(scene->path);
    free(scene->name);
    scene->path = strdup(path);
    scene->name = name_of(path);
    if (scene->path && scene->name) return SB_OK;
    return sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
}

static sb_status set_value(yaml_source* src, const char* name, const char* text) {
    sb_status status = check_events(src, (const unsigned char*)text, strlen(text));
    if (status != SB_OK) return status;
    yaml_parser_t parser;
    yaml_document_t doc;
    yaml_parser_initialize(&parser);
    yaml_parser_set_input_string(&parser, (const unsigned char*)text, strlen(text));
    if (!yaml_parser_load(&parser, &doc)) {
        status = yaml_fail(src, &parser);
    } else {
        src->doc = &doc;
        yaml_node_t* root = yaml_document_get_root_node(&doc);
        status = root ? apply(src, root, name, root) : source_fail(src, &(yaml_node_t){0}, "missing value after '='");
        yaml_document_delete(&doc);
    }
    yaml_parser_delete(&parser);
    return status;
}

sb_status sb_scene_set(sb_scene* scene, const char* assignment, sb_error* err) {
    char where[320];
    snprintf(where, sizeof where, "--set %s", assignment);
    yaml_source src = {.scene = scene, .name = where, .err = err};
    const char* equals = strchr(assignment, '=');
    if (!equals || equals == assignment) return source_fail(&src, &(yaml_node_t){0}, "expected key=value");
    char name[256];
    snprintf(name, sizeof name, "%.*s", (int)(equals - assignment), assignment);
    return set_value(&src, name, equals + 1);
}
