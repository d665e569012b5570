/* `softbond keys [KEY|PREFIX] [--markdown]`: every scene key, its type,
 * default, unit and meaning, printed from the tables the parser itself uses
 * (SB_SCENE_KEYS, scenes/scene.h; then the keys of the lists' entries, from
 * scenes/colliders.c, handles.c and blades.c, as `colliders[].radius`).
 * docs/scene_keys.md is the output of `softbond keys --markdown`; a test
 * (scene_keys_doc) fails when they differ. */
#include "cli/cli.h"
#include "scenes/blades.h"
#include "scenes/colliders.h"
#include "scenes/handles.h"
#include "scenes/scene.h"
#include "scenes/suggest.h"

#include <string.h>

/* The lists whose entries have keys of their own, in the order printed. */
static const struct entry_list {
    const char* list; /* the top-level key */
    const sb_entry_key* (*keys)(size_t* count);
    const char* about; /* the --markdown section's first sentence */
} entry_lists[] = {
    {"colliders", sb_scene_collider_keys,
     "Each entry of `colliders` is a map of these keys; `type` decides which others it may have (the shapes "
     "column). A key of another shape, an unknown key or a missing required one is an error naming "
     "`colliders[i].key` and its line."},
    {"handles", sb_scene_handle_keys,
     "Each entry of `handles` is a map of these keys, with `vertices` or `at` (not both); see "
     "[handles.md](handles.md)."},
    {"blades", sb_scene_blade_keys, "Each entry of `blades` is a map of these keys; see [breakage.md](breakage.md)."},
};
enum { ENTRY_LIST_COUNT = sizeof entry_lists / sizeof entry_lists[0] };

/* "colliders[].radius" */
static const char* entry_name(const struct entry_list* list, const sb_entry_key* key, char* out, size_t size) {
    snprintf(out, size, "%s[].%s", list->list, key->name);
    return out;
}

/* "sphere, capsule", or "all" */
static void shapes_text(unsigned shapes, char* out, size_t size) {
    out[0] = '\0';
    if (shapes == (1u << SB_COLLIDER_SHAPE_COUNT) - 1u) {
        snprintf(out, size, "all");
        return;
    }
    for (int s = 0; s < SB_COLLIDER_SHAPE_COUNT; s++) {
        if (!(shapes & (1u << s))) continue;
        size_t used = strlen(out);
        snprintf(out + used, size - used, "%s%s", used ? ", " : "", sb_collider_shape_name((sb_collider_shape)s));
    }
}

void sb_cli_keys_usage(FILE* stream) {
    fprintf(stream, "usage: softbond keys [KEY|PREFIX] [--markdown]\n"
                    "Prints every scene key (or the one named, or those under a prefix such as\n"
                    "'haptics'): its type, default, unit and meaning, from the parser's own table;\n"
                    "then the keys of the lists' entries, as colliders[].radius ('colliders' selects\n"
                    "the list and its entries' keys).\n"
                    "  --markdown   the reference page docs/scene_keys.md, a Markdown table\n"
                    "  -h, --help   this help\n");
}

static const char* type_name(sb_scene_type type) {
    switch (type) {
    case SB_SCENE_NUMBER: return "number";
    case SB_SCENE_INTEGER: return "integer";
    case SB_SCENE_STRING: return "string";
    case SB_SCENE_BOOL: return "bool";
    case SB_SCENE_VEC3: return "[x, y, z]";
    case SB_SCENE_VEC3_OR_NUMBER: return "number or [x, y, z]";
    case SB_SCENE_INDICES: return "list of indices";
    case SB_SCENE_NAMES: return "list of names";
    case SB_SCENE_LIST: return "list of maps";
    }
    return "?";
}

/* KEY itself, or every key under "PREFIX." (or "LIST[]."). */
static bool selected(const char* name, const char* pick) {
    if (!pick) return true;
    size_t n = strlen(pick);
    return strcmp(name, pick) == 0 || (strncmp(name, pick, n) == 0 && (name[n] == '.' || name[n] == '['));
}

static bool required(const sb_entry_key* key) { return strcmp(key->default_value, SB_ENTRY_REQUIRED) == 0; }

/* Markdown table cells: a '|' would end the cell. */
static void cell(const char* text) {
    for (const char* c = text; *c; c++) {
        if (*c == '|')
            fputs("\\|", stdout);
        else
            putchar(*c);
    }
}

static void print_markdown_entries(const struct entry_list* list, const char* pick) {
    size_t count;
    const sb_entry_key* keys = list->keys(&count);
    char name[96], shapes[96];
    bool any = false, colliders = keys[0].shapes != 0;
    for (size_t i = 0; i < count; i++) any = any || selected(entry_name(list, &keys[i], name, sizeof name), pick);
    if (!any) return;
    printf("\n## `%s` entries\n\n%s\n\n", list->list, list->about);
    puts(colliders ? "| key | type | default | unit | shapes | meaning |\n|---|---|---|---|---|---|"
                   : "| key | type | default | unit | meaning |\n|---|---|---|---|---|");
    for (size_t i = 0; i < count; i++) {
        const sb_entry_key* key = &keys[i];
        if (!selected(entry_name(list, key, name, sizeof name), pick)) continue;
        printf("| `%s` | %s | %s%s%s | %s | ", name, type_name(key->type), required(key) ? "" : "`", key->default_value,
               required(key) ? "" : "`", key->unit[0] ? key->unit : "-");
        if (colliders) {
            shapes_text(key->shapes, shapes, sizeof shapes);
            printf("%s | ", shapes);
        }
        cell(key->meaning);
        puts(" |");
    }
}

