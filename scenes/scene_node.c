/* Structured scene values (see scene_node.h). The tree is made from the
 * YAML document in scene_yaml.c. */
#include "scenes/scene_node.h"
#include "common/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void node_release(sb_scene_node* node) {
    free(node->text);
    for (size_t i = 0; i < node->count && node->items; i++) node_release(&node->items[i]);
    for (size_t i = 0; i < node->count && node->keys; i++) node_release(&node->keys[i]);
    free(node->items);
    free(node->keys);
}

void sb_scene_tree_free(sb_scene_tree* tree) {
    if (!tree) return;
    node_release(&tree->root);
    free(tree->source);
    free(tree);
}

sb_status sb_scene_node_fail(const sb_scene_tree* tree, const sb_scene_node* node, sb_error* err, const char* format,
                             ...) {
    va_list args;
    va_start(args, format);
    sb_error_vset(err, SB_ERR_INVALID, format, args);
    va_end(args);
    if (!node->line) return sb_error_prefix(err, SB_ERR_INVALID, tree->source);
    char where[400];
    snprintf(where, sizeof where, "%s:%zu", tree->source, node->line);
    return sb_error_prefix(err, SB_ERR_INVALID, where);
}

void sb_scene_node_describe(const sb_scene_node* node, char* out, size_t size) {
    if (node->kind == SB_NODE_SEQUENCE)
        snprintf(out, size, "a sequence of %zu", node->count);
    else if (node->kind == SB_NODE_MAP)
        snprintf(out, size, "a map");
    else
        snprintf(out, size, "'%.80s'", node->text);
}

bool sb_scene_scalar_number(const char* text, bool plain, double* out) {
    if (!plain || !text[0]) return false;
    char* end;
    *out = strtod(text, &end);
    return *end == '\0';
}

bool sb_scene_node_number(const sb_scene_node* node, double* out) {
    return node->kind == SB_NODE_SCALAR && sb_scene_scalar_number(node->text, node->plain, out);
}

bool sb_scene_comma_vec3(const char* text, bool plain, double out[3]) {
    if (!plain || strlen(text) >= 256) return false;
    char copy[256];
    snprintf(copy, sizeof copy, "%s", text);
    char* part = copy;
    for (int i = 0; i < 3; i++) {
        char* comma = strchr(part, ',');
        if ((i < 2) != (comma != NULL)) return false;
        if (comma) *comma = '\0';
        while (*part == ' ') part++;
        size_t n = strlen(part);
        while (n > 0 && part[n - 1] == ' ') part[--n] = '\0';
        if (!sb_scene_scalar_number(part, true, &out[i])) return false;
        if (comma) part = comma + 1;
    }
    return true;
}
