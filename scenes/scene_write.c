/* A scene written back as YAML (see scene.h, sb_scene_write): every key of
 * SB_SCENE_KEYS with its value now, nested as the loader reads it (the
 * dotted names grouped under their first parts, in the table's order of
 * first appearance), so that loading the text gives the same values.
 *
 * Numbers are written with 17 significant digits (a double read back is the
 * same double), strings single-quoted, the lists (colliders, handles,
 * blades) in block style as read: a scalar plain when it was plain, quoted
 * otherwise. Paths are made absolute (mesh.file, haptics.file, a mesh
 * collider's file), so the text loads the same from any folder. */
#define _XOPEN_SOURCE 700
#include "scenes/scene.h"

#include <limits.h>
#include <stdlib.h>
#include <string.h>

static void put_quoted(FILE* f, const char* text) {
    fputc('\'', f);
    for (const char* p = text; *p; p++) {
        if (*p == '\'') fputc('\'', f);
        fputc(*p, f);
    }
    fputc('\'', f);
}

/* dir/path made absolute (realpath when it exists); caller frees. */
static char* absolute(const char* dir, const char* path) {
    if (path[0] == '\0') return strdup(path);
    size_t size = strlen(path) + (dir ? strlen(dir) : 1) + 2;
    char* joined = malloc(size);
    if (!joined) return NULL;
    if (path[0] == '/')
        snprintf(joined, size, "%s", path);
    else
        snprintf(joined, size, "%s/%s", dir ? dir : ".", path);
    char* real = realpath(joined, NULL);
    if (!real) return joined;
    free(joined);
    return real;
}

static void put_number(FILE* f, double value) { fprintf(f, "%.17g", value); }

static void put_indent(FILE* f, int indent) {
    for (int i = 0; i < indent; i++) fputc(' ', f);
}

static void put_scalar(FILE* f, const sb_scene_node* node, const char* dir, bool is_path) {
    if (is_path) {
        char* path = absolute(dir, node->text);
        put_quoted(f, path ? path : node->text);
        free(path);
    } else if (node->plain && node->text[0])
        fputs(node->text, f);
    else
        put_quoted(f, node->text);
}

/* A list's node in block style at `indent`; `dir` resolves the paths of a
 * map's `file` key (colliders). */
static void put_node(FILE* f, const sb_scene_node* node, int indent, const char* dir);

static void put_child(FILE* f, const sb_scene_node* node, int indent, const char* dir, bool is_path) {
    if (node->kind == SB_NODE_SCALAR) {
        fputc(' ', f);
        put_scalar(f, node, dir, is_path);
        fputc('\n', f);
    } else if (node->count == 0)
        fputs(node->kind == SB_NODE_MAP ? " {}\n" : " []\n", f);
    else {
        fputc('\n', f);
        put_node(f, node, indent, dir);
    }
}

static void put_node(FILE* f, const sb_scene_node* node, int indent, const char* dir) {
    for (size_t i = 0; i < node->count; i++) {
        put_indent(f, indent);
        if (node->kind == SB_NODE_MAP) {
            put_scalar(f, &node->keys[i], NULL, false);
            fputc(':', f);
            put_child(f, &node->items[i], indent + 2, dir, strcmp(node->keys[i].text, "file") == 0);
        } else {
            fputc('-', f);
            put_child(f, &node->items[i], indent + 2, dir, false);
        }
    }
}

static bool is_path_key(sb_scene_key key) { return key == SB_KEY_MESH_FILE || key == SB_KEY_HAPTICS_FILE; }

static void put_value(FILE* f, const sb_scene* scene, sb_scene_key key, int indent) {
    const sb_scene_value* value = &scene->values[key];
    switch (sb_scene_key_get(key)->type) {
    case SB_SCENE_NUMBER:
        fputc(' ', f);
        put_number(f, value->number);
        break;
    case SB_SCENE_INTEGER: fprintf(f, " %lld", (long long)value->integer); break;
    case SB_SCENE_BOOL: fputs(value->boolean ? " true" : " false", f); break;
    case SB_SCENE_STRING:
    case SB_SCENE_NAMES: {
        fputc(' ', f);
        char* path = is_path_key(key) ? absolute(value->base_dir, value->string) : NULL;
        put_quoted(f, path ? path : value->string);
        free(path);
        break;
    }
    case SB_SCENE_VEC3:
    case SB_SCENE_VEC3_OR_NUMBER:
        for (int k = 0; k < 3; k++) {
            fputs(k ? ", " : " [", f);
            put_number(f, value->vec3[k]);
        }
        fputc(']', f);
        break;
    case SB_SCENE_INDICES:
        fputs(" [", f);
        for (uint32_t i = 0; i < value->index_count; i++) fprintf(f, "%s%u", i ? ", " : "", value->indices[i]);
        fputc(']', f);
        break;
    case SB_SCENE_LIST:
        if (!value->tree || value->tree->root.count == 0) {
            fputs(" []\n", f);
            return;
        }
        fputc('\n', f);
        put_node(f, &value->tree->root, indent + 2, value->base_dir);
        return;
    }
    fputc('\n', f);
}

/* False for a key whose being set is itself a setting and that was not set:
 * tissue.young_modulus and tissue.density win over the material's only
 * when set, so they are written as a comment instead. */
static bool set_or_plain(const sb_scene* scene, sb_scene_key key) {
    return (key != SB_KEY_TISSUE_YOUNG_MODULUS && key != SB_KEY_TISSUE_DENSITY) || scene->values[key].where[0];
}

/* The length of the first `parts` dotted parts of name (the whole name when it has fewer). */
static size_t prefix_length(const char* name, int parts) {
    size_t n = 0;
    for (int p = 0; p < parts; p++) {
        n += strcspn(name + n, ".");
        if (name[n] == '\0') return n;
        if (p + 1 < parts) n++;
    }
    return n;
}

/* Every key whose name starts with `prefix` (length n, the first `depth`
 * parts), grouped by the next part, from key `from` on. */
static void put_group(FILE* f, const sb_scene* scene, const char* prefix, size_t n, int depth, bool* done) {
    for (int key = 0; key < SB_KEY_COUNT; key++) {
        const char* name = sb_scene_key_get((sb_scene_key)key)->name;
        if (done[key] || (n && (strncmp(name, prefix, n) != 0 || name[n] != '.'))) continue;
        size_t start = n ? n + 1 : 0;
        size_t part = prefix_length(name, depth + 1);
        put_indent(f, 2 * depth);
        bool unset = name[part] == '\0' && !set_or_plain(scene, (sb_scene_key)key);
        fprintf(f, "%s%.*s:", unset ? "# " : "", (int)(part - start), name + start);
        if (unset) {
            fputs(" not set: the material's\n", f);
            done[key] = true;
        } else if (name[part] == '\0') {
            put_value(f, scene, (sb_scene_key)key, 2 * depth);
            done[key] = true;
        } else {
            fputc('\n', f);
            put_group(f, scene, name, part, depth + 1, done);
        }
    }
}

void sb_scene_write(const sb_scene* scene, FILE* f) {
    bool done[SB_KEY_COUNT] = {false};
    put_group(f, scene, "", 0, 0, done);
}