static void print_markdown(const char* pick) {
    puts("# Scene keys\n\n"
         "<!-- Generated by `softbond keys --markdown` from the parser's key tables\n"
         "     (SB_SCENE_KEYS, scenes/scene.h; the entries' keys in scenes/colliders.c,\n"
         "     handles.c and blades.c); do not edit: the test scene_keys_doc fails when\n"
         "     this page and the tables differ. -->\n\n"
         "Every key a scene file (or `--set key=value`) may set, in the order of the\n"
         "parser's table. Nested maps are dotted keys: `bond: {k: 1}` is `bond.k: 1`.\n"
         "Units are SI; `1` marks a ratio and `-` a count, a name or a switch. An\n"
         "unknown key, a wrong type or a duplicate is an error naming the file and\n"
         "line. The entries of `colliders`, `handles` and `blades` have keys of their\n"
         "own, listed [after these](#colliders-entries) as `colliders[].radius`.\n"
         "`softbond keys KEY` prints one key in a terminal (`softbond keys colliders`\n"
         "the list and its entries' keys).\n\n"
         "| key | type | default | unit | meaning |\n"
         "|---|---|---|---|---|");
    for (int i = 0; i < SB_KEY_COUNT; i++) {
        const sb_scene_key_info* key = sb_scene_key_get((sb_scene_key)i);
        if (!selected(key->name, pick)) continue;
        printf("| `%s` | %s | `%s` | %s | ", key->name, type_name(key->type), key->default_value,
               key->unit[0] ? key->unit : "-");
        cell(key->meaning);
        puts(" |");
    }
    for (int l = 0; l < ENTRY_LIST_COUNT; l++) print_markdown_entries(&entry_lists[l], pick);
}

static void print_text(const char* pick) {
    for (int i = 0; i < SB_KEY_COUNT; i++) {
        const sb_scene_key_info* key = sb_scene_key_get((sb_scene_key)i);
        if (!selected(key->name, pick)) continue;
        printf("%s\n    type: %s, default: %s%s%s\n    %s\n", key->name, type_name(key->type), key->default_value,
               key->unit[0] ? ", unit: " : "", key->unit, key->meaning);
    }
    for (int l = 0; l < ENTRY_LIST_COUNT; l++) {
        size_t count;
        const sb_entry_key* keys = entry_lists[l].keys(&count);
        char name[96], shapes[96];
        for (size_t i = 0; i < count; i++) {
            const sb_entry_key* key = &keys[i];
            if (!selected(entry_name(&entry_lists[l], key, name, sizeof name), pick)) continue;
            shapes_text(key->shapes, shapes, sizeof shapes);
            printf("%s\n    type: %s, default: %s%s%s%s%s\n    %s\n", name, type_name(key->type), key->default_value,
                   key->unit[0] ? ", unit: " : "", key->unit, key->shapes ? ", shapes: " : "",
                   key->shapes ? shapes : "", key->meaning);
        }
    }
}

int sb_cli_keys(int argc, char** argv) {
    const char* pick = NULL;
    bool markdown = false;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            sb_cli_keys_usage(stdout);
            return SB_EXIT_OK;
        }
        if (strcmp(argv[i], "--markdown") == 0) {
            markdown = true;
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "softbond: keys: unknown option '%s' (softbond keys takes --markdown and --help)\n",
                    argv[i]);
            return SB_EXIT_INPUT;
        } else if (pick) {
            fprintf(stderr, "softbond: keys: one KEY or PREFIX at most, got '%s' and '%s'\n", pick, argv[i]);
            return SB_EXIT_INPUT;
        } else {
            pick = argv[i];
        }
    }
    if (pick) {
        /* every name, the entries' ones written out, for the selection and the suggestion */
        enum { MAX_NAMES = SB_KEY_COUNT + ENTRY_LIST_COUNT * SB_MAP_MAX_KEYS };
        static char entry_names[MAX_NAMES][96];
        const char* names[MAX_NAMES];
        size_t name_count = 0;
        for (int i = 0; i < SB_KEY_COUNT; i++) names[name_count++] = sb_scene_key_get((sb_scene_key)i)->name;
        for (int l = 0; l < ENTRY_LIST_COUNT; l++) {
            size_t count;
            const sb_entry_key* keys = entry_lists[l].keys(&count);
            for (size_t i = 0; i < count && name_count < MAX_NAMES; i++, name_count++)
                names[name_count] =
                    entry_name(&entry_lists[l], &keys[i], entry_names[name_count], sizeof entry_names[name_count]);
        }
        bool any = false;
        for (size_t i = 0; i < name_count; i++) any = any || selected(names[i], pick);
        if (!any) {
            const char* near = sb_suggest(pick, names, name_count);
            fprintf(stderr, "softbond: keys: no scene key '%s'%s%s%s; softbond keys lists them all\n", pick,
                    near ? " (did you mean '" : "", near ? near : "", near ? "'?)" : "");
            return SB_EXIT_INPUT;
        }
    }
    if (markdown)
        print_markdown(pick);
    else
        print_text(pick);
    return fflush(stdout) == 0 && !ferror(stdout) ? SB_EXIT_OK : SB_EXIT_FAILURE;
}
